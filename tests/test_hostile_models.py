"""The hostile corpus, models in a run: no silent wrong result (issue 15).

* The engine taken outside its envelope by a scenario (Mach 3 at 30 km): its gas path cannot be
  matched; the run fails with one line naming the component, the time and the cause, unless the
  user accepts a degraded run (``engine.accept_solver_failure``), which then records
  ``solver_failed``.
* A NaN reaching an engine input fails the step naming the input.
* A bad mission file reaches the user as the mission's own error (file:line first), not as a
  wrapped ``MissionError(...)`` repr.
"""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from conftest import table
from openemss.orchestrator.cli.main import main
from systems import Comp, write_system

ENGINE = [("mach", "input", "Real"), ("alt_m", "input", "Real"), ("distortion_dPt_frac", "input", "Real"),
          ("Fn_N", "output", "Real"), ("solver_failed", "output", "Boolean")]


@pytest.fixture()
def engine_system(tmp_path: Path, project_fmus: dict[str, Path]) -> Path:
    folder = tmp_path / "sys"
    shutil.copy2(project_fmus["engine"], tmp_path / "Engine.fmu")
    write_system(folder, tmp_path, [Comp("engine", "Engine.fmu", ENGINE,
                                         {"start_N1_pct": 80.0})], [], stop_time=2.0)
    return folder


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    rc = main(list(argv))
    return rc, [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]


def _scenario(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "scenario.yaml"
    path.write_text("events:\n  - at: 1.0\n    set: {" + body + "}\n", encoding="utf-8")
    return path


def test_engine_outside_its_envelope_fails_the_run(engine_system: Path, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    scenario = _scenario(tmp_path, "engine.mach: 3.0, engine.alt_m: 30000.0")
    rc, err = _run(capsys, "run", str(engine_system), "--scenario", str(scenario), "--out", str(tmp_path / "out"))
    assert rc == 3 and len(err) == 1, err
    for fragment in ("component 'engine'", "fmi2DoStep", "t = 1", "gas path not matched", "Mach=3",
                     "accept_solver_failure"):
        assert fragment in err[0], (fragment, err[0])


def test_engine_degraded_run_is_recorded_when_accepted(engine_system: Path, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    scenario = _scenario(tmp_path, "engine.mach: 3.0, engine.alt_m: 30000.0")
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(engine_system), "--scenario", str(scenario), "--out", str(out),
                   "--set", "engine.accept_solver_failure=true")
    assert rc == 0, err
    data = table(out)
    failed = list(data["time_s"][data["engine.solver_failed"] == 1])
    assert failed and failed[0] == pytest.approx(1.05)  # recorded from the first step it could not match


def test_nan_engine_input_fails_the_step(tmp_path: Path, fmu_dir: Path, project_fmus: dict[str, Path],
                                         capsys: pytest.CaptureFixture[str]) -> None:
    """A NaN distortion deficit from another FMU (NanSource: NaN before its first step) is not taken as
    'no distortion': the engine's step fails naming the input."""
    shutil.copy2(project_fmus["engine"], fmu_dir / "Engine.fmu") if not (fmu_dir / "Engine.fmu").exists() else None
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [Comp("nan", "NanSource.fmu", [("target", "output", "Real")]),
                                   Comp("engine", "Engine.fmu", ENGINE, {"start_N1_pct": 80.0})],
                 [("nan.target", "engine.distortion_dPt_frac")], stop_time=1.0)
    rc, err = _run(capsys, "run", str(folder), "--out", str(tmp_path / "out"))
    assert rc == 3 and len(err) == 1, err
    for fragment in ("component 'engine'", "fmi2DoStep", "t = 0", "not finite", "distortion_dPt_frac=nan"):
        assert fragment in err[0], (fragment, err[0])


def test_nan_parameter_set_refused_where_it_enters(engine_system: Path, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """A NaN distortion deficit in an SSV written by hand (YAML refuses NaN) is refused on reading."""
    ssv = tmp_path / "nan.ssv"
    ssv.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet '
                   'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="n">'
                   '<ssv:Parameters><ssv:Parameter name="engine.distortion_dPt_frac"><ssv:Real value="NaN"/>'
                   '</ssv:Parameter></ssv:Parameters></ssv:ParameterSet>\n')
    rc, err = _run(capsys, "run", str(engine_system), "--params", str(ssv), "--out", str(tmp_path / "out"))
    assert rc == 2 and len(err) == 1 and "Real value='NaN'" in err[0] and str(ssv) in err[0], err


MISSION_ERRORS = {  # a mission file's bytes, and how the one line must start (after the file name)
    "duplicate_waypoint": (b"mission: {name: bad}\nplaces:\n  waypoints:\n    A: {lat_deg: 48.0, lon_deg: 11.0}\n"
                           b"    A: {lat_deg: 47.0, lon_deg: 9.0}\nsections:\n  - {type: Levelling, altitude_m: 500, "
                           b"speed: {mach: 0.4}}\n", ":5: key 'A' is given twice"),
    "not_utf8": ("mission: {name: Môle}\n".encode("latin-1"), ":1: the mission file is not UTF-8 text: byte 0xf4"),
}


@pytest.mark.parametrize("case", sorted(MISSION_ERRORS))
def test_mission_error_is_the_missions_own(tmp_path: Path, project_fmus: dict[str, Path],
                                           capsys: pytest.CaptureFixture[str], case: str) -> None:
    content, start = MISSION_ERRORS[case]
    bad = tmp_path / "bad.yaml"
    bad.write_bytes(content)
    shutil.copy2(project_fmus["fcs"], tmp_path / "Fcs.fmu")
    folder = tmp_path / "sys"
    write_system(folder, tmp_path, [Comp("fcs", "Fcs.fmu", [("section_index", "output", "Integer")])], [],
                 stop_time=1.0)
    rc, err = _run(capsys, "run", str(folder), "--set", f"fcs.mission_file={bad}", "--out", str(tmp_path / "out"))
    assert rc == 2 and len(err) == 1, err  # an error before the first step: bad input
    assert err[0].startswith(f"emss run: error: {bad}{start}"), err[0]
    assert "MissionError(" not in err[0] and "component 'fcs'" in err[0]
