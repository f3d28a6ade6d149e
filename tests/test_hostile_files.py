"""The hostile corpus, files: missions, scenarios, studies and SSP files written by a hostile user.

Each case builds its file here and asserts the reliability rules of issue 15: one clear line
naming the file and line (or the element), never a silent wrong value, never unbounded work.
Independent references: the line numbers are those of the text the test writes, counted here.
"""
from __future__ import annotations

import json
import tracemalloc
import zipfile
from collections.abc import Callable
from pathlib import Path

import pytest

from openemss.models.mission.mission import load_mission
from openemss.models.infra import safe_yaml
from openemss.models.mission.errors import MissionError
from openemss.orchestrator.errors import EmssError, SystemStructureError
from openemss.orchestrator.scenarios.manipulators import ScenarioError, load_scenario
from openemss.orchestrator.ssp.read import load_system
from openemss.study.spec import StudyError, load_study
from systems import GAIN_CONNECTORS, Comp, write_system


def _peak_bytes(fn: Callable[[], object]) -> tuple[BaseException | None, int]:
    """Call ``fn``; return the exception it raised (or None) and the peak of memory Python allocated
    meanwhile [bytes]: a refusal that expanded an alias bomb or built a billion-point grid would have
    allocated gigabytes (the bomb took 4.5 GB), one that refused up front a few megabytes."""
    tracemalloc.start()
    try:
        fn()
        err: BaseException | None = None
    except BaseException as exc:  # noqa: BLE001 - returned to the caller, which asserts its type
        err = exc
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return err, peak


_BOUND_BYTES = 64 * 2 ** 20  # refused before anything big is built

MISSION = """mission: {name: hostile}
places:
  waypoints:
    A: {lat_deg: 48.0, lon_deg: 11.0}
    B: {lat_deg: 48.1, lon_deg: 11.2}
sections:
  - type: WaypointFollowing
    waypoints: [A, B]
    altitude_m: 1000
    speed: {mach: 0.4}
"""

#: An alias bomb: nine aliases per level, eight levels (9^8 = 43 million nodes when expanded).
BOMB = "".join(f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 9 if i else ["x"] * 9) + "]\n" for i in range(8))


def line_of(text: str, fragment: str, nth: int = 1) -> int:
    """1-based line of the nth line of ``text`` containing ``fragment`` (the independent reference)."""
    hits = [i for i, ln in enumerate(text.splitlines(), start=1) if fragment in ln]
    return hits[nth - 1]


def one_line(exc: BaseException, *fragments: str) -> str:
    msg = str(exc)
    assert "\n" not in msg and "Traceback" not in msg and "internal error" not in msg, msg
    for f in fragments:
        assert f in msg, (f, msg)
    return msg


# -- missions ------------------------------------------------------------------------------------
MISSION_CASES: dict[str, tuple[Callable[[str], str | bytes], Callable[[str], list[str]]]] = {
    # a second WP definition would silently reroute the mission
    "duplicate_waypoint": (lambda m: m.replace("    B: {lat_deg: 48.1", "    A: {lat_deg: 47.0, lon_deg: 9.0}\n    B: "
                                                                          "{lat_deg: 48.1"),
                           lambda t: [f":{line_of(t, 'A: {lat_deg: 47.0')}:", "key 'A' is given twice",
                                      f"first at line {line_of(t, 'A: {lat_deg: 48.0')}"]),
    "duplicate_field_in_section": (lambda m: m + "    altitude_m: 3000\n",
                                   lambda t: [f":{line_of(t, 'altitude_m: 3000')}:", "key 'altitude_m' is given twice",
                                              f"first at line {line_of(t, 'altitude_m: 1000')}"]),
    "duplicate_top_level": (lambda m: m + "mission: {name: other}\n",
                            lambda t: ["key 'mission' is given twice", "first at line 1"]),
    "nan_altitude": (lambda m: m.replace("altitude_m: 1000", "altitude_m: .nan"),
                     lambda t: [f":{line_of(t, '.nan')}:", "not a finite number"]),
    "inf_latitude": (lambda m: m.replace("lat_deg: 48.0", "lat_deg: -.inf"),
                     lambda t: [f":{line_of(t, '-.inf')}:", "not a finite number"]),
    "alias_bomb": (lambda m: m + "x_bomb:\n" + "".join("  " + ln + "\n" for ln in BOMB.splitlines()),
                   lambda t: ["expands to more than", "aliases included"]),
    "recursive_alias": (lambda m: m.replace("waypoints: [A, B]", "waypoints: &w [A, *w]"),
                        lambda t: ["recursive alias"]),
    "not_utf8": (lambda m: m.replace("hostile", "hostile\xff").encode("latin-1"),
                 lambda t: [":1:", "not UTF-8", "0xff"]),
    "python_tag": (lambda m: m.replace("{name: hostile}", "!!python/object/apply:os.system [echo]"),
                   lambda t: [":1:", "not valid YAML"]),
    "oversize": (lambda m: m + "#" * (safe_yaml.MAX_BYTES + 1) + "\n", lambda t: ["larger than", "refused"]),
}


@pytest.mark.parametrize("case", sorted(MISSION_CASES))
def test_hostile_mission(tmp_path: Path, case: str) -> None:
    make, expect = MISSION_CASES[case]
    content = make(MISSION)
    path = tmp_path / f"{case}.yaml"
    if isinstance(content, bytes):
        path.write_bytes(content)
        text = content.decode("latin-1")
    else:
        path.write_text(content, encoding="utf-8")
        text = content
    err, peak = _peak_bytes(lambda: load_mission(path))
    assert isinstance(err, MissionError), err
    assert peak < _BOUND_BYTES  # refused, not expanded
    msg = one_line(err, str(path), *expect(text))
    assert msg.startswith(f"{path}:") or msg.startswith(str(path))


def test_hostile_plan_with_nan(tmp_path: Path) -> None:
    path = tmp_path / "nan.plan"
    path.write_text('{"fileType": "Plan", "mission": {"items": [{"params": [NaN, 0, 0, 0, 48.0, 11.0, 500]}]}}')
    with pytest.raises(MissionError) as exc:
        load_mission(path)
    one_line(exc.value, str(path), "NaN is not a finite number")


def test_the_good_mission_still_loads(tmp_path: Path) -> None:
    path = tmp_path / "good.yaml"
    path.write_text(MISSION, encoding="utf-8")
    assert [s.type for s in load_mission(path).sections] == ["WaypointFollowing"]


WEATHER = "wind:\n  layers:\n    - {alt_m: 450.0, from_deg: 240.0, speed_kt: 10.0}\nturbulence: {severity: light, seed: 1}\n"
WEATHER_CASES: dict[str, tuple[str, list[str]]] = {
    "duplicate_layer_field": (WEATHER.replace("speed_kt: 10.0}", "speed_kt: 10.0, speed_kt: 90.0}"),
                              [":3:", "key 'speed_kt' is given twice"]),
    "nan_speed": (WEATHER.replace("10.0", ".nan"), [":3:", "not a finite number"]),
    "alias_bomb": (WEATHER + BOMB.replace("l", "x_l"), ["expands to more than"]),
}


@pytest.mark.parametrize("case", sorted(WEATHER_CASES))
def test_hostile_weather(tmp_path: Path, case: str) -> None:
    from openemss.models.mission.weather import load_weather

    text, fragments = WEATHER_CASES[case]
    path = tmp_path / "weather.yaml"
    path.write_text(text, encoding="utf-8")
    err, peak = _peak_bytes(lambda: load_weather(path))
    assert isinstance(err, MissionError), err
    assert peak < _BOUND_BYTES
    one_line(err, str(path), *fragments)


# -- scenarios -----------------------------------------------------------------------------------
SCENARIO = "events:\n  - at: 1.0\n    set: {a.u_real: 2.0}\n"
SCENARIO_CASES: dict[str, tuple[str, list[str]]] = {
    "at_nan": ("events:\n  - at: .nan\n    set: {a.u_real: 2.0}\n", [":2:", "'.nan' is not a finite number"]),
    "at_inf": ("events:\n  - at: .inf\n    set: {a.u_real: 2.0}\n", [":2:", "not a finite number"]),
    "at_twice": ("events:\n  - at: 1.0\n    set: {a.u_real: 2.0}\n    at: 5.0\n",
                 [":4:", "key 'at' is given twice", "first at line 2"]),
    "variable_twice": ("events:\n  - at: 1.0\n    set:\n      a.u_real: 2.0\n      a.u_real: 3.0\n",
                       [":5:", "key 'a.u_real' is given twice", "first at line 4"]),
    "value_nan": ("events:\n  - at: 1.0\n    set: {a.u_real: .NaN}\n", [":3:", "not a finite number"]),
    "ramp_from_nan": ("events:\n  - from: .nan\n    to: 2.0\n    ramp: {a.u_real: [0, 1]}\n",
                      [":2:", "not a finite number"]),
    "ramp_values_inf": ("events:\n  - from: 1.0\n    to: 2.0\n    ramp: {a.u_real: [0, .inf]}\n",
                        [":4:", "not a finite number"]),
    "after_nan": ("events:\n  - when: a.y_real > 1\n    after: .nan\n    set: {a.u_real: 1}\n",
                  [":3:", "not a finite number"]),
    "when_nan": ("events:\n  - when: a.y_real > nan\n    set: {a.u_real: 1}\n", [":2:", "finite number"]),
    "when_inf": ("events:\n  - when: a.y_real < inf\n    set: {a.u_real: 1}\n", [":2:", "finite number"]),
    "alias_bomb": (BOMB + SCENARIO, ["expands to more than"]),
    "events_twice": (SCENARIO + "events: []\n", [":4:", "key 'events' is given twice"]),
}


@pytest.mark.parametrize("case", sorted(SCENARIO_CASES))
def test_hostile_scenario(tmp_path: Path, case: str) -> None:
    text, fragments = SCENARIO_CASES[case]
    path = tmp_path / f"{case}.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as exc:
        load_scenario(path)
    one_line(exc.value, str(path), *fragments)


def test_hostile_scenario_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin.yaml"
    path.write_bytes(b"# \xe9v\xe9nements\nevents: []\n")
    with pytest.raises(ScenarioError) as exc:
        load_scenario(path)
    one_line(exc.value, f"{path}:1:", "not UTF-8", "0xe9")


# -- studies -------------------------------------------------------------------------------------
def study_text(system: Path, body: str) -> str:
    return f"study: hostile\nsystem: {system}\nstop_time_s: 1.0\n{body}"


STUDY_CASES: dict[str, tuple[str, list[str]]] = {
    "variant_dotdot": ("variants:\n  - {name: '..', values: {a.k: 1.0}}\n", ["'..'", "one path component"]),
    "variant_dot": ("variants:\n  - {name: '.', values: {a.k: 1.0}}\n", ["'.'", "one path component"]),
    "mission_dotdot": ("missions: {'..': m.yaml}\n", ["'..'", "one path component"]),
    "scenario_dotdot": ("scenarios: {'..': null}\n", ["'..'", "one path component"]),
    "grid_num_huge": ("grid:\n  a.k: {from: 0, to: 1, num: 1000000000}\n", [":5:", "num", "from 1 to 100000"]),
    "grid_product_huge": ("grid:\n  a.k: {from: 0, to: 1, num: 1000}\n  b.k: {from: 0, to: 1, num: 1000}\n",
                          ["more than 100000 grid points"]),
    "values_nan": ("values: {a.k: .nan}\n", [":4:", "not a finite number"]),
    "stop_time_twice": ("stop_time_s: 2.0\n", [":4:", "key 'stop_time_s' is given twice", "first at line 3"]),
    "variant_key_twice": ("variants:\n  - name: x\n    values: {a.k: 1.0}\n    name: y\n",
                          [":7:", "key 'name' is given twice", "first at line 5"]),
    "alias_bomb": (BOMB.replace("l", "x_l"), ["expands to more than"]),
}


@pytest.mark.parametrize("case", sorted(STUDY_CASES))
def test_hostile_study(tmp_path: Path, case: str) -> None:
    body, fragments = STUDY_CASES[case]
    system = tmp_path / "sys"
    system.mkdir()
    (system / "SystemStructure.ssd").write_text("<x/>")
    (tmp_path / "m.yaml").write_text(MISSION)
    path = tmp_path / "study.yaml"
    path.write_text(study_text(system, body), encoding="utf-8")
    err, peak = _peak_bytes(lambda: load_study(path))
    assert isinstance(err, StudyError), err
    assert peak < _BOUND_BYTES  # refused before a billion points are built
    one_line(err, str(path), *fragments)


# -- SSD, SSV, SSM, SSP --------------------------------------------------------------------------
def gain_system(folder: Path, fmu_dir: Path) -> Path:
    write_system(folder, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS), Comp("b", "Gain.fmu", GAIN_CONNECTORS)],
                 [("a.y_real", "b.u_real")], stop_time=1.0)
    return folder


def _edit(ssd: Path, old: str, new: str) -> str:
    text = ssd.read_text()
    assert old in text, old
    text = text.replace(old, new, 1)
    ssd.write_text(text)
    return text


SSV_NS = 'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"'
SSD_CASES: dict[str, tuple[str, str, list[str]]] = {
    "xxe_entity": ('<?xml version="1.0" encoding="UTF-8"?>\n',
                   '<?xml version="1.0" encoding="UTF-8"?>\n<!DOCTYPE x [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>\n',
                   ["DOCTYPE", "not allowed", "xxe"]),
    "billion_laughs": ('<?xml version="1.0" encoding="UTF-8"?>\n',
                       '<?xml version="1.0" encoding="UTF-8"?>\n'
                       '<!DOCTYPE x [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;&a;">]>\n',
                       ["DOCTYPE", "not allowed"]),
    "start_time_nan": ('startTime="0"', 'startTime="NaN"', ["startTime='NaN'", "finite number"]),
    "stop_time_inf": ('stopTime="1.0"', 'stopTime="INF"', ["stopTime='INF'", "finite number"]),
    "connection_factor_nan": ('endElement="b" endConnector="u_real"/>',
                              'endElement="b" endConnector="u_real"><ssc:LinearTransformation factor="NaN"/>'
                              '</ssd:Connection>', ["LinearTransformation factor='NaN'", "finite number"]),
    "connection_offset_inf": ('endElement="b" endConnector="u_real"/>',
                              'endElement="b" endConnector="u_real"><ssc:LinearTransformation offset="-INF"/>'
                              '</ssd:Connection>', ["LinearTransformation offset='-INF'", "finite number"]),
    "unit_factor_zero": ('  </ssd:System>\n', '  </ssd:System>\n  <ssd:Units><ssc:Unit name="zero"><ssc:BaseUnit m="1" '
                                             'factor="0"/></ssc:Unit></ssd:Units>\n',
                         ["BaseUnit factor='0'", "other than 0"]),
    "unit_offset_nan": ('  </ssd:System>\n', '  </ssd:System>\n  <ssd:Units><ssc:Unit name="odd"><ssc:BaseUnit K="1" '
                                            'offset="NaN"/></ssc:Unit></ssd:Units>\n',
                        ["BaseUnit offset='NaN'", "finite number"]),
    "inline_parameter_nan": ('<ssd:Connectors>\n          <ssd:Connector name="u_real"',
                             '<ssd:Connectors>\n          <ssd:Connector name="u_real"', ["finite number"]),
}


@pytest.mark.parametrize("case", sorted(SSD_CASES))
def test_hostile_ssd(tmp_path: Path, fmu_dir: Path, case: str) -> None:
    old, new, fragments = SSD_CASES[case]
    folder = gain_system(tmp_path / "sys", fmu_dir)
    ssd = folder / "SystemStructure.ssd"
    if case == "inline_parameter_nan":
        write_system(folder, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS, {"k": 1.5})], [], stop_time=1.0)
        text = ssd.read_text().replace('value="1.5"', 'value="NaN"')
        ssd.write_text(text)
        fragments = [*fragments, "Real value='NaN'"]
    else:
        text = _edit(ssd, old, new)
    with pytest.raises(SystemStructureError) as exc:
        load_system(folder)
    msg = one_line(exc.value, str(ssd), *fragments)
    if case not in ("xxe_entity", "billion_laughs"):
        marker = {"unit_factor_zero": 'factor="0"', "unit_offset_nan": 'offset="NaN"',
                  "inline_parameter_nan": 'value="NaN"'}.get(case, new.split('"')[0].split()[-1])
        assert f"{ssd}:{line_of(text, marker)}:" in msg, (msg, marker)
    assert "root:" not in msg  # nothing of /etc/passwd


@pytest.mark.parametrize("value", ["NaN", "-INF"])
def test_hostile_ssv_value(tmp_path: Path, fmu_dir: Path, value: str) -> None:
    from openemss.orchestrator.ssp.system import bind_system

    folder = gain_system(tmp_path / "sys", fmu_dir)
    ssv = tmp_path / "p.ssv"
    ssv.write_text(f'<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet {SSV_NS} version="1.0" name="p">'
                   f'<ssv:Parameters>\n<ssv:Parameter name="a.k"><ssv:Real value="{value}"/></ssv:Parameter>'
                   '</ssv:Parameters></ssv:ParameterSet>\n')
    with pytest.raises(SystemStructureError) as exc:
        bind_system(load_system(folder), [ssv])
    one_line(exc.value, f"{ssv}:3:", f"Real value='{value}'", "finite number")


def test_hostile_ssm_transformation(tmp_path: Path, fmu_dir: Path) -> None:
    folder = gain_system(tmp_path / "sys", fmu_dir)
    (folder / "p.ssv").write_text(f'<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet {SSV_NS} version="1.0" '
                                  'name="p"><ssv:Parameters><ssv:Parameter name="gain"><ssv:Real value="2"/>'
                                  '</ssv:Parameter></ssv:Parameters></ssv:ParameterSet>\n')
    (folder / "p.ssm").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<ssm:ParameterMapping '
        'xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping" '
        'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0">\n'
        '<ssm:MappingEntry source="gain" target="k">\n<ssc:LinearTransformation factor="NaN"/></ssm:MappingEntry>'
        '</ssm:ParameterMapping>\n')
    ssd = folder / "SystemStructure.ssd"
    _edit(ssd, '<ssd:Component name="a" source="resources/Gain.fmu">',
          '<ssd:Component name="a" source="resources/Gain.fmu"><!-- bound below -->')
    _edit(ssd, '</ssd:Connectors>\n      </ssd:Component>',
          '</ssd:Connectors>\n        <ssd:ParameterBindings><ssd:ParameterBinding source="p.ssv">'
          '<ssd:ParameterMapping source="p.ssm"/></ssd:ParameterBinding></ssd:ParameterBindings>\n'
          '      </ssd:Component>')
    with pytest.raises(SystemStructureError) as exc:
        load_system(folder)
    one_line(exc.value, f"{folder / 'p.ssm'}:4:", "factor='NaN'")


def _ssp(tmp_path: Path, fmu_dir: Path, extra: Callable[[zipfile.ZipFile], None]) -> Path:
    folder = gain_system(tmp_path / "sys", fmu_dir)
    archive = tmp_path / "system.ssp"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as z:
        for f in folder.rglob("*"):
            if f.is_file():
                z.write(f, f.relative_to(folder).as_posix())
        extra(z)
    return archive


def test_hostile_ssp_zip_bomb(tmp_path: Path, fmu_dir: Path) -> None:
    archive = _ssp(tmp_path, fmu_dir, lambda z: z.writestr("resources/zeros.bin", bytes(8 * 1024 ** 2)))
    assert archive.stat().st_size < 1024 ** 2  # 8 MiB of zeros compress to a few KiB
    with pytest.raises(SystemStructureError) as exc:
        load_system(archive)
    one_line(exc.value, f"{archive}!resources/zeros.bin", "zip bomb")


def test_hostile_ssp_too_many_entries(tmp_path: Path, fmu_dir: Path) -> None:
    def many(z: zipfile.ZipFile) -> None:
        for i in range(10_001):
            z.writestr(f"resources/e{i}", b"")

    archive = _ssp(tmp_path, fmu_dir, many)
    with pytest.raises(SystemStructureError) as exc:
        load_system(archive)
    one_line(exc.value, str(archive), "entries, more than 10000")


def test_hostile_ssp_entry_outside(tmp_path: Path, fmu_dir: Path) -> None:
    archive = _ssp(tmp_path, fmu_dir, lambda z: z.writestr("../../evil.txt", b"x"))
    with pytest.raises(SystemStructureError) as exc:
        load_system(archive)
    one_line(exc.value, "unsafe archive entry")
    assert not (tmp_path.parent / "evil.txt").exists()


def test_hostile_fmu_zip_bomb(tmp_path: Path, fmu_dir: Path) -> None:
    """A component's FMU that is a zip bomb is refused before it is extracted, naming the component: when
    the system is bound, and (an FMU replaced after binding) when it is instantiated."""
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.ssp.system import bind_system

    folder = gain_system(tmp_path / "sys", fmu_dir)
    fmu = folder / "resources" / "Gain.fmu"
    bound = bind_system(load_system(folder))
    with zipfile.ZipFile(fmu, "a", zipfile.ZIP_DEFLATED) as z:
        z.writestr("resources/zeros.bin", bytes(8 * 1024 ** 2))
    with pytest.raises(SystemStructureError) as bind_exc:
        bind_system(load_system(folder))
    one_line(bind_exc.value, f"{fmu}!resources/zeros.bin", "component 'a'", "zip bomb")
    ex = Execution(bound)
    with pytest.raises(EmssError) as exc:
        ex.run(0.1)
    one_line(exc.value, "component 'a'", "fmi2Instantiate", "zip bomb")


def test_safe_yaml_accepts_what_it_should() -> None:
    """Anchors used a few times, finite numbers, repeated keys in different mappings are fine."""
    text = "base: &b {x: 1.5, y: [1, 2]}\none: *b\ntwo: {x: 2, y: -3.0e+2}\n"
    assert safe_yaml.load(text, "t.yaml") == {"base": {"x": 1.5, "y": [1, 2]}, "one": {"x": 1.5, "y": [1, 2]},
                                              "two": {"x": 2, "y": -300.0}}
    assert json.dumps(safe_yaml.load("a: 1\n", "t.yaml")) == '{"a": 1}'
