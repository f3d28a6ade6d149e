"""A failing FMU stops the run with one message naming it and the time; what was recorded stays."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from conftest import table
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import InitializationError
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import GAIN_CONNECTORS, Comp, write_system

CLOCK = [("clock_s", "output", "Real")]


def test_fmu_raising_at_3_s_stops_the_run_and_keeps_the_rows(
        tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_system(tmp_path / "sys", fmu_dir, [Comp("clock", "FailingClock.fmu", CLOCK, {"fail_time_s": 3.0}),
                                             Comp("g", "Gain.fmu", GAIN_CONNECTORS)],
                 [("clock.clock_s", "g.u_real")], stop_time=10.0)
    out = tmp_path / "out"
    rc = main(["run", str(tmp_path / "sys"), "--out", str(out), "--rate", "20"])
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert rc != 0 and len(err) == 1, err
    assert "component 'clock'" in err[0] and "fmi2DoStep" in err[0] and "t = 3 s" in err[0]
    assert "deliberate failure" in err[0]  # the Python exception, as the FMU logged it
    data = table(out)
    times = list(data["time_s"])
    assert times[0] == 0.0 and times[-1] == pytest.approx(3.0) and len(times) == 61
    # the rows are the real history: the clock integrated 0.05 s per step up to 3 s; the gain (k = 1)
    # stepped from the input set at the start of the last step, so under Jacobi it shows 2.95 s.
    assert data["clock.clock_s"][-1] == pytest.approx(3.0)
    assert data["g.y_real"][-1] == pytest.approx(2.95)
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "failed" and "clock" in run["error"] and run["stop_time_s"] == pytest.approx(3.0)


def test_algebraic_loop_that_does_not_settle_names_its_variables(tmp_path: Path, fmu_dir: Path) -> None:
    # y = 2 u around a loop of two gains: the initial exchange doubles the values forever.
    write_system(tmp_path, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS, {"k": 2.0, "u_real": 1.0}),
                                     Comp("b", "Gain.fmu", GAIN_CONNECTORS, {"k": 1.0})],
                 [("a.y_real", "b.u_real"), ("b.y_real", "a.u_real")])
    ex = Execution(bind_system(load_system(tmp_path)), rate_hz=10.0)
    with pytest.raises(InitializationError) as info:
        ex.run(1.0)
    assert "a.y_real" in str(info.value) and "b.y_real" in str(info.value)


def test_algebraic_loop_that_settles(tmp_path: Path, fmu_dir: Path) -> None:
    # y = 0.5 u around the loop: the fixed point is 0, reached geometrically within the iteration bound;
    # the Integer loop (y = u + 1) never settles, so only the Real one is looped here.
    conn = [("a.y_real", "b.u_real"), ("b.y_real", "a.u_real")]
    write_system(tmp_path, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS, {"k": 0.5, "u_real": 1.0}),
                                     Comp("b", "Gain.fmu", GAIN_CONNECTORS, {"k": 0.5})], conn)
    ex = Execution(bind_system(load_system(tmp_path)), rate_hz=10.0, max_init_iterations=100)
    ex.run(0.1)
    assert abs(ex.vectors["Real"].outputs).max() < 1e-10


def test_nan_outputs_settle_in_initialization(tmp_path: Path, fmu_dir: Path) -> None:
    """An output that is NaN until the first step (no target yet) is a fixed point too."""
    nan = [("u", "input", "Real"), ("target", "output", "Real"), ("echo", "output", "Real")]
    write_system(tmp_path, fmu_dir, [Comp("a", "NanSource.fmu", nan), Comp("b", "NanSource.fmu", nan)],
                 [("a.target", "b.u"), ("b.echo", "a.u")])
    ex = Execution(bind_system(load_system(tmp_path)), rate_hz=10.0, record=["b.u"])
    from openemss.orchestrator.recording.observers import MemoryRecorder

    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(0.3)
    u = rec.result()["b.u"]
    assert np.isnan(u[0]) and np.all(u[1:] == 1.0)
