"""The models' one parameter mechanism (models/infra/params.py): parameter files read against frozen
dataclasses with file:line errors, and the FMU parameters generated from them with their ranges.

The files are compared with themselves read by plain PyYAML (an independent reader), the FMUs' ranges
with the files, and every error case names the line the test wrote the fault on.
"""
from __future__ import annotations

import dataclasses
import json
import math
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest
import yaml

from openemss.models.airframe.settings import PARAMETER_SETS as AIRFRAME_SETS
from openemss.models.electric.params import parameter_sets
from openemss.models.engine.engine_signals import PARAMETER_SETS
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.settings import engine_set
from openemss.models.infra.params import ParameterError, parameter_set_from_text

ROOT = Path(__file__).resolve().parents[2]


@dataclasses.dataclass(frozen=True)
class _Set:
    gain: float
    count: int
    enabled: bool


GOOD = """\
demo:
  source: "a test"
  gain: {value: 2.0, unit: 1/s, min: 0.0, max: 10.0, note: "a gain"}
  count: {value: 3, unit: "1", min: 1, max: 5, note: "a count"}
  enabled: {value: true, note: "a switch"}
"""


def _spec(text: str = GOOD):  # type: ignore[no-untyped-def]
    return parameter_set_from_text(_Set, text, "demo.yaml", "demo")


def test_a_section_builds_its_frozen_set_with_units_ranges_and_sources() -> None:
    spec = _spec()
    p = spec.make()
    assert p == _Set(2.0, 3, True) and isinstance(p.gain, float) and isinstance(p.count, int)
    gain = spec.param("gain")
    assert (gain.unit, gain.min, gain.max, gain.note, gain.source, gain.where) == \
        ("1/s", 0.0, 10.0, "a gain", "a test", "demo.yaml:3")
    assert spec.make(gain=4) == _Set(4.0, 3, True)
    assert spec.replace(p, count=5.0).count == 5  # an FMI Real that is a whole number
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.gain = 1.0  # type: ignore[misc]


@pytest.mark.parametrize("text, message", [
    (GOOD.replace("value: 2.0", "value: 20.0"), r"demo.yaml:3: demo.gain: value 20.0 outside the allowed range"),
    (GOOD.replace("value: 3,", "value: 3.5,"), r"demo.yaml:4: demo.count: expected an integer from 1 to 5"),
    (GOOD.replace("value: true", "value: 1"), r"demo.yaml:5: demo.enabled: expected true or false"),
    (GOOD.replace("value: 2.0", "value: '2.0'"), r"demo.yaml:3: demo.gain: .*without quotes"),
    (GOOD.replace("  enabled: {value: true, note: \"a switch\"}\n", ""), r"demo.yaml:2: section 'demo' lacks "
                                                                           r"parameter\(s\) enabled of _Set"),
    (GOOD + "  on: {value: true}\n", r"unknown parameter true \(YAML reads yes/no/on/off as true/false\)"),
    (GOOD + "  extra: {value: 1.0}\n", r"demo.yaml:6: unknown parameter 'extra' in section 'demo'"),
    (GOOD.replace("min: 0.0, max: 10.0", "min: 11.0, max: 10.0"), r"demo.yaml:3: demo.gain: min 11.0 is above max"),
    (GOOD.replace("note: \"a gain\"", "nite: 1"), r"demo.yaml:3: demo.gain: unknown key 'nite'"),
    (GOOD.replace("  gain: {", "  gain: {value: 1.0}\n  gain: {"), r"demo.yaml:4: key 'gain' is given twice"),
    (GOOD.replace("demo:", "other:"), r"demo.yaml:1: no section 'demo' \(sections: other\)"),
    (GOOD.replace("max: 10.0", "max: .inf"), r"demo.yaml:3: .*not a finite number"),
    (GOOD.replace("  enabled: {value: true, ", "  enabled: {value: true, min: 0, "),
     r"demo.yaml:5: demo.enabled: a Boolean has no min"),
])
def test_a_bad_file_is_one_line_naming_its_line(text: str, message: str) -> None:
    with pytest.raises(ParameterError, match=message) as e:
        _spec(text)
    assert "\n" not in str(e.value)


def test_a_value_set_later_is_checked_against_the_files_range() -> None:
    spec = _spec()
    with pytest.raises(ParameterError, match=r"fmu.gain: value -1.0 outside the allowed range \[0.0, 10.0\] 1/s "
                                             r"\(see demo.yaml:3\)"):
        spec.check("gain", -1.0, "fmu")
    with pytest.raises(ParameterError, match="unknown parameter 'gains'; _Set has: gain, count, enabled"):
        spec.make(gains=1.0)


def test_signal_rows_carry_the_range_the_unit_and_the_note() -> None:
    rows = {r.name: r for r in _spec().signals("demo.", starts={"demo.gain": 5.0})}
    g, c, o = rows["demo.gain"], rows["demo.count"], rows["demo.enabled"]
    assert (g.type, g.unit, g.start, g.min, g.max, g.variability) == ("Real", "1/s", 5.0, 0.0, 10.0, "tunable")
    assert (c.type, c.min, c.max, o.type, o.min, o.max) == ("Integer", 1.0, 5.0, "Boolean", None, None)
    assert g.description.startswith("a gain (demo.yaml)")
    with pytest.raises(ParameterError, match="outside the allowed range"):
        _spec().signals("demo.", starts={"demo.gain": 50.0})


def test_the_engine_file_fills_its_sets_and_refuses_out_of_range_with_the_engines_error() -> None:
    doc = json.loads((ROOT / "models/engine/data/engine.json").read_text())
    for section, (cls, _) in PARAMETER_SETS.items():
        spec = engine_set(cls, section)
        made = spec.make()
        for f in dataclasses.fields(cls):
            assert getattr(made, f.name) == doc[section][f.name]["value"], (section, f.name)
    with pytest.raises(OutOfRangeError, match=r"limits.N1_max_pct: value 500.0 outside .*engine.json:\d+"):
        engine_set(PARAMETER_SETS["limits"][0], "limits").make(N1_max_pct=500.0)


def _ranges(fmu: Path) -> dict[str, tuple[str | None, str | None, str]]:
    with zipfile.ZipFile(fmu) as z:
        root = ElementTree.fromstring(z.read("modelDescription.xml"))
    out = {}
    for sv in root.iter("ScalarVariable"):
        t = next(iter(sv))
        out[sv.get("name")] = (t.get("min"), t.get("max"), t.tag)
    return out


def _file_entries(path: Path, prefix: dict[str, str] | None = None, sections: tuple[str, ...] | None = None) \
        -> dict[str, dict]:
    """Every entry of a parameter file read by plain PyYAML, under its FMU name."""
    doc = json.loads(path.read_text()) if path.suffix == ".json" else yaml.safe_load(path.read_text())
    out = {}
    for section, block in doc.items():
        if section.startswith("_") or (sections is not None and section not in sections):
            continue
        for key, e in block.items():
            if key != "source":
                pre = prefix.get(section, "") if prefix is not None else f"{section}."
                out[pre + key] = e
    return out


@pytest.mark.parametrize("fmu_name, entries", [
    ("engine", lambda: _file_entries(ROOT / "models/engine/data/engine.json",
                                     {s: p for s, (_, p) in PARAMETER_SETS.items()})),
    ("electric", lambda: _file_entries(ROOT / "models/electric/data/electric.yaml", sections=tuple(parameter_sets()))),
    ("airframe", lambda: _file_entries(ROOT / "models/airframe/data/airframe.yaml", dict.fromkeys(AIRFRAME_SETS, ""))),
    ("fcs", lambda: {k: e for f in sorted((ROOT / "models/fcs/data").glob("*.yaml")) for k, e in _file_entries(f).items()}),
])
def test_every_fmu_parameter_of_a_file_has_its_range_in_the_model_description(
        project_fmus: dict[str, Path], fmu_name: str, entries) -> None:  # type: ignore[no-untyped-def]
    if fmu_name not in project_fmus:
        pytest.skip(f"no {fmu_name} FMU built")
    ranges = _ranges(project_fmus[fmu_name])
    want = entries()
    assert want
    for name, e in want.items():
        assert name in ranges, name
        lo, hi, tag = ranges[name]
        if isinstance(e["value"], bool | str):
            assert (lo, hi) == (None, None) and tag == ("Boolean" if isinstance(e["value"], bool) else "String"), name
            continue
        for got, key in ((lo, "min"), (hi, "max")):
            if key in e:
                assert got is not None and math.isclose(float(got), float(e[key]), rel_tol=0, abs_tol=0), (name, key)
            else:
                assert got is None, (name, key)


def test_a_json_parameter_file_names_its_lines_too() -> None:
    text = ('{\n  "_about": "a test",\n  "demo": {\n    "source": "a test",\n'
            '    "gain": {"value": 2.0, "unit": "1/s", "min": 0.0, "max": 10.0},\n'
            '    "count": {"value": 30, "min": 1, "max": 5},\n    "enabled": {"value": false}\n  }\n}\n')
    with pytest.raises(ParameterError, match=r"demo.json:6: demo.count: value 30 outside the allowed range"):
        parameter_set_from_text(_Set, text, "demo.json", "demo")
    ok = parameter_set_from_text(_Set, text.replace('"value": 30', '"value": 3'), "demo.json", "demo")
    assert ok.make() == _Set(2.0, 3, False) and ok.param("gain").where == "demo.json:5"
    with pytest.raises(ParameterError, match=r"demo.json:1: no section 'other' \(sections: demo\)"):
        parameter_set_from_text(_Set, text, "demo.json", "other")


def test_an_optional_value_is_computed_by_the_model() -> None:
    @dataclasses.dataclass(frozen=True)
    class Start:
        lat0_deg: float | None

    text = "start:\n  lat0_deg: {value: null, unit: deg, min: -90.0, max: 90.0}\n"
    spec = parameter_set_from_text(Start, text, "s.yaml", "start")
    assert spec.make() == Start(None) and spec.signals()[0].start is None and spec.make(lat0_deg=48) == Start(48.0)
    with pytest.raises(ParameterError, match=r"s.yaml:2: start.lat0_deg: value 91 outside"):
        parameter_set_from_text(Start, text.replace("null", "91"), "s.yaml", "start")
    with pytest.raises(ParameterError, match=r"s.yaml:2: start.x: expected a finite number, got null"):
        parameter_set_from_text(_X, "start:\n  x: {value: null}\n", "s.yaml", "start")  # not optional


@dataclasses.dataclass(frozen=True)
class _X:
    x: float


def test_a_set_collected_from_fmu_names_names_the_fmu_variable() -> None:
    values = {"demo_gain": 3.0, "demo_count": 2.0, "demo_enabled": False}
    assert _spec().collect(values.__getitem__, "demo_", "fmu") == _Set(3.0, 2, False)
    values["demo_gain"] = 11.0
    with pytest.raises(ParameterError, match=r"^fmu.demo_gain: value 11.0 outside the allowed range \[0.0, 10.0\]"):
        _spec().collect(values.__getitem__, "demo_", "fmu")
