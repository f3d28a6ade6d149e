"""The feasibility checks of the shipped section types (:attr:`.sections.SectionType.feasibility`).

Each is a :data:`~.feasibility_checker.FeasibilityCheck`: it reads its section, adds findings through the
:class:`~.feasibility_checker.Checker`, fills the figures of its :class:`~.feasibility.SectionCheck`, moves the
state to the section's end and returns the altitude the section ends at [m]. What each compares, and the
references (Anderson 1999 for climbs, descents and turns; Raymer 2018 for the take-off roll), are in
:mod:`.feasibility`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..common.airspeed import cas_from_tas, tas_from_cas
from ..mission.geo import destination, distance_m, final_bearing_rad, initial_bearing_rad, wrap_pi
from ..mission.speed import SpeedCommand
from .atmosphere import G0_M_S2, isa
from .feasibility_checker import NOTE, Checker, CheckState, Finding, pct
from .guidance import FLY_BY_MAX_TURN_RAD

if TYPE_CHECKING:
    from ..mission.mission import Section

__all__ = ["rolling", "takeoff", "waypoint_following", "orbiting", "gturns", "levelling", "landing"]


def rolling(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    rwy = sec["runway"]
    atm = isa(rwy.elevation_m, ck.dT)
    v_r = tas_from_cas(sec["rotate_cas_m_s"], atm)
    w = ck.wind.ne_m_s(rwy.elevation_m) if ck.wind is not None else (0.0, 0.0)
    tail = w[0] * math.cos(rwy.heading_rad) + w[1] * math.sin(rwy.heading_rad)  # wind along the runway
    v_g = max(v_r + tail, 1.0)  # ground speed at rotation
    t = ck.perf.thrust_max_N(rwy.elevation_m, min(max(v_r / math.sqrt(2.0) / atm.a_m_s, 0.0), 0.3))
    a = t * sec["lever"] / st.mass_kg - ck.perf.rolling_friction * G0_M_S2
    roll = v_g * v_g / (2.0 * a) if a > 0 else math.inf
    out.update(tas_m_s=v_r, mach=v_r / atm.a_m_s, distance_m=rwy.length_m, needed_distance_m=roll)
    ck.findings.append(Finding(NOTE, f"take-off roll about {roll:.0f} m of {rwy.length_m:.0f} m"))
    ck.flag(roll, rwy.length_m, lambda v: f"take-off roll to {sec['rotate_cas_m_s']:.0f} m/s CAS takes about "
              f"{roll:.0f} m (mean acceleration at V/sqrt(2), rolling friction {ck.perf.rolling_friction:g}) "
              f"of the runway's {rwy.length_m:.0f} m: {v}")
    st.pos = rwy.point(min(roll, rwy.length_m))
    st.alt_m, st.tas_m_s, st.course_rad = rwy.elevation_m, v_r, rwy.heading_rad
    return rwy.elevation_m


def takeoff(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    rwy = sec["runway"]
    h1 = rwy.elevation_m + sec["until_height_agl_m"]
    spd = sec["climb_speed"]
    tas, mach = ck.speed(spd, h1)
    out.update(tas_m_s=tas, mach=mach)
    _, can, needed = ck.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, None, rwy.heading_rad)
    out.update(achievable_gradient=can, needed_distance_m=needed)
    p = ck.point(h1, spd, st.mass_kg)
    st.pos = destination(st.pos, rwy.heading_rad, needed or 0.0)
    ck.fuel(st, p, needed or 0.0, tas)
    st.alt_m, st.tas_m_s = h1, tas
    return h1


def waypoint_following(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    h1, spd, wps = sec["altitude_m"], sec["speed"], list(sec["waypoints"])
    tas, mach = ck.speed(spd, h1)
    out.update(tas_m_s=tas, mach=mach)
    # the altitude is due at the section's altitude_at waypoint, by default its last (as the flight
    # control plans it); the distance is the path's from the previous section's end
    due = sec.get("altitude_at") or wps[-1]
    k = wps.index(due) if due in wps else len(wps) - 1
    path = [st.pos, *wps[:k + 1]]
    d0 = sum(distance_m(a, b) for a, b in zip(path, path[1:], strict=False))
    course = initial_bearing_rad(st.pos, wps[0]) if distance_m(st.pos, wps[0]) > 1.0 else st.course_rad
    req, can, needed = ck.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, d0, course,
                                     what=f"to {ck.name(wps[k])}: ")
    out.update(distance_m=d0, required_gradient=req, achievable_gradient=can, needed_distance_m=needed)
    p = ck.point(h1, spd, st.mass_kg)
    out["thrust_ratio"] = ck.level(p, 1.0, "")
    # fly-by turns: the anticipation at each waypoint against the legs on either side
    pts = [st.pos, *wps]
    if sec["fly_by"] and ck.next_fix is not None:  # the turn at the last waypoint, towards the next section
        pts.append(ck.next_fix)
    lead, radius = [0.0] * len(pts), None
    for i in range(1, len(pts) - 1):
        if not sec["fly_by"] or distance_m(pts[i - 1], pts[i]) < 1.0 or distance_m(pts[i], pts[i + 1]) < 1.0:
            continue
        c_in = final_bearing_rad(pts[i - 1], pts[i])
        dpsi = wrap_pi(initial_bearing_rad(pts[i], pts[i + 1]) - c_in)
        r = ck.turn_radius(ck.ground_speed(tas, h1, c_in), ck.lim.fly_by_bank_frac)
        radius = r if radius is None else max(radius, r)
        lead[i] = r * math.tan(abs(dpsi) / 2.0) if abs(dpsi) <= FLY_BY_MAX_TURN_RAD else 0.0
    legs = []
    for i in range(len(pts) - 1):
        leg = distance_m(pts[i], pts[i + 1])
        legs.append(leg)
        use = lead[i] + lead[i + 1] if i > 0 else lead[i + 1]
        if use > 0.0:
            a, b = ck.name(pts[i]), ck.name(pts[i + 1])
            ck.flag(use, leg, lambda v, a=a, b=b, use=use, leg=leg: (
                f"the fly-by turns on the leg {a} -> {b} ({leg / 1e3:.1f} km) take {use / 1e3:.1f} km of turn "
                f"anticipation at {math.degrees(ck.lim.fly_by_bank_frac * ck.lim.phi_max_rad):.0f} deg of "
                f"bank: {v}"))
    out.update(turn_radius_m=radius, geometry_radius_m=min(legs) if legs else None)
    total = sum(legs[:len(wps)])
    ck.fuel(st, p, total, tas)
    st.pos, st.alt_m, st.tas_m_s = wps[-1], h1, tas
    st.course_rad = final_bearing_rad(pts[len(wps) - 1], wps[-1]) if len(pts) > 1 else st.course_rad
    return h1


def orbiting(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    h1, spd, c, R = sec["altitude_m"], sec["speed"], sec["center"], sec["radius_m"]
    tas, mach = ck.speed(spd, h1)
    approach = max(distance_m(st.pos, c) - R, 0.0)
    dist = approach + sec["turns"] * 2.0 * math.pi * R
    gs_max = ck.max_ground_speed(tas, h1)
    phi = math.atan(gs_max * gs_max / (G0_M_S2 * R))
    n_mean = 1.0 / math.cos(math.atan(tas * tas / (G0_M_S2 * R)))
    req, can, needed = ck.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, dist, None, n=n_mean)
    r_min = ck.turn_radius(gs_max)
    out.update(tas_m_s=tas, mach=mach, distance_m=dist, required_gradient=req, achievable_gradient=can,
               needed_distance_m=needed, turn_radius_m=r_min, geometry_radius_m=R)
    wind = f" (ground speed up to {gs_max:.0f} m/s in the wind)" if gs_max > tas + 0.5 else ""
    ck.flag(r_min, R, lambda v: f"the orbit of {R / 1e3:.1f} km radius at {tas:.0f} m/s TAS{wind} needs "
              f"{math.degrees(phi):.0f} deg of bank; at the limit of {math.degrees(ck.lim.phi_max_rad):.0f} deg "
              f"(guidance.phi_max_rad) the radius is {r_min / 1e3:.1f} km: {v}")
    p = ck.point(h1, spd, st.mass_kg)
    out["thrust_ratio"] = ck.level(p, 1.0 / math.cos(min(phi, ck.lim.phi_max_rad)), "")
    brg = initial_bearing_rad(c, st.pos) if distance_m(c, st.pos) > 1.0 else 0.0
    d = 1.0 if sec["direction"] == "clockwise" else -1.0
    exit_brg = brg + d * 2.0 * math.pi * sec["turns"]
    ck.fuel(st, p, dist, tas)
    st.pos, st.alt_m, st.tas_m_s = destination(c, exit_brg, R), h1, tas
    st.course_rad = exit_brg + d * math.pi / 2.0
    return h1


def gturns(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    h1 = sec["altitude_m"] if sec["altitude_m"] is not None else st.alt_m
    spd = sec["speed"] if sec["speed"] is not None else SpeedCommand(st.tas_m_s)
    tas, mach = ck.speed(spd, h1)
    n = sec["load_factor"]
    R = tas * tas / (G0_M_S2 * math.tan(math.acos(1.0 / n)))
    arc = (math.radians(sec["heading_change_deg"]) * R if sec["heading_change_deg"] is not None
           else sec["duration_s"] * tas)
    req, can, needed = ck.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, arc, None, n=n)
    p = ck.point(h1, spd, st.mass_kg)
    out.update(tas_m_s=tas, mach=mach, distance_m=arc, required_gradient=req, achievable_gradient=can,
               needed_distance_m=needed, turn_radius_m=R, thrust_ratio=ck.level(p, n, ""))
    ck.fuel(st, p, arc, tas)
    st.alt_m, st.tas_m_s = h1, tas
    return h1


def levelling(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    h1, spd = sec["altitude_m"], sec["speed"]
    tas, mach = ck.speed(spd, h1)
    course = math.radians(sec["heading_deg"]) if sec["heading_deg"] is not None else st.course_rad
    _, can, needed = ck.vertical(st.alt_m, h1, st.tas_m_s, spd, st.mass_kg, None, course)
    p = ck.point(h1, spd, st.mass_kg)
    out.update(tas_m_s=tas, mach=mach, achievable_gradient=can, needed_distance_m=needed,
               thrust_ratio=ck.level(p, 1.0, ""))
    if course is not None and needed:
        st.pos = destination(st.pos, course, needed)
    ck.fuel(st, p, (needed or 0.0) + sec["hold_s"] * tas, tas)
    st.alt_m, st.tas_m_s = h1, tas
    return h1


def landing(ck: Checker, sec: Section, st: CheckState, out: dict[str, float | None]) -> float:
    rwy, h_app, spd = sec["runway"], sec["approach_altitude_m"], sec["approach_speed"]
    tas, mach = ck.speed(spd, h_app)
    gs_angle = ck.lim.gs_angle_rad
    intercept_m = max(h_app - rwy.elevation_m - ck.lim.tch_m, 0.0) / math.tan(gs_angle)
    fix = rwy.point(-intercept_m)
    out.update(tas_m_s=tas, mach=mach)
    if st.alt_m - h_app > ck.lim.hold_enter_m:
        ck.findings.append(Finding(NOTE, f"descends {st.alt_m - h_app:.0f} m to the approach altitude in a hold"))
    else:
        d = distance_m(st.pos, fix)
        ck.vertical(st.alt_m, h_app, st.tas_m_s, spd, st.mass_kg, d,
                      initial_bearing_rad(st.pos, fix) if d > 1.0 else None, what="to the glide slope intercept: ")
    # on the glide slope: gear down, approach speed held only if idle lets it descend that steeply
    h_mid = rwy.elevation_m + 0.5 * (h_app - rwy.elevation_m)
    p = ck.point(h_mid, spd, st.mass_kg, gear_down=True)
    gs_ground = ck.ground_speed(p.tas_m_s, h_mid, rwy.heading_rad)
    need = math.tan(gs_angle)
    can_gs = p.descent_gradient() * p.tas_m_s / gs_ground
    out.update(distance_m=intercept_m, required_gradient=-need, achievable_gradient=-can_gs,
               needed_distance_m=intercept_m * need / can_gs if can_gs > 0 else math.inf)
    ck.flag(need, can_gs, lambda v: f"the {math.degrees(gs_angle):.1f}-deg glide slope at "
              f"{cas_from_tas(p.tas_m_s, isa(h_mid, ck.dT)):.0f} m/s CAS needs a descent gradient of "
              f"{pct(need)}; at idle with the gear down the aircraft descends at {pct(can_gs)} "
              f"(drag {p.drag_N / 1e3:.2f} kN, idle thrust {p.thrust_idle_N / 1e3:.2f} kN) and would "
              f"accelerate: {v}")
    ck.fuel(st, p, intercept_m + distance_m(st.pos, fix), p.tas_m_s)
    st.pos, st.alt_m, st.tas_m_s = rwy.threshold, rwy.elevation_m, 0.0
    return rwy.elevation_m
