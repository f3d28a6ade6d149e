"""Vertical navigation: top of descent and of climb, the managed descent path, the deceleration
segment and the planned hold, from the aircraft's energy and its achievable gradients.

A waypoint section's altitude is a constraint *at* its constraint point (its last waypoint, or the
one ``altitude_at`` names; with fly-by waypoints where the turn there begins); its speed is to be
flown from there on. The planner works backwards from the constraint point in the distance to go
s (:mod:`.profile`) with the performance model (:mod:`.performance`), as an airliner's FMS does:

1. *Deceleration segment*, level at the constraint altitude h_c: from the descent speed to the
   target, at idle with the planned airbrake (at most ``Vdot_max``, TECS's limit), plus the tail of
   TECS's exponential speed capture, k_V: ds = m V dV / (D - T_idle + D_ab).
2. *Idle descent* from h_c up to the entry altitude h0 at the descent speed (the entry's CAS held,
   :func:`descent_speed`; the target's when that is faster): the energy falls at the
   idle energy gradient G = (D + D_ab - T_idle)/W per distance flown, and dE = dh (1 + V/g dV/dh),
   so sin(gamma) = G / (1 + V/g dV/dh) (the drag at the lift of level flight: 0.6 % at 6 deg),
   no steeper than ``gamma_path_max``
   (TECS's flight-path limit keeps the rest for corrections); steps of ``dh_step_m``.
3. Corners rounded for ``nz_path`` g (:class:`.profile.VerticalProfile`): the level-off at the
   bottom of descent (BOD) and the push-over at the top (TOD).

TOD is the distance the three take. When it exceeds the distance available, the airbrake is
planned, as little as makes the path fit, at most ``airbrake_plan_max`` (the rest is the margin for
corrections). When even that does not fit, the path starts at the section's start with
that airbrake. The fix is then reached high, and a descending hold (a spiral of radius
``hold_radius_m`` about the constraint's waypoint) is planned and flagged. It loses the rest of the
height at the spiral's idle gradient with ``airbrake_plan_max`` and the bank's load factor.

A climb is flown at once at maximum thrust (TECS's open climb). Its top of climb is predicted
from the climb gradient (T_max - D)/W, with dE = dh (1 + V/g dV/dh) and no steeper than TECS's
gamma_max. The acceleration to the target speed comes first, at the entry altitude. When the top
of climb falls beyond the constraint point, a climbing hold there is planned and flagged.

References
----------
RTCA DO-236C, "Minimum aviation system performance standards: required navigation performance
for area navigation", 2013, sec. 3.2.8 (vertical path: altitude constraints, TOD, deceleration).
S. Liden, "The evolution of flight management systems", IEEE/AIAA 13th DASC, 1994 (VNAV path
computed backwards from the constraints at idle with the descent speed schedule).
E. Torenbeek, "Advanced Aircraft Design", Wiley, 2013, ch. 11 (energy height, energy gradient).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..common.airspeed import cas_from_tas
from ..mission.speed import SpeedCommand, SpeedKind
from .atmosphere import G0_M_S2, isa
from .performance import Performance
from .profile import VerticalProfile
from .tunable import Tunable, load_params

__all__ = ["VnavParams", "Vnav", "DescentPlan", "ClimbPlan", "descent_speed"]

_FAR_M = 1.0e7  # the profile's end nodes: level beyond them [m]


@dataclass(frozen=True, slots=True)
class VnavParams:
    """Vertical navigation parameters (data/vnav.yaml, section ``vnav``); see the file for units."""

    gamma_path_max_rad: float
    airbrake_plan_max: float
    nz_path_g: float
    dh_step_m: float
    level_band_m: float
    speed_tail_m_s: float
    hold_radius_m: float
    hold_exit_m: float
    unable_margin_m: float
    replan_period_s: float
    overspeed_m_s: float
    path_lead_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> VnavParams:
        """Parameter set of ``data/vnav.yaml``, section ``vnav``."""
        return load_params(cls, "vnav.yaml", "vnav", **overrides)


@dataclass(frozen=True, slots=True)
class DescentPlan:
    """A planned descent to a constraint.

    Attributes
    ----------
    h_entry_m, h_target_m : float
        Altitude at the start and the constraint [m].
    s_avail_m : float
        Distance to go to the constraint point when planned [m].
    s_tod_m, s_bod_m, s_decel_m : float
        Distance to go where the path leaves the entry altitude (TOD), reaches the constraint
        altitude (BOD, end of its rounding) and where the deceleration to the target speed starts [m].
    airbrake : float
        Airbrake position the path is planned with [-].
    feasible : bool
        The constraint is met on the path; else a hold at the fix is planned.
    hold_height_m : float
        Height to lose in the hold at the fix [m] (0 when feasible).
    hold_turns : float
        Turns of the hold (spiral) planned [-].
    profile : VerticalProfile
        The path.
    speed_descent, speed_target : SpeedCommand
        Speed flown until ``s_decel_m`` and from there on.
    """

    h_entry_m: float
    h_target_m: float
    s_avail_m: float
    s_tod_m: float
    s_bod_m: float
    s_decel_m: float
    airbrake: float
    feasible: bool
    hold_height_m: float
    hold_turns: float
    profile: VerticalProfile
    speed_descent: SpeedCommand
    speed_target: SpeedCommand


@dataclass(frozen=True, slots=True)
class ClimbPlan:
    """A predicted climb: ``s_toc_m`` the distance to the top of climb from the start [m], ``feasible`` when
    it lies before the constraint point (``s_avail_m`` away when planned)."""

    h_entry_m: float
    h_target_m: float
    s_avail_m: float
    s_toc_m: float
    feasible: bool


def descent_speed(entry: SpeedCommand, target: SpeedCommand, h_entry_m: float, h_target_m: float,
                  dT_isa_K: float = 0.0) -> SpeedCommand:
    """The speed of a descent: the entry's calibrated airspeed held (so the Mach number falls as the aircraft
    descends, the Mach/CAS schedule of an airliner with its crossover at the entry), or the target itself
    when that is faster at the constraint (no deceleration segment then)."""
    atm0 = isa(h_entry_m, dT_isa_K)
    held = SpeedCommand(cas_from_tas(entry.tas_m_s(h_entry_m, dT_isa_K), atm0), SpeedKind.CAS)
    if held.tas_m_s(h_target_m, dT_isa_K) <= target.tas_m_s(h_target_m, dT_isa_K):
        return target
    return held


class Vnav(Tunable[VnavParams]):
    """The vertical planner: descents, climbs and holds over the performance model ``perf``."""

    tunable_name = "vnav"

    def __init__(self, perf: Performance, params: VnavParams | None = None) -> None:
        self.perf = perf
        self._params = params if params is not None else VnavParams.from_file()

    # -- pieces ----------------------------------------------------------------------------
    def decel_distance_m(self, h_m: float, v_from: float, v_to: float, mass_kg: float, airbrake: float,
                         vdot_max: float, k_V: float, dT_isa_K: float = 0.0) -> float:
        """Level deceleration from ``v_from`` to ``v_to`` [m/s TAS] at ``h_m`` at idle with ``airbrake``,
        at most ``vdot_max`` [m/s^2], plus the tail of TECS's capture (k_V [1/s]) from vdot_max/k_V down to
        ``speed_tail_m_s`` [m]; inf when idle and airbrake cannot decelerate."""
        if v_from <= v_to:
            return 0.0
        p, perf = self._params, self.perf
        n = max(int((v_from - v_to) / 2.0) + 1, 4)
        dv = (v_from - v_to) / n
        s = 0.0
        for i in range(n):
            v = v_from - (i + 0.5) * dv
            # level flight: dV/dt = (T - D)/m = g G, G the energy gradient, so the deceleration is -g G
            decel = -G0_M_S2 * perf.energy_gradient(h_m, v, mass_kg, "idle", airbrake, dT_isa_K=dT_isa_K)
            decel = min(decel, vdot_max)
            if decel <= 1e-3:
                return math.inf
            s += v * dv / decel
        if k_V > 0.0 and vdot_max / k_V > p.speed_tail_m_s:
            s += v_to * math.log(vdot_max / k_V / p.speed_tail_m_s) / k_V
        return s

    def _descent_nodes(self, h0: float, h_c: float, speed: SpeedCommand, mass_kg: float, airbrake: float,
                       dT: float) -> tuple[list[float], list[float], list[float]]:
        """(ds per altitude step [m], heights [m], speeds [m/s]) of the idle path from h_c up to h0."""
        p, perf = self._params, self.perf
        n = max(int(math.ceil((h0 - h_c) / p.dh_step_m)), 1)
        dh = (h0 - h_c) / n
        tan_max = math.tan(p.gamma_path_max_rad)
        ds, hs, vs = [], [h_c], [speed.tas_m_s(h_c, dT)]
        for i in range(n):
            ha, hb = h_c + i * dh, h_c + (i + 1) * dh
            hm = 0.5 * (ha + hb)
            va, vb, vm = speed.tas_m_s(ha, dT), speed.tas_m_s(hb, dT), speed.tas_m_s(hm, dT)
            grad = -perf.energy_gradient(hm, vm, mass_kg, "idle", airbrake, dT_isa_K=dT)
            dvdh = (vb - va) / dh
            tan_g = _tan_gamma(grad / (1.0 + vm / G0_M_S2 * dvdh)) if grad > 0.0 else 0.0
            tan_g = min(tan_g, tan_max) if tan_g > 0.0 else 0.0
            ds.append(dh / tan_g if tan_g > 0.0 else math.inf)
            hs.append(hb)
            vs.append(vb)
        return ds, hs, vs

    def _layout(self, h0: float, h_c: float, speed: SpeedCommand, target: SpeedCommand, mass_kg: float,
                airbrake: float, vdot_max: float, k_V: float, dT: float) -> tuple[float, float, list[float],
                                                                                 list[float], list[float]]:
        """(s_decel, s_total, node s, node h, node speeds) of the descent flown with ``airbrake``."""
        p = self._params
        v_des, v_c = speed.tas_m_s(h_c, dT), target.tas_m_s(h_c, dT)
        s_dec = self.decel_distance_m(h_c, v_des, v_c, mass_kg, airbrake, vdot_max, k_V, dT)
        ds, hs, vs = self._descent_nodes(h0, h_c, speed, mass_kg, airbrake, dT)
        if math.isinf(s_dec) or any(math.isinf(d) for d in ds):
            return s_dec, math.inf, [], [], []
        nz = p.nz_path_g * G0_M_S2
        w_bod = vs[0] ** 2 * (hs[1] - hs[0]) / ds[0] / (2.0 * nz)
        w_tod = vs[-1] ** 2 * (hs[-1] - hs[-2]) / ds[-1] / (2.0 * nz)
        s_bod = s_dec + w_bod
        nodes_s = [s_bod]
        for d in ds:
            nodes_s.append(nodes_s[-1] + d)
        return s_dec, nodes_s[-1] + w_tod, nodes_s, hs, vs

    # -- plans -----------------------------------------------------------------------------
    def plan_descent(self, h0: float, h_c: float, s_avail: float, entry: SpeedCommand, target: SpeedCommand,
                     mass_kg: float, vdot_max: float, k_V: float, dT_isa_K: float = 0.0) -> DescentPlan:
        """Plan the descent from ``h0`` to ``h_c`` [m] within ``s_avail`` [m] of distance to go, entering at the
        speed ``entry`` and to fly ``target`` from the constraint point on (mass [kg]; TECS's acceleration
        limit [m/s^2] and speed gain [1/s], for the deceleration)."""
        p = self._params
        speed = descent_speed(entry, target, h0, h_c, dT_isa_K)

        def layout(ab: float) -> tuple:
            return self._layout(h0, h_c, speed, target, mass_kg, ab, vdot_max, k_V, dT_isa_K)

        airbrake, lay = 0.0, layout(0.0)
        if lay[1] > s_avail:
            hi = layout(p.airbrake_plan_max)
            if hi[1] > s_avail:
                airbrake, lay = p.airbrake_plan_max, hi
            else:
                lo_ab, hi_ab = 0.0, p.airbrake_plan_max
                for _ in range(30):
                    mid = 0.5 * (lo_ab + hi_ab)
                    if layout(mid)[1] > s_avail:
                        lo_ab = mid
                    else:
                        hi_ab = mid
                airbrake, lay = hi_ab, layout(hi_ab)
        s_dec, s_total, ns, hs, vs = lay
        if math.isinf(s_total):  # idle cannot descend at this speed: the whole height is lost in the hold
            prof = VerticalProfile.rounded([-_FAR_M, _FAR_M], [h0, h0], [1.0, 1.0], p.nz_path_g)
            hold_h = h0 - h_c
            return DescentPlan(h0, h_c, s_avail, 0.0, 0.0, 0.0, airbrake, False, hold_h,
                               self.hold_turns(hold_h, h_c, target, mass_kg, dT_isa_K), prof, speed, target)
        nodes_s = [-_FAR_M, 0.0] + ns + [_FAR_M]
        nodes_h = [h_c, h_c] + hs + [h0]
        vg = [vs[0], vs[0]] + vs + [vs[-1]]
        if s_total <= s_avail:
            prof = VerticalProfile.rounded(nodes_s, nodes_h, vg, p.nz_path_g)
            return DescentPlan(h0, h_c, s_avail, s_total, s_dec, s_dec, airbrake, True, 0.0, 0.0, prof, speed, target)
        # infeasible: the path starts where the section does, and reaches the fix high
        shift = s_total - s_avail
        shifted = [s - shift for s in nodes_s[1:-1]]
        h_fix = _height_at(shifted, nodes_h[1:-1], 0.0)
        keep = [i for i, s in enumerate(shifted) if s > 0.0]
        prof = VerticalProfile.rounded([-_FAR_M, 0.0] + [shifted[i] for i in keep] + [_FAR_M],
                                       [h_fix, h_fix] + [nodes_h[1 + i] for i in keep] + [h0],
                                       [vg[1 + keep[0]]] * 2 + [vg[1 + i] for i in keep] + [vg[-1]], p.nz_path_g)
        hold_h = h_fix - h_c
        return DescentPlan(h0, h_c, s_avail, s_avail, 0.0, max(s_dec - shift, 0.0), airbrake, False, hold_h,
                           self.hold_turns(hold_h, h_c, target, mass_kg, dT_isa_K), prof, speed, target)

    def hold_turns(self, height_m: float, h_c: float, speed: SpeedCommand, mass_kg: float,
                   dT_isa_K: float = 0.0) -> float:
        """Turns of a spiral of ``hold_radius_m`` that loses ``height_m`` [m] above ``h_c`` [-]."""
        tan_g = self.spiral_tan_gamma(h_c + 0.5 * height_m, speed, mass_kg, dT_isa_K)
        return height_m / (2.0 * math.pi * self._params.hold_radius_m * tan_g)

    def spiral_tan_gamma(self, h_m: float, speed: SpeedCommand, mass_kg: float, dT_isa_K: float = 0.0) -> float:
        """tan of the descent gradient in the hold's spiral at idle with ``airbrake_plan_max``: the bank for
        ``hold_radius_m`` at the speed raises the drag due to lift by n^2 (n = 1/cos(bank)); no steeper than
        ``gamma_path_max`` [-]."""
        p = self._params
        v = speed.tas_m_s(h_m, dT_isa_K)
        n = math.sqrt(1.0 + (v * v / (G0_M_S2 * p.hold_radius_m)) ** 2)
        g = -self.perf.energy_gradient(h_m, v, mass_kg, "idle", p.airbrake_plan_max, load_factor=n,
                                       dT_isa_K=dT_isa_K)
        return min(_tan_gamma(max(g, 1e-3)), math.tan(p.gamma_path_max_rad))

    def plan_climb(self, h0: float, h_c: float, s_avail: float, speed: SpeedCommand, v0_m_s: float,
                   mass_kg: float, gamma_max_rad: float, dT_isa_K: float = 0.0) -> ClimbPlan:
        """Predict the top of climb from ``h0`` to ``h_c`` [m] at maximum thrust and ``speed``, from the true
        airspeed ``v0_m_s`` [m/s] (accelerating first at ``h0``), within ``s_avail`` [m]."""
        p, perf = self._params, self.perf
        s = 0.0
        v1 = speed.tas_m_s(h0, dT_isa_K)
        if v1 > v0_m_s:  # accelerate at h0
            n = max(int((v1 - v0_m_s) / 2.0) + 1, 4)
            dv = (v1 - v0_m_s) / n
            for i in range(n):
                v = v0_m_s + (i + 0.5) * dv
                acc = G0_M_S2 * perf.energy_gradient(h0, v, mass_kg, "max", dT_isa_K=dT_isa_K)
                if acc <= 1e-3:
                    return ClimbPlan(h0, h_c, s_avail, math.inf, False)
                s += v * dv / acc
        n = max(int(math.ceil((h_c - h0) / p.dh_step_m)), 1)
        dh = (h_c - h0) / n
        tan_max = math.tan(gamma_max_rad)
        for i in range(n):
            ha, hb = h0 + i * dh, h0 + (i + 1) * dh
            hm = 0.5 * (ha + hb)
            vm = speed.tas_m_s(hm, dT_isa_K)
            grad = perf.energy_gradient(hm, vm, mass_kg, "max", dT_isa_K=dT_isa_K)
            dvdh = (speed.tas_m_s(hb, dT_isa_K) - speed.tas_m_s(ha, dT_isa_K)) / dh
            tan_g = min(_tan_gamma(grad / (1.0 + vm / G0_M_S2 * dvdh)), tan_max)
            if tan_g <= 1e-4:
                return ClimbPlan(h0, h_c, s_avail, math.inf, False)
            s += dh / tan_g
        return ClimbPlan(h0, h_c, s_avail, s, s <= s_avail)


def _tan_gamma(sin_like: float) -> float:
    """tan(gamma) of a path whose energy changes by ``sin_like`` (1 + V/g dV/dh) per distance flown along it:
    per horizontal distance that is sin_like / cos(gamma), so tan(gamma) = x / sqrt(1 - x^2) (x < 1)."""
    x = min(sin_like, 0.999)
    return x / math.sqrt(1.0 - x * x)


def _height_at(s_nodes: list[float], h_nodes: list[float], s: float) -> float:
    for i in range(len(s_nodes) - 1):
        if s_nodes[i] <= s <= s_nodes[i + 1]:
            a, b = s_nodes[i], s_nodes[i + 1]
            return h_nodes[i] + (h_nodes[i + 1] - h_nodes[i]) * (s - a) / (b - a)
    return h_nodes[-1]

