"""The FCS flying the UPERA JSBSim airframe (6 DoF) through the Munich mission and an
ILS approach in a crosswind (issue 7, "shown by"; the engine is a first-order stand-in,
see upera_loop.py).

Stated bounds: every section of the Munich mission completes; in the level parts of the
waypoint and orbit sections altitude within 50 m of the command and Mach within 0.01 once
captured (as tests/fcs/test_mission_run.py); touchdown in the touchdown zone (150-900 m past
the threshold), within 5 m of the centre line, sink rate under 2 m/s; stop on the runway.
The ILS approach starts 10 NM out, 1 km off the centre line, in a 10 kt crosswind.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("jsbsim")
adapter = pytest.importorskip("openemss.models.airframe.adapter")

from upera_loop import Run, fly_upera  # noqa: E402

from openemss.models.fcs.fcs import FlightControlSystem  # noqa: E402
from openemss.models.fcs.mission import load_mission, parse_mission  # noqa: E402

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
    fcs = FlightControlSystem(m, Wf0_kg_s=0.012)
    return m, fcs, fly_upera(af, s, fcs, 8000.0, N1c0=25.0)


def test_munich_on_upera_completes_every_section(munich) -> None:
    m, fcs, run = munich
    assert fcs.finished
    assert [h[1] for h in fcs.runner.history] == list(range(len(m.sections) + 1))


def test_munich_on_upera_follows_profile_in_level_parts(munich) -> None:
    m, fcs, run = munich
    sec, alt, cmd = np.array(run.sec), np.array(run.alt), np.array(run.alt_cmd)
    mach, mcmd = np.array(run.mach), np.array(run.mach_cmd)
    for s in m.sections:
        if s.type not in ("WaypointFollowing", "Orbiting"):
            continue
        sel = sec == s.index
        cap = np.flatnonzero(np.abs(alt[sel] - cmd[sel]) < 10.0)
        if cap.size == 0:
            continue
        assert np.max(np.abs(alt[sel][cap[0]:] - cmd[sel][cap[0]:])) < 50.0, s.name
        mm, mc = mach[sel][cap[0]:], mcmd[sel][cap[0]:]
        if not np.isnan(mc[0]):
            ok = np.flatnonzero(np.abs(mm - mc) < 0.005)
            if ok.size:
                assert np.max(np.abs(mm[ok[0]:] - mc[ok[0]:])) < 0.01, s.name


def test_munich_on_upera_waypoints_and_orbit(munich) -> None:
    """Fly-over waypoints passed within 600 m (legs of 20-60 km flown at 140-250 m/s with 30-deg
    bank: a turn radius is 2-11 km, so a leg may end before the overshoot of the previous turn has
    died out; measured 2-570 m); the orbit radius within 5 % from capture on (measured 3.5 %)."""
    from openemss.models.fcs.geo import distance_m

    m, fcs, run = munich
    for name, wp in m.waypoints:
        assert min(distance_m(p, wp) for p in run.pos) < 600.0, name
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
    s = af.start_air(3000.0, tr.tas_m_s, 0.0, alpha_rad=tr.alpha_rad, elevator=tr.elevator, thrust_N=tr.thrust_N)
    N1c0 = 100.0 * math.sqrt(tr.thrust_N / (13000.0 * (s.rho_kg_m3 / 1.225) ** 0.7))
    fcs = FlightControlSystem(parse_mission(GTURN), Wf0_kg_s=N1c0 / 400.0 * (s.p_Pa / 101325.0)
                              * math.sqrt(s.T_K / 288.15), elevator0=tr.elevator)
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
                     alpha_rad=tr.alpha_rad, elevator=tr.elevator, thrust_N=tr.thrust_N,
                     ground_elevation_m=rwy.elevation_m)
    N1c0 = 100.0 * math.sqrt(tr.thrust_N / (13000.0 * (s.rho_kg_m3 / 1.225) ** 0.7))
    fcs = FlightControlSystem(m, Wf0_kg_s=N1c0 / 400.0 * (s.p_Pa / 101325.0) * math.sqrt(s.T_K / 288.15))
    run = fly_upera(af, s, fcs, 1200.0, N1c0=N1c0)
    assert fcs.finished
    assert {"LOC", "GS", "FLARE", "ROLLOUT"} <= set(run.phase)
    _check_landing(run, rwy)
