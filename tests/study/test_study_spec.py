"""Study files: cases expanded from variants, grids, missions and scenarios; bad files refused in one line."""
from __future__ import annotations

from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main
from openemss.study.plan import expand_cases
from openemss.study.spec import StudyError, load_study

ROOT = Path(__file__).resolve().parents[2]
OSC = ROOT / "examples" / "oscillator"


def study(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "s.yaml"
    p.write_text(text, encoding="utf-8")
    return p


def test_cases_are_every_combination_typed_as_the_fmu_variables(tmp_path: Path, oscillator: Path) -> None:
    (tmp_path / "sc.yaml").write_text("events: []\n", encoding="utf-8")
    p = study(tmp_path, f"study: combos\nsystem: {oscillator}\nstop_time_s: 1\n"
                        "variants:\n  - {name: a, values: {mass2.m2_kg: 3}}\n  - {name: b}\n"
                        "grid:\n  mass1.m1_kg: [1, 2.5]\n  mass1.k1_N_m: {from: 10, to: 30, num: 3}\n"
                        "scenarios: {plain: null, sc: sc.yaml}\n")
    cases = expand_cases(load_study(p))
    assert len(cases) == 2 * 2 * 3 * 2
    assert len({c.name for c in cases}) == len(cases) and len({c.digest for c in cases}) == len(cases)
    first = cases[0]
    assert first.name == "a-m1_kg=1-k1_N_m=10-plain"
    values = dict(first.values)
    # YAML integers become Reals where the FMU variable is Real
    assert values == {"mass2.m2_kg": 3.0, "mass1.m1_kg": 1.0, "mass1.k1_N_m": 10.0}
    assert all(isinstance(v, float) for v in values.values())
    assert [dict(c.values)["mass1.k1_N_m"] for c in cases[:6:2]] == [10.0, 20.0, 30.0]
    assert cases[1].scenario == str((tmp_path / "sc.yaml").resolve()) and cases[0].scenario is None


def test_a_variant_replaces_the_studys_values_for_its_cases_only(tmp_path: Path, oscillator: Path) -> None:
    p = study(tmp_path, f"study: defaults\nsystem: {oscillator}\nstop_time_s: 1\nvalues: {{mass2.m2_kg: 2}}\n"
                        "variants:\n  - {name: light}\n  - {name: heavy, values: {mass2.m2_kg: 5}}\n")
    cases = {c.name: dict(c.values) for c in expand_cases(load_study(p))}
    assert cases == {"light": {"mass2.m2_kg": 2.0}, "heavy": {"mass2.m2_kg": 5.0}}


@pytest.mark.parametrize(("text", "line", "needle"), [
    ("study: x\nsystem: {osc}\nstop_time_s: -1\n", 3, "field 'stop_time_s': value -1 outside the allowed range [1e-09,"),
    ("study: x\nsystem: {osc}\ngrid:\n  mass1.m1_kg: []\n", 4, "field 'grid.mass1.m1_kg': expected a non-empty list"),
    ("study: x\nsystem: {osc}\ngrid:\n  m1_kg: [1]\n", 4, "field 'grid.m1_kg': 'm1_kg': expected component.variable"),
    ("study: x\nsystem: {osc}\nrate_hz: 500\n", 3, "field 'rate_hz': value 500 outside the allowed range [0.1, 100.0]"),
    ("study: x\nsystem: nowhere\n", 2, "field 'system': 'nowhere' does not exist"),
    ("study: x\nsystem: {osc}\nmissoins: {{}}\n", 3, "field 'missoins': unknown key"),
    ("study: x\nsystem: {osc}\nvariants:\n  - {{name: a}}\n  - {{name: a}}\n", 3, "two variants are named 'a'"),
    ("study: x\nsystem: {osc}\nvariants:\n  - {{name: a, param: []}}\n", 4, "field 'param': variants[0]: unknown key"),
    ("study: x y\nsystem: {osc}\n", 1, "field 'study': 'x y': a name of"),
    ("study: x\nsystem: {osc}\nrecord_every: 0\n", 3, "field 'record_every'"),
])
def test_bad_study_files_name_line_and_field(tmp_path: Path, text: str, line: int, needle: str) -> None:
    p = study(tmp_path, text.format(osc=OSC))
    with pytest.raises(StudyError) as err:
        load_study(p)
    msg = str(err.value)
    assert msg.startswith(f"{p}:{line}: ") and needle in msg and "\n" not in msg


@pytest.mark.parametrize(("text", "needle"), [
    ("values: {mass1.nope: 1.0}", "field 'values.mass1.nope': 'mass1.nope' is not a variable of system"),
    ("values: {mass1.x1_m: 1.0}", "'mass1.x1_m' is a output"),
    ("grid: {mass1.m1_kg: [heavy]}", "field 'grid.mass1.m1_kg': 'mass1.m1_kg': 'heavy' is not a valid Real value"),
])
def test_parameters_are_checked_against_the_system(tmp_path: Path, oscillator: Path, text: str, needle: str) -> None:
    p = study(tmp_path, f"study: x\nsystem: {oscillator}\n{text}\n")
    with pytest.raises(StudyError) as err:
        expand_cases(load_study(p))
    assert needle in str(err.value), str(err.value)


def test_cli_bad_study_is_one_line_and_exit_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = study(tmp_path, "study: x\nsystem: [1, 2]\n")
    assert main(["study", "run", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"emss study: error: {p}:2: field 'system': expected a file or folder path (relative to the " \
                  "study file)"
    assert main(["study", "run", str(tmp_path / "missing.yaml")]) == 2
    assert "cannot read the study file" in capsys.readouterr().err


def test_cli_lists_cases(tmp_path: Path, oscillator: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = study(tmp_path, f"study: x\nsystem: {oscillator}\ngrid: {{mass1.m1_kg: [1, 2]}}\n")
    assert main(["study", "cases", str(p)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == ["m1_kg=1  (mass1.m1_kg=1.0)", "m1_kg=2  (mass1.m1_kg=2.0)"]
