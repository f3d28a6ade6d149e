"""emss run of the coupled system (engine, airframe, FCS FMUs wired by ssp/) writes summary.json,
the mission as flown and the plots; also after a failed run, from what was recorded.

Conservation: the engine's counter ``fuel_burned_kg`` adds the fuel flow it burned over each
step times the step, and every step is recorded, so the integral of the recorded fuel flow
(held-before rule) equals the counter's increase to round-off: 1e-9 relative covers the sum
of about a thousand terms in double precision with a wide margin.

The sections are checked against what any mission's run must show, not against the shipped mission's
numbers: they follow one another without a gap from the start, each owns the samples where the FCS's recorded
``section_index`` names it, their status follows the last recorded index, and a Rolling section ends within
one communication step after the recorded calibrated airspeed first reaches its ``rotate_cas_m_s`` (the FCS
reads the airframe's output of the step before at the latest).
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from openemss.models.mission.mission import load_mission
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.recording.timeseries import read_timeseries

ROOT = Path(__file__).resolve().parents[2]
FIGURES = {"ground_track.png", "altitude_mach.png", "fuel_burned.png", "fuel_flow_tt4.png", "spool_speeds.png",
           "attitude.png", "thrust.png", "sfc_surge_margin.png", "life.png"}


@pytest.fixture()
def coupled_system(tmp_path: Path, project_fmus: dict[str, Path]) -> Path:
    """A private copy of ssp/ with the session's freshly built project FMUs."""
    copy = tmp_path / "ssp"
    shutil.copytree(ROOT / "ssp", copy, ignore=shutil.ignore_patterns("resources", "__pycache__", "*.py"))
    (copy / "resources").mkdir()
    for path in project_fmus.values():
        shutil.copy2(path, copy / "resources" / path.name)
    return copy


def _check_fuel_and_sections(s: dict, out: Path) -> None:
    ts = read_timeseries(out)
    t, idx = ts.data["time_s"], np.rint(ts.data["fcs.section_index"]).astype(int)
    assert s["fuel_burned_kg"] > 0.0
    assert abs(s["fuel_flow_integral_kg"] - s["fuel_burned_kg"]) <= 1e-9 * s["fuel_burned_kg"]
    assert sum(x["fuel_burned_kg"] for x in s["sections"]) == pytest.approx(s["fuel_flow_integral_kg"], rel=1e-12)
    assert sum(x["duration_s"] for x in s["sections"]) == pytest.approx(s["sim_time_s"], rel=1e-12)
    mission = load_mission(out / "mission.yaml")
    assert [x["type"] for x in s["sections"]] == [sec.type for sec in mission.sections]
    reached = [x for x in s["sections"] if x["start_time_s"] is not None]
    assert reached and reached[0]["start_time_s"] == t[0]
    for a, b in zip(reached, reached[1:], strict=False):
        assert b["start_time_s"] == a["end_time_s"]  # no gap, no overlap
    for x in reached:
        mine = (t >= x["start_time_s"]) & (t < x["end_time_s"])
        assert (idx[mine] == x["index"]).all(), x["name"]
    last = idx[-1]
    assert [x["status"] for x in s["sections"]] == [
        "completed" if i < last or s["mission_completed"] else "active" if i == last else "not reached"
        for i in range(len(s["sections"]))]
    h_s = float(np.max(np.diff(t)))
    cas = ts.data["airframe.cas_m_s"]
    for sec, x in zip(mission.sections, s["sections"], strict=True):
        if sec.type == "Rolling" and x["status"] == "completed":
            start = t >= x["start_time_s"]
            reached_cas = t[np.argmax(start & (cas >= sec["rotate_cas_m_s"]))]
            assert reached_cas <= x["end_time_s"] <= reached_cas + h_s + 1e-9, (reached_cas, x["end_time_s"])


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
    _check_fuel_and_sections(s, out)
    ts = read_timeseries(out)
    assert s["mission_completed"] is bool(ts.data["fcs.mission_completed"][-1] > 0.5)
    assert s["landing"]["airborne"] is bool((ts.data["airframe.on_ground"] < 0.5).any())
    assert not s["landed"] or (s["landing"]["airborne"] and s["landing"]["on_ground"])  # landed: flew, then stood
    assert s["max_Tt4_K"] == float(np.max(ts.data["engine.Tt4_K"]))
    assert {"surge", "flameout", "overspeed", "Tt41_limit", "N1_limit"} <= set(s["limits_hit"])
    assert {f.name for f in out.glob("*.png")} == FIGURES and (out / "report.html").is_file()


def test_failed_run_is_summarized_from_what_was_recorded(coupled_system: Path, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    """A scenario sets an FCS limit out of its range at 30 s: the FCS refuses, the run stops."""
    scenario = tmp_path / "fault.yaml"
    scenario.write_text("events:\n  - at: 30.0\n    set: {fcs.fuel_control.Tt41_max_K: 5000.0}\n")
    out = tmp_path / "run"
    assert main(["run", str(coupled_system), "--stop-time", "60", "--out", str(out),
                 "--scenario", str(scenario)]) == 3  # failed (exit codes: README)
    err = capsys.readouterr().err
    assert "results so far in" in err and "Traceback" not in err
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and s["error"]
    assert 25.0 < s["sim_time_s"] <= 30.0
    _check_fuel_and_sections(s, out)
