"""emss run of the coupled system (engine, airframe, FCS FMUs wired by ssp/) writes summary.json,
the mission as flown and the plots; also after a failed run, from what was recorded.

Conservation: the engine's counter ``fuel_burned_kg`` adds the fuel flow it burned over each
step times the step, and every step is recorded, so the integral of the recorded fuel flow
(held-before rule) equals the counter's increase to round-off: 1e-9 relative covers the sum
of about a thousand terms in double precision with a wide margin.
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import yaml

from openemss.orchestrator.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
FIGURES = {"ground_track.png", "altitude_mach.png", "fuel_burned.png", "fuel_flow_tt4.png", "spool_speeds.png",
           "attitude.png", "thrust.png", "sfc_surge_margin.png"}


@pytest.fixture()
def coupled_system(tmp_path: Path, project_fmus: dict[str, Path]) -> Path:
    """A private copy of ssp/ with the session's freshly built project FMUs."""
    copy = tmp_path / "ssp"
    shutil.copytree(ROOT / "ssp", copy, ignore=shutil.ignore_patterns("resources", "__pycache__", "*.py"))
    (copy / "resources").mkdir()
    for path in project_fmus.values():
        shutil.copy2(path, copy / "resources" / path.name)
    return copy


def _check_fuel_and_sections(s: dict) -> None:
    assert s["fuel_burned_kg"] > 0.5
    assert abs(s["fuel_flow_integral_kg"] - s["fuel_burned_kg"]) <= 1e-9 * s["fuel_burned_kg"]
    assert sum(x["fuel_burned_kg"] for x in s["sections"]) == pytest.approx(s["fuel_flow_integral_kg"], rel=1e-12)
    assert sum(x["duration_s"] for x in s["sections"]) == pytest.approx(s["sim_time_s"], rel=1e-12)
    roll = s["sections"][0]
    assert (roll["type"], roll["status"], roll["start_time_s"]) == ("Rolling", "completed", 0.0)
    assert 5.0 < roll["end_time_s"] < 30.0  # rotation speed reached after a take-off roll
    assert all(x["status"] == "not reached" for x in s["sections"][3:])


def test_run_writes_summary_mission_and_plots(coupled_system: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    assert main(["run", str(coupled_system), "--stop-time", "40", "--out", str(out)]) == 0
    assert "written after the run: summary.json, mission.yaml" in capsys.readouterr().out
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "completed" and s["sim_time_s"] == pytest.approx(40.0)
    assert s["wall_time_s"] > 0 and s["realtime_factor"] > 0
    mission = yaml.safe_load((out / "mission.yaml").read_text())
    assert len(mission["sections"]) == s["mission"]["sections"] == len(s["sections"])
    assert [x["name"] for x in s["sections"]] == [m.get("name", m["type"]) for m in mission["sections"]]
    _check_fuel_and_sections(s)
    assert s["mission_completed"] is False and s["landed"] is False and s["landing"]["airborne"] is True
    assert 1000.0 < s["max_Tt4_K"] < 2000.0
    assert {"surge", "flameout", "overspeed", "Tt41_limit", "N1_limit"} <= set(s["limits_hit"])
    assert {f.name for f in out.glob("*.png")} == FIGURES and (out / "report.html").is_file()


def test_failed_run_is_summarized_from_what_was_recorded(coupled_system: Path, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    """A scenario sets an FCS limit out of its range at 30 s: the FCS refuses, the run stops."""
    scenario = tmp_path / "fault.yaml"
    scenario.write_text("events:\n  - at: 30.0\n    set: {fcs.fuel_control.Tt41_max_K: 5000.0}\n")
    out = tmp_path / "run"
    assert main(["run", str(coupled_system), "--stop-time", "60", "--out", str(out),
                 "--scenario", str(scenario)]) == 1
    err = capsys.readouterr().err
    assert "results so far in" in err and "Traceback" not in err
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and s["error"]
    assert 25.0 < s["sim_time_s"] <= 30.0
    _check_fuel_and_sections(s)
