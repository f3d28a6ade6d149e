"""The master leaves out a batched set whose values have not changed since it last sent them.

Two ``LoopElement`` FMUs (``y = k*u + c + x``, ``dx/dt = g*u``, tests/fmus/loop_element.py) in a
chain ``src.y -> int.u``: ``src`` is a constant (``k = 0``), ``int`` an integrator (``g = 1``), so
``int.x(t)`` is the integral of what ``int.u`` really held, known in closed form. A set left out
wrongly (a changed value not delivered, or a state restored with other inputs) shows in ``int.x``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.scenarios.manipulators import ScenarioManipulator, load_scenario
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import Comp, write_system

CONNECTORS = [("u", "input", "Real"), ("y", "output", "Real"), ("x", "output", "Real")]
H = 0.1  # macro step [s]
N = 20  # macro steps


def chain(folder: Path, fmu: Path, c_src: float) -> Path:
    write_system(folder, fmu.parent, [Comp("src", fmu.name, CONNECTORS, {"k": 0.0, "c": c_src}),
                                      Comp("int", fmu.name, CONNECTORS, {"k": 0.0, "g": 1.0})],
                 [("src.y", "int.u")])
    return folder


def execution(folder: Path, scenario: Path | None = None) -> tuple[Execution, MemoryRecorder]:
    ex = Execution(bind_system(load_system(folder)), "gauss-seidel", rate_hz=1 / H, record=["int.u", "int.x"])
    if scenario is not None:
        ex.add_manipulator(ScenarioManipulator(load_scenario(scenario)))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    return ex, rec


def integrator(ex: Execution) -> int:
    return next(i for i, s in enumerate(ex.slaves) if s.name == "int")


def test_a_held_input_is_sent_once_and_held_by_the_fmu(tmp_path: Path, fmu_dir: Path) -> None:
    ex, rec = execution(chain(tmp_path / "sys", fmu_dir / "LoopElement.fmu", 2.0))
    ex.run(N * H)
    r = rec.result()
    assert np.allclose(r["int.x"], 2.0 * r["time_s"], rtol=0, atol=1e-12)  # x = 2 t: the FMU held u = 2
    assert ex.slaves[integrator(ex)].stats.sets_skipped >= N - 1  # the set of every step after the first


def test_a_changed_input_is_sent_after_steps_left_out(tmp_path: Path, fmu_dir: Path) -> None:
    scenario = tmp_path / "step.yaml"  # src.c (an unconnected parameter) from 2 to 5 at t = 1 s
    scenario.write_text("events:\n  - at: 1.0\n    set: {src.c: 5.0}\n")
    ex, rec = execution(chain(tmp_path / "sys", fmu_dir / "LoopElement.fmu", 2.0), scenario)
    ex.run(N * H)
    r = rec.result()
    t = r["time_s"]
    # the set at t = 1 s reaches src before it steps; int steps from 1 s with src's new output
    x = 2.0 * np.minimum(t, 1.0) + 5.0 * np.maximum(t - 1.0, 0.0)
    assert np.allclose(r["int.x"], x, rtol=0, atol=1e-12)
    assert ex.slaves[integrator(ex)].stats.sets_skipped >= N - 3


def test_a_restored_state_gets_its_inputs_sent_again(tmp_path: Path, state_fmu: Path) -> None:
    ex, _ = execution(chain(tmp_path / "sys", state_fmu, 2.0))
    ex.initialize(N * H)
    i = integrator(ex)
    slave, u = ex.slaves[i], ex.inputs_of(i)[0]
    x_var = slave.model.variables["x"]
    u[0] = 1.0
    slave.set_inputs()
    ex.save_state(i)  # the FMU's u is 1
    u[0] = 3.0
    slave.set_inputs()  # now 3
    ex.restore_state(i)  # back to u = 1 inside the FMU; the master's buffer still says 3
    x0 = slave.get_value(x_var)
    slave.set_inputs()  # must send 3 again, though the master sent 3 last
    slave.do_step(0.0, H)
    assert slave.get_value(x_var) == pytest.approx(x0 + 3.0 * H, abs=1e-12)
