"""Scenarios (timed overrides), real-time pacing and step statistics."""
from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import table
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder, RealTimePacer
from openemss.orchestrator.scenarios.manipulators import ScenarioError, ScenarioManipulator, load_scenario
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import GAIN_CONNECTORS, Comp, write_system

SCENARIO = """description: override, ramp and release a connected input; set an unconnected one and a parameter
events:
  - at: 2.0
    set: {b.u_real: 5.0}
  - from: 4.0
    to: 6.0
    ramp: {b.u_real: [0.0, 10.0]}
  - at: 8.0
    release: [b.u_real]
  - at: 3.0
    set: {a.u_real: 2.0, c.k: 4.0, c.u_bool: true}
  - at: 9.0
    hold: [a.u_real]
"""


def expected_b_input(t: np.ndarray) -> np.ndarray:
    """b.u_real by hand: a.y_real = a.k * a.u_real = 1 (2 from t = 3 s) unless overridden."""
    base = np.where(t < 3.0 - 1e-9, 1.0, 2.0)
    out = base.copy()
    out[(t >= 2.0 - 1e-9) & (t < 4.0 - 1e-9)] = 5.0
    ramp = (t >= 4.0 - 1e-9) & (t < 8.0 - 1e-9)
    out[ramp] = np.minimum(10.0, 10.0 * (t[ramp] - 4.0) / 2.0)
    return out


@pytest.fixture()
def system(tmp_path: Path, fmu_dir: Path) -> Path:
    write_system(tmp_path / "sys", fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS, {"u_real": 1.0}),
                                             Comp("b", "Gain.fmu", GAIN_CONNECTORS),
                                             Comp("c", "Gain.fmu", GAIN_CONNECTORS, {"u_real": 1.0})],
                 [("a.y_real", "b.u_real")], stop_time=10.0)
    (tmp_path / "scenario.yaml").write_text(SCENARIO)
    return tmp_path / "sys"


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_overrides_and_ramps_appear_exactly_in_the_recorded_inputs(system: Path, algorithm: str) -> None:
    ex = Execution(bind_system(load_system(system)), rate_hz=10.0, algorithm=algorithm,
                   record=["a.u_real", "b.u_real", "b.y_real", "c.y_real", "c.y_bool"])
    ex.add_manipulator(ScenarioManipulator(load_scenario(system.parent / "scenario.yaml")))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(10.0)
    r = rec.result()
    t = r["time_s"]
    assert np.max(np.abs(r["b.u_real"] - expected_b_input(t))) < 1e-12
    # what b made of it: its output at t + h is k * (its input at t), whatever the algorithm
    assert np.max(np.abs(r["b.y_real"][1:] - r["b.u_real"][:-1])) < 1e-12
    # unconnected input set at 3 s and held from 9 s; tunable parameter c.k and Boolean input c.u_bool set at 3 s
    assert np.all(r["a.u_real"][t >= 3.0 - 1e-9] == 2.0) and np.all(r["a.u_real"][t < 3.0 - 1e-9] == 1.0)
    assert r["c.y_real"][-1] == 4.0 and r["c.y_bool"][-1] == 0  # not True


@pytest.mark.parametrize("text, fragment, line", [
    ("events:\n  - at: 1\n    sett: {b.u_real: 1}\n", "unknown key 'sett'", 2),
    ("events:\n  - set: {b.u_real: 1}\n", "'set' needs 'at'", 2),
    ("events:\n  - from: 3\n    to: 2\n    ramp: {b.u_real: [0, 1]}\n", "'to' > 'from'", 2),
    ("events:\n  - at: 1\n    set: {b.u_real: fast}\n", "must be a number or true/false", 3),
    ("events:\n  - at: 1\n    ramp: {b.u_real: [0, 1]}\n", "a ramp needs 'from' and 'to'", 2),
    ("events: [\n", "not valid YAML", 2),
    ("events:\n  - at: one\n    set: {b.u_real: 1}\n", "'at' must be a number", 2),
    ("events:\n  - when: b.u_real ~ 3\n    set: {b.u_real: 1}\n", "'when' must read", 2),
    ("events:\n  - when: b.u_real > fast\n    set: {b.u_real: 1}\n", "compares with a number", 2),
    ("events:\n  - at: 1\n    when: b.u_real > 1\n    set: {b.u_real: 1}\n", "'at' or 'when'", 2),
    ("events:\n  - at: 1\n    after: 2\n    set: {b.u_real: 1}\n", "'after' needs 'when'", 2),
])
def test_bad_scenario_files_name_the_line(tmp_path: Path, text: str, fragment: str, line: int) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(text)
    with pytest.raises(ScenarioError) as info:
        load_scenario(f)
    assert fragment in str(info.value) and f"bad.yaml:{line}:" in str(info.value), str(info.value)


CONDITIONAL = """events:
  - from: 0.0
    to: 10.0
    ramp: {a.u_real: [0.0, 10.0]}
  - when: a.y_real >= 4
    after: 1.0
    set: {b.u_real: 100.0}
  - when: a.y_real >= 4
    from: 2.0
    to: 3.0
    ramp: {c.u_real: [0.0, 1.0]}
  - when: b.y_real > 1000
    set: {c.k: 7.0}
"""


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_conditions_fire_once_where_the_variable_first_meets_them(system: Path, tmp_path: Path,
                                                                    algorithm: str) -> None:
    f = tmp_path / "when.yaml"
    f.write_text(CONDITIONAL)
    ex = Execution(bind_system(load_system(system)), rate_hz=10.0, algorithm=algorithm,
                   record=["a.y_real", "b.u_real", "c.u_real", "c.k"])
    manip = ScenarioManipulator(load_scenario(f))
    ex.add_manipulator(manip)
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(10.0)
    r = rec.result()
    t, h = r["time_s"], 0.1
    # the condition is checked on the exchanged values at the start of each step: the first recorded
    # sample of a.y_real (= a.u_real, ramped 1 per s) at or above 4
    t_fire = t[np.argmax(r["a.y_real"] >= 4.0)]
    assert 4.0 - 1e-9 <= t_fire <= 4.0 + h + 1e-9
    assert manip.fired == [(pytest.approx(t_fire), "a.y_real >= 4")]
    later = t >= t_fire + 1.0 - 1e-9
    assert np.all(r["b.u_real"][later] == 100.0) and np.all(r["b.u_real"][~later] != 100.0)
    # a ramp counts 'from'/'to' from the condition (c.u_real keeps its start value 1 until then)
    expected_c = np.where(t < t_fire + 2.0 - 1e-9, 1.0, np.clip(t - (t_fire + 2.0), 0.0, 1.0))
    assert np.max(np.abs(r["c.u_real"] - expected_c)) < 1e-12
    assert np.all(r["c.k"] == 1.0)  # b.y_real never exceeds 1000 within 10 s: never fired


def test_condition_on_an_unknown_variable_is_refused(system: Path, tmp_path: Path) -> None:
    f = tmp_path / "s.yaml"
    f.write_text("events:\n  - when: b.nope > 1\n    set: {b.u_real: 1}\n")
    with pytest.raises(ConfigurationError, match="'when' names no variable 'b.nope'"):
        ex = Execution(bind_system(load_system(system)), rate_hz=10.0)
        ex.add_manipulator(ScenarioManipulator(load_scenario(f)))
        ex.run(1.0)


@pytest.mark.parametrize("variable, fragment", [("b.nope", "no variable 'b.nope'"),
                                                ("b.y_real", "only inputs and tunable parameters")])
def test_scenario_on_a_variable_that_cannot_be_changed(system: Path, tmp_path: Path, variable: str,
                                                       fragment: str, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "s.yaml"
    f.write_text(f"events:\n  - at: 1\n    set: {{{variable}: 1}}\n")
    with pytest.raises(ConfigurationError, match=fragment):
        ex = Execution(bind_system(load_system(system)), rate_hz=10.0)
        ex.add_manipulator(ScenarioManipulator(load_scenario(f)))
        ex.run(1.0)
    rc = main(["run", str(system), "--scenario", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "s.yaml:3" in err[0] and fragment in err[0]


class FakeWall:
    """A wall clock that moves only when the pacer sleeps or a step is said to cost ``step_cost_s``."""

    def __init__(self, step_cost_s: float) -> None:
        self.now_s = 100.0
        self.step_cost_s = step_cost_s
        self.slept_s: list[float] = []

    def clock(self) -> float:
        self.now_s += self.step_cost_s  # every reading follows some work
        return self.now_s

    def sleep(self, dt_s: float) -> None:
        self.slept_s.append(dt_s)
        self.now_s += dt_s


@pytest.mark.parametrize("factor", [0.5, 1.0, 4.0])
def test_pacing_waits_exactly_until_each_steps_wall_time(factor: float) -> None:
    """Each step ends no earlier than its simulated time over ``factor`` (the pacer never runs ahead of the
    wall clock) and no later than the work took: with cheap steps the achieved factor is the target."""
    wall = FakeWall(step_cost_s=1e-4)
    pacer = RealTimePacer(factor, clock=wall.clock, sleep=wall.sleep)
    pacer.start(SimpleNamespace(time_s=0.0))
    wall0 = wall.now_s
    for k in range(1, 201):
        pacer.sample(k, 0.05 * k)
        assert wall.now_s >= wall0 + 0.05 * k / factor - 1e-12
    pacer.finish(SimpleNamespace(time_s=10.0), None)
    rep = pacer.report()["realtime"]
    assert rep["achieved_factor"] == pytest.approx(factor, rel=1e-3) and rep["overruns"] == 0


def test_pacing_counts_the_steps_that_end_late() -> None:
    """Steps that cost more than their share of wall time are overruns; the pacer never sleeps then."""
    wall = FakeWall(step_cost_s=0.06)  # 20 Hz steps (0.05 s) that take 0.06 s of wall time each
    pacer = RealTimePacer(1.0, clock=wall.clock, sleep=wall.sleep)
    pacer.start(SimpleNamespace(time_s=0.0))
    for k in range(1, 11):
        pacer.sample(k, 0.05 * k)
    pacer.finish(SimpleNamespace(time_s=0.5), None)
    rep = pacer.report()["realtime"]
    assert not wall.slept_s and rep["overruns"] == 10 and rep["max_lag_s"] == pytest.approx(0.1, rel=1e-6)


def test_realtime_option_paces_the_run_and_its_absence_does_not(system: Path, tmp_path: Path) -> None:
    assert main(["run", str(system), "--stop-time", "1", "--rate", "20", "--realtime", "1.0",
                 "--out", str(tmp_path / "rt")]) == 0
    paced = json.loads((tmp_path / "rt" / "run.json").read_text())["realtime"]
    assert paced["target_factor"] == 1.0 and paced["achieved_factor"] <= 1.001  # never ahead of the wall clock
    assert main(["run", str(system), "--stop-time", "1", "--rate", "20", "--out", str(tmp_path / "fast")]) == 0
    assert "realtime" not in json.loads((tmp_path / "fast" / "run.json").read_text())


def test_negative_realtime_factor_is_refused(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(system), "--realtime", "-1", "--out", str(tmp_path / "o")]) == 2
    assert "--realtime -1.0: must be >= 0" in capsys.readouterr().err


def test_step_statistics_printed_and_in_run_json(system: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(system), "--stop-time", "1", "--rate", "10", "--stats", "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert "doStep s" in out and all(f"\n{c} " in out for c in ("a", "b", "c"))
    stats = json.loads((tmp_path / "o" / "run.json").read_text())["step_statistics"]
    assert {c: s["steps"] for c, s in stats.items()} == {"a": 10, "b": 10, "c": 10}
    assert all(s["do_step_s"] > 0 and s["get_s"] > 0 for s in stats.values())


def test_until_ends_the_run_at_the_first_step_the_condition_holds(system: Path, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """a.u_real ramps 1 per s (scenario); --until 'a.y_real >= 4' (a.y_real = a.u_real, k = 1) ends the run
    after the first recorded step at which a.y_real >= 4, long before the stop time of 10 s; the recorded
    rows and run.json end there."""
    f = tmp_path / "ramp.yaml"
    f.write_text("events:\n  - from: 0.0\n    to: 10.0\n    ramp: {a.u_real: [0.0, 10.0]}\n")
    out = tmp_path / "o"
    rc = main(["run", str(system), "--scenario", str(f), "--until", "a.y_real >= 4", "--rate", "10",
               "--out", str(out), "--record", "a.y_real"])
    assert rc == 0
    assert "stopped early: a.y_real >= 4" in capsys.readouterr().out
    data = table(out)
    y = list(data["a.y_real"])
    assert y[-1] >= 4.0 and all(v < 4.0 for v in y[:-1])
    assert 4.0 <= data["time_s"][-1] <= 4.1 + 1e-9
    assert json.loads((out / "run.json").read_text())["steps"] == len(y) - 1


@pytest.mark.parametrize("cond, fragment", [("a.nope > 1", "no variable 'a.nope'"),
                                            ("a.y_real ~ 1", "must read 'component.variable OP number'")])
def test_until_with_a_bad_condition_is_one_line(system: Path, tmp_path: Path, cond: str, fragment: str,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["run", str(system), "--until", cond, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc != 0 and len(err) == 1 and fragment in err[0], err
