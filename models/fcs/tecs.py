"""Total Energy Control System (TECS): thrust and pitch from energy rates.

Lambregts' formulation. With flight-path angle gamma, true airspeed V and its
rate Vdot, the specific total energy E/W = h + V^2/(2g) changes at

    d/dt (h + V^2 / 2g) = V (sin gamma + Vdot / g)                        (1)

so ``sin gamma + Vdot/g`` is the *specific total energy rate* (per unit V) and
``sin gamma - Vdot/g`` the *energy distribution rate*. Thrust changes the
first, at constant thrust pitch only trades between height and speed, so:

* commands: gamma_c = clip(k_h (h_c - h) / V, gamma_min, gamma_max) (altitude
  mode: first-order capture with time constant 1/k_h, no overshoot), or a
  given gamma_c (path mode, e.g. glide slope, flare); Vdot_c = clip(k_V (V_c - V),
  +-Vdot_max);
* errors: e_g = sin gamma_c - sin gamma, e_v = (Vdot_c - Vdot) / g;
  E_err = e_g + e_v (total), L_err = w_g e_g - w_v e_v (distribution);
* thrust: T_c / W = k_TP E_err + k_TI Int E_err dt (the integral holds D/W);
* pitch: theta_c = k_EP L_err + k_EI Int L_err dt (the integral holds the trim alpha).

Weights (w_g, w_v) are (1, 1) normally. When the thrust saturates (maximum in a
climb, idle in a descent) or below V_min (underspeed protection) the thrust
channel can no longer supply the energy error: the thrust integral stops and
the pitch channel takes *speed priority*, (w_g, w_v) = (0, 2): pitch flies the
speed, the height follows from the energy available. While a climb (descent)
steeper than gamma_priority is commanded, the speed change asked of pitch is
limited to what the energy rate gives at level flight, so an idle descent that must
also slow down does not first climb, and a full-thrust climb that must also
accelerate does not first descend; at level flight the height pays for the speed. This is how a speed step
at constant (limiting) thrust is flown by pitch. In *path priority* (flare,
idle thrust by command), (w_g, w_v) = (2, 0). In underspeed the thrust lever is
also set to its maximum and the speed command raised to V_min.

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
in Advances in Aerospace Guidance, Navigation and Control, Springer, 2013.
B. R. Faleiro, A. A. Lambregts, "Analysis and tuning of a Total Energy Control
System control law using eigenstructure assignment", Aerospace Science and
Technology 3(3), 127-140, 1999.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from .atmosphere import G0_M_S2, cas_from_tas, isa, tas_from_cas, tas_from_mach
from .errors import FcsError
from .tunable import Tunable, load_params

__all__ = ["TecsParams", "SpeedKind", "SpeedCommand", "TecsInput", "TecsOutput", "Tecs",
           "specific_energy_rate_m_s", "RHO0_KG_M3"]

RHO0_KG_M3 = 1.225


class SpeedKind(StrEnum):
    """How a speed command is expressed."""

    MACH = "mach"
    CAS = "cas"
    TAS = "tas"


@dataclass(frozen=True, slots=True)
class SpeedCommand:
    """A speed target: ``value`` is a Mach number [-] or an airspeed [m/s] per ``kind``."""

    value: float
    kind: SpeedKind = SpeedKind.TAS

    def tas_m_s(self, alt_m: float, dT_isa_K: float = 0.0) -> float:
        """The target as true airspeed at altitude ``alt_m`` [m/s]."""
        atm = isa(alt_m, dT_isa_K)
        if self.kind is SpeedKind.MACH:
            return tas_from_mach(self.value, atm)
        if self.kind is SpeedKind.CAS:
            return tas_from_cas(self.value, atm)
        return self.value


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
    gamma_priority_rad: float
    V_min_cas_m_s: float
    underspeed_margin: float
    mach_max: float
    tau_Vdot_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> TecsParams:
        """Parameter set of ``data/tecs.yaml``, section ``tecs``."""
        return load_params(cls, "tecs.yaml", "tecs", **overrides)


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
    """

    alt_m: float
    tas_m_s: float
    Vdot_m_s2: float
    gamma_rad: float
    mass_kg: float
    dT_isa_K: float = 0.0


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
        ``"normal"``, ``"speed"`` or ``"path"``.
    underspeed : bool
        Underspeed protection active.
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


def specific_energy_rate_m_s(tas_m_s: float, Vdot_m_s2: float, gamma_rad: float) -> float:
    """d/dt (h + V^2/2g) = V (sin gamma + Vdot/g), the specific total energy rate [m/s]."""
    return tas_m_s * (math.sin(gamma_rad) + Vdot_m_s2 / G0_M_S2)


class Tecs(Tunable[TecsParams]):
    """Total energy control: speed and altitude (or path) targets -> thrust and pitch commands."""

    tunable_name = "tecs"

    def __init__(self, params: TecsParams | None = None) -> None:
        self._params = params if params is not None else TecsParams.from_file()
        self._iT = 0.0
        self._iL = 0.0

    def reset(self, thrust_N: float, weight_N: float, theta_rad: float, gamma_rad: float = 0.0) -> None:
        """Bumpless engagement from the current thrust [N], weight [N], pitch and path angles [rad]."""
        self._iT = thrust_N / weight_N
        self._iL = theta_rad

    def available_thrust_N(self, alt_m: float, dT_isa_K: float = 0.0) -> float:
        """Estimate of the maximum thrust at altitude, thrust_sls (rho/rho0)^n [N]."""
        p = self._params
        return p.thrust_sls_N * (isa(alt_m, dT_isa_K).rho_kg_m3 / RHO0_KG_M3) ** p.thrust_lapse_exp

    def step(self, dt_s: float, x: TecsInput, speed: SpeedCommand, alt_cmd_m: float | None = None,
             gamma_cmd_rad: float | None = None, lever_fixed: float | None = None) -> TecsOutput:
        """One step of the energy loops.

        Parameters
        ----------
        dt_s : float
            Step [s].
        x : TecsInput
            Measured state.
        speed : SpeedCommand
            Speed target (Mach, CAS or TAS); clipped to ``mach_max``.
        alt_cmd_m : float, optional
            Altitude target [m] (altitude mode).
        gamma_cmd_rad : float, optional
            Flight-path angle target [rad] (path mode), used when ``alt_cmd_m`` is None.
        lever_fixed : float, optional
            Fixed thrust lever (e.g. idle in the flare, take-off power) [-]: the thrust
            channel is bypassed and pitch flies the path (``gamma_cmd_rad`` given) or the speed.

        Returns
        -------
        TecsOutput
        """
        p = self._params
        if alt_cmd_m is None and gamma_cmd_rad is None:
            raise FcsError("tecs.step: give alt_cmd_m (altitude mode) or gamma_cmd_rad (path mode)")
        V = max(x.tas_m_s, 1.0)
        atm = isa(x.alt_m, x.dT_isa_K)
        W = x.mass_kg * G0_M_S2
        V_c = min(speed.tas_m_s(x.alt_m, x.dT_isa_K), p.mach_max * atm.a_m_s)
        cas = cas_from_tas(V, atm)
        underspeed = cas < p.V_min_cas_m_s
        if underspeed:
            V_c = max(V_c, tas_from_cas(p.V_min_cas_m_s * p.underspeed_margin, atm))
        if alt_cmd_m is not None:
            g_c = p.k_h_1_s * (alt_cmd_m - x.alt_m) / V
        else:
            g_c = float(gamma_cmd_rad)  # type: ignore[arg-type]
        g_c = min(max(g_c, p.gamma_min_rad), p.gamma_max_rad)
        a_c = min(max(p.k_V_1_s * (V_c - V), -p.Vdot_max_m_s2), p.Vdot_max_m_s2)
        e_g = math.sin(g_c) - math.sin(x.gamma_rad)
        e_v = (a_c - x.Vdot_m_s2) / G0_M_S2
        E_err = e_g + e_v

        T_avail = self.available_thrust_N(x.alt_m, x.dT_isa_K)
        if lever_fixed is not None:
            lever = min(max(lever_fixed, 0.0), 1.0)
            T_c = lever * T_avail
            priority = "path" if alt_cmd_m is None else "speed"
            self._iT = T_c / W  # tracks, for a bumpless return to energy control
        else:
            T_c = W * (p.k_TP * E_err + self._iT)
            lever = T_c / T_avail
            sat_hi = lever >= p.lever_max or underspeed
            sat_lo = lever <= p.lever_min
            if not ((sat_hi and E_err > 0) or (sat_lo and E_err < 0)):
                self._iT += p.k_TI_1_s * E_err * dt_s
            if underspeed:
                lever = p.lever_max
            lever = min(max(lever, p.lever_min), p.lever_max)
            T_c = lever * T_avail
            priority = "speed" if (sat_hi and E_err > 0) or (sat_lo and E_err < 0) or underspeed else "normal"
        if priority == "speed" and alt_cmd_m is not None and not underspeed:
            # a climb (descent) asked for with the thrust at maximum (idle): pitch flies
            # the speed, but not against the height -- the speed change is limited to what the energy
            # rate allows at level flight, E_rate = sin(gamma) + Vdot/g, so gamma keeps its sign
            E_rate = math.sin(x.gamma_rad) + x.Vdot_m_s2 / G0_M_S2
            if g_c >= p.gamma_priority_rad and a_c > G0_M_S2 * E_rate:
                a_c = max(G0_M_S2 * E_rate, 0.0)
            elif g_c <= -p.gamma_priority_rad and a_c < G0_M_S2 * E_rate:
                a_c = min(G0_M_S2 * E_rate, 0.0)
            e_v = (a_c - x.Vdot_m_s2) / G0_M_S2
        w_g, w_v = {"normal": (1.0, 1.0), "speed": (0.0, 2.0), "path": (2.0, 0.0)}[priority]
        L_err = w_g * e_g - w_v * e_v
        theta_c = p.k_EP * L_err + self._iL
        if p.theta_min_rad < theta_c < p.theta_max_rad or (theta_c >= p.theta_max_rad) != (L_err > 0):
            self._iL += p.k_EI_1_s * L_err * dt_s
        theta_c = min(max(p.k_EP * L_err + self._iL, p.theta_min_rad), p.theta_max_rad)
        return TecsOutput(T_c, lever, theta_c, g_c, a_c, V_c, E_err, L_err, priority, underspeed)
