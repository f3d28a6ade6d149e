"""Winds aloft and turbulence in the airframe (models/airframe/adapter.py, fmus/airframe.py).

* The wind triangle: in steady level flight the ground velocity, measured from the change of
  position over 10 s (not from JSBSim's own ground speed), is the air velocity (true airspeed
  along the heading: wings level, no sideslip) plus the wind of the profile at the flight
  altitude, interpolated by hand between two layers.
* Turbulence (JSBSim's MIL-F-8785C model): two runs with the same seed are identical to the last
  bit; another seed gives another trajectory; severity 0 is still air.
* The FMU's ``weather_file``: the same trajectory as the adapter given the same profile, and a
  missing file refused with one line.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import open_slave
from openemss.models.airframe.adapter import Airframe
from openemss.models.airframe.trim import trim_level
from openemss.models.mission.geo import LatLon, local_ne_m
from openemss.models.mission.weather import WindLayer, WindProfile

ALT_M = 2000.0
# a west wind of 10 m/s at 1000 m turning to a north-west wind of 20 m/s at 3000 m
PROFILE = WindProfile((WindLayer(1000.0, 270.0, 10.0), WindLayer(3000.0, 315.0, 20.0)))
# by hand at 2000 m, half way: towards (north, east) = mean of (0, 10) and (-20 cos 315, -20 sin 315)
WIND_2000_NE = (0.5 * (0.0 - 20.0 * math.cos(math.radians(315.0))), 0.5 * (10.0 - 20.0 * math.sin(math.radians(315.0))))


def _level(af: Airframe, heading_deg: float, seconds: float, alt_m: float = ALT_M) -> list:
    """Trim in still air (airspeed and attitude do not depend on a steady wind), start in the wind, fly
    with the trim's controls; the states at 10 Hz."""
    tr = trim_level(alt_m, 0.4, 1900.0)
    af.start_air(alt_m, tr.tas_m_s, heading_deg, alpha_rad=tr.alpha_rad, elevator=tr.elevator,
                 Fn_N=tr.Fn_N, fuel_kg=400.0)
    states = []
    for _ in range(int(round(seconds * 10))):
        af.step(0.1)
        states.append(af.state())
    return states


@pytest.mark.parametrize("heading_deg", [0.0, 135.0, 250.0])
def test_wind_triangle_in_steady_level_flight(heading_deg: float) -> None:
    """Ground velocity = the air velocity (TAS cos(gamma) along the heading) + the wind interpolated by hand
    at 2000 m, within 0.025 m/s.

    The tolerance covers what the sum leaves out: the height wanders by up to 3 m with the controls fixed,
    and the profile's shear is 0.0074 m/s per metre there (0.022 m/s); sideslip and bank stay below
    1e-3 rad (their effect averages out over the window). The position change is taken at the flight
    altitude (at 2000 m an arc is 0.03 % longer than at sea level: 0.04 m/s)."""
    af = Airframe(wind_profile=PROFILE.ned_m_s)
    states = _level(af, heading_deg, 20.0)
    window = states[99:]  # 10 s to 20 s
    a, b = window[0], window[-1]
    h = float(np.mean([s.alt_m for s in window]))
    n, e = local_ne_m(LatLon.from_deg(a.lat_deg, a.lon_deg), LatLon.from_deg(b.lat_deg, b.lon_deg), h)
    vg = np.array([n, e]) / (b.time_s - a.time_s)
    air = np.mean([[s.tas_m_s * math.cos(math.asin(s.vs_m_s / s.tas_m_s)) * math.cos(s.psi_rad),
                    s.tas_m_s * math.cos(math.asin(s.vs_m_s / s.tas_m_s)) * math.sin(s.psi_rad)] for s in window],
                  axis=0)
    assert max(abs(s.alt_m - ALT_M) for s in window) < 3.0
    assert max(abs(s.beta_rad) + abs(s.phi_rad) for s in window) < 1e-3
    np.testing.assert_allclose(vg - air, WIND_2000_NE, atol=0.025)
    # and JSBSim's ground speed is the magnitude of the same vector sum
    gs = np.mean([s.gs_m_s for s in window])
    assert gs == pytest.approx(float(np.hypot(*(air + np.array(WIND_2000_NE)))), abs=0.025)


def test_wind_follows_the_altitude() -> None:
    """The wind applied is the profile's at the aircraft's altitude of each step: JSBSim's wind property
    against the profile evaluated at the altitude the step started at (to the round-off of ft <-> m)."""
    af = Airframe(wind_profile=PROFILE.ned_m_s)
    tr = trim_level(1500.0, 0.4, 1900.0)
    af.start_air(1500.0, tr.tas_m_s, 0.0, alpha_rad=tr.alpha_rad + 0.03, elevator=tr.elevator - 0.05,
                 Fn_N=2.0 * tr.Fn_N, fuel_kg=400.0)  # climbs through the profile
    heights = []
    for _ in range(100):
        h = af.state().alt_m
        heights.append(h)
        af.step(0.05)
        n = af.get_property("atmosphere/wind-north-fps") * 0.3048
        e = af.get_property("atmosphere/wind-east-fps") * 0.3048
        assert (n, e) == pytest.approx(PROFILE.ne_m_s(h), abs=1e-9)
    assert max(heights) - min(heights) > 20.0  # it climbed: the wind changed with the altitude


def _turbulent(seed: int, severity: int = 3) -> np.ndarray:
    af = Airframe(turbulence_severity=severity, turbulence_wind_20ft_m_s=7.7, seed=seed)
    states = _level(af, 0.0, 10.0, alt_m=1500.0)
    return np.array([[s.alt_m, s.tas_m_s, s.alpha_rad, s.phi_rad, s.q_rad_s, s.lat_deg] for s in states])


def test_turbulence_is_seeded_and_deterministic() -> None:
    a, b, c, still = _turbulent(7), _turbulent(7), _turbulent(8), _turbulent(7, severity=0)
    assert np.array_equal(a, b)  # the same seed: the same flight, bit for bit
    assert np.max(np.abs(a[:, 1] - c[:, 1])) > 0.1  # another seed: other gusts (airspeed differs by > 0.1 m/s)
    assert np.std(np.diff(a[:, 2])) > 10 * np.std(np.diff(still[:, 2]))  # turbulence moves the angle of attack
    assert np.array_equal(still, _turbulent(8, severity=0))  # off: the seed plays no part


def test_fmu_weather_file_flies_as_the_adapter(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    """The FMU with a weather file (wind profile, light turbulence, seed 5) against the adapter given the
    same profile and turbulence: the same JSBSim run, to round-off."""
    f = tmp_path / "weather.yaml"
    f.write_text("wind: {layers: [{alt_m: 1000, from_deg: 270, speed_m_s: 10}, {alt_m: 3000, from_deg: 315, "
                 "speed_m_s: 20}]}\nturbulence: {severity: light, seed: 5}\n")
    slave, vr = open_slave(project_fmus["airframe"], "weather")
    try:
        slave.setString([vr["weather_file"]], [str(f)])
        slave.setBoolean([vr["start_on_runway"]], [False])
        slave.setReal([vr["alt0_m"], vr["tas0_m_s"], vr["fuel0_kg"], vr["heading0_deg"]], [ALT_M, 130.0, 400.0, 30.0])
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        thrust, elevator = slave.getReal([vr["trim_Fn_N"], vr["trim_elevator_norm"]])
        slave.setReal([vr["Fn_N"], vr["elevator_norm"]], [thrust, elevator])
        got = []
        for k in range(100):
            slave.doStep(k * 0.05, 0.05)
            got.append(slave.getReal([vr["alt_m"], vr["lat_deg"], vr["lon_deg"], vr["tas_m_s"]]))
    finally:
        slave.fmi2FreeInstance(slave.component)
    # the FMU's air start (fmus/airframe.py): trimmed in the wind at its altitude, gear down (its input's start)
    af = Airframe(turbulence_severity=3, turbulence_wind_20ft_m_s=15 * 1852 / 3600, seed=5,
                  wind_profile=PROFILE.ned_m_s)
    # the FMU's default start: the departure runway of missions/munich.yaml (26R threshold, its elevation)
    import yaml
    rwy = yaml.safe_load((Path(__file__).resolve().parents[2] / "missions" / "munich.yaml").read_text())[
        "places"]["runways"]["EDDM_26R"]
    lat, lon, elev = rwy["threshold_lat_deg"], rwy["threshold_lon_deg"], rwy["elevation_m"]
    af.start_air(ALT_M, 100.0, 30.0, fuel_kg=400.0, ground_elevation_m=elev)
    mach = 130.0 / (af.get_property("atmosphere/a-fps") * 0.3048)
    tr = trim_level(ALT_M, mach, af.geometry.oem_kg + 400.0, airframe=af, gear_down=True, heading_deg=30.0,
                    lat_deg=lat, lon_deg=lon)
    af.start_air(ALT_M, 130.0, 30.0, lat, lon, alpha_rad=tr.alpha_rad, elevator=tr.elevator,
                 Fn_N=tr.Fn_N, gear_down=True, fuel_kg=400.0, ground_elevation_m=elev)
    ref = []
    for _ in range(100):
        af.step(0.05)
        s = af.state()
        ref.append((s.alt_m, s.lat_deg, s.lon_deg, s.tas_m_s))
    np.testing.assert_allclose(np.array(got), np.array(ref), rtol=1e-9, atol=1e-9)


def test_fmu_missing_weather_file_is_one_clear_error(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    slave, vr = open_slave(project_fmus["airframe"], "no_weather")
    try:
        slave.setString([vr["weather_file"]], [str(tmp_path / "none.yaml")])
        slave.enterInitializationMode()
        with pytest.raises(Exception, match="fmi2ExitInitializationMode"):
            slave.exitInitializationMode()
    finally:
        slave.fmi2FreeInstance(slave.component)
