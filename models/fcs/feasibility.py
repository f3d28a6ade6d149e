"""Can the aircraft fly a mission as planned? Per section: required against achievable gradients and turns.

Before a mission is flown, each section's altitude change is compared with what the aircraft
can do there, and its turns with the bank limit of the guidance:

* **Climb and descent.** A section's altitude is reached by its constraint point: the waypoint
  ``altitude_at`` of a WaypointFollowing section, by default its last (as the flight control's
  vertical planner takes it; the distance runs along the legs), the end of its turns for an
  Orbiting section (approach to the circle plus ``turns`` x 2 pi R), the glide slope intercept
  for a Landing. The required gradient is the altitude change over the ground distance from the
  previous section's end. The achievable one follows from the
  specific excess power [1]_: the total energy height ``E = h + V^2 / 2g`` changes along the air
  path at ``dE/ds = (T - D) / W``, with T the maximum thrust (climb) or the idle thrust (descent)
  and D the level-flight drag of the trimmed aircraft at the section's speed, altitude and
  estimated mass; over the ground ``dE/dx = (T - D)/W * TAS/GS`` in the wind. The distance needed
  is the larger of ``|dE| * mean(1/|dE/dx|)`` (thrust, averaged over the altitude band with
  Simpson's rule) and ``|dh| / tan(gamma_limit)`` (the TECS flight-path-angle limits). A speed
  change is part of ``dE``.
* **Turns.** Radius at the bank limit ``R = GS^2 / (g tan phi_max)`` with the largest ground speed
  (TAS plus the wind speed) against the orbit radius; the turn anticipation of fly-by waypoints
  ``R tan(dpsi/2)`` (at ``fly_by_bank_frac`` of the limit, as the sequencer plans it) against the
  leg lengths; the thrust for the turn's load factor ``n = 1/cos(phi)``: ``D(n) = D + q S k CL^2
  (n^2 - 1)`` (drag due to lift grows with n^2) against the maximum thrust, and ``n CL`` against
  the maximum lift coefficient.
* **Level flight.** Maximum thrust against the drag at each section's speed and altitude; the
  speed within the trim envelope (no stall) and the TECS Mach limit; the glide slope of a
  Landing against the idle descent gradient with the gear down (the approach speed is held on
  the glide path only if idle thrust lets the aircraft descend that steeply).

A section is *infeasible* when the achievable falls short of the required, *marginal* when it
is within ``margin`` (default 20 %) of it. The mass falls along the mission by an estimate of
the fuel burned (cruise at the engine's fuel flow for the drag, climbs at maximum thrust).

The physics of the aircraft and engine come in through :class:`Performance` (in openEMSS:
``openemss.report.model_performance``, the trimmed JSBSim airframe and the engine model of the
system's parameter set), so this module depends on neither.

References
----------
.. [1] Anderson, J. D., *Aircraft Performance and Design*, McGraw-Hill, 1999, sect. 5.3 (rate of
   climb, specific excess power) and 5.8 (energy height); sect. 5.4 (gliding flight).
.. [2] Raymer, D. P., *Aircraft Design: A Conceptual Approach*, 6th ed., AIAA, 2018, sect. 17.8
   (ground roll with the mean acceleration at V/sqrt(2)).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from .atmosphere import G0_M_S2, cas_from_tas, isa, mach_from_tas, tas_from_cas
from .errors import FcsError
from .feasibility_perf import Limits, Performance, PerformanceError, PerfPoint
from .geo import LatLon, destination, distance_m, final_bearing_rad, initial_bearing_rad, wrap_pi
from .guidance import FLY_BY_MAX_TURN_RAD
from .mission import Mission, Section
from .tecs import SpeedCommand
from .weather import WindProfile

__all__ = ["PerfPoint", "Performance", "PerformanceError", "Limits", "Finding", "SectionCheck", "MissionCheck",
           "check_mission", "VERDICTS"]

VERDICTS = ("ok", "marginal", "infeasible")  #: a section's verdict, by severity
NOTE = "note"  #: a finding that informs and judges nothing


@dataclass(frozen=True, slots=True)
class Finding:
    """One finding of a section: ``verdict`` (``marginal``, ``infeasible`` or ``note``) and what, with the numbers."""

    verdict: str
    text: str


@dataclass(frozen=True, slots=True)
class SectionCheck:
    """The check of one section. Gradients are dimensionless (0.05 = 5 %), positive up.

    Attributes
    ----------
    index, type, name : the section.
    verdict : str
        ``ok``, ``marginal`` or ``infeasible`` (the worst of ``findings``), or ``n/a``.
    alt_from_m, alt_to_m : float
        Altitude at the start and the section's target altitude [m].
    tas_m_s, mach, mass_kg : float
        Target true airspeed [m/s] and Mach [-] at the target altitude, estimated mass at entry [kg].
    distance_m : float or None
        Ground distance available for the altitude change [m] (None: no constraint).
    required_gradient, achievable_gradient : float or None
        Altitude change over ``distance_m``, and over the distance needed at full thrust (climb)
        or idle (descent) within the flight-path-angle limits [-].
    needed_distance_m : float or None
        Distance the altitude (and speed) change takes [m].
    turn_radius_m, geometry_radius_m : float or None
        Radius at the bank limit and at the largest ground speed [m]; the radius or leg length the
        section offers [m].
    thrust_ratio : float or None
        Maximum thrust over drag at the target (in the turn for orbits and G-turns) [-].
    findings : tuple of Finding
    """

    index: int
    type: str
    name: str
    verdict: str
    alt_from_m: float
    alt_to_m: float
    tas_m_s: float | None
    mach: float | None
    mass_kg: float
    distance_m: float | None
    required_gradient: float | None
    achievable_gradient: float | None
    needed_distance_m: float | None
    turn_radius_m: float | None
    geometry_radius_m: float | None
    thrust_ratio: float | None
    findings: tuple[Finding, ...]


@dataclass(frozen=True, slots=True)
class MissionCheck:
    """The check of a whole mission."""

    mission: str
    source: str
    margin: float
    mass_kg: float
    sections: tuple[SectionCheck, ...]
    fuel_estimate_kg: float
    time_estimate_s: float
    #: findings of the whole mission (e.g. more fuel needed than on board)
    notes: tuple[Finding, ...] = ()

    @property
    def findings(self) -> list[tuple[SectionCheck, Finding]]:
        """Every finding with its section, in mission order."""
        return [(s, f) for s in self.sections for f in s.findings]

    def count(self, verdict: str) -> int:
        """Number of sections with this verdict."""
        return sum(1 for s in self.sections if s.verdict == verdict)


@dataclass
class _State:
    pos: LatLon
    alt_m: float
    tas_m_s: float
    mass_kg: float
    course_rad: float | None   # ground track on arrival
    time_s: float = 0.0
    fuel_kg: float = 0.0


def _pct(x: float) -> str:
    return f"{100.0 * x:.1f} % ({math.degrees(math.atan(x)):.1f} deg)"


class _Checker:
    def __init__(self, mission: Mission, perf: Performance, limits: Limits, wind: WindProfile | None,
                 isa_dev_K: float, margin: float) -> None:
        self.m, self.perf, self.lim, self.wind, self.dT, self.margin = mission, perf, limits, wind, isa_dev_K, margin
        self.findings: list[Finding] = []

    # -- helpers ------------------------------------------------------------------------------
    def flag(self, need: float, can: float, text: Callable[[str], str]) -> None:
        """A finding when ``can`` falls short of ``need`` (infeasible) or of ``need (1 + margin)``."""
        if can < need:
            self.findings.append(Finding("infeasible", text("infeasible")))
        elif can < need * (1.0 + self.margin):
            self.findings.append(Finding("marginal", text(f"marginal (margin {100.0 * (can / need - 1.0):.0f} %, "
                                                          f"less than {100.0 * self.margin:.0f} %)")))

    def speed(self, spd: SpeedCommand, alt_m: float) -> tuple[float, float]:
        """(TAS [m/s], Mach [-]) of a speed command at an altitude, Mach clipped as the TECS does."""
        atm = isa(alt_m, self.dT)
        tas = spd.tas_m_s(alt_m, self.dT)
        mach = mach_from_tas(tas, atm)
        if mach > self.lim.mach_max:
            mach = self.lim.mach_max
            tas = mach * atm.a_m_s
        return tas, mach

    def ground_speed(self, tas: float, alt_m: float, course_rad: float | None) -> float:
        """Ground speed along ``course_rad`` [m/s] (TAS when still air or no course)."""
        if self.wind is None or course_rad is None:
            return tas
        n, e = self.wind.ne_m_s(alt_m)
        along = n * math.cos(course_rad) + e * math.sin(course_rad)
        cross = -n * math.sin(course_rad) + e * math.cos(course_rad)
        return along + math.sqrt(max(tas * tas - cross * cross, 1.0))

    def max_ground_speed(self, tas: float, alt_m: float) -> float:
        if self.wind is None:
            return tas
        return tas + math.hypot(*self.wind.ne_m_s(alt_m))

    def point(self, alt_m: float, spd: SpeedCommand, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        return self.perf.point(alt_m, self.speed(spd, alt_m)[1], mass_kg, gear_down)

    # -- vertical -----------------------------------------------------------------------------
    def vertical(self, h0: float, h1: float, v0: float, spd: SpeedCommand, mass: float, dist: float | None,
                 course: float | None, n: float = 1.0, gear_down: bool = False, what: str = "") \
            -> tuple[float | None, float | None, float | None]:
        """(required, achievable gradient, needed distance) of an altitude and speed change."""
        v1 = self.speed(spd, h1)[0]
        dE = (h1 - h0) + (v1 * v1 - v0 * v0) / (2.0 * G0_M_S2)
        dh = h1 - h0
        if abs(dh) < 1.0:  # a speed change at one altitude: the level-flight thrust check covers it
            return None, None, None
        climb = dE > 0.0
        inv, inv_ab = [], []
        for h in (h0, 0.5 * (h0 + h1), h1):
            p = self.point(h, spd, mass, gear_down)
            g = p.climb_gradient(n) if climb else p.descent_gradient(n)
            g_ab = g if climb else p.descent_gradient(n, self.lim.airbrake_plan_max)
            if g <= 0.0:
                why = (f"drag {p.drag_in_turn_N(n) / 1e3:.2f} kN exceeds the maximum thrust "
                       f"{p.thrust_max_N / 1e3:.2f} kN" if climb else
                       f"idle thrust {p.thrust_idle_N / 1e3:.2f} kN exceeds the drag "
                       f"{p.drag_in_turn_N(n) / 1e3:.2f} kN")
                self.findings.append(Finding("infeasible", f"{what}{'climb' if climb else 'descent'} "
                                             f"{h0:.0f} -> {h1:.0f} m: at {h:.0f} m and M {p.mach:.2f} the {why}"))
                return (None if dist is None else abs(dh) / dist), 0.0, math.inf
            gs_ratio = self.ground_speed(p.tas_m_s, h, course) / p.tas_m_s
            inv.append(gs_ratio / g)
            inv_ab.append(gs_ratio / g_ab)
        d_energy = abs(dE) * (inv[0] + 4.0 * inv[1] + inv[2]) / 6.0
        # A descent that idle cannot make in the distance is planned with the airbrake, up to
        # vnav.airbrake_plan_max of its travel (the rest is the flight management's margin).
        d_energy_ab = abs(dE) * (inv_ab[0] + 4.0 * inv_ab[1] + inv_ab[2]) / 6.0
        airbrake = (not climb and dist is not None and self.lim.airbrake_plan_max > 0.0
                    and d_energy > dist and d_energy_ab < d_energy)
        if airbrake:
            d_energy_idle, d_energy = d_energy, d_energy_ab
        gamma_lim = self.lim.gamma_max_rad if dh > 0 else -self.lim.gamma_min_rad
        gs_air = self.ground_speed(v1, h1, course) / v1
        d_gamma = abs(dh) / math.tan(max(gamma_lim, 1e-3)) * gs_air
        needed = max(d_energy, d_gamma)
        can = abs(dh) / needed if needed > 0 else math.inf
        if dist is None:
            return None, math.copysign(can, dh), needed
        need = abs(dh) / max(dist, 1.0)
        by = "thrust" if d_energy >= d_gamma else \
            f"the flight-path limit {math.degrees(gamma_lim):.1f} deg (tecs.gamma_{'max' if dh > 0 else 'min'}_rad)"
        setting = "at full thrust" if climb else (
            f"at idle with the airbrake planned up to {100.0 * self.lim.airbrake_plan_max:.0f} %" if airbrake
            else "at idle")
        spdtxt = f"M {self.speed(spd, h1)[1]:.2f}"
        self.flag(need, can, lambda v: (
            f"{what}{'climb' if dh > 0 else 'descent'} {h0:.0f} -> {h1:.0f} m over {dist / 1e3:.1f} km needs "
            f"{_pct(need)}; {setting} at {spdtxt} the aircraft makes {_pct(can)} (limited by {by}), i.e. "
            f"{needed / 1e3:.1f} km: {v}"))
        if airbrake and can >= need:
            self.findings.append(Finding("note", f"{what}descent {h0:.0f} -> {h1:.0f} m over {dist / 1e3:.1f} km: idle "
                                         f"alone needs {d_energy_idle / 1e3:.1f} km; planned with the airbrake"))
        return math.copysign(need, dh), math.copysign(can, dh), needed

    def level(self, p: PerfPoint, n: float, what: str) -> float:
        """Maximum thrust over drag at load factor ``n``; findings for thrust and lift."""
        d = p.drag_in_turn_N(n)
        ratio = p.thrust_max_N / d if d > 0 else math.inf
        turn = f" in a {math.degrees(math.acos(1.0 / n)):.0f}-deg banked turn" if n > 1.0001 else ""
        self.flag(1.0, ratio, lambda v: f"{what}level flight at {p.alt_m:.0f} m, M {p.mach:.2f}{turn} needs "
                  f"{d / 1e3:.2f} kN, the engine gives at most {p.thrust_max_N / 1e3:.2f} kN: {v}")
        if n > 1.0001:
            self.flag(n * p.CL, 0.95 * p.CL_max, lambda v: f"{what}the turn at {n:.2f} g needs CL = {n * p.CL:.2f}, "
                      f"95 % of CL_max = {0.95 * p.CL_max:.2f}: {v}")
        cas = cas_from_tas(p.tas_m_s, isa(p.alt_m, self.dT))
        if cas < self.lim.v_min_cas_m_s:
            self.findings.append(Finding("marginal", f"{what}{cas:.0f} m/s CAS is below the underspeed protection "
                                         f"{self.lim.v_min_cas_m_s:.0f} m/s (tecs.V_min_cas_m_s): the TECS flies "
                                         "faster"))
        return ratio

    def turn_radius(self, gs: float, bank_frac: float = 1.0) -> float:
        return gs * gs / (G0_M_S2 * math.tan(max(bank_frac * self.lim.phi_max_rad, 1e-3)))

    def fuel(self, st: _State, p: PerfPoint, dist_m: float, gs: float) -> None:
        t = dist_m / max(gs, 1.0)
        wf = self.perf.cruise_fuel_kg_s(p.alt_m, p.mach, p.drag_N)
        st.time_s += t
        st.fuel_kg += wf * t
        st.mass_kg -= wf * t

    # -- sections -----------------------------------------------------------------------------
    def section(self, sec: Section, st: _State, nxt: Section | None) -> SectionCheck:
        self.findings = []
        h0, mass0 = st.alt_m, st.mass_kg
        out: dict[str, float | None] = dict(tas_m_s=None, mach=None, distance_m=None, required_gradient=None,
                                            achievable_gradient=None, needed_distance_m=None, turn_radius_m=None,
                                            geometry_radius_m=None, thrust_ratio=None)
        h1 = h0
        try:
            h1 = getattr(self, f"_{sec.type.lower()}")(sec, st, nxt, out)
        except PerformanceError as e:
            self.findings.append(Finding("infeasible", str(e)))
        if sec.type == "Custom":
            verdict = "n/a"
        else:
            verdict = max((f.verdict for f in self.findings if f.verdict != NOTE), key=VERDICTS.index, default="ok")
        return SectionCheck(sec.index, sec.type, sec.name, verdict, h0, h1, mass_kg=mass0,
                            findings=tuple(self.findings), **out)  # type: ignore[arg-type]

    def _rolling(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        rwy = sec["runway"]
        atm = isa(rwy.elevation_m, self.dT)
        v_r = tas_from_cas(sec["rotate_cas_m_s"], atm)
        w = self.wind.ne_m_s(rwy.elevation_m) if self.wind is not None else (0.0, 0.0)
        tail = w[0] * math.cos(rwy.heading_rad) + w[1] * math.sin(rwy.heading_rad)  # wind along the runway
        v_g = max(v_r + tail, 1.0)  # ground speed at rotation
        t = self.perf.thrust_max_N(rwy.elevation_m, min(max(v_r / math.sqrt(2.0) / atm.a_m_s, 0.0), 0.3))
        a = t * sec["lever"] / st.mass_kg - self.perf.rolling_friction * G0_M_S2
        roll = v_g * v_g / (2.0 * a) if a > 0 else math.inf
        out.update(tas_m_s=v_r, mach=v_r / atm.a_m_s, distance_m=rwy.length_m, needed_distance_m=roll)
        self.findings.append(Finding(NOTE, f"take-off roll about {roll:.0f} m of {rwy.length_m:.0f} m"))
        self.flag(roll, rwy.length_m, lambda v: f"take-off roll to {sec['rotate_cas_m_s']:.0f} m/s CAS takes about "
                  f"{roll:.0f} m (mean acceleration at V/sqrt(2), rolling friction {self.perf.rolling_friction:g}) "
                  f"of the runway's {rwy.length_m:.0f} m: {v}")
        st.pos = rwy.point(min(roll, rwy.length_m))
        st.alt_m, st.tas_m_s, st.course_rad = rwy.elevation_m, v_r, rwy.heading_rad
        return rwy.elevation_m

    def _takeoff(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        rwy = sec["runway"]
        h1 = rwy.elevation_m + sec["until_height_agl_m"]
        spd = sec["climb_speed"]
        tas, mach = self.speed(spd, h1)
        out.update(tas_m_s=tas, mach=mach)
        _, can, needed = self.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, None, rwy.heading_rad)
        out.update(achievable_gradient=can, needed_distance_m=needed)
        p = self.point(h1, spd, st.mass_kg)
        st.pos = destination(st.pos, rwy.heading_rad, needed or 0.0)
        self.fuel(st, p, needed or 0.0, tas)
        st.alt_m, st.tas_m_s = h1, tas
        return h1

    def _waypointfollowing(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        h1, spd, wps = sec["altitude_m"], sec["speed"], list(sec["waypoints"])
        tas, mach = self.speed(spd, h1)
        out.update(tas_m_s=tas, mach=mach)
        # the altitude is due at the section's altitude_at waypoint, by default its last (as the flight
        # control plans it); the distance is the path's from the previous section's end
        due = sec.get("altitude_at") or wps[-1]
        k = wps.index(due) if due in wps else len(wps) - 1
        path = [st.pos, *wps[:k + 1]]
        d0 = sum(distance_m(a, b) for a, b in zip(path, path[1:], strict=False))
        course = initial_bearing_rad(st.pos, wps[0]) if distance_m(st.pos, wps[0]) > 1.0 else st.course_rad
        req, can, needed = self.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, d0, course,
                                         what=f"to {self.name(wps[k])}: ")
        out.update(distance_m=d0, required_gradient=req, achievable_gradient=can, needed_distance_m=needed)
        p = self.point(h1, spd, st.mass_kg)
        out["thrust_ratio"] = self.level(p, 1.0, "")
        # fly-by turns: the anticipation at each waypoint against the legs on either side
        pts = [st.pos, *wps]
        if nxt is not None and nxt.type == "WaypointFollowing" and sec["fly_by"] and nxt["fly_by"]:
            pts.append(nxt["waypoints"][0])
        lead, radius = [0.0] * len(pts), None
        for i in range(1, len(pts) - 1):
            if not sec["fly_by"] or distance_m(pts[i - 1], pts[i]) < 1.0 or distance_m(pts[i], pts[i + 1]) < 1.0:
                continue
            c_in = final_bearing_rad(pts[i - 1], pts[i])
            dpsi = wrap_pi(initial_bearing_rad(pts[i], pts[i + 1]) - c_in)
            r = self.turn_radius(self.ground_speed(tas, h1, c_in), self.lim.fly_by_bank_frac)
            radius = r if radius is None else max(radius, r)
            lead[i] = r * math.tan(abs(dpsi) / 2.0) if abs(dpsi) <= FLY_BY_MAX_TURN_RAD else 0.0
        legs = []
        for i in range(len(pts) - 1):
            leg = distance_m(pts[i], pts[i + 1])
            legs.append(leg)
            use = lead[i] + lead[i + 1] if i > 0 else lead[i + 1]
            if use > 0.0:
                a, b = self.name(pts[i]), self.name(pts[i + 1])
                self.flag(use, leg, lambda v, a=a, b=b, use=use, leg=leg: (
                    f"the fly-by turns on the leg {a} -> {b} ({leg / 1e3:.1f} km) take {use / 1e3:.1f} km of turn "
                    f"anticipation at {math.degrees(self.lim.fly_by_bank_frac * self.lim.phi_max_rad):.0f} deg of "
                    f"bank: {v}"))
        out.update(turn_radius_m=radius, geometry_radius_m=min(legs) if legs else None)
        total = sum(legs[:len(wps)])
        self.fuel(st, p, total, tas)
        st.pos, st.alt_m, st.tas_m_s = wps[-1], h1, tas
        st.course_rad = final_bearing_rad(pts[len(wps) - 1], wps[-1]) if len(pts) > 1 else st.course_rad
        return h1

    def _orbiting(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        h1, spd, c, R = sec["altitude_m"], sec["speed"], sec["center"], sec["radius_m"]
        tas, mach = self.speed(spd, h1)
        approach = max(distance_m(st.pos, c) - R, 0.0)
        dist = approach + sec["turns"] * 2.0 * math.pi * R
        gs_max = self.max_ground_speed(tas, h1)
        phi = math.atan(gs_max * gs_max / (G0_M_S2 * R))
        n_mean = 1.0 / math.cos(math.atan(tas * tas / (G0_M_S2 * R)))
        req, can, needed = self.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, dist, None, n=n_mean)
        r_min = self.turn_radius(gs_max)
        out.update(tas_m_s=tas, mach=mach, distance_m=dist, required_gradient=req, achievable_gradient=can,
                   needed_distance_m=needed, turn_radius_m=r_min, geometry_radius_m=R)
        wind = f" (ground speed up to {gs_max:.0f} m/s in the wind)" if gs_max > tas + 0.5 else ""
        self.flag(r_min, R, lambda v: f"the orbit of {R / 1e3:.1f} km radius at {tas:.0f} m/s TAS{wind} needs "
                  f"{math.degrees(phi):.0f} deg of bank; at the limit of {math.degrees(self.lim.phi_max_rad):.0f} deg "
                  f"(guidance.phi_max_rad) the radius is {r_min / 1e3:.1f} km: {v}")
        p = self.point(h1, spd, st.mass_kg)
        out["thrust_ratio"] = self.level(p, 1.0 / math.cos(min(phi, self.lim.phi_max_rad)), "")
        brg = initial_bearing_rad(c, st.pos) if distance_m(c, st.pos) > 1.0 else 0.0
        d = 1.0 if sec["direction"] == "clockwise" else -1.0
        exit_brg = brg + d * 2.0 * math.pi * sec["turns"]
        self.fuel(st, p, dist, tas)
        st.pos, st.alt_m, st.tas_m_s = destination(c, exit_brg, R), h1, tas
        st.course_rad = exit_brg + d * math.pi / 2.0
        return h1

    def _gturns(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        h1 = sec["altitude_m"] if sec["altitude_m"] is not None else st.alt_m
        spd = sec["speed"] if sec["speed"] is not None else SpeedCommand(st.tas_m_s)
        tas, mach = self.speed(spd, h1)
        n = sec["load_factor"]
        R = tas * tas / (G0_M_S2 * math.tan(math.acos(1.0 / n)))
        arc = (math.radians(sec["heading_change_deg"]) * R if sec["heading_change_deg"] is not None
               else sec["duration_s"] * tas)
        req, can, needed = self.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, arc, None, n=n)
        p = self.point(h1, spd, st.mass_kg)
        out.update(tas_m_s=tas, mach=mach, distance_m=arc, required_gradient=req, achievable_gradient=can,
                   needed_distance_m=needed, turn_radius_m=R, thrust_ratio=self.level(p, n, ""))
        self.fuel(st, p, arc, tas)
        st.alt_m, st.tas_m_s = h1, tas
        return h1

    def _levelling(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        h1, spd = sec["altitude_m"], sec["speed"]
        tas, mach = self.speed(spd, h1)
        course = math.radians(sec["heading_deg"]) if sec["heading_deg"] is not None else st.course_rad
        _, can, needed = self.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, None, course)
        p = self.point(h1, spd, st.mass_kg)
        out.update(tas_m_s=tas, mach=mach, achievable_gradient=can, needed_distance_m=needed,
                   thrust_ratio=self.level(p, 1.0, ""))
        if course is not None and needed:
            st.pos = destination(st.pos, course, needed)
        self.fuel(st, p, (needed or 0.0) + sec["hold_s"] * tas, tas)
        st.alt_m, st.tas_m_s = h1, tas
        return h1

    def _landing(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        rwy, h_app, spd = sec["runway"], sec["approach_altitude_m"], sec["approach_speed"]
        tas, mach = self.speed(spd, h_app)
        gs_angle = self.lim.gs_angle_rad
        intercept_m = max(h_app - rwy.elevation_m - self.lim.tch_m, 0.0) / math.tan(gs_angle)
        fix = rwy.point(-intercept_m)
        out.update(tas_m_s=tas, mach=mach)
        if st.alt_m - h_app > self.lim.hold_enter_m:
            self.findings.append(Finding(NOTE, f"descends {st.alt_m - h_app:.0f} m to the approach altitude in a hold"))
        else:
            d = distance_m(st.pos, fix)
            self.vertical(st.alt_m, h_app, st.tas_m_s, spd, st.mass_kg, d,
                          initial_bearing_rad(st.pos, fix) if d > 1.0 else None, what="to the glide slope intercept: ")
        # on the glide slope: gear down, approach speed held only if idle lets it descend that steeply
        h_mid = rwy.elevation_m + 0.5 * (h_app - rwy.elevation_m)
        p = self.point(h_mid, spd, st.mass_kg, gear_down=True)
        gs_ground = self.ground_speed(p.tas_m_s, h_mid, rwy.heading_rad)
        need = math.tan(gs_angle)
        can_gs = p.descent_gradient() * p.tas_m_s / gs_ground
        out.update(distance_m=intercept_m, required_gradient=-need, achievable_gradient=-can_gs,
                   needed_distance_m=intercept_m * need / can_gs if can_gs > 0 else math.inf)
        self.flag(need, can_gs, lambda v: f"the {math.degrees(gs_angle):.1f}-deg glide slope at "
                  f"{cas_from_tas(p.tas_m_s, isa(h_mid, self.dT)):.0f} m/s CAS needs a descent gradient of "
                  f"{_pct(need)}; at idle with the gear down the aircraft descends at {_pct(can_gs)} "
                  f"(drag {p.drag_N / 1e3:.2f} kN, idle thrust {p.thrust_idle_N / 1e3:.2f} kN) and would "
                  f"accelerate: {v}")
        self.fuel(st, p, intercept_m + distance_m(st.pos, fix), p.tas_m_s)
        st.pos, st.alt_m, st.tas_m_s = rwy.threshold, rwy.elevation_m, 0.0
        return rwy.elevation_m

    def _custom(self, sec: Section, st: _State, nxt: Section | None, out: dict) -> float:
        self.findings.append(Finding(NOTE, "Custom sections fly open-loop commands: not checked"))
        return st.alt_m

    def name(self, p: LatLon) -> str:
        for n, w in self.m.waypoints:
            if w == p:
                return n
        return f"({p.lat_deg:.3f}, {p.lon_deg:.3f})"


def check_mission(mission: Mission, perf: Performance, limits: Limits, mass_kg: float, *,
                  start: tuple[LatLon, float, float] | None = None, wind: WindProfile | None = None,
                  isa_dev_K: float = 0.0, margin: float = 0.2, fuel_kg: float | None = None) -> MissionCheck:
    """Check every section of ``mission`` (see the module docstring).

    Parameters
    ----------
    mission : Mission
        The validated mission.
    perf : Performance
        Trimmed aircraft and engine.
    limits : Limits
        The flight control's limits.
    mass_kg : float
        Mass at the start [kg]; reduced along the mission by the fuel estimate.
    start : (LatLon, alt_m, tas_m_s), optional
        Where the mission starts; default the first section's runway threshold at rest.
    wind : WindProfile, optional
        Winds aloft (ground speeds, turn radii).
    isa_dev_K : float
        ISA temperature deviation [K].
    margin : float
        Relative margin below which a feasible section is marginal [-].
    fuel_kg : float, optional
        Fuel on board at the start [kg], against the estimate of the fuel the mission burns.
    """
    if not 0.0 <= margin <= 10.0:
        raise FcsError(f"feasibility: margin {margin} outside the allowed range 0 to 10")
    if start is None:
        rwy = next((s["runway"] for s in mission.sections if s.type in ("Rolling", "TakeOff")), None)
        if rwy is None:
            raise FcsError(f"{mission.source}: the mission starts with no Rolling or TakeOff section; give the "
                           "start position, altitude and speed")
        start = (rwy.threshold, rwy.elevation_m, 0.0)
    pos, alt, tas = start
    st = _State(pos, alt, tas, mass_kg, None)
    ck = _Checker(mission, perf, limits, wind, isa_dev_K, margin)
    secs = mission.sections
    results = tuple(ck.section(s, st, secs[i + 1] if i + 1 < len(secs) else None) for i, s in enumerate(secs))
    notes = []
    if fuel_kg is not None:
        ck.findings = []
        ck.flag(st.fuel_kg, fuel_kg, lambda v: f"the mission burns about {st.fuel_kg:.0f} kg of fuel (a rough "
                f"estimate), {fuel_kg:.0f} kg are on board: {v}")
        notes = ck.findings
    return MissionCheck(mission.name, mission.source, margin, mass_kg, results, st.fuel_kg, st.time_s, tuple(notes))
