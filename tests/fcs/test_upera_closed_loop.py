"""The FCS flying the UPERA JSBSim airframe (6 DoF) through the Munich mission and an
ILS approach in a crosswind (issue 7, "shown by"; the engine is a first-order stand-in,
see upera_loop.py).

Stated bounds: every section of the Munich mission completes and it flies its plan (issue 14):
in the level parts of the waypoint and orbit sections (vertical mode ALT, after the capture
within 10 m; Mach steps, fly-by turns at up to 30 deg of bank) altitude within 30 m of the
command (measured 13 m) and Mach within 0.01 once captured; on the managed descent paths
within 40 m of the path (measured 19 m); every waypoint section ends within 30 m of its
constraint (measured 15 m); no hold is planned. The ILS: the glide slope captured within
50 m of the planned approach altitude (measured 0.1 m); the localizer captured from one side
without crossing the centre line by more than 15 m (measured: it never crosses; 61 m before the
localizer's damping term), the glide slope from below without rising more than 5 m above it
(measured 0.4 m). Touchdown in the touchdown zone (150-900 m past the threshold),
within 5 m of the centre line, sink rate under 2 m/s; stop on the runway.
The ILS approach starts 10 NM out, 1 km off the centre line, in a 10 kt crosswind.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("jsbsim")
adapter = pytest.importorskip("openemss.models.airframe.adapter")

from perf_models import upera_standin  # noqa: E402
from upera_loop import Run, fly_upera  # noqa: E402

from openemss.models.fcs.fcs import FlightControlSystem  # noqa: E402
from openemss.models.fcs.performance import Performance  # noqa: E402
from openemss.models.mission.mission import load_mission, parse_mission  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
KT = 1852.0 / 3600.0


def _touchdown(run: Run) -> int:
    g = np.array(run.on_ground)
    airborne = np.flatnonzero(~g)
    assert airborne.size, "never airborne"
    after = np.flatnonzero(g[airborne[-1]:])
    return int(airborne[-1] + after[0])


def _check_landing(run: Run, rwy) -> None:
    i = _touchdown(run)
    along, cross = rwy.local(run.pos[i])
    assert 150.0 < along < 900.0, along
    assert abs(cross) < 5.0, cross
    assert -min(run.vs[i - 3:i + 1]) < 2.0
    end_along, end_cross = rwy.local(run.pos[-1])
    assert 0.0 < end_along < rwy.length_m and abs(end_cross) < rwy.width_m / 2


@pytest.fixture(scope="module")
def munich():
    m = load_mission(ROOT / "missions" / "munich.yaml")
    rwy = m.sections[0]["runway"]
    p0 = rwy.point(50.0)
    af = adapter.Airframe()
    s = af.start_runway(p0.lat_deg, p0.lon_deg, math.degrees(rwy.heading_rad), rwy.elevation_m)
    fcs = FlightControlSystem(m, Wf0_kg_s=0.012, performance=Performance(upera_standin()))
    return m, fcs, fly_upera(af, s, fcs, 8000.0, N1c0=25.0)


def test_munich_on_upera_completes_every_section(munich) -> None:
    m, fcs, run = munich
    assert fcs.finished
    assert [h[1] for h in fcs.runner.history] == list(range(len(m.sections) + 1))


def test_munich_on_upera_flies_its_vertical_plan(munich) -> None:
    m, fcs, run = munich
    assert fcs.runner.holds == []
    sec, alt, cmd, mode = np.array(run.sec), np.array(run.alt), np.array(run.alt_cmd), np.array(run.mode)
    mach, mcmd = np.array(run.mach), np.array(run.mach_cmd)
    for s in m.sections:
        if s.type not in ("WaypointFollowing", "Orbiting"):
            continue
        sel = sec == s.index
        h, c, md, mm, mc = alt[sel], cmd[sel], mode[sel], mach[sel], mcmd[sel]
        lv = md == "ALT"
        cap = np.flatnonzero(lv & (np.abs(h - c) < 10.0))
        if cap.size:
            k = slice(cap[0], None)
            assert np.max(np.abs(h[k][lv[k]] - c[k][lv[k]])) < 30.0, s.name
            if not np.isnan(mc[0]):
                ok = np.flatnonzero(lv[k] & (np.abs(mm[k] - mc[k]) < 0.005))
                if ok.size:
                    j = slice(ok[0], None)
                    keep = lv[k][j]
                    assert np.max(np.abs(mm[k][j][keep] - mc[k][j][keep])) < 0.01, s.name
        path = (md == "PATH") | (md == "DECEL")
        if path.any():
            assert np.max(np.abs(h[path] - c[path])) < 40.0, s.name
        if s.type == "WaypointFollowing":
            assert abs(h[-1] - s["altitude_m"]) < 30.0, s.name


def test_munich_on_upera_captures_the_ils_as_planned(munich) -> None:
    from openemss.models.fcs.approach import ApproachParams, ils_deviation

    m, fcs, run = munich
    land = m.sections[-1]
    rwy, ap = land["runway"], ApproachParams.from_file()
    ph = np.array(run.phase)
    sel = np.array(run.sec) == land.index
    alt = np.array(run.alt)
    i_gs = int(np.flatnonzero(sel & (ph == "GS"))[0])
    assert abs(alt[i_gs] - land["approach_altitude_m"]) < 50.0
    loc = np.flatnonzero(sel & np.isin(ph, ("LOC", "GS")))
    xtk = np.array(run.xtk)[loc]
    side = np.sign(xtk[0])
    assert np.max(-side * xtk) < 15.0  # no overshoot of the centre line
    gs = [ils_deviation(rwy, ap, run.pos[i], run.alt[i]).gs_m for i in range(i_gs, len(run.t)) if ph[i] == "GS"]
    assert -ap.gs_capture_m - 1.0 < gs[0] < 0.0  # captured from below, within the capture band
    assert max(gs) < 5.0 and min(gs) >= gs[0] - 1.0  # closes onto it without overshoot


def _route(m) -> list[tuple]:  # noqa: ANN001
    """(name, waypoint, the place before it or None, the next place flown to or None, section) for every
    waypoint of the mission's waypoint sections, in order. Across consecutive waypoint sections the route
    runs on (a section's last waypoint leads to the next section's first); otherwise None."""
    names = {id(wp): n for n, wp in m.waypoints}
    out = []
    prev_sec_last = None
    for i, s in enumerate(m.sections):
        if s.type != "WaypointFollowing":
            prev_sec_last = None
            continue
        wps = list(s["waypoints"])
        nxt = m.sections[i + 1] if i + 1 < len(m.sections) else None
        after = nxt["waypoints"][0] if nxt is not None and nxt.type == "WaypointFollowing" else None
        for j, wp in enumerate(wps):
            before = wps[j - 1] if j else prev_sec_last
            out.append((names.get(id(wp), "?"), wp, before, wps[j + 1] if j + 1 < len(wps) else after, s))
        prev_sec_last = wps[-1]
    return out


def test_munich_on_upera_waypoints_and_orbit(munich) -> None:
    """Fly-over waypoints passed within 600 m (legs of 20-60 km flown at 140-250 m/s with 30-deg
    bank: a turn radius is 2-11 km, so a leg may end before the overshoot of the previous turn has
    died out; measured 2-570 m). Fly-by waypoints (the shipped mission's; turns up to 120 deg) are
    turned inside: passed within the fly-by arc's distance R (1/cos(dpsi/2) - 1), R the turn radius at
    80 % of the bank limit and the section's highest Mach number times the sea-level speed of sound (at
    least its true airspeed; no wind), plus the same 600 m. The orbit radius within 5 % from capture on
    (measured 3.5 %)."""
    from openemss.models.fcs.guidance import FLY_BY_MAX_TURN_RAD
    from openemss.models.mission.geo import distance_m, final_bearing_rad, initial_bearing_rad, wrap_pi

    m, fcs, run = munich
    gp = fcs.runner.guidance.parameters
    for name, wp, before, nxt, sec in _route(m):
        bound = 600.0
        if before is None:  # the section's first leg starts where the aircraft was when it began
            before = next(p for p, k in zip(run.pos, run.sec, strict=True) if k == sec.index)
        if sec["fly_by"] and nxt is not None:
            dpsi = abs(wrap_pi(initial_bearing_rad(wp, nxt) - final_bearing_rad(before, wp)))
            if dpsi <= FLY_BY_MAX_TURN_RAD:
                vg = 340.3 * max(v for v, k in zip(run.mach, run.sec, strict=True) if k == sec.index)
                r = vg * vg / (9.80665 * math.tan(gp.fly_by_bank_frac * gp.phi_max_rad))
                bound += r * (1.0 / math.cos(dpsi / 2.0) - 1.0)
        assert min(distance_m(p, wp) for p in run.pos) < bound, name
    orb = next(s for s in m.sections if s.type == "Orbiting")
    sel = [i for i, (k, ph) in enumerate(zip(run.sec, run.phase, strict=True))
           if k == orb.index and ph.startswith("ORBIT ")]
    r = np.array([distance_m(orb["center"], run.pos[i]) for i in sel])
    assert np.max(np.abs(r - orb["radius_m"])) / orb["radius_m"] < 0.05
    assert run.phase[sel[-1]] == "ORBIT 2.00"


GTURN = """
mission: {name: g-turn and levelling}
sections:
  - {type: Levelling, altitude_m: 3000, speed: {mach: 0.5}, tolerance_m: 10, hold_s: 20}
  - {type: GTurns, load_factor: 2.0, direction: left, heading_change_deg: 360, altitude_m: 3000,
     speed: {mach: 0.5}}
  - {type: Levelling, altitude_m: 3300, speed: {mach: 0.5}, tolerance_m: 10, hold_s: 30}
"""


def test_gturn_and_levelling_on_upera() -> None:
    """A 2 g level turn holds Nz within 0.1 g once rolled in; levelling captures 3300 m within 10 m."""
    from openemss.models.airframe.trim import trim_level

    tr = trim_level(3000.0, 0.5)
    af = adapter.Airframe()
    s = af.start_air(3000.0, tr.tas_m_s, 0.0, alpha_rad=tr.alpha_rad, elevator=tr.elevator, Fn_N=tr.Fn_N)
    N1c0 = 100.0 * math.sqrt(tr.Fn_N / (13000.0 * (s.rho_amb_kg_m3 / 1.225) ** 0.7))
    fcs = FlightControlSystem(parse_mission(GTURN), Wf0_kg_s=N1c0 / 400.0 * (s.p_amb_Pa / 101325.0)
                              * math.sqrt(s.T_amb_K / 288.15), elevator0=tr.elevator)
    run = fly_upera(af, s, fcs, 900.0, N1c0=N1c0)
    assert fcs.finished
    sec, t, nz, alt = np.array(run.sec), np.array(run.t), np.array(run.nz), np.array(run.alt)
    turn = sec == 1
    steady = turn & (t > t[turn][0] + 10.0)
    assert np.max(np.abs(nz[steady] - 2.0)) < 0.1
    lev = sec == 2
    assert np.max(np.abs(alt[lev][-int(30 / 0.05):] - 3300.0)) < 10.0
    assert np.max(alt[lev]) < 3310.0


def test_munich_on_upera_lands(munich) -> None:
    m, fcs, run = munich
    _check_landing(run, m.sections[-1]["runway"])


@pytest.mark.parametrize("xwind_kt", [10.0, -10.0])
def test_ils_approach_in_crosswind_on_upera(xwind_kt: float) -> None:
    base = load_mission(ROOT / "missions" / "munich.yaml")
    rwy = base.runway("EDDM_26R")
    text = f"""
mission: {{name: ILS 26R from 10 NM}}
places:
  runways:
    R: {{threshold_lat_deg: {rwy.threshold.lat_deg}, threshold_lon_deg: {rwy.threshold.lon_deg},
        heading_deg: {math.degrees(rwy.heading_rad)}, elevation_m: {rwy.elevation_m}, length_m: {rwy.length_m},
        width_m: {rwy.width_m}}}
sections:
  - {{type: Landing, runway: R, approach_altitude_m: {rwy.elevation_m + 900.0}, approach_speed: {{cas_m_s: 68}}}}
"""
    m = parse_mission(text)
    xw = xwind_kt * KT
    wind = (-xw * math.sin(rwy.heading_rad), xw * math.cos(rwy.heading_rad), 0.0)
    af = adapter.Airframe()
    af.set_atmosphere(wind_ned_m_s=wind)
    from openemss.models.airframe.trim import trim_level

    alt0 = rwy.elevation_m + 900.0
    tr = trim_level(alt0, 0.23, heading_deg=math.degrees(rwy.heading_rad) - 20.0)
    p0 = rwy.point(-18520.0, 1000.0)
    s = af.start_air(alt0, tr.tas_m_s, math.degrees(rwy.heading_rad) - 20.0, p0.lat_deg, p0.lon_deg,
                     alpha_rad=tr.alpha_rad, elevator=tr.elevator, Fn_N=tr.Fn_N,
                     ground_elevation_m=rwy.elevation_m)
    N1c0 = 100.0 * math.sqrt(tr.Fn_N / (13000.0 * (s.rho_amb_kg_m3 / 1.225) ** 0.7))
    fcs = FlightControlSystem(m, Wf0_kg_s=N1c0 / 400.0 * (s.p_amb_Pa / 101325.0) * math.sqrt(s.T_amb_K / 288.15),
                              performance=Performance(upera_standin()))
    run = fly_upera(af, s, fcs, 1200.0, N1c0=N1c0)
    assert fcs.finished
    assert {"LOC", "GS", "FLARE", "ROLLOUT"} <= set(run.phase)
    _check_landing(run, rwy)
