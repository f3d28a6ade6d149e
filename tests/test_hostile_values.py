"""The hostile corpus, values (issue 33, point 4): every value of a file a user edits -- missions, QGroundControl
plans, engine design files, studies -- is checked where it enters, with its type, finiteness and range.

Each case builds its file here and runs the command a user would (``emss mission check``, ``emss engine
design``, ``emss study cases``); it asserts exit code 1, exactly one line on stderr without a traceback or
"internal error", naming the file the test wrote and the line the test counted in its own text (the independent
reference), and the file left as written. Kinds: a list or mapping where a name or a number is, text, null
and Booleans (YAML's ``yes``) where numbers are, 401-digit integers, NaN and 1e999, keys given twice (also in
two spellings of one key), legs whose great-circle course is undefined (identical or antipodal waypoints),
grids that would give NaN or the same case twice, files of one name that would be one case, binary files.
A second part checks what must be accepted (a BOM, two missions of one name in two folders) and the two
failures of the README (the pre-run hook and ``emss mission check`` with ``design_override`` on a preset
sized by thrust).
"""
from __future__ import annotations

import json
import shutil
import zipfile
from collections.abc import Callable
from pathlib import Path
from xml.etree import ElementTree

import pytest

from openemss.models.mission.mission import load_mission
from openemss.orchestrator.cli.main import main
from openemss.study.spec import load_study

ROOT = Path(__file__).resolve().parents[1]
HUGE = "9" * 401

MISSION = """mission: {name: hostile values}
places:
  runways:
    R: {threshold_lat_deg: 48.366887, threshold_lon_deg: 11.821173, heading_deg: 263.42, elevation_m: 441.7}
  waypoints:
    A: {lat_deg: 48.30, lon_deg: 11.50}
    B: {lat_deg: 48.40, lon_deg: 11.30}
    C: {lat_deg: 48.20, lon_deg: 11.20}
sections:
  - {type: Rolling, runway: R, rotate_cas_m_s: 62.0}
  - {type: TakeOff, runway: R, climb_speed: {cas_m_s: 80.0}}
  - {type: WaypointFollowing, waypoints: [A, B], altitude_m: 1000.0, speed: {mach: 0.4}}
  - {type: Orbiting, center: C, radius_m: 5000.0, turns: 1, altitude_m: 1000.0, speed: {mach: 0.4}}
wind: {layers: [{alt_m: 450.0, from_deg: 240.0, speed_kt: 8.0}]}
"""


def line_of(text: str, fragment: str, nth: int = 1) -> int:
    """1-based line of the nth line of ``text`` containing ``fragment`` (the independent reference)."""
    return [i for i, ln in enumerate(text.splitlines(), start=1) if fragment in ln][nth - 1]


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    rc = main(list(argv))
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    return rc, err


def refused(capsys: pytest.CaptureFixture[str], path: Path, content: str | bytes, argv: list[str],
            line: int | None, *words: str) -> str:
    """Run ``argv`` on ``path`` written with ``content``: exit 2 (bad input), one line naming ``path:line`` and ``words``,
    the file as written."""
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    before = path.read_bytes()
    rc, err = run(capsys, *argv)
    assert rc == 2 and len(err) == 1, (rc, err)
    msg = err[0]
    assert "Traceback" not in msg and "internal error" not in msg, msg
    assert f"{path}:{line}: " in msg if line is not None else str(path) in msg, msg
    for w in words:
        assert w in msg, (w, msg)
    assert path.read_bytes() == before
    return msg


# -- missions (emss mission check FILE) ---------------------------------------------------------------
def _sub(old: str, new: str) -> Callable[[str], str]:
    def make(text: str) -> str:
        assert old in text, old
        return text.replace(old, new, 1)
    return make


#: case -> (edit of MISSION, fragment of the line the error is on (in the edited text), words of the message)
MISSION_CASES: dict[str, tuple[Callable[[str], str], str, tuple[str, ...]]] = {
    "type_as_list": (_sub("type: Orbiting", "type: [Orbiting]"), "[Orbiting]", ("unknown section type a list",)),
    "type_as_mapping": (_sub("type: Orbiting", "type: {Orbiting: 1}"), "{Orbiting: 1}",
                        ("unknown section type a mapping", "allowed: Rolling")),
    "waypoint_name_as_list": (_sub("waypoints: [A, B]", "waypoints: [[A], B]"), "[[A], B]",
                              ("field 'waypoints'", "a waypoint name (text), got a list")),
    "runway_as_mapping": (_sub("runway: R, rotate", "runway: {R: 1}, rotate"), "{R: 1}",
                          ("field 'runway'", "got a mapping")),
    "centre_as_null": (_sub("center: C", "center: null"), "center: null", ("field 'center'", "got null")),
    "mission_name_as_list": (_sub("{name: hostile values}", "{name: [a, b]}"), "name: [a, b]",
                             ("mission's name (text), got a list",)),
    "section_name_as_mapping": (_sub("rotate_cas_m_s: 62.0}", "rotate_cas_m_s: 62.0, name: {x: 1}}"), "name: {x",
                                ("field 'name'", "got a mapping")),
    "key_as_list": (_sub("    A: {lat", "    [A]: {lat"), "[A]: {lat", ("a key is a list",)),
    "huge_integer_altitude": (_sub("altitude_m: 1000.0, speed: {mach: 0.4}}\n  - {type: Orb",
                                   f"altitude_m: {HUGE}, speed: {{mach: 0.4}}}}\n  - {{type: Orb"), HUGE,
                              ("'altitude_m'", "401 characters is too large")),
    "huge_integer_latitude": (_sub("lat_deg: 48.30", f"lat_deg: {HUGE}"), HUGE, ("too large for a number",)),
    "yes_as_altitude": (_sub("turns: 1, altitude_m: 1000.0", "turns: 1, altitude_m: yes"), "altitude_m: yes",
                        ("field 'altitude_m'", "got true", "yes/no")),
    "text_as_speed": (_sub("speed: {mach: 0.4}}\n  - {type: Orb", "speed: {mach: '0.4'}}\n  - {type: Orb"),
                      "'0.4'", ("field 'speed'", "the text '0.4'", "without quotes")),
    "exponent_read_as_text": (_sub("radius_m: 5000.0", "radius_m: 5e3"), "5e3", ("the text '5e3'", "1.0e+5")),
    "custom_lever_huge": (_sub("wind:", "  - {type: Custom, duration_s: 5.0, commands: "
                               f"[{{t_s: 0.0, lever: 1{'0' * 400}, pitch_deg: 2.0, bank_deg: 0.0}}]}}\nwind:"),
                          "type: Custom", ("too large for a number",)),
    "wind_speed_as_text": (_sub("speed_kt: 8.0", "speed_kt: fast"), "speed_kt: fast",
                           ("'speed_kt'", "the text 'fast'")),
    "turbulence_seed_as_list": (lambda m: m + "turbulence: {severity: light, seed: [7]}\n", "seed: [7]",
                                ("'seed'", "got a list")),
    "identical_consecutive_waypoints": (_sub("waypoints: [A, B]", "waypoints: [A, B, B]"), "[A, B, B]",
                                        ("field 'waypoints'", "from B to B", "coincide")),
    "two_names_one_place": (_sub("B: {lat_deg: 48.40, lon_deg: 11.30}", "B: {lat_deg: 48.30, lon_deg: 11.50}"),
                            "waypoints: [A, B]", ("from A to B", "coincide")),
    "antipodal_waypoints": (_sub("B: {lat_deg: 48.40, lon_deg: 11.30}", "B: {lat_deg: -48.30, lon_deg: -168.50}"),
                            "waypoints: [A, B]", ("from A to B", "antipodal", "opposite points of the Earth")),
    "fly_by_into_its_own_last_waypoint": (
        _sub("  - {type: Orbiting", "  - {type: WaypointFollowing, waypoints: [B, C], fly_by: true, altitude_m: "
             "1000.0, speed: {mach: 0.4}}\n  - {type: WaypointFollowing, waypoints: [C, A], altitude_m: 1000.0, "
             "speed: {mach: 0.4}}\n  - {type: Orbiting"), "waypoints: [B, C], fly_by",
        ("from C to where section 4 (WaypointFollowing) begins", "coincide")),
    "one_key_in_two_spellings": (_sub("    C: {lat", "    1: {lat_deg: 47.0, lon_deg: 11.0}\n    0x1: {lat"),
                                 "0x1: {lat", ("key '0x1' is given twice",)),
    "one_waypoint_under_two_keys": (_sub("    C: {lat", "    1: {lat_deg: 47.0, lon_deg: 11.0}\n    '1': {lat"),
                                    "'1': {lat", ("waypoint '1' is defined twice",)),
    "note_as_mapping": (_sub("lon_deg: 11.20}", "lon_deg: 11.20, note: {a: 1}}"), "note: {a: 1}",
                        ("field 'note'", "got a mapping")),
}


@pytest.mark.parametrize("case", sorted(MISSION_CASES))
def test_hostile_mission_value(tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    edit, fragment, words = MISSION_CASES[case]
    text = edit(MISSION)
    path = tmp_path / f"{case}.yaml"
    # the mission is read before the system is: no system folder is needed to be refused
    refused(capsys, path, text, ["mission", "check", str(path), "--system", str(tmp_path / "no-system")],
            line_of(text, fragment), *words)


def test_binary_and_empty_missions(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "binary.yaml"
    refused(capsys, path, b"mission: {name: x}\nsections:\n  - \x00\x01\x02\n", ["mission", "check", str(path)],
            3, "binary file")
    path = tmp_path / "empty.yaml"
    refused(capsys, path, "", ["mission", "check", str(path)], 1, "a mission file is a mapping")


def test_a_byte_order_mark_is_read_as_nothing(tmp_path: Path) -> None:
    """A UTF-8 BOM (Windows editors write one) does not change the mission: the same places and sections."""
    plain, bom = tmp_path / "plain.yaml", tmp_path / "bom.yaml"
    plain.write_text(MISSION, encoding="utf-8")
    bom.write_bytes(b"\xef\xbb\xbf" + MISSION.encode("utf-8"))
    a, b = load_mission(plain), load_mission(bom)
    assert (a.name, a.waypoints, a.runways, [s.fields for s in a.sections]) == \
        (b.name, b.waypoints, b.runways, [s.fields for s in b.sections])


# -- QGroundControl plans ---------------------------------------------------------------------------
def _plan(items: list[list[object]]) -> str:
    """A plan of SimpleItems [command, lat, lon, alt], one item a line (the lines the tests count)."""
    rows = ",\n".join(json.dumps({"type": "SimpleItem", "command": c, "frame": 3, "params": [1, 0, 2000, None, la, lo, al]})
                      for c, la, lo, al in items)
    return ('{"fileType": "Plan", "mission": {"cruiseSpeed": 60,\n"plannedHomePosition": [48.35, 11.78, 450],\n'
            f'"items": [\n{rows}\n]}}}}\n')


PLAN_ITEMS: list[list[object]] = [[22, 48.36, 11.70, 300], [16, 48.30, 11.50, 1000], [16, 48.40, 11.30, 1000],
                                  [21, 48.35, 11.78, 0]]
PLAN_CASES: dict[str, tuple[Callable[[list[list[object]]], None], int, tuple[str, ...]]] = {
    "null_latitude": (lambda it: it[1].__setitem__(1, None), 5, ("mission item 1", "latitude", "got null")),
    "infinite_longitude": (lambda it: it[2].__setitem__(2, "1e999"), 6, ("1e999 is not a finite number",)),
    "huge_altitude": (lambda it: it[1].__setitem__(3, HUGE), 5, ("401 digits is too large",)),
    "text_altitude": (lambda it: it[1].__setitem__(3, "high"), 5, ("param7 altitude", "the text 'high'")),
    "command_as_list": (lambda it: it[2].__setitem__(0, [16]), 6, ("mission item 2", "MAV_CMD a list")),
    "identical_consecutive_waypoints": (lambda it: it[2].__setitem__(slice(1, 3), [48.30, 11.50]), 5,
                                        ("mission item 1 (WAYPOINT)", "from WP1 to WP2", "coincide")),
}


@pytest.mark.parametrize("case", sorted(PLAN_CASES))
def test_hostile_plan_value(tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    """A plan's errors name the plan's own line (not the line of the mission converted from it)."""
    edit, line, words = PLAN_CASES[case]
    items = [list(i) for i in PLAN_ITEMS]
    edit(items)
    text = _plan(items).replace('"1e999"', "1e999").replace(f'"{HUGE}"', HUGE)
    path = tmp_path / f"{case}.plan"
    msg = refused(capsys, path, text, ["mission", "check", str(path), "--system", str(tmp_path / "no-system")],
                  line, *words)
    assert "(converted)" not in msg


# -- engine design files (emss engine design --params FILE) -------------------------------------------
ENGINE = (ROOT / "models" / "engine" / "presets" / "larzac04_sls.json").read_text(encoding="utf-8")
ENGINE_CASES: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "number_as_text": ('"W2_kg_s": 27.64', '"W2_kg_s": "27.64"', ("'W2_kg_s'", "the text '27.64'")),
    "number_as_null": ('"BPR": 1.13', '"BPR": null', ("'BPR'", "got null")),
    "number_as_true": ('"W2_kg_s": 27.64', '"W2_kg_s": true', ("'W2_kg_s'", "got true")),
    "number_overflowing": ('"W2_kg_s": 27.64', '"W2_kg_s": 1e999', ("'W2_kg_s'", "1e999 is not a finite number")),
    "huge_integer": ('"W2_kg_s": 27.64', f'"W2_kg_s": {HUGE}', ("'W2_kg_s'", "401 digits is too large")),
    "absurd_mass_flow": ('"W2_kg_s": 27.64', '"W2_kg_s": 1e300', ("'W2_kg_s'", "outside the valid range")),
    "kind_as_list": ('"engine": "turbofan"', '"engine": ["turbofan"]', ("'engine'", "got a list")),
    "stages_not_an_integer": ('"hpc_stages": 4', '"hpc_stages": 4.5', ("'hpc_stages'", "expected an integer")),
    "bleed_name_as_list": ('"name": "cool_hpt_ngv"', '"name": ["cool"]', ("bleed 0 'name'", "got a list")),
    "key_twice": ('"alt_m": 0.0', '"alt_m": 0.0,\n  "alt_m": 1000.0', ("key 'alt_m' is given twice",)),
}


@pytest.mark.parametrize("case", sorted(ENGINE_CASES))
def test_hostile_engine_value(tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    old, new, words = ENGINE_CASES[case]
    assert old in ENGINE
    text = ENGINE.replace(old, new, 1)
    path = tmp_path / f"{case}.json"
    refused(capsys, path, text, ["engine", "design", "--params", str(path)], line_of(text, new.splitlines()[-1]),
            *words)


# -- studies (emss study cases FILE) --------------------------------------------------------------------
def _study(tmp_path: Path, extra: str) -> str:
    (tmp_path / "a").mkdir(exist_ok=True)
    (tmp_path / "b").mkdir(exist_ok=True)
    for d in ("a", "b"):
        (tmp_path / d / "m.yaml").write_text(MISSION, encoding="utf-8")
    return f"study: hostile\nsystem: {ROOT / 'ssp'}\n{extra}"


STUDY_CASES: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "algorithm_as_list": ("algorithm: [jacobi]\n", "algorithm", ("field 'algorithm'", "got a list")),
    "name_as_mapping": ("variants:\n  - {name: {a: 1}}\n", "name: {a", ("got a mapping",)),
    "grid_range_giving_nan": ("grid:\n  engine.design_BPR: {from: -1.0e+308, to: 1.0e+308, num: 3}\n"
                              "  engine.design_PR_hpc: [1.0, nan]\n", "design_PR_hpc",
                              ("field 'grid.engine.design_PR_hpc'", "'nan' is not a valid Real value")),
    "grid_value_twice": ("grid:\n  engine.design_BPR: [1, 1.0]\n", "design_BPR", ("the value 1.0 is given twice",)),
    "grid_range_of_one_value": ("grid:\n  engine.design_BPR: {from: 2, to: 2, num: 3}\n", "design_BPR",
                                ("given twice",)),
    "huge_rate": (f"rate_hz: {HUGE}\n", "rate_hz", ("401 characters is too large",)),
    "yes_as_stop_time": ("stop_time_s: yes\n", "stop_time_s", ("field 'stop_time_s'", "got true")),
    "record_every_beyond_any_run": ("record_every: 99999999999999\n", "record_every",
                                    ("field 'record_every'", "an integer from 1 to")),
    "key_as_list": ("? [study2]\n: x\n", "[study2]", ("a key is a list",)),
    "one_mission_file_twice": ("missions: [a/m.yaml, b/../a/m.yaml]\n", "missions", ("is given twice",)),
    "variable_set_twice": ("values: {engine.design_BPR: 1.5}\ngrid:\n  engine.design_BPR: [1.0, 2.0]\n",
                           "  engine.design_BPR", ("set by both values and grid",)),
    "mission_file_set_twice": ("missions: [a/m.yaml]\nvalues: {fcs.mission_file: x.yaml}\n", "missions",
                               ("set by both values and missions",)),
}


@pytest.mark.parametrize("case", sorted(STUDY_CASES))
def test_hostile_study_value(tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    extra, fragment, words = STUDY_CASES[case]
    text = _study(tmp_path, extra)
    path = tmp_path / f"{case}.yaml"
    refused(capsys, path, text, ["study", "cases", str(path)], line_of(text, fragment), *words)


def test_two_missions_of_one_name_are_two_cases(tmp_path: Path) -> None:
    """Two mission files named m.yaml in two folders: two missions of two names, each its own file (before,
    the second replaced the first without a word)."""
    path = tmp_path / "s.yaml"
    path.write_text(_study(tmp_path, "missions: [a/m.yaml, b/m.yaml]\n"), encoding="utf-8")
    missions = load_study(path).missions
    assert [p for _, p in missions] == [(tmp_path / "a" / "m.yaml").resolve(), (tmp_path / "b" / "m.yaml").resolve()]
    assert len({n for n, _ in missions}) == 2


def test_a_grid_range_over_the_whole_float_line_is_finite(tmp_path: Path) -> None:
    """from -1e308 to 1e308 in 3 points: -1e308, 0, 1e308 (b - a overflowed to inf, the middle point was NaN)."""
    path = tmp_path / "s.yaml"
    path.write_text(_study(tmp_path, "grid:\n  engine.design_BPR: {from: -1.0e+308, to: 1.0e+308, num: 3}\n"),
                    encoding="utf-8")
    assert load_study(path).grid == (("engine.design_BPR", (-1e308, 0.0, 1e308)),)


# -- the README's two failures ----------------------------------------------------------------------
def _fmu_start(fmu: Path, name: str) -> float:
    with zipfile.ZipFile(fmu) as z:
        root = ElementTree.fromstring(z.read("modelDescription.xml"))
    sv = next(v for v in root.iter("ScalarVariable") if v.attrib["name"] == name)
    return float(next(c.attrib["start"] for c in sv if "start" in c.attrib))


def test_design_override_on_a_preset_sized_by_thrust(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    """reference_study gives Fn_target_N and no W2_kg_s: with design_override the check takes each design value
    as the engine FMU does (set, else the FMU's start value), read here from the FMU's modelDescription.xml;
    the pre-run hook (README's second example) warns, it does not fail."""
    from openemss.report.mission_check import pre_run, setup_from_system

    comps = {"fcs": project_fmus["fcs"], "engine": project_fmus["engine"], "airframe": project_fmus["airframe"]}
    mission = tmp_path / "m.yaml"
    shutil.copy(ROOT / "missions" / "munich.yaml", mission)
    bound = {"engine.preset": "reference_study", "engine.design_override": True, "fcs.mission_file": str(mission),
             "engine.design_BPR": 2.0}
    setup = setup_from_system(comps, bound)
    assert setup is not None and setup.engine_label == "reference_study with design_override"
    assert setup.engine.Fn_target_N is None and setup.engine.BPR == 2.0
    assert setup.engine.W2_kg_s == _fmu_start(project_fmus["engine"], "design_W2_kg_s")
    assert setup.engine.PR_hpc == _fmu_start(project_fmus["engine"], "design_PR_hpc")
    lines = pre_run(comps, bound)
    assert all(ln.startswith("mission check: ") for ln in lines)


@pytest.fixture(scope="module")
def system(project_system: Path) -> Path:
    """The project's system with this session's FMUs (conftest.project_system)."""
    return project_system


@pytest.mark.parametrize("value", ["nan", "1e999", "yes"])
def test_mission_check_reads_set_values_as_emss_run_does(system: Path, tmp_path: Path, value: str,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    """``--set airframe.fuel0_kg=nan`` was taken by Python's float: a NaN take-off mass, no word."""
    mission = tmp_path / "m.yaml"
    mission.write_text(MISSION, encoding="utf-8")
    rc, err = run(capsys, "mission", "check", str(mission), "--system", str(system), "--set",
                  f"airframe.fuel0_kg={value}")
    err = [ln for ln in err if not ln.startswith(("built:", "up to"))]
    assert rc == 2 and len(err) == 1 and "internal error" not in err[0], err
    assert "--set" in err[0] and f"airframe.fuel0_kg={value}" in err[0] and "not a valid Real value" in err[0], err
