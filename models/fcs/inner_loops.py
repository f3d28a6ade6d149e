"""The FCS's inner loops in one compiled step: airspeed-rate estimate, energy limits, TECS, airbrake, pitch,
lateral and fuel control.

:func:`inner_step` is what :meth:`.fcs.FlightControlSystem.step` runs after the mission's sections gave
their targets. It calls the laws' one implementation (:func:`.estimation.estimator_law`,
:func:`.performance.energy_rates_law`, :func:`.tecs.tecs_law`, :func:`.performance.airbrake_position_law`,
:func:`.pitch.pitch_law`, :func:`.lateral.lateral_law`, :func:`.fuel_control.fuel_law`), which the
controllers' own ``step`` methods call as plain Python; numba compiles them into this one function
(``jitable``), so that a step is one compiled call on plain floats and the controllers' parameter and
state arrays, which it borrows (:func:`..common.jit.borrowed`).

Why compiled: in the whole mission the FCS's Python step cost two and a half times what it costs alone,
the engine and the airframe evicting its code and objects from the caches between two steps; the
inner loops, a third of the step's Python work, are a few kilobytes of machine code here (issue 14,
point 8: at most 40 us per step in the mission). Without numba (``OPENEMSS_NO_JIT``) the same function
runs as Python.
"""
from __future__ import annotations

import math

import numpy as np

from ..common.jit import borrowed, jit
from .estimation import estimator_law
from .fuel_control import fuel_law
from .lateral import lateral_law
from .performance import airbrake_position_law, energy_rates_law
from .pitch import pitch_law, turn_pitch_rate
from .tecs import TP, tecs_law

__all__ = ["inner_step", "PERF_VALUES"]

#: The layout of ``perf_v``: the performance model's look-up (CD0, k, idle and maximum thrust [N]) then
#: :meth:`.performance.Performance.airbrake_values`.
PERF_VALUES = ("cd0", "k", "t_idle_N", "t_max_N", "S_m2", "cd_gear", "airbrake_full_N_Pa", "airbrake_max_rad",
               "airbrake_blowback_qbar_Pa")


@jit
def inner_step(tau_cross_s: float, est_s: np.ndarray, fcs_s: np.ndarray, tecs_p: np.ndarray, tecs_s: np.ndarray,
               pitch_p: np.ndarray, pitch_s: np.ndarray, lat_p: np.ndarray, lat_s: np.ndarray, fuel_p: np.ndarray,
               fuel_s: np.ndarray, perf_v: np.ndarray, dt_s: float, alt_m: float, tas_m_s: float, Vdot_m_s2: float,
               gamma_rad: float, vn_m_s: float, ve_m_s: float, psi_rad: float, phi_rad: float, theta_rad: float,
               p_rad_s: float, q_rad_s: float, r_rad_s: float, beta_rad: float, qbar_Pa: float, mass_kg: float,
               dT_isa_K: float, on_ground: bool, N1c_pct: float, N1_pct: float, Tt41_K: float, tecs_on: bool,
               theta_cmd_rad: float, lever_cmd: float, has_lever: bool, speed: float, speed_kind: int,
               alt_cmd_m: float, has_alt: bool, gamma_cmd_rad: float, hdot_ff_m_s: float, priority: int,
               gear_down: bool, airbrake_allowed: bool, ground_gains: bool, phi_cmd_rad: float, has_phi: bool,
               heading_cmd_rad: float, has_heading: bool) -> tuple:
    """One step of the inner loops (see the module; the FCS's step documents the law).

    Parameters
    ----------
    tau_cross_s, est_s : float, array
        The estimator's crossover time constant [s] and state (:class:`.estimation.AirspeedRateEstimator`).
    fcs_s : array
        The FCS's low-passed airspeed rate: (1 once set, the rate [m/s^2]).
    tecs_p, tecs_s, pitch_p, pitch_s, lat_p, lat_s, fuel_p, fuel_s : array
        Parameters (``values()``) and state of the TECS, pitch, lateral and fuel controllers.
    perf_v : array
        The performance model's values, :data:`PERF_VALUES`.
    dt_s, ... Tt41_K : float
        The step [s] and the measured state (:class:`.state.AircraftState`, :class:`.state.EngineState`); a NaN
        ``Vdot_m_s2`` is estimated.
    tecs_on ... has_heading
        The section's targets: energy control on (else ``theta_cmd_rad`` and the lever are flown), the fixed
        lever, the speed target (value, kind code), the altitude or path-angle target, the vertical speed of a
        managed path [m/s], the priority's code (:data:`.tecs.PRIORITIES`), gear, airbrake allowed, the ground
        gains of the pitch loop, the bank or heading command [rad].

    Returns
    -------
    tuple
        elevator, aileron, rudder, lever, fuel-flow command [kg/s], pitch and bank commands [rad], speed target
        as true airspeed [m/s] (NaN without energy control), fuel limiter's code, airbrake position [0, 1], and
        False if the altitude was outside the atmosphere's range (then the FCS raises its error).
    """
    est_s, fcs_s, tecs_p, tecs_s = borrowed((est_s, fcs_s, tecs_p, tecs_s))
    pitch_p, pitch_s, lat_p, lat_s, fuel_p, fuel_s, perf_v = borrowed((pitch_p, pitch_s, lat_p, lat_s, fuel_p,
                                                                      fuel_s, perf_v))
    vdot, tas = Vdot_m_s2, tas_m_s
    if vdot != vdot:  # NaN: estimated, then low-passed (tecs.tau_Vdot_s)
        raw = estimator_law(tau_cross_s, est_s, dt_s, tas_m_s, vn_m_s, ve_m_s, tas_m_s * math.sin(gamma_rad),
                            phi_rad, theta_rad, psi_rad, beta_rad, gamma_rad)
        tau = tecs_p[TP.tau_Vdot_s]
        vdot = raw if fcs_s[0] == 0.0 else fcs_s[1] + (raw - fcs_s[1]) * dt_s / (tau + dt_s)
        fcs_s[0], fcs_s[1] = 1.0, vdot
        if est_s[0] != 0.0:
            tas = est_s[1]
    tas_cmd = math.nan
    airbrake = 0.0
    ok = True
    if not tecs_on:
        theta_c = theta_cmd_rad
        lever = lever_cmd if has_lever else 0.0
    else:
        if on_ground or tas_m_s < 30.0:
            e_min, e_max, ab_max = math.nan, math.nan, 0.0
        else:
            e_min, e_max, ab_max = energy_rates_law(perf_v[0], perf_v[1], perf_v[2], perf_v[3], perf_v[4], perf_v[5],
                                                    perf_v[6], perf_v[7], perf_v[8], qbar_Pa, mass_kg, phi_rad,
                                                    gear_down, airbrake_allowed)
        out = tecs_law(tecs_p, tecs_s, dt_s, alt_m, tas, vdot, gamma_rad, mass_kg, dT_isa_K, e_min, e_max, speed,
                       speed_kind, alt_cmd_m, has_alt, gamma_cmd_rad, lever_cmd, has_lever, hdot_ff_m_s, priority,
                       ab_max)
        # (the fields of TecsOutput: thrust, lever, theta_cmd, gamma_cmd, Vdot_cmd, tas_cmd, ..., airbrake)
        lever, theta_c, tas_cmd, ok = out[1], out[2], out[5], out[12]
        if out[10] > 0.0:
            airbrake = airbrake_position_law(perf_v[6], perf_v[7], out[10], qbar_Pa)
    q_turn = 0.0 if on_ground else turn_pitch_rate(phi_rad, tas_m_s)
    elevator = pitch_law(pitch_p, pitch_s, dt_s, theta_c, theta_rad, q_rad_s, qbar_Pa, q_turn, ground_gains)
    # (no track command: the track, the fourth argument, is not used)
    aileron, rudder, phi_cmd = lateral_law(lat_p, lat_s, dt_s, phi_rad, theta_rad, psi_rad, math.nan, p_rad_s,
                                           r_rad_s, beta_rad, tas_m_s, qbar_Pa, phi_cmd_rad, has_phi,
                                           heading_cmd_rad, has_heading, math.nan, False)
    f = fuel_law(fuel_p, fuel_s, dt_s, lever, N1c_pct, N1_pct, Tt41_K)
    return elevator, aileron, rudder, lever, f[0], theta_c, phi_cmd, tas_cmd, f[4], airbrake, ok
