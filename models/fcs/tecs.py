"""Total Energy Control System (TECS): thrust and pitch from energy rates.

Lambregts' formulation. With flight-path angle gamma, true airspeed V and its
rate Vdot, the specific total energy E/W = h + V^2/(2g) changes at

    d/dt (h + V^2 / 2g) = V (sin gamma + Vdot / g)                        (1)

so ``sin gamma + Vdot/g`` is the *specific total energy rate* (per unit V) and
``sin gamma - Vdot/g`` the *energy distribution rate*. Thrust changes the
first, at constant thrust pitch only trades between height and speed, so:

* commands: gamma_c = clip(gamma_ff + k_h (h_c - h) / V, gamma_min, gamma_max)
  (altitude mode: first-order capture with time constant 1/k_h, no overshoot;
  gamma_ff = asin(hdot_ff / V) the feed-forward of a managed vertical path, 0 for
  a level), or a given gamma_c (path mode, e.g. glide slope, flare);
  Vdot_c = clip(k_V (V_c - V), +-Vdot_max), changing by at most jerk_max per second
  (a speed step does not kick the pitch before the thrust can follow);
* errors: e_g = sin gamma_c - sin gamma, e_v = (Vdot_c - Vdot) / g;
  E_err = e_g + e_v (total), L_err = w_g e_g - w_v e_v (distribution);
* thrust: T_c / W = k_TP E_err + k_TI Int E_err dt (the integral holds D/W);
* pitch: theta_c = k_EP L_err + k_EI Int L_err dt (the integral holds the trim alpha).

Energy-rate command limiting (Lambregts 2013). The energy rate the thrust can
give, [E_min, E_max] = [(T_idle - D - D_airbrake) / W, (T_max - D) / W], is an
input (from the performance model, :mod:`.performance`). A demand sin gamma_c +
Vdot_c/g outside it (less ``energy_margin``, or a quarter of the headroom over sin gamma_c
where that is smaller) is cut back before the loops see it, in the channel that
has no priority:

* *path priority* (altitude hold and capture, a managed path, the glide slope):
  the acceleration command is cut -- in level flight a speed step at maximum
  thrust accelerates at what the thrust gives and the height is held;
* *speed priority* (an open climb or descent: the altitude command asks for more
  than the flight-path limit, or the caller says so): the flight-path command is
  cut -- a climb at maximum thrust climbs at what is left after the acceleration,
  but no less than level (the acceleration is cut beyond), so a climb that must
  also accelerate does not first descend, nor an idle descent that must also slow
  down first climb.

If the thrust saturates nevertheless (the model's limits are estimates), the
weights (w_g, w_v) blend from (1, 1) to (2, 0) (path) or (0, 2) (speed) with the
time constant ``tau_priority_s``, and back when the thrust comes off its limit
(with ``priority="path_only"``, a deceleration segment, they blend to the path's in
any case).
In underspeed (below V_min) speed has priority at once and the thrust lever goes
to its maximum, the speed command is raised to V_min; with a fixed lever (take-off,
flare) pitch flies the path (``gamma_cmd``) or the speed.

Below idle the thrust channel goes on into the airbrake where the caller allows
it (``airbrake_max_N`` > 0, in descents): the drag it asks for beyond idle is
``airbrake_drag_N``, through a first-order lag ``tau_airbrake_s`` (the airbrake acts at once
on the drag, where the engine's thrust lags its spools: without the lag the thrust loop's
proportional gain would close a one-step loop through it and chatter); the airbrake's drag
extends the lower energy limit.

Speed commands may be Mach, calibrated or true airspeed: they are turned into
true airspeed through the ISA (:mod:`.atmosphere`) at the current altitude.

The thrust command is given both in newtons and as a thrust lever, dividing by
an estimate of the available thrust thrust_sls (rho/rho0)^n; the lever feeds
the fuel controller, whose N1c loop and this loop's integral absorb the error
of that estimate.

References
----------
A. A. Lambregts, "Vertical flight path and speed control autopilot design using
total energy principles", AIAA paper 83-2239, 1983.
A. A. Lambregts, "TECS generalized airplane control system design -- an update",
in Advances in Aerospace Guidance, Navigation and Control, Springer, 2013
(energy-rate command limiting, speed and path priority).
B. R. Faleiro, A. A. Lambregts, "Analysis and tuning of a Total Energy Control
System control law using eigenstructure assignment", Aerospace Science and
Technology 3(3), 127-140, 1999.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..common.airspeed import cas_from_tas_values, tas_from_cas_values
from ..infra.jit import jitable
from ..infra.records import fast_init
from ..mission.speed import SpeedCommand, SpeedKind
from .atmosphere import G0_M_S2, isa, isa_values
from .clip import clip
from .errors import FcsError
from .tunable import Tunable, field_index, load_params

__all__ = ["TecsParams", "TecsInput", "TecsOutput", "Tecs", "tecs_law",
           "specific_energy_rate_m_s", "RHO0_KG_M3", "PRIORITIES", "SPEED_KINDS"]

#: Reference density of the available-thrust fit (thrust_sls_N (rho/rho0)^thrust_lapse_exp), the fit's own rounded
#: sea-level value, kept so that the fitted gains hold (the ISA's is models/common/atmosphere.RHO0_KG_M3, 1.2250114)
RHO0_KG_M3 = 1.225


_MACH, _CAS = SpeedKind.MACH, SpeedKind.CAS


@dataclass(frozen=True, slots=True)
class TecsParams:
    """TECS gains and limits (data/tecs.yaml, section ``tecs``); see the file for units and sources."""

    k_h_1_s: float
    k_V_1_s: float
    gamma_max_rad: float
    gamma_min_rad: float
    Vdot_max_m_s2: float
    k_TP: float
    k_TI_1_s: float
    k_EP: float
    k_EI_1_s: float
    theta_max_rad: float
    theta_min_rad: float
    thrust_sls_N: float
    thrust_lapse_exp: float
    lever_min: float
    lever_max: float
    energy_margin: float
    tau_priority_s: float
    V_min_cas_m_s: float
    underspeed_margin: float
    mach_max: float
    tau_Vdot_s: float
    jerk_max_m_s3: float
    tau_airbrake_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> TecsParams:
        """Parameter set of ``data/tecs.yaml``, section ``tecs``."""
        return load_params(cls, "tecs.yaml", "tecs", **overrides)


@fast_init
@dataclass(frozen=True, slots=True)
class TecsInput:
    """Measured longitudinal state.

    Attributes
    ----------
    alt_m : float
        Pressure (geopotential) altitude [m].
    tas_m_s : float
        True airspeed [m/s].
    Vdot_m_s2 : float
        Rate of change of true airspeed [m/s^2].
    gamma_rad : float
        Flight-path angle relative to the air mass, asin(hdot/V) [rad].
    mass_kg : float
        Aircraft mass [kg].
    dT_isa_K : float
        ISA temperature deviation [K].
    E_rate_min, E_rate_max : float
        Specific energy rate per unit airspeed, (T - D)/W, that idle (with the airbrake allowed) and
        maximum thrust give now [-]; NaN: unknown (no command limiting).
    """

    alt_m: float
    tas_m_s: float
    Vdot_m_s2: float
    gamma_rad: float
    mass_kg: float
    dT_isa_K: float = 0.0
    E_rate_min: float = math.nan
    E_rate_max: float = math.nan


@fast_init
@dataclass(frozen=True, slots=True)
class TecsOutput:
    """TECS commands and internal signals (all recorded for plots).

    Attributes
    ----------
    thrust_cmd_N : float
        Thrust command [N].
    lever : float
        Thrust lever command for the fuel controller [-].
    theta_cmd_rad : float
        Pitch attitude command for the inner loop [rad].
    gamma_cmd_rad : float
        Flight-path angle command [rad].
    Vdot_cmd_m_s2 : float
        Acceleration command [m/s^2].
    tas_cmd_m_s : float
        Speed target as true airspeed [m/s].
    energy_rate_err : float
        E_err = e_g + e_v [-].
    distribution_err : float
        L_err [-].
    priority : str
        ``"normal"``, ``"speed"`` or ``"path"``: the channel the limiting or the saturation favours.
    underspeed : bool
        Underspeed protection active.
    airbrake_drag_N : float
        Drag asked of the airbrake beyond idle [N] (0 unless allowed).
    limited : bool
        A command was cut to the energy rate the thrust can give.
    """

    thrust_cmd_N: float
    lever: float
    theta_cmd_rad: float
    gamma_cmd_rad: float
    Vdot_cmd_m_s2: float
    tas_cmd_m_s: float
    energy_rate_err: float
    distribution_err: float
    priority: str
    underspeed: bool
    airbrake_drag_N: float = 0.0
    limited: bool = False


def specific_energy_rate_m_s(tas_m_s: float, Vdot_m_s2: float, gamma_rad: float) -> float:
    """d/dt (h + V^2/2g) = V (sin gamma + Vdot/g), the specific total energy rate [m/s]."""
    return tas_m_s * (math.sin(gamma_rad) + Vdot_m_s2 / G0_M_S2)


class Tecs(Tunable[TecsParams]):
    """Total energy control: speed and altitude (or path) targets -> thrust and pitch commands."""

    tunable_name = "tecs"

    def __init__(self, params: TecsParams | None = None) -> None:
        self._params = params if params is not None else TecsParams.from_file()
        self._s = np.zeros(5)  # the state of tecs_law (_I_T, _I_L, _SIGMA, _A_C, _AB)

    def reset(self, Fn_N: float, weight_N: float, theta_rad: float, gamma_rad: float = 0.0) -> None:
        """Bumpless engagement from the current thrust [N], weight [N], pitch and path angles [rad]."""
        self._s[:] = (Fn_N / weight_N, theta_rad, 0.0, 0.0, 0.0)

    def available_thrust_N(self, alt_m: float, dT_isa_K: float = 0.0) -> float:
        """Estimate of the maximum thrust at altitude, thrust_sls (rho/rho0)^n [N]."""
        p = self._params
        return p.thrust_sls_N * (isa(alt_m, dT_isa_K).rho_kg_m3 / RHO0_KG_M3) ** p.thrust_lapse_exp

    def step(self, dt_s: float, x: TecsInput, speed: SpeedCommand, alt_cmd_m: float | None = None,
             gamma_cmd_rad: float | None = None, lever_fixed: float | None = None, hdot_ff_m_s: float = 0.0,
             priority: str | None = None, airbrake_max_N: float = 0.0) -> TecsOutput:
        """One step of the energy loops.

        Parameters
        ----------
        dt_s : float
            Step [s].
        x : TecsInput
            Measured state (and the energy rates the thrust can give).
        speed : SpeedCommand
            Speed target (Mach, CAS or TAS); clipped to ``mach_max``.
        alt_cmd_m : float, optional
            Altitude target [m] (altitude mode).
        gamma_cmd_rad : float, optional
            Flight-path angle target [rad] (path mode), used when ``alt_cmd_m`` is None.
        lever_fixed : float, optional
            Fixed thrust lever (e.g. idle in the flare, take-off power) [-]: the thrust
            channel is bypassed and pitch flies the path (``gamma_cmd_rad`` given) or the speed.
        hdot_ff_m_s : float
            Vertical speed of the commanded altitude (a managed path) [m/s], altitude mode.
        priority : str, optional
            ``"path"`` or ``"speed"``: which command the energy limits leave alone. Default: speed when
            the altitude command saturates the flight-path limit (an open climb or descent), else path.
            ``"path_only"``: path, and the pitch weights blend to the path's (2, 0) also while the thrust
            is not saturated: pitch holds the path alone and the speed is the thrust's and the airbrake's
            (a deceleration segment, where the engine's spool-down would otherwise lift the aircraft).
        airbrake_max_N : float
            Drag the airbrake may add below idle [N] (0: not allowed).

        Returns
        -------
        TecsOutput
        """
        return TecsOutput(*self.step_values(dt_s, x.alt_m, x.tas_m_s, x.Vdot_m_s2, x.gamma_rad, x.mass_kg,
                                            x.dT_isa_K, x.E_rate_min, x.E_rate_max, speed, alt_cmd_m, gamma_cmd_rad,
                                            lever_fixed, hdot_ff_m_s, priority, airbrake_max_N))

    def step_values(self, dt_s: float, alt_m: float, tas_m_s: float, Vdot_m_s2: float, gamma_rad: float,
                    mass_kg: float, dT_isa_K: float, E_rate_min: float, E_rate_max: float, speed: SpeedCommand,
                    alt_cmd_m: float | None = None, gamma_cmd_rad: float | None = None,
                    lever_fixed: float | None = None, hdot_ff_m_s: float = 0.0, priority: str | None = None,
                    airbrake_max_N: float = 0.0) -> tuple:
        """:meth:`step` on plain values: the fields of :class:`TecsInput` in their order, then :meth:`step`'s
        arguments; returns the fields of :class:`TecsOutput` in their order, as a tuple (:func:`tecs_law`,
        the one implementation of the loops, which the FCS's compiled step calls too)."""
        if alt_cmd_m is None and gamma_cmd_rad is None:
            raise FcsError("tecs.step: give alt_cmd_m (altitude mode) or gamma_cmd_rad (path mode)")
        out = tecs_law(self.values(), self._s, dt_s, alt_m, tas_m_s, Vdot_m_s2, gamma_rad, mass_kg, dT_isa_K,
                       E_rate_min, E_rate_max, speed.value, speed_kind_code(speed.kind),
                       math.nan if alt_cmd_m is None else alt_cmd_m, alt_cmd_m is not None,
                       math.nan if gamma_cmd_rad is None else gamma_cmd_rad,
                       math.nan if lever_fixed is None else lever_fixed, lever_fixed is not None, hdot_ff_m_s,
                       priority_code(priority), airbrake_max_N)
        if not out[12]:
            isa(alt_m, dT_isa_K)  # raises the atmosphere's error, which names the altitude
        return (*(float(v) for v in out[:8]), PRIORITIES[out[8]], bool(out[9]), float(out[10]), bool(out[11]))


#: Codes of the priorities in :func:`tecs_law`: in its ``priority`` argument 0 is the default (``None``: chosen
#: from the altitude command), in its result "normal" (none favoured).
PRIORITIES = ("normal", "path", "speed", "path_only")
_AUTO = _NORMAL = 0
_PATH, _SPEED, _PATH_ONLY = 1, 2, 3
#: Codes of the speed kinds in :func:`tecs_law`.
SPEED_KINDS = (SpeedKind.MACH, SpeedKind.CAS, SpeedKind.TAS)
_KIND_MACH, _KIND_CAS = 0, 1
_KIND_CODE = {k: i for i, k in enumerate(SPEED_KINDS)}
_PRIORITY_CODE = {None: _AUTO, "path": _PATH, "speed": _SPEED, "path_only": _PATH_ONLY}
#: Index of each field of TecsParams in :meth:`Tecs.values`.
TP = field_index(TecsParams)
#: The TECS's state, ``Tecs._s``: thrust integral [-] (T/W), pitch integral [rad], blend of the weights towards
#: the priority's [0, 1], acceleration command of the previous step [m/s^2], filtered airbrake drag [N].
_I_T, _I_L, _SIGMA, _A_C, _AB = range(5)


def speed_kind_code(kind: SpeedKind) -> int:
    """The code of a speed kind in :func:`tecs_law`."""
    return _KIND_CODE[kind]


def priority_code(priority: str | None) -> int:
    """The code of a priority argument of :meth:`Tecs.step` in :func:`tecs_law`."""
    code = _PRIORITY_CODE.get(priority)
    if code is None:
        raise FcsError(f"tecs.step: priority {priority!r} must be one of None, 'path', 'speed', 'path_only'")
    return code


@jitable
def tecs_law(p: np.ndarray, s: np.ndarray, dt_s: float, alt_m: float, tas_m_s: float, Vdot_m_s2: float,
             gamma_rad: float, mass_kg: float, dT_isa_K: float, E_rate_min: float, E_rate_max: float, speed: float,
             speed_kind: int, alt_cmd_m: float, has_alt: bool, gamma_cmd_rad: float, lever_fixed: float,
             has_lever: bool, hdot_ff_m_s: float, priority: int, airbrake_max_N: float) -> tuple:
    """One step of the energy loops on plain values (see :meth:`Tecs.step` for the arguments; the module for the
    law): parameters ``p`` (:meth:`Tecs.values`, indexed by :data:`TP`) and the state ``s`` (updated in place),
    the speed target's value and kind code, the altitude target (``has_alt``; else the path angle's), the fixed
    lever (``has_lever``) and the priority's code (:data:`PRIORITIES`, 0 for the default). Returns the fields of
    :class:`TecsOutput` in their order (the priority as its code), then False if the altitude or the ISA
    deviation is outside the atmosphere's range (the other values are then not to be used)."""
    V = 1.0 if 1.0 > tas_m_s else tas_m_s  # max(tas, 1.0), NaN kept
    T_K, p_Pa, rho, a, ok = isa_values(alt_m, dT_isa_K)
    W = mass_kg * G0_M_S2
    if speed_kind == _KIND_MACH:
        V_c = speed * a
    elif speed_kind == _KIND_CAS:
        V_c = tas_from_cas_values(speed, p_Pa, a)
    else:
        V_c = speed
    V_max = p[TP.mach_max] * a
    if V_max < V_c:
        V_c = V_max
    underspeed = cas_from_tas_values(V, p_Pa, a) < p[TP.V_min_cas_m_s]
    if underspeed:  # max(V_c, V at the margin over the minimum)
        v = tas_from_cas_values(p[TP.V_min_cas_m_s] * p[TP.underspeed_margin], p_Pa, a)
        V_c = v if v > V_c else V_c
    if has_alt:
        ff = clip(hdot_ff_m_s / V, -1.0, 1.0)
        g_raw = math.asin(ff) + p[TP.k_h_1_s] * (alt_cmd_m - alt_m) / V
    else:
        g_raw = gamma_cmd_rad
    # clip(v, lo, hi) written out as its two comparisons (clip.py: the same value, NaN included)
    g_min, g_max = p[TP.gamma_min_rad], p[TP.gamma_max_rad]
    g_c = g_min if g_min > g_raw else g_raw
    g_c = g_max if g_max < g_c else g_c
    a_max = p[TP.Vdot_max_m_s2]
    a_c = p[TP.k_V_1_s] * (V_c - V)
    a_c = -a_max if -a_max > a_c else a_c
    a_c = a_max if a_max < a_c else a_c
    jerk = p[TP.jerk_max_m_s3]
    if not underspeed and jerk > 0.0:
        da = jerk * dt_s
        lo = s[_A_C] - da
        a_c = lo if lo > a_c else a_c
        hi = s[_A_C] + da
        a_c = hi if hi < a_c else a_c
    strict = priority == _PATH_ONLY
    if priority == _AUTO:
        priority = _SPEED if g_raw != g_c else _PATH
    elif strict:
        priority = _PATH
    limited = False
    s_gc = math.sin(g_c)
    if not has_lever and not underspeed:
        # energy-rate command limiting: cut the channel without priority back to what the thrust gives
        # the margin shrinks with the headroom over the path's own need, so a small but feasible speed
        # change is still flown (slowly) rather than cut to nothing
        demand = s_gc + a_c / G0_M_S2
        lim = math.nan
        margin = p[TP.energy_margin]
        # min(margin, 0.25 max(room, 0)) written out (the same values)
        room = E_rate_max - s_gc
        room = 0.25 * (0.0 if 0.0 > room else room)
        hi = E_rate_max - (room if room < margin else margin)
        room = s_gc - E_rate_min
        room = 0.25 * (0.0 if 0.0 > room else room)
        lo = E_rate_min + (room if room < margin else margin)
        if demand > hi:
            lim = hi
        elif demand < lo:
            lim = lo
        if lim == lim:  # not NaN
            limited = True
            if priority == _PATH:
                a_c = clip(G0_M_S2 * (lim - s_gc), -a_max, a_max)
            else:
                # the flight path is cut, but a climb is not turned into a descent (nor a descent into a
                # climb) to pay for a speed change: beyond level flight the acceleration is cut instead
                sg = lim - a_c / G0_M_S2
                if (g_c > 0.0 and sg < 0.0) or (g_c < 0.0 and sg > 0.0):
                    sg = 0.0
                    a_c = clip(G0_M_S2 * lim, -a_max, a_max)
                g_c = math.asin(clip(sg, math.sin(g_min), math.sin(g_max)))
                s_gc = math.sin(g_c)
    s[_A_C] = a_c
    e_g = s_gc - math.sin(gamma_rad)
    e_v = (a_c - Vdot_m_s2) / G0_M_S2
    E_err = e_g + e_v

    T_avail = p[TP.thrust_sls_N] * (rho / RHO0_KG_M3) ** p[TP.thrust_lapse_exp]  # available_thrust_N
    T_idle = p[TP.lever_min] * T_avail
    airbrake = 0.0
    if has_lever:
        lever = clip(lever_fixed, 0.0, 1.0)
        T_c = lever * T_avail
        prio = _SPEED if has_alt else _PATH
        s[_I_T] = T_c / W  # tracks, for a bumpless return to energy control
        s[_SIGMA] = 1.0
    else:
        T_c = W * (p[TP.k_TP] * E_err + s[_I_T])
        T_lo = T_idle - (0.0 if 0.0 > airbrake_max_N else airbrake_max_N)  # max(airbrake_max_N, 0)
        T_hi = p[TP.lever_max] * T_avail
        sat_hi = T_c >= T_hi or underspeed
        sat_lo = T_c <= T_lo
        saturated = (sat_hi and E_err > 0) or (sat_lo and E_err < 0)
        if not saturated:
            s[_I_T] += p[TP.k_TI_1_s] * E_err * dt_s
        if underspeed:
            T_c = T_hi
        else:  # clip(T_c, T_lo, T_hi)
            T_c = T_lo if T_lo > T_c else T_c
            T_c = T_hi if T_hi < T_c else T_c
        if T_c < T_idle:
            airbrake, T_c = T_idle - T_c, T_idle
        # the airbrake acts at once on the drag (the engine's thrust with its spool lag): filtered to the
        # thrust's pace, or the proportional gain k_TP closes a one-step loop through it and chatters
        tau = p[TP.tau_airbrake_s]
        s[_AB] = airbrake if tau <= 0.0 else s[_AB] + (airbrake - s[_AB]) * dt_s / (tau + dt_s)
        airbrake = s[_AB]
        lever = T_c / T_avail
        prio = _SPEED if underspeed else (priority if saturated else _NORMAL)
        sigma_target = 1.0 if saturated or strict else 0.0
        tau_p = p[TP.tau_priority_s]
        if underspeed:
            s[_SIGMA] = 1.0
        elif tau_p > 0.0:
            f = dt_s / tau_p
            s[_SIGMA] += (sigma_target - s[_SIGMA]) * (1.0 if 1.0 < f else f)  # min(f, 1)
        else:
            s[_SIGMA] = sigma_target
    sg = s[_SIGMA]
    if prio == _PATH or (prio == _NORMAL and priority == _PATH):  # weights (w_g, w_v) -> (2, 0)
        w_g, w_v = 1.0 + sg * (2.0 - 1.0), 1.0 + sg * (0.0 - 1.0)
    else:  # -> (0, 2)
        w_g, w_v = 1.0 + sg * (0.0 - 1.0), 1.0 + sg * (2.0 - 1.0)
    L_err = w_g * e_g - w_v * e_v
    k_EP = p[TP.k_EP]
    theta_c = k_EP * L_err + s[_I_L]
    th_min, th_max = p[TP.theta_min_rad], p[TP.theta_max_rad]
    if th_min < theta_c < th_max or (theta_c >= th_max) != (L_err > 0):
        s[_I_L] += p[TP.k_EI_1_s] * L_err * dt_s
    theta_c = k_EP * L_err + s[_I_L]  # clip(theta_c, theta_min_rad, th_max)
    theta_c = th_min if th_min > theta_c else theta_c
    theta_c = th_max if th_max < theta_c else theta_c
    return T_c, lever, theta_c, g_c, a_c, V_c, E_err, L_err, prio, underspeed, airbrake, limited, ok
