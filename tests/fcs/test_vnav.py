"""The vertical planner (models/fcs/vnav.py, profile.py, vertical.py) against hand calculations.

A synthetic aircraft makes the numbers workable by hand: no drag (CD0 = k = 0), idle thrust -0.07 W
and maximum thrust 0.10 W everywhere (2000 kg). So the idle energy gradient is -0.07 and the climb
gradient +0.10 at any speed, the load factor of a turn changes nothing, and at constant true airspeed
sin(gamma) is the gradient. The references are worked in the tests' docstrings:

* top of descent: the descent 4000 m at sin(gamma) = 0.07, plus the roundings at the top and the
  bottom, w = V^2 tan(gamma) / (2 n_z g) each;
* the deceleration segment: (V1^2 - V2^2) / (2 g 0.07), plus TECS's exponential tail
  V2 ln(Vdot_max / k_V / tail) / k_V;
* the planned hold: the height the path cannot lose before the fix, over 2 pi R tan(gamma) per turn;
* the top of climb: the acceleration (V1^2 - V0^2) / (2 g 0.10), then 3000 m at sin(gamma) = 0.10;
* the route's distance to go: the legs, less a fly-by turn's shortening R (2 tan(dpsi/2) - dpsi);
* the profile's rounding: a parabola with the vertical acceleration n_z g at the ground speed;
* in flight, the height a descent would still have at its fix at the steepest path.
"""
from __future__ import annotations

import dataclasses
import math

import pytest
from perf_models import synthetic

from openemss.models.fcs.atmosphere import G0_M_S2
from openemss.models.fcs.guidance import GuidanceParams
from openemss.models.fcs.performance import Performance
from openemss.models.fcs.profile import VerticalProfile
from openemss.models.fcs.vertical import RouteDistance, SectionVnav
from openemss.models.fcs.vnav import Vnav, VnavParams
from openemss.models.mission.geo import LatLon, destination, distance_m, final_bearing_rad, initial_bearing_rad, wrap_pi
from openemss.models.mission.speed import SpeedCommand, SpeedKind

MASS = 2000.0
W = MASS * G0_M_S2
G_IDLE, G_MAX = 0.07, 0.10
VDOT_MAX, K_V = 1.5, 0.15


@pytest.fixture(scope="module")
def vnav() -> Vnav:
    data = synthetic(0.0, 0.0, lambda h, m, n1c: -G_IDLE * W, lambda h, m: G_MAX * W)
    return Vnav(Performance(data), VnavParams.from_file())


def _tan(sin_g: float) -> float:
    return sin_g / math.sqrt(1.0 - sin_g * sin_g)


def test_top_of_descent_by_hand(vnav: Vnav) -> None:
    """6000 -> 2000 m at 150 m/s TAS: tan(gamma) = 0.07/sqrt(1 - 0.07^2) = 0.070173 (4.01 deg, inside the
    6-deg limit), 4000 m take 57 002 m; roundings w = 150^2 x 0.070173 / (2 x 0.07 x 9.80665) = 1150 m at
    the top and the bottom: TOD 59 303 m before the constraint, no deceleration, no airbrake."""
    p = vnav.parameters
    v = SpeedCommand(150.0, SpeedKind.TAS)
    plan = vnav.plan_descent(6000.0, 2000.0, 80e3, v, v, MASS, VDOT_MAX, K_V)
    t = _tan(G_IDLE)
    w = 150.0 ** 2 * t / (2.0 * p.nz_path_g * G0_M_S2)
    assert plan.feasible and plan.airbrake == 0.0 and plan.hold_height_m == 0.0
    assert plan.s_decel_m == 0.0 and plan.s_bod_m == 0.0
    assert plan.s_tod_m == pytest.approx(w + 4000.0 / t + w, rel=1e-9)
    # on the straight part the path is the line through the corner (s = w, 2000 m) at tan(gamma)
    assert plan.profile.at(30e3)[0] == pytest.approx(2000.0 + t * (30e3 - w), rel=1e-9)
    assert plan.profile.at(30e3)[1] == pytest.approx(t, rel=1e-9)
    # the bottom rounding passes (b - a) w / 4 above the corner, and levels at 2000 m at s = 0
    assert plan.profile.at(w)[0] == pytest.approx(2000.0 + t * w / 4.0, rel=1e-9)
    assert plan.profile.at(0.0) == (2000.0, 0.0)
    assert plan.profile.at(plan.s_tod_m + 1.0) == (6000.0, 0.0)


def test_deceleration_segment_by_hand(vnav: Vnav) -> None:
    """200 -> 150 m/s at idle: 0.07 g = 0.686 m/s^2 (below Vdot_max): (200^2 - 150^2) / (2 x 0.686) =
    12 747 m, plus the tail 150 ln(1.5 / 0.15 / 2) / 0.15 = 1609 m (tail 2 m/s)."""
    tail = vnav.parameters.speed_tail_m_s
    s = vnav.decel_distance_m(2000.0, 200.0, 150.0, MASS, 0.0, VDOT_MAX, K_V)
    ref = (200.0 ** 2 - 150.0 ** 2) / (2.0 * G0_M_S2 * G_IDLE) + 150.0 * math.log(VDOT_MAX / K_V / tail) / K_V
    assert s == pytest.approx(ref, rel=1e-9)


def test_planned_hold_by_hand(vnav: Vnav) -> None:
    """The same descent within 30 km: the path starts at the section's start and reaches the fix at
    2000 + 0.070173 x (59 303 - 30 000 - 1150 ... ) -- i.e. the line through (w - 29 303 m, 2000 m) at 0
    -- 3975.5 m; the hold loses the 1975.5 m left on a spiral of 5000 m radius at the same gradient:
    1975.5 / (2 pi 5000 x 0.070173) = 0.896 turns."""
    p = vnav.parameters
    v = SpeedCommand(150.0, SpeedKind.TAS)
    plan = vnav.plan_descent(6000.0, 2000.0, 30e3, v, v, MASS, VDOT_MAX, K_V)
    t = _tan(G_IDLE)
    w = 150.0 ** 2 * t / (2.0 * p.nz_path_g * G0_M_S2)
    shift = (2 * w + 4000.0 / t) - 30e3
    h_fix = 2000.0 + t * (0.0 - (w - shift))
    assert not plan.feasible and plan.s_tod_m == pytest.approx(30e3)
    assert plan.hold_height_m == pytest.approx(h_fix - 2000.0, rel=1e-9)
    assert plan.hold_turns == pytest.approx((h_fix - 2000.0) / (2 * math.pi * p.hold_radius_m * t), rel=1e-9)


def test_top_of_climb_by_hand(vnav: Vnav) -> None:
    """1000 -> 4000 m, 140 -> 150 m/s TAS at maximum thrust (0.10 W): accelerate (150^2 - 140^2)/(2 x 0.981)
    = 1479 m, then 3000 m at tan(gamma) = 0.10/sqrt(0.99) = 0.1005 (5.7 deg, inside the 10-deg limit):
    29 850 m; top of climb 31 329 m from the start."""
    plan = vnav.plan_climb(1000.0, 4000.0, 40e3, SpeedCommand(150.0, SpeedKind.TAS), 140.0, MASS, 0.175)
    ref = (150.0 ** 2 - 140.0 ** 2) / (2.0 * G0_M_S2 * G_MAX) + 3000.0 / _tan(G_MAX)
    assert plan.feasible and plan.s_toc_m == pytest.approx(ref, rel=1e-9)
    assert not vnav.plan_climb(1000.0, 4000.0, 0.9 * ref, SpeedCommand(150.0, SpeedKind.TAS), 140.0, MASS,
                               0.175).feasible


def test_route_distance_by_hand() -> None:
    """A -> B 20 km east, B -> C 20 km north (a 90-deg fly-by turn at B), the constraint at C: the distance to
    go on the first leg is the rest of it plus B -> C less the turn's shortening R (2 tan 45 - pi/2), R the
    radius at 100 m/s and 80 % of the 30-deg bank limit; on the last leg it is the rest of the leg."""
    gp = dataclasses.replace(GuidanceParams.from_file(), wp_fly_by=True)
    a = LatLon.from_deg(48.0, 11.0)
    b = destination(a, math.pi / 2, 20e3)
    c = destination(b, 0.0, 20e3)
    route = RouteDistance(a, [b, c], None, 1, gp, 100.0, 100.0)
    r = 100.0 ** 2 / (G0_M_S2 * math.tan(gp.fly_by_bank_frac * gp.phi_max_rad))
    dpsi = abs(wrap_pi(initial_bearing_rad(b, c) - final_bearing_rad(a, b)))  # 90 deg less the meridians' 0.2
    assert dpsi == pytest.approx(math.pi / 2, abs=0.005)
    cut = r * (2.0 * math.tan(dpsi / 2) - dpsi)
    assert route.lead_m == 0.0
    assert route.dtg(0, 5e3) == pytest.approx(5e3 + distance_m(b, c) - cut, rel=1e-6)
    assert route.dtg(1, 7e3) == pytest.approx(7e3)
    assert route.dtg(2, 0.0) < 0.0
    # with a next point after C (a 90-deg turn back west), the route ends R tan 45 = R before C
    route2 = RouteDistance(a, [b, c], destination(c, -math.pi / 2, 20e3), 1, gp, 100.0, 100.0)
    dpsi2 = abs(wrap_pi(initial_bearing_rad(c, destination(c, -math.pi / 2, 20e3)) - final_bearing_rad(b, c)))
    assert route2.lead_m == pytest.approx(r * math.tan(dpsi2 / 2), rel=1e-9)


def test_profile_rounding_has_the_stated_vertical_acceleration() -> None:
    """A descent at 0.1 from s = 1000 m to 21 000 m (2000 m), level on both sides, rounded for 0.07 g at 150 m/s:
    half-width w = 150^2 x 0.1 / (2 x 0.07 g) = 1639 m; in the rounding d2h/ds2 = 0.1 / (2 w), so at 150 m/s the
    vertical acceleration is 0.07 g; the height and slope are continuous where it joins the lines."""
    vg = 150.0
    prof = VerticalProfile.rounded([-1e7, 1000.0, 21000.0, 1e7], [0.0, 0.0, 2000.0, 2000.0], [vg] * 4, 0.07)
    w = vg ** 2 * 0.1 / (2 * 0.07 * G0_M_S2)
    assert prof.w_m[1] == pytest.approx(w, rel=1e-12) and prof.w_m[2] == pytest.approx(w, rel=1e-12)
    d = 10.0
    h0, h1, h2 = (prof.at(1000.0 + x)[0] for x in (-d, 0.0, d))
    assert vg ** 2 * (h0 - 2 * h1 + h2) / d ** 2 == pytest.approx(0.07 * G0_M_S2, rel=1e-6)
    for s_join, line in ((1000.0 - w, 0.0), (1000.0 + w, 0.1 * w)):
        for eps in (-1e-6, 1e-6):
            h, slope = prof.at(s_join + eps)
            assert h == pytest.approx(line, abs=1e-6)
    assert prof.at(1000.0 + w + 1e-6)[1] == pytest.approx(0.1, abs=1e-9)
    assert prof.at(11000.0) == (pytest.approx(1000.0), pytest.approx(0.1))


def test_a_descent_found_unable_in_flight_plans_a_flagged_hold(vnav: Vnav) -> None:
    """In flight, every replan_period_s: 20 km before the fix at 5000 m for 2000 m, even the steepest path
    (6 deg) would reach it 5000 - 2000 - 20 000 tan 6 deg = 898 m high, beyond unable_margin_m: a hold is
    planned then ("unable", that height), before the fix; within the margin nothing is planned."""
    import dataclasses as dc

    from openemss.models.fcs.state import AircraftState

    p = vnav.parameters
    gp = dc.replace(GuidanceParams.from_file(), wp_fly_by=True)
    a = LatLon.from_deg(48.0, 11.0)
    b = destination(a, math.pi / 2, 60e3)
    v = SpeedCommand(150.0, SpeedKind.TAS)

    def state(pos: LatLon, h: float) -> AircraftState:
        return AircraftState(pos, h, 150.0, 0.0, 0.0, 0.0, 150.0, math.pi / 2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e4,
                             MASS, False)

    sv = SectionVnav(vnav, gp, 3, 2000.0, v, v, a, [b], 0, None, state(a, 5000.0), 0.0, (VDOT_MAX, K_V, 0.175))
    assert sv.kind == "descent" and sv.hold is None  # 60 km are enough for 3000 m at 4 deg
    here = destination(a, math.pi / 2, 40e3)
    excess = 5000.0 - 2000.0 - 20e3 * math.tan(p.gamma_path_max_rad)
    sv.step(p.replan_period_s, state(here, 5000.0), 0, distance_m(here, b))
    assert sv.hold is not None and sv.hold.reason == "unable" and sv.hold.planned_at_s == p.replan_period_s
    assert sv.hold.height_m == pytest.approx(excess, rel=1e-3)
    sv2 = SectionVnav(vnav, gp, 3, 2000.0, v, v, a, [b], 0, None, state(a, 5000.0), 0.0, (VDOT_MAX, K_V, 0.175))
    ok_h = 2000.0 + 20e3 * math.tan(p.gamma_path_max_rad) + 0.5 * p.unable_margin_m
    sv2.step(p.replan_period_s, state(here, ok_h), 0, distance_m(here, b))
    assert sv2.hold is None
