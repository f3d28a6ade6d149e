"""Winds aloft and turbulence in mission files (models/mission/weather.py): the profile against hand
interpolation, the severities against JSBSim's reference table, and every bad input refused with
one line naming the file, the line and what is allowed."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from openemss.models.mission.errors import MissionError
from openemss.models.mission.mission import load_mission, parse_mission
from openemss.models.mission.weather import KT_M_S, load_weather

ROOT = Path(__file__).resolve().parents[2]
MISSION = """mission: {name: windy}
places:
  waypoints:
    A: {lat_deg: 48.0, lon_deg: 11.0}
sections:
  - {type: WaypointFollowing, waypoints: [A], altitude_m: 3000, speed: {mach: 0.5}}
"""


def test_profile_interpolates_the_components_and_holds_beyond_the_layers(tmp_path: Path) -> None:
    """Hand values: a 10 m/s west wind (from 270) blows towards the east, a 20 m/s north wind (from 360)
    towards the south; half way between them the components are the means, (-10, 5) m/s."""
    f = tmp_path / "w.yaml"
    f.write_text("wind: {layers: [{alt_m: 1000, from_deg: 270, speed_m_s: 10},\n"
                 "                {alt_m: 3000, from_deg: 360, speed_m_s: 20}]}\n")
    w = load_weather(f).wind
    assert w is not None
    for alt, (n, e) in ((2000.0, (-10.0, 5.0)), (1500.0, (-5.0, 7.5)), (0.0, (0.0, 10.0)), (9000.0, (-20.0, 0.0))):
        got = w.ne_m_s(alt)
        assert got == pytest.approx((n, e), abs=1e-12), alt
    assert w.ned_m_s(2000.0)[2] == 0.0
    assert w.max_speed_m_s == 20.0


def test_knots_and_named_severities() -> None:
    """1 kt = 1852/3600 m/s exactly; light/moderate/severe are JSBSim's severities 3/4/6 with 15/30/45 kt at
    20 ft (FGWinds.h), unless the file gives the wind at 20 ft."""
    m = parse_mission(MISSION + "wind: {layers: [{alt_m: 500, from_deg: 90, speed_kt: 20}]}\n"
                      "turbulence: {severity: moderate, seed: 11}\n", "m.yaml")
    assert m.weather is not None and m.weather.wind is not None and m.weather.turbulence is not None
    layer = m.weather.wind.layers[0]
    assert layer.speed_m_s == pytest.approx(20 * 1852 / 3600, rel=1e-15)
    assert layer.east_m_s == pytest.approx(-20 * KT_M_S) and abs(layer.north_m_s) < 1e-12  # an east wind blows west
    t = m.weather.turbulence
    assert (t.severity, t.seed, t.wind_20ft_m_s) == (4, 11, pytest.approx(30 * KT_M_S))
    for sev, code, w20_kt in (("light", 3, 15.0), ("severe", 6, 45.0), (2, 2, 15.0), (0, 0, 0.0)):
        m = parse_mission(MISSION + f"turbulence: {{severity: {sev}}}\n", "m.yaml")
        assert (m.weather.turbulence.severity, m.weather.turbulence.seed) == (code, 0)
        assert m.weather.turbulence.wind_20ft_m_s == pytest.approx(w20_kt * KT_M_S)
    m = parse_mission(MISSION + "turbulence: {severity: light, wind_20ft_m_s: 3.5}\n", "m.yaml")
    assert m.weather.turbulence.wind_20ft_m_s == 3.5


def test_missions_without_weather_and_the_shipped_weather_file() -> None:
    assert load_mission(ROOT / "missions" / "munich.yaml").weather is None
    assert load_weather(ROOT / "missions" / "munich.yaml").wind is None  # a mission file: still air
    w = load_weather(ROOT / "missions" / "weather" / "munich_wind_light_turbulence.yaml")
    assert w.wind is not None and w.turbulence is not None
    assert max(layer.speed_m_s for layer in w.wind.layers) == pytest.approx(20 * KT_M_S)
    assert w.turbulence.severity == 3
    assert "light turbulence" in w.describe()


@pytest.mark.parametrize(("extra", "line", "words"), [
    ("wind: {layers: [{alt_m: 500, from_deg: 90, speed_kt: 20, gust_kt: 5}]}", 7, ("unknown field 'gust_kt'",
                                                                                    "allowed: alt_m")),
    ("wind: {layers: [{alt_m: .nan, from_deg: 90, speed_kt: 20}]}", 7, ("'alt_m'", "finite number")),
    ("wind: {layers: [{alt_m: 500, from_deg: 90, speed_kt: .inf}]}", 7, ("'speed_kt'", "finite number")),
    ("wind: {layers: [{alt_m: 500, from_deg: 400, speed_kt: 20}]}", 7, ("'from_deg'", "[0.0, 360.0]")),
    ("wind: {layers: [{alt_m: 500, from_deg: 90, speed_m_s: 150}]}", 7, ("'speed_m_s'", "[0.0, 100.0]")),
    ("wind: {layers: [{alt_m: 500, from_deg: 90, speed_m_s: 5, speed_kt: 9}]}", 7,
     ("exactly one of speed_m_s, speed_kt",)),
    ("wind: {layers: [{alt_m: 500, from_deg: 90}]}", 7, ("exactly one of speed_m_s, speed_kt",)),
    ("wind: {layers: [{from_deg: 90, speed_kt: 3}]}", 7, ("missing field 'alt_m'",)),
    ("wind:\n  layers:\n    - {alt_m: 900, from_deg: 90, speed_kt: 3}\n    - {alt_m: 800, from_deg: 90, speed_kt: 3}",
     10, ("altitudes must increase", "800 m after 900 m")),
    ("wind: {layers: []}", 7, ("non-empty list",)),
    ("wind: {speed_kt: 20}", 7, ("'layers'",)),
    ("wind: {layers: [{alt_m: 0, from_deg: 0, speed_kt: 1}], shear: 2}", 7, ("unknown key 'shear'",)),
    ("turbulence: {severity: strong}", 7, ("'strong'", "light, moderate, severe", "0 to 7")),
    ("turbulence: {severity: 8}", 7, ("severity", "0 to 7")),
    ("turbulence: {severity: true}", 7, ("severity", "0 to 7")),
    ("turbulence: {severity: light, seed: -1}", 7, ("'seed'", "integer")),
    ("turbulence: {severity: light, seed: 1.5}", 7, ("'seed'", "integer")),
    ("turbulence: {severity: light, scale: 2}", 7, ("unknown field 'scale'", "allowed: severity, seed")),
    ("turbulence: {seed: 3}", 7, ("'severity'",)),
    ("turbulence: {severity: light, wind_20ft_kt: -3}", 7, ("'wind_20ft_kt'", "[0.0, 100.0]")),
    ("weather: {wind: 3}", 7, ("unknown top-level key 'weather'", "wind, turbulence")),
])
def test_bad_weather_is_one_line_with_file_and_line(tmp_path: Path, extra: str, line: int,
                                                    words: tuple[str, ...]) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(MISSION + extra + "\n")
    with pytest.raises(MissionError) as exc:
        load_mission(f)
    msg = str(exc.value)
    assert msg.startswith(f"{f}:{line}: ") and "\n" not in msg, msg
    for w in words:
        assert w in msg, msg
    if not extra.startswith("weather"):  # the airframe reads the same keys with the same messages
        with pytest.raises(MissionError) as exc2:
            load_weather(f)
        assert str(exc2.value) == msg


def test_weather_file_refuses_other_keys_and_missing_files(tmp_path: Path) -> None:
    f = tmp_path / "w.yaml"
    f.write_text("turbulence: {severity: light}\nwinds: {layers: []}\n")
    with pytest.raises(MissionError, match=rf"^{f}:2: unknown top-level key 'winds'; allowed: wind, turbulence"):
        load_weather(f)
    with pytest.raises(MissionError, match="cannot read the weather file"):
        load_weather(tmp_path / "none.yaml")
    f.write_text("")
    w = load_weather(f)
    assert w.wind is None and w.turbulence is None and math.isfinite(len(w.describe()))
