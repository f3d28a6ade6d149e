"""L1 guidance, waypoint sequencing and orbits on real coordinates (around Munich),
closed loop on the kinematic lateral model (kinematic.py).

Bounds (stated): fly-over waypoints are each passed within wp_accept_m (300 m);
fly-by waypoints (ARINC 424 turn anticipation) keep the cross-track error of the new
leg below 1.5 turn radii during the turn; in the last quarter of each leg the
cross-track error stays below 40 m (fly-by) or 300 m (fly-over, which overshoots each
new leg by about a turn radius; legs here are 20-30 km with 60-120 deg turns at 180 m/s),
with or without a 10 m/s wind
(the L1 loop at 180 m/s has L1 = one 30-deg turn radius, 5.7 km, so it converges over
~30 s = 6 km); orbit radius within 5 % of the command from capture on (the issue's
bound) and within 1 % after the first turn; the turns counted equal the swept angle.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from kinematic import Kinematic

from openemss.models.fcs.errors import FcsError
from openemss.models.fcs.guidance import L1Guidance, OrbitTracker, WaypointSequencer
from openemss.models.mission.geo import (
    LatLon,
    along_track_m,
    cross_track_m,
    destination,
    distance_m,
    initial_bearing_rad,
)

DT = 0.05
EDDM = LatLon.from_deg(48.3538, 11.7861)
WPS = [LatLon.from_deg(*ll) for ll in ((48.40, 11.40), (48.25, 11.15), (48.00, 11.35), (48.05, 11.85),
                                       (48.30, 12.05))]


@pytest.mark.parametrize("fly_by", [False, True])
@pytest.mark.parametrize("wind", [(0.0, 0.0), (0.0, 10.0), (-7.0, -7.0)])
def test_waypoint_sequence_followed(wind: tuple[float, float], fly_by: bool) -> None:
    g = L1Guidance()
    g.set_parameter("wp_fly_by", fly_by)
    ac = Kinematic(EDDM, math.radians(262.0), 180.0, wind_n=wind[0], wind_e=wind[1])
    seq = WaypointSequencer(g, WPS, EDDM)
    closest = [math.inf] * len(WPS)
    xtk_late: list[float] = []
    xtk_all: list[float] = []
    t = 0.0
    while not seq.done and t < 3000.0:
        i = seq.index
        a, b = seq.leg
        cmd = seq.step(ac.pos, ac.vn, ac.ve, ac.psi)
        closest[i] = min(closest[i], distance_m(ac.pos, WPS[i]))
        if i > 0:
            xtk_all.append(abs(cmd.xtk_m))
        if seq.index == i and cmd.dist_to_go_m < 0.25 * distance_m(a, b):
            xtk_late.append(abs(cmd.xtk_m))
        ac.step(DT, cmd.phi_cmd_rad)
        t += DT
    assert seq.done
    r_turn = g.turn_radius_m(190.0)
    if fly_by:
        assert max(xtk_all) < 1.5 * r_turn
    else:
        assert all(c < g.parameters.wp_accept_m for c in closest), closest
    assert max(xtk_late) < (40.0 if fly_by else 300.0)


def _deviation_after_wp2(split: bool, anticipate: bool) -> float:
    """Largest distance from the leg WP2 -> WP3 while flying it, on the kinematic model at 180 m/s: the
    waypoints in one fly-by sequencer, or split into two sections after WP2 as the mission runner does."""
    g = L1Guidance()
    g.set_parameter("wp_fly_by", True)
    ac = Kinematic(EDDM, math.radians(262.0), 180.0)
    first = WaypointSequencer(g, WPS[:3] if split else WPS, EDDM, then=WPS[3] if anticipate else None)
    second: WaypointSequencer | None = None
    dev: list[float] = []
    t = 0.0
    while t < 3000.0:
        seq = first if second is None else second
        cmd = seq.step(ac.pos, ac.vn, ac.ve, ac.psi)
        if split and second is None and first.done:  # the next section, started as the mission runner does
            second = WaypointSequencer(g, WPS[3:], WPS[2] if anticipate else ac.pos)
        on_leg = (second is not None and second.index == 0) if split else first.index == 3
        if on_leg and along_track_m(WPS[2], WPS[3], ac.pos) > 0.0:
            dev.append(abs(cross_track_m(WPS[2], WPS[3], ac.pos)))
        if (second if split else first) is not None and (second if split else first).done:
            break
        ac.step(DT, cmd.phi_cmd_rad)
        t += DT
    return max(dev)


def test_fly_by_turn_into_the_next_section() -> None:
    """Split into two sections after WP2, with the next section's first waypoint given (``then``) and the
    next section starting its first leg at WP2, the turn at WP2 is flown exactly as inside one section
    (the same deviation from the leg WP2 -> WP3, to 1 m); without it the turn is flown over and overshoots
    that leg by more."""
    one = _deviation_after_wp2(split=False, anticipate=False)
    split = _deviation_after_wp2(split=True, anticipate=True)
    over = _deviation_after_wp2(split=True, anticipate=False)
    print(f"deviation from the leg WP2-WP3: one section {one:.0f} m, two with anticipation {split:.0f} m, "
          f"two without {over:.0f} m")
    assert split == pytest.approx(one, abs=1.0)
    assert over > 1.5 * one


def test_straight_leg_capture_from_offset_is_damped() -> None:
    """2 km off a straight leg: the L1 loop (period 20 s, damping 0.75) converges with <10 % overshoot."""
    g = L1Guidance()
    a = LatLon.from_deg(48.0, 11.0)
    b = destination(a, math.radians(90.0), 100e3)
    ac = Kinematic(destination(a, 0.0, 2000.0), math.radians(90.0), 150.0)
    xtk = []
    for _ in range(int(300 / DT)):
        cmd = g.leg(ac.pos, ac.vn, ac.ve, a, b)
        xtk.append(cmd.xtk_m)
        ac.step(DT, cmd.phi_cmd_rad)
    xtk_arr = np.array(xtk)
    assert xtk_arr[0] == pytest.approx(-2000.0, rel=1e-3)  # north of an eastbound leg: left
    assert xtk_arr.max() < 0.1 * 2000.0
    assert abs(xtk_arr[-1]) < 5.0


@pytest.mark.parametrize("direction, wind", [(1, (0.0, 0.0)), (-1, (0.0, 0.0)), (1, (8.0, -6.0))])
def test_orbit_radius_held_and_turns_counted(direction: int, wind: tuple[float, float]) -> None:
    g = L1Guidance()
    center = LatLon.from_deg(47.95, 11.60)
    R = 8000.0
    ac = Kinematic(destination(center, 0.5, 20e3), math.radians(180.0), 170.0, wind_n=wind[0], wind_e=wind[1])
    orb = OrbitTracker(g, center, R, direction, turns=2.0)
    r_after: list[float] = []
    turns: list[float] = []
    brg0 = None
    swept = 0.0
    prev = None
    t = 0.0
    while not orb.done and t < 3000.0:
        cmd = orb.step(ac.pos, ac.vn, ac.ve, ac.psi)
        if orb.captured:
            r_after.append(distance_m(center, ac.pos))
            turns.append(orb.turns_flown)
            brg = initial_bearing_rad(center, ac.pos)
            if prev is not None:
                swept += direction * math.remainder(brg - prev, 2 * math.pi)
            prev = brg
            brg0 = brg if brg0 is None else brg0
        ac.step(DT, cmd.phi_cmd_rad)
        t += DT
    assert orb.done
    r = np.array(r_after)
    assert np.max(np.abs(r - R)) / R < 0.05
    assert np.max(np.abs(r[np.array(turns) >= 1.0] - R)) / R < 0.01
    assert swept / (2 * math.pi) == pytest.approx(2.0, abs=0.01)


def test_orbit_direction_must_be_plus_or_minus_one() -> None:
    with pytest.raises(FcsError, match=r"allowed: \+1"):
        L1Guidance().orbit(EDDM, 100.0, 0.0, WPS[0], 5000.0, 0)
