"""The mission feasibility check (models/fcs/feasibility.py) on an analytic aircraft, against hand calculations.

The aircraft: drag D, maximum thrust T_max and idle thrust T_idle independent of altitude and speed,
no fuel burn (the mass stays), so every gradient is a ratio of forces: climb (T_max - D)/W, idle
descent (D - T_idle)/W, and the distance an altitude change takes is |dE| W / |T - D| with the
energy height E = h + V^2/2g, or |dh| / tan(gamma_limit) where the TECS's path limit binds. Turns:
R = GS^2 / (g tan(phi_max)). Waypoints lie on a meridian, so their distances are R_earth dlat.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import pytest

from openemss.models.fcs.atmosphere import G0_M_S2, isa
from openemss.models.fcs.feasibility import check_mission
from openemss.models.fcs.feasibility_perf import Limits, PerfPoint
from openemss.models.mission.geo import R_EARTH_M, LatLon
from openemss.models.mission.mission import parse_mission
from openemss.models.mission.weather import WindLayer, WindProfile

LAT0, LON0 = 48.0, 11.0
MASS = 2000.0
W = MASS * G0_M_S2
LIMITS = Limits(phi_max_rad=math.radians(30.0), fly_by_bank_frac=0.8, gamma_max_rad=0.3, gamma_min_rad=-0.3,
                mach_max=0.9, v_min_cas_m_s=50.0, gs_angle_rad=math.radians(3.0), tch_m=15.0, hold_enter_m=150.0)


@dataclass
class Analytic:
    """Forces independent of the flight condition [N]."""

    drag: float = 2000.0
    t_max: float = 10000.0
    t_idle: float = 0.0
    drag_gear: float = 2500.0
    rolling_friction: float = 0.02

    def point(self, alt_m: float, mach: float, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        drag = self.drag_gear if gear_down else self.drag
        return PerfPoint(alt_m, mach, mach * isa(alt_m).a_m_s, mass_kg, drag, 0.3, 1.3, 0.05, mass_kg * G0_M_S2 / 0.3,
                         self.t_max, self.t_idle, 0.2, 0.02)

    def thrust_max_N(self, alt_m: float, mach: float) -> float:
        return self.t_max

    def cruise_fuel_kg_s(self, alt_m: float, mach: float, Fn_N: float) -> float:
        return 0.0


def _north(km: float) -> tuple[float, float]:
    """Latitude and longitude of a point km north of the start [deg]."""
    return LAT0 + math.degrees(km * 1e3 / R_EARTH_M), LON0


def _east(lat: float, km: float) -> tuple[float, float]:
    return lat, LON0 + math.degrees(km * 1e3 / (R_EARTH_M * math.cos(math.radians(lat))))


def _mission(sections: str, waypoints: dict[str, tuple[float, float]], runways: str = "") -> object:
    wps = "\n".join(f"    {n}: {{lat_deg: {la!r}, lon_deg: {lo!r}}}" for n, (la, lo) in waypoints.items())
    text = f"mission: {{name: t}}\nplaces:\n{runways}  waypoints:\n{wps}\nsections:\n{sections}"
    return parse_mission(text, "t.yaml")


def _check(mission: object, alt0: float, tas0: float = 150.0, perf: Analytic | None = None,
           wind: WindProfile | None = None, margin: float = 0.2, limits: Limits = LIMITS) -> object:
    return check_mission(mission, perf or Analytic(), limits, MASS, start=(LatLon.from_deg(LAT0, LON0), alt0, tas0),
                         wind=wind, margin=margin)  # type: ignore[arg-type]


@pytest.mark.parametrize(("km", "verdict"), [(20.0, "infeasible"), (32.0, "marginal"), (40.0, "ok")])
def test_idle_descent_gradient(km: float, verdict: str) -> None:
    """5000 -> 2000 m at constant TAS: idle gradient D/W = 2000 N / 19613 N = 10.2 %, 29.42 km needed."""
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 2000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(km)})
    s = _check(m, 5000.0).sections[0]
    assert s.verdict == verdict
    assert s.distance_m == pytest.approx(km * 1e3, rel=1e-6)
    assert s.required_gradient == pytest.approx(-3000.0 / (km * 1e3), rel=1e-6)
    assert s.achievable_gradient == pytest.approx(-2000.0 / W, rel=1e-9)
    assert s.needed_distance_m == pytest.approx(3000.0 * W / 2000.0, rel=1e-9)
    if verdict == "marginal":
        margin = (2000.0 / W) / (3000.0 / 32e3) - 1.0
        assert f"margin {100 * margin:.0f} %" in s.findings[0].text
    if verdict != "ok":
        assert "descent 5000 -> 2000 m over" in s.findings[0].text and "limited by thrust" in s.findings[0].text


def test_climb_limited_by_the_flight_path_angle() -> None:
    """1000 -> 4000 m over 25 km: (T - D)/W = 40.8 % but gamma_max = 0.1 rad: 3000 m / tan(0.1) = 29.90 km."""
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 4000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(25.0)})
    s = _check(m, 1000.0, limits=dataclasses.replace(LIMITS, gamma_max_rad=0.1)).sections[0]
    assert s.verdict == "infeasible"
    assert s.needed_distance_m == pytest.approx(3000.0 / math.tan(0.1), rel=1e-9)
    assert s.achievable_gradient == pytest.approx(math.tan(0.1), rel=1e-9)
    assert "flight-path limit 5.7 deg (tecs.gamma_max_rad)" in s.findings[0].text


def test_a_speed_change_is_energy_to_spend() -> None:
    """5000 m at 200 m/s to 2000 m at 150 m/s: dE = -3000 m - (200^2 - 150^2)/2g = -3892.3 m at D/W."""
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 2000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(60.0)})
    s = _check(m, 5000.0, tas0=200.0).sections[0]
    dE = 3000.0 + (200.0 ** 2 - 150.0 ** 2) / (2 * G0_M_S2)
    assert s.needed_distance_m == pytest.approx(dE * W / 2000.0, rel=1e-9)
    assert s.verdict == "ok"


def test_headwind_steepens_the_ground_gradient() -> None:
    """A 10 m/s headwind on a northbound climb at 150 m/s TAS: over the ground the gradient is
    (T - D)/W * TAS/GS with GS = 140 m/s."""
    perf = Analytic(t_max=4000.0)  # (T - D)/W = 10.2 %, below the path limit
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 3000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(50.0)})
    wind = WindProfile((WindLayer(0.0, 0.0, 10.0),))  # from the north
    s = _check(m, 1000.0, perf=perf, wind=wind).sections[0]
    assert s.achievable_gradient == pytest.approx(2000.0 / W * 150.0 / 140.0, rel=1e-9)
    still = _check(m, 1000.0, perf=Analytic(t_max=4000.0)).sections[0]
    assert still.achievable_gradient == pytest.approx(2000.0 / W, rel=1e-9)


@pytest.mark.parametrize(("radius_m", "verdict"), [(4000.0, "infeasible"), (5000.0, "marginal"), (6000.0, "ok")])
def test_orbit_radius_against_the_bank_limit_in_the_wind(radius_m: float, verdict: str) -> None:
    """150 m/s TAS and 10 m/s of wind: 160 m/s over the ground downwind, R = 160^2/(g tan 30 deg) = 4521 m."""
    m = _mission(f"  - {{type: Orbiting, center: C, radius_m: {radius_m}, turns: 1, altitude_m: 3000, "
                 "speed: {tas_m_s: 150}}\n", {"C": _north(20.0)})
    s = _check(m, 3000.0, wind=WindProfile((WindLayer(0.0, 90.0, 10.0),))).sections[0]
    r_min = 160.0 ** 2 / (G0_M_S2 * math.tan(math.radians(30.0)))
    assert s.turn_radius_m == pytest.approx(r_min, rel=1e-9)
    assert s.verdict == verdict
    if verdict != "ok":
        bank = math.degrees(math.atan(160.0 ** 2 / (G0_M_S2 * radius_m)))
        assert f"needs {bank:.0f} deg of bank" in s.findings[0].text and f"{r_min / 1e3:.1f} km" in s.findings[0].text
    assert s.distance_m == pytest.approx(20e3 - radius_m + 2 * math.pi * radius_m, rel=1e-6)


def test_fly_by_turn_anticipation_against_the_leg() -> None:
    """A right angle at A flown by at 80 % of 30 deg: R = 150^2/(g tan 24 deg) = 5153 m, lead R tan 45 deg = R;
    the next leg of 4 km is too short for it."""
    a = _north(30.0)
    m = _mission("  - {type: WaypointFollowing, fly_by: true, waypoints: [A, B], altitude_m: 3000, "
                 "speed: {tas_m_s: 150}}\n", {"A": a, "B": _east(a[0], 4.0)})
    s = _check(m, 3000.0).sections[0]
    r = 150.0 ** 2 / (G0_M_S2 * math.tan(0.8 * math.radians(30.0)))
    assert s.turn_radius_m == pytest.approx(r, rel=1e-6)
    assert s.verdict == "infeasible"
    text = next(f.text for f in s.findings if "A -> B" in f.text)
    assert f"take {r * math.tan(math.radians(45.0)) / 1e3:.1f} km of turn anticipation" in text
    assert s.geometry_radius_m == pytest.approx(4000.0, rel=1e-3)


@pytest.mark.parametrize(("drag_gear_N", "verdict"), [(900.0, "infeasible"), (1150.0, "marginal"), (1500.0, "ok")])
def test_glide_slope_at_idle_with_the_gear_down(drag_gear_N: float, verdict: str) -> None:
    """3 deg = 5.24 %: the gear-down idle gradient is D_gear/W (4.6, 5.9, 7.6 %)."""
    rw = ("  runways:\n    R: {threshold_lat_deg: 48.1, threshold_lon_deg: 11.0, heading_deg: 180.0, "
          "elevation_m: 500.0}\n")
    m = _mission("  - {type: Landing, runway: R, approach_altitude_m: 1000, approach_speed: {tas_m_s: 70}}\n",
                 {"A": _north(1.0)}, runways=rw)
    s = _check(m, 1000.0, tas0=70.0, perf=Analytic(drag_gear=drag_gear_N)).sections[0]
    assert s.required_gradient == pytest.approx(-math.tan(math.radians(3.0)), rel=1e-12)
    assert s.achievable_gradient == pytest.approx(-drag_gear_N / W, rel=1e-9)
    assert s.distance_m == pytest.approx((1000.0 - 500.0 - 15.0) / math.tan(math.radians(3.0)), rel=1e-12)
    assert s.verdict == verdict


def test_level_flight_needs_more_thrust_than_drag() -> None:
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 3000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(30.0)})
    s = _check(m, 3000.0, perf=Analytic(t_max=1800.0)).sections[0]
    assert s.verdict == "infeasible" and s.thrust_ratio == pytest.approx(0.9)
    assert "needs 2.00 kN, the engine gives at most 1.80 kN" in s.findings[0].text
    s = _check(m, 3000.0, perf=Analytic(t_max=2200.0)).sections[0]
    assert s.verdict == "marginal" and "margin 10 %" in s.findings[0].text


def test_margin_option_and_counts() -> None:
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 2000, speed: {tas_m_s: 150}}\n"
                 "  - {type: WaypointFollowing, waypoints: [B], altitude_m: 2000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(32.0), "B": _north(60.0)})
    c = _check(m, 5000.0)
    assert [s.verdict for s in c.sections] == ["marginal", "ok"] and c.count("marginal") == 1
    assert _check(m, 5000.0, margin=0.05).sections[0].verdict == "ok"  # 8.8 % of margin > 5 %


@dataclass
class WithAirbrake(Analytic):
    """The analytic aircraft with an airbrake adding ``drag_ab`` [N] fully out."""

    drag_ab: float = 2000.0

    def point(self, alt_m: float, mach: float, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        return dataclasses.replace(super().point(alt_m, mach, mass_kg, gear_down), drag_airbrake_N=self.drag_ab)


@pytest.mark.parametrize(("km", "verdict"), [(25.0, "ok"), (21.0, "marginal"), (17.0, "infeasible")])
def test_airbrake_planned_where_idle_is_not_enough(km: float, verdict: str) -> None:
    """5000 -> 2000 m at constant TAS: idle alone, 2000 N of drag, needs 29.42 km (see above); with the
    airbrake planned up to half of its 2000 N, (2000 + 1000)/19613 = 15.3 %: 19.61 km. An aircraft
    without an airbrake or an FCS that plans none gets the idle figure."""
    m = _mission("  - {type: WaypointFollowing, waypoints: [A], altitude_m: 2000, speed: {tas_m_s: 150}}\n",
                 {"A": _north(km)})
    lim = dataclasses.replace(LIMITS, airbrake_plan_max=0.5)
    s = _check(m, 5000.0, perf=WithAirbrake(), limits=lim).sections[0]
    assert s.verdict == verdict
    assert s.achievable_gradient == pytest.approx(-3000.0 / W, rel=1e-9)
    assert s.needed_distance_m == pytest.approx(3000.0 * W / 3000.0, rel=1e-9)
    noted = any("planned with the airbrake" in f.text and "idle alone needs 29.4 km" in f.text for f in s.findings)
    assert noted is (verdict != "infeasible")
    assert _check(m, 5000.0, perf=WithAirbrake()).sections[0].verdict == "infeasible"  # none planned
    assert _check(m, 5000.0, limits=lim).sections[0].verdict == "infeasible"           # none fitted
