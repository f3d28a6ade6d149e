"""Mission files: the shipped Munich mission, the corpus of bad files (each gives one clear
error naming file:line, section and field), the state machine's section reporting, and the
QGroundControl .plan import (MAVLink items 16, 18, 21, 22)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from openemss.models.mission.errors import MissionError
from openemss.models.mission.geo import LatLon
from openemss.models.mission.mission import SECTION_TYPES, load_mission, parse_mission
from openemss.models.mission.speed import SpeedKind

ROOT = Path(__file__).resolve().parents[2]
BAD = Path(__file__).parent / "data" / "bad_missions"

# file -> (line, fragments the message must contain)
CORPUS = {
    "unknown_section_type.yaml": (7, ["section 1", "unknown section type 'Loop'", "allowed: Rolling"]),
    "missing_field.yaml": (6, ["section 0 (Orbiting)", "missing field 'turns'"]),
    "unknown_waypoint.yaml": (8, ["section 0 (WaypointFollowing)", "field 'waypoints'", "unknown waypoint 'WP9'",
                                  "defined waypoints: A, B"]),
    "impossible_value.yaml": (7, ["section 0 (GTurns)", "field 'load_factor'",
                                  "outside the allowed range [1.02, 6.0]"]),
    "bad_speed.yaml": (9, ["field 'speed'", "exactly one of mach"]),
    "unknown_runway.yaml": (7, ["section 0 (Landing)", "unknown runway 'EDDM_26L'", "defined runways: EDDM_26R"]),
    "misspelt_field.yaml": (9, ["section 0 (Levelling)", "unknown field 'tolerence_m'", "tolerance_m"]),
    "gturn_both_criteria.yaml": (3, ["section 0 (GTurns)", "exactly one of 'heading_change_deg' or 'duration_s'"]),
    "bad_latitude.yaml": (4, ["waypoint 'A'", "[-90.0, 90.0]"]),
    "not_yaml.yaml": (2, ["not valid YAML"]),
}


def test_corpus_is_complete() -> None:
    assert {p.name for p in BAD.glob("*.yaml")} == set(CORPUS)


@pytest.mark.parametrize("name", sorted(CORPUS))
def test_bad_mission_gives_one_clear_error(name: str) -> None:
    line, fragments = CORPUS[name]
    with pytest.raises(MissionError) as exc:
        load_mission(BAD / name)
    msg = str(exc.value)
    assert msg.startswith(f"{BAD / name}:{line}: "), msg
    for f in fragments:
        assert f in msg, msg
    assert "\n" not in msg


def test_munich_mission_loads_and_follows_spec() -> None:
    m = load_mission(ROOT / "missions" / "munich.yaml")
    types = [s.type for s in m.sections]
    assert types[0] == "Rolling" and types[1] == "TakeOff" and types[-1] == "Landing"
    wps = dict(m.waypoints)
    assert [f"WP{i}" for i in range(1, 15)] == list(wps)
    climb = m.sections[2]
    assert climb["waypoints"][-1] == wps["WP2"] and climb["altitude_m"] == 1000.0
    orbit = next(s for s in m.sections if s.type == "Orbiting")
    assert orbit["center"] == wps["WP8"] and orbit["turns"] == 2 and orbit["altitude_m"] == 2500.0
    assert {s["altitude_m"] for s in m.sections[3:5]} == {5000.0}
    ret = [s for s in m.sections if s.type == "WaypointFollowing" and s["altitude_m"] == 7500.0]
    assert {s["speed"].value for s in ret} == {0.7, 0.8} and all(s["speed"].kind is SpeedKind.MACH for s in ret)
    low = [s["speed"].value for s in m.sections[2:7] if s.get("speed") is not None]
    assert min(low) == 0.4 and max(low) == 0.6
    rwy = m.sections[-1]["runway"]
    # WP 14 lies on the extended centre line of the landing runway
    along, cross = rwy.local(wps["WP14"])
    assert along < -15e3 and abs(cross) < 5.0



def test_munich_runway_data_is_consistent_with_published_geometry() -> None:
    """Independent published figures (AIP via SKYbrary/Wikipedia): runways 4000 m long, centre lines
    2300 m apart, ILS courses 080/260 deg magnetic with about 3 deg E variation; the aerodrome
    reference point 48 21 14 N 011 47 10 E lies between the runways."""
    m = load_mission(ROOT / "missions" / "munich.yaml")
    r = {name: m.runway(name) for name in ("EDDM_08L", "EDDM_26R", "EDDM_08R", "EDDM_26L")}
    for a, b in (("EDDM_08L", "EDDM_26R"), ("EDDM_08R", "EDDM_26L")):
        along, cross = r[a].local(r[b].threshold)
        assert along == pytest.approx(4000.0, abs=2.0) and abs(cross) < 1.0
        assert math.degrees(r[b].heading_rad - r[a].heading_rad) == pytest.approx(180.0, abs=0.05)
        assert 82.0 < math.degrees(r[a].heading_rad) < 85.0
    _, sep = r["EDDM_08L"].local(r["EDDM_08R"].threshold)
    assert sep == pytest.approx(2300.0, abs=10.0)  # the 08R centre line is 2300 m right of 08L's
    arp = LatLon.from_deg(48.353783, 11.786086)
    _, c_north = r["EDDM_08L"].local(arp)
    _, c_south = r["EDDM_08R"].local(arp)
    assert c_north > 0.0 > c_south  # right of the northern runway, left of the southern one


def test_all_section_types_parse() -> None:
    text = """
mission: {name: all types}
places:
  runways:
    R: {threshold_lat_deg: 48.0, threshold_lon_deg: 11.0, heading_deg: 90, elevation_m: 500}
  waypoints:
    A: {lat_deg: 48.0, lon_deg: 11.2}
sections:
  - {type: Rolling, runway: R, rotate_cas_m_s: 60}
  - {type: TakeOff, runway: R, climb_speed: {cas_m_s: 80}}
  - {type: WaypointFollowing, waypoints: [A], altitude_m: 1500, speed: {tas_m_s: 120}}
  - {type: Orbiting, center: A, radius_m: 5000, turns: 1, altitude_m: 1500, speed: {mach: 0.4}}
  - {type: GTurns, load_factor: 2, duration_s: 30}
  - {type: Levelling, altitude_m: 2000, speed: {cas_m_s: 120}}
  - {type: Custom, duration_s: 10, commands: [{t_s: 0, lever: 0.5, pitch_deg: 2, bank_deg: 0}]}
  - {type: Landing, runway: R, approach_altitude_m: 1100, approach_speed: {cas_m_s: 68}}
"""
    m = parse_mission(text)
    assert [s.type for s in m.sections] == list(SECTION_TYPES[:2]) + ["WaypointFollowing", "Orbiting", "GTurns",
                                                                     "Levelling", "Custom", "Landing"]
    assert m.sections[3]["direction"] == "clockwise"  # default
    assert m.sections[4]["direction"] == "right"


def _plan(items: list[dict], home=(48.35, 11.78, 450.0), cruise: float = 140.0) -> str:
    return json.dumps({"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
                       "mission": {"version": 2, "firmwareType": 12, "vehicleType": 1, "cruiseSpeed": cruise,
                                   "hoverSpeed": 5, "plannedHomePosition": list(home), "items": items},
                       "geoFence": {}, "rallyPoints": {}})


def _item(seq: int, cmd: int, lat: float, lon: float, alt: float, p1: float = 0.0, p3: float = 0.0,
          frame: int = 3) -> dict:
    return {"type": "SimpleItem", "autoContinue": True, "command": cmd, "doJumpId": seq + 1, "frame": frame,
            "params": [p1, 0, p3, None, lat, lon, alt]}


def test_qgc_plan_import(tmp_path: Path) -> None:
    items = [_item(0, 22, 48.36, 11.70, 300.0), _item(1, 16, 48.30, 11.50, 1000.0), _item(2, 16, 48.20, 11.40, 1000.0),
             _item(3, 16, 48.10, 11.50, 1500.0), _item(4, 18, 48.05, 11.60, 1500.0, p1=2.0, p3=-6000.0),
             _item(5, 16, 48.30, 12.10, 800.0), _item(6, 21, 48.35, 11.80, 0.0)]
    p = tmp_path / "flight.plan"
    p.write_text(_plan(items))
    m = load_mission(p)
    assert [s.type for s in m.sections] == ["Rolling", "TakeOff", "WaypointFollowing", "WaypointFollowing",
                                            "Orbiting", "WaypointFollowing", "Landing"]
    assert m.sections[1]["until_height_agl_m"] == 300.0
    assert len(m.sections[2]["waypoints"]) == 2 and m.sections[2]["altitude_m"] == 1450.0  # relative + home
    orb = m.sections[4]
    assert orb["turns"] == 2.0 and orb["radius_m"] == 6000.0 and orb["direction"] == "counterclockwise"
    rwy = m.sections[-1]["runway"]
    assert rwy.elevation_m == 450.0
    # the landing runway points from the previous item to the land point
    assert rwy.local(LatLon.from_deg(48.30, 12.10))[0] < 0.0
    assert math.degrees(m.sections[0]["runway"].heading_rad) == pytest.approx(275.0, abs=20.0)


def test_qgc_unsupported_item_is_named(tmp_path: Path) -> None:
    p = tmp_path / "bad.plan"
    p.write_text(_plan([_item(0, 16, 48.3, 11.5, 500.0), _item(1, 20, 48.3, 11.5, 500.0)]))
    with pytest.raises(MissionError, match=r"mission item 1: MAV_CMD 20 is not supported; allowed: WAYPOINT \(16\)"):
        load_mission(p)


def test_readme_documents_every_section_and_field() -> None:
    from openemss.models.mission.mission import SECTION_FIELDS

    text = (ROOT / "missions" / "README.md").read_text()
    for typ, fields in SECTION_FIELDS.items():
        assert f"### {typ}" in text
        for f in fields:
            assert f"`{f}`" in text, (typ, f)


def test_a_section_type_is_one_registered_class() -> None:
    """Fields, step and completion of a type live in its class (models/fcs/sections.py, deriving from the
    mission's declaration), registered once: a type added by subclassing is read from a mission file and flown,
    with no other change; its declaration is in the mission's registry, its flight law in the FCS's."""
    import math

    from openemss.models.fcs.sections import LAWS, SectionType, register, unregister
    from openemss.models.fcs.state import AircraftState
    from openemss.models.fcs.state_machine import MissionRunner
    from openemss.models.mission.geo import LatLon
    from openemss.models.mission.sections import REGISTRY

    for name, cls in REGISTRY.items():
        assert cls.type_name == name and cls.fields and cls.completion, name
        assert issubclass(LAWS[name], cls), name  # every shipped type is flown
    with pytest.raises(ValueError, match="taken"):
        register(type("Again", (SectionType,), {"type_name": "Rolling"}))

    class Glide(SectionType):
        type_name = "Glide"
        completion = "``duration_s`` elapsed"
        speed_field = None
        fields = {"duration_s": ("number", True, None, (0.1, 100.0), "duration [s]")}

        def step(self, t_s, dt_s, x):  # noqa: ANN001, ANN201
            self.done = t_s - self.t0 >= self.sec["duration_s"]
            return self.targets(phase="GLIDE", theta_cmd_rad=0.0, lever=0.0, phi_cmd_rad=0.0, gear_down=False)

    register(Glide)
    assert REGISTRY["Glide"] is Glide and LAWS["Glide"] is Glide
    try:
        m = parse_mission("mission: {name: g}\nsections:\n  - {type: Glide, duration_s: 1.0}\n", "g.yaml")
        with pytest.raises(MissionError, match=r"g.yaml:3: section 0 \(Glide\): unknown field 'x'"):
            parse_mission("mission: {name: g}\nsections:\n  - {type: Glide, duration_s: 1.0, x: 2}\n", "g.yaml")
        run = MissionRunner(m)
        x = AircraftState(pos=LatLon.from_deg(48.0, 11.0), alt_m=1000.0, tas_m_s=100.0, Vdot_m_s2=0.0, gamma_rad=0.0,
                          vn_m_s=100.0, ve_m_s=0.0, psi_rad=0.0, phi_rad=0.0, theta_rad=0.0, p_rad_s=0.0, q_rad_s=0.0,
                          r_rad_s=0.0, beta_rad=0.0, qbar_Pa=5000.0, mass_kg=2000.0, on_ground=False)
        phases = [run.step(0.1 * k, 0.1, x).phase for k in range(12)]
        assert phases[0] == "GLIDE" and run.finished and math.isclose(run.history[-1][0], 1.0)
    finally:
        unregister("Glide")
    assert "Glide" not in REGISTRY and "Glide" not in LAWS
