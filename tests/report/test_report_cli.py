"""The report plugin through the emss command: emss plot (one run, two runs, bad input),
emss summary, the post-run hook on a system without mission signals, the progress bar's status."""
from __future__ import annotations

import io
import json
import re
from pathlib import Path

import numpy as np
import pytest
from synthetic_runs import WF_KG_S, N, Runs

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import Progress
from openemss.orchestrator.results import MANIFEST_NAME
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from openemss.report.plugin import status_variable

FIGURES = {"ground_track.png", "altitude_mach.png", "fuel_burned.png", "fuel_flow_tt4.png", "spool_speeds.png",
           "attitude.png", "life.png"}


def _pngs(folder: Path) -> set[str]:
    names = set()
    for f in folder.glob("*.png"):
        assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and f.stat().st_size > 5000, f
        names.add(f.name)
    return names


def _one_line_error(capsys: pytest.CaptureFixture[str], *words: str) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for w in words:
        assert w in err, err
    return err


def test_plot_one_run_writes_every_figure(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = Runs(tmp_path).make("flight")
    assert main(["plot", str(run)]) == 0
    assert _pngs(run) == FIGURES
    assert "8 file(s) of flight" in capsys.readouterr().out  # the seven figures its signals allow, report.html


def test_plot_two_runs_on_one_figure(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    runs = Runs(tmp_path)
    a = runs.make("engine_a")
    b = runs.make("engine_b", columns={"engine.Wf_kg_s": np.full(N, 0.8 * WF_KG_S),
                                       "engine.fuel_burned_kg": 0.8 * WF_KG_S * np.arange(N) * 0.05})
    out = tmp_path / "compare"
    assert main(["plot", str(a), str(b), "--out", str(out), "--window", "5", "20", "--json"]) == 0
    assert [Path(f).name for f in json.loads(capsys.readouterr().out)] and _pngs(out) == FIGURES
    assert main(["plot", str(a), str(b)]) == 0  # default folder: under the first run
    assert _pngs(a / "compare_engine_b") == FIGURES


def test_plot_never_replaces_a_figure_another_plot_made(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A windowed comparison gets its own folder; into a folder the user names, a plot of other runs or another
    window is refused (one line naming the plot that made the figure) and the figures there stay byte for byte;
    the same plot again redraws them."""
    runs = Runs(tmp_path)
    a, b = runs.make("engine_a"), runs.make("engine_b")
    assert main(["plot", str(a), str(b)]) == 0
    whole = (a / "compare_engine_b" / "fuel_flow_tt4.png").read_bytes()
    assert main(["plot", str(a), str(b), "--window", "5", "20"]) == 0
    assert _pngs(a / "compare_engine_b_window_5-20") == FIGURES
    assert (a / "compare_engine_b" / "fuel_flow_tt4.png").read_bytes() == whole
    assert main(["plot", str(a), "--window", "5", "20"]) == 0  # one run, windowed: not over its own figures
    assert _pngs(a / "window_5-20") == FIGURES
    out = tmp_path / "mine"
    assert main(["plot", str(a), str(b), "--out", str(out), "--window", "5", "20"]) == 0
    before = {f.name: f.read_bytes() for f in out.iterdir()}
    capsys.readouterr()
    assert main(["plot", str(a), str(b), "--out", str(out), "--window", "2", "30"]) == 2
    _one_line_error(capsys, f"--out {out}", "--window 5 20", "plots.json")
    assert main(["plot", str(b), "--out", str(out)]) == 2
    _one_line_error(capsys, f"emss plot {a.resolve()} {b.resolve()}")
    assert {f.name: f.read_bytes() for f in out.iterdir()} == before
    assert main(["plot", str(a), str(b), "--out", str(out), "--window", "5", "20"]) == 0  # the same plot again
    assert main(["plot", str(a)]) == 0  # the run's own report, drawn again
    assert main(["plot", str(a), "--out", str(a), "--window", "5", "20"]) == 2  # ... is not replaced by a window
    capsys.readouterr()


@pytest.mark.parametrize(("args", "words"), [
    (["{tmp}/missing"], ("no such results folder",)),
    (["{tmp}"], ("no timeseries.parquet, timeseries.csv",)),
    (["{run}", "--window", "20", "5"], ("--window 20 5", "T0 < T1")),
    (["{run}", "--window", "100", "200"], ("outside run",)),
    (["{osc}", "mass1.y1_m"], ("mass1.y1_m: not recorded", "did you mean mass1.x1_m")),
    (["{run}"] * 5, ("at most 4",)),
])
def test_plot_bad_input_is_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str],
                                                words: tuple[str, ...]) -> None:
    run = Runs(tmp_path).make("flight")
    osc = tmp_path / "oscillator_run"
    osc.mkdir()
    (osc / "timeseries.csv").write_text("time_s,mass1.x1_m\n0,0.1\n0.05,0.2\n")
    argv = [a.format(tmp=tmp_path, run=run, osc=osc) for a in args]
    assert main(["plot", *argv]) == 2
    _one_line_error(capsys, "emss plot: error:", *words)
    assert not list(tmp_path.glob("**/*.png"))


def test_plot_window_must_be_numbers(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["plot", "x", "--window", "a", "5"])
    assert exc.value.code == 2
    _one_line_error(capsys, "'a' is not a time [s]")


def test_summary_command_prints_the_sections(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = Runs(tmp_path).make("flight")
    assert main(["summary", str(run)]) == 0
    out = capsys.readouterr().out
    assert "out to WP1" in out and "not reached" in out and "limits hit: none" in out
    assert main(["summary", str(run), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["sections"][1]["name"] == "lift-off"
    assert main(["summary", str(tmp_path / "nope")]) == 2
    _one_line_error(capsys, "no such results folder")


def test_post_run_hook_leaves_a_system_without_mission_signals_alone(
        oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(out)]) == 0
    assert sorted(f.name for f in out.iterdir()) == sorted([MANIFEST_NAME, "run.json", "timeseries.parquet"])
    assert "written after the run" not in capsys.readouterr().out


def test_status_variable_is_the_fcs_section_name() -> None:
    assert status_variable(["a.x", "fcs.section_index", "fcs.section_name"]) == "fcs.section_name"
    assert status_variable(["a.x", "b.section_name"]) is None


class Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_shows_the_status_variable(oscillator: Path) -> None:
    """A parameter the slaves do not get each step is read with one FMI call when the bar is drawn;
    an output from the exchange vector."""
    for path, expect in (("mass2.kc_N_m", r"real time  50 +$"), ("mass1.x1_m", r"real time  -?[0-9.]+(e-?\d+)? +$")):
        stream = Tty()
        ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
        ex.add_observer(Progress(2.0, stream=stream, delay_s=0.0, interval_s=0.0, status=path))
        ex.run(2.0)
        *_, drawn, last = stream.getvalue().split("\r")
        assert re.search(expect, drawn), drawn
        assert "100.0%" in last and last.rstrip().endswith("completed"), last  # the last draw: how it ended


def test_bad_status_variable_is_one_line(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(tmp_path / "o"),
                 "--status", "mass1.nothing"]) == 2
    _one_line_error(capsys, "--status 'mass1.nothing'")
