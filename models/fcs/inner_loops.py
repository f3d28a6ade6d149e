"""The FCS's inner loops in one compiled step: airspeed-rate estimate, energy limits, TECS, airbrake, pitch,
lateral and fuel control.

:func:`inner_step` is what :meth:`.fcs.FlightControlSystem.step` runs after the mission's sections gave
their targets. It calls the laws' one implementation (:func:`.estimation.estimator_law`,
:func:`.performance.energy_rates_law`, :func:`.tecs.tecs_law`, :func:`.performance.airbrake_position_law`,
:func:`.pitch.pitch_law`, :func:`.lateral.lateral_law`, :func:`.fuel_control.fuel_law`), which the
controllers' own ``step`` methods call as plain Python; numba compiles them into this one function
(``jitable``), so that a step is one compiled call on plain floats and two buffers, the controllers'
states and parameters (:data:`STATE_BLOCKS`, :data:`PARAM_BLOCKS`), which it borrows
(:func:`..infra.jit.borrowed`).

Why compiled: in the whole mission the FCS's Python step cost two and a half times what it costs alone,
the engine and the airframe evicting its code and objects from the caches between two steps; the
inner loops, a third of the step's Python work, are a few kilobytes of machine code here (issue 14,
point 8: at most 40 us per step in the mission). Without numba (``OPENEMSS_NO_JIT``) the same function
runs as Python.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..infra.jit import borrowed, jit
from .estimation import EstimationParams, estimator_law
from .fuel_control import FuelControlParams, fuel_law
from .lateral import LateralParams, lateral_law
from .performance import airbrake_position_law, energy_rates_law
from .pitch import PitchParams, pitch_law, turn_pitch_rate
from .tecs import TP, TecsParams, tecs_law

__all__ = ["inner_step", "PERF_VALUES", "STATE_BLOCKS", "PARAM_BLOCKS", "blocks"]

#: The performance model's values in its block of the parameter buffer: the look-up (CD0, k, idle and maximum
#: thrust [N]) then :meth:`.performance.Performance.airbrake_values`.
PERF_VALUES = ("cd0", "k", "t_idle_N", "t_max_N", "S_m2", "cd_gear", "airbrake_full_N_Pa", "airbrake_max_rad",
               "airbrake_blowback_qbar_Pa")
#: The blocks of the state buffer, (name, size): each controller's state array (``_s``) is a view of its block,
#: ``rate_filter`` the FCS's low-passed airspeed rate (1 once set, the rate [m/s^2]). One buffer, not one array per
#: controller: numba wraps every array argument of a call from Python in a new reference-counted record.
STATE_BLOCKS = (("estimation", 8), ("rate_filter", 2), ("tecs", 5), ("pitch", 1), ("lateral", 1),
                ("fuel_control", 5))
#: The blocks of the parameter buffer, (name, size): the controllers' ``values()`` and the performance model's.
PARAM_BLOCKS = tuple((name, len(dataclasses.fields(cls))) for name, cls in (
    ("estimation", EstimationParams), ("tecs", TecsParams), ("pitch", PitchParams), ("lateral", LateralParams),
    ("fuel_control", FuelControlParams))) + (("performance", len(PERF_VALUES)),)


def blocks(layout: tuple[tuple[str, int], ...]) -> dict[str, tuple[int, int]]:
    """(start, end) of each block of a buffer's layout."""
    out, start = {}, 0
    for name, size in layout:
        out[name] = (start, start + size)
        start += size
    return out


_SB, _PB = blocks(STATE_BLOCKS), blocks(PARAM_BLOCKS)
# the blocks' bounds as module constants, which numba compiles in
_S_EST0, _S_EST1 = _SB["estimation"]
_S_RATE = _SB["rate_filter"][0]
_S_TECS0, _S_TECS1 = _SB["tecs"]
_S_PITCH0, _S_PITCH1 = _SB["pitch"]
_S_LAT0, _S_LAT1 = _SB["lateral"]
_S_FUEL0, _S_FUEL1 = _SB["fuel_control"]
_P_EST = _PB["estimation"][0]
_P_TECS0, _P_TECS1 = _PB["tecs"]
_P_PITCH0, _P_PITCH1 = _PB["pitch"]
_P_LAT0, _P_LAT1 = _PB["lateral"]
_P_FUEL0, _P_FUEL1 = _PB["fuel_control"]
_P_PERF = _PB["performance"][0]


@jit
def inner_step(state: np.ndarray, params: np.ndarray, dt_s: float, alt_m: float, tas_m_s: float, Vdot_m_s2: float,
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
    state, params : array
        The state buffer (:data:`STATE_BLOCKS`, updated in place) and the parameter buffer (:data:`PARAM_BLOCKS`).
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
    state, params = borrowed((state, params))
    est_s, tecs_s, fuel_s = state[_S_EST0:_S_EST1], state[_S_TECS0:_S_TECS1], state[_S_FUEL0:_S_FUEL1]
    tecs_p = params[_P_TECS0:_P_TECS1]
    perf_v = params[_P_PERF:]
    vdot, tas = Vdot_m_s2, tas_m_s
    if vdot != vdot:  # NaN: estimated, then low-passed (tecs.tau_Vdot_s)
        raw = estimator_law(params[_P_EST], est_s, dt_s, tas_m_s, vn_m_s, ve_m_s, tas_m_s * math.sin(gamma_rad),
                            phi_rad, theta_rad, psi_rad, beta_rad, gamma_rad)
        tau = tecs_p[TP.tau_Vdot_s]
        vf = state[_S_RATE + 1]
        vdot = raw if state[_S_RATE] == 0.0 else vf + (raw - vf) * dt_s / (tau + dt_s)
        state[_S_RATE], state[_S_RATE + 1] = 1.0, vdot
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
    elevator = pitch_law(params[_P_PITCH0:_P_PITCH1], state[_S_PITCH0:_S_PITCH1], dt_s, theta_c, theta_rad, q_rad_s,
                         qbar_Pa, q_turn, ground_gains)
    # (no track command: the track, the fourth argument, is not used)
    aileron, rudder, phi_cmd = lateral_law(params[_P_LAT0:_P_LAT1], state[_S_LAT0:_S_LAT1], dt_s, phi_rad,
                                           theta_rad, psi_rad, math.nan, p_rad_s, r_rad_s, beta_rad, tas_m_s,
                                           qbar_Pa, phi_cmd_rad, has_phi, heading_cmd_rad, has_heading, math.nan,
                                           False)
    f = fuel_law(params[_P_FUEL0:_P_FUEL1], fuel_s, dt_s, lever, N1c_pct, N1_pct, Tt41_K)
    return elevator, aileron, rudder, lever, f[0], theta_c, phi_cmd, tas_cmd, f[4], airbrake, ok
