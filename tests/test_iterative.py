"""Iterative Gauss-Seidel on loops with a known solution (issue 20).

Two ``LoopElement`` FMUs (``y = k*u + c + x``, ``dx/dt = g*u``, tests/fmus/loop_element.py) in a
ring ``a.y -> b.u``, ``b.y -> a.u``:

* an algebraic loop (``g = 0``): in every macro step the inputs must sit at the fixed point
  ``a.u = (k_b*c_a + c_b) / (1 - k_a*k_b)``, while ``c_a`` ramps (so plain Gauss-Seidel, which solves
  the loop one substitution per step, lags);
* a dynamic loop (``g_a != 0``): the converged step is the implicit coupling of the two, whose
  state follows the linear recurrence ``x_{n+1} = (1 + alpha) x_n + beta`` in closed form;
* a loop gain above 1: no sweep converges, the run fails with one line naming the loop;
* FMUs that cannot get and set their state are refused by name.

The state-capable FMU is the ``state_fmu`` fixture (tests/conftest.py); the project's ``build-fmus``
(the ``fmu_dir`` fixture) builds the same script without ``canGetAndSetFMUstate``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError, CouplingError
from openemss.orchestrator.master import algorithm_registry
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.master.iterative import IterativeGaussSeidel
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.recording.timeseries import read_timeseries
from openemss.orchestrator.scenarios.manipulators import ScenarioManipulator, load_scenario
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import Comp, write_system

CONNECTORS = [("u", "input", "Real"), ("y", "output", "Real"), ("x", "output", "Real")]
H = 0.1  # macro step [s]
RING = [("a.y", "b.u"), ("b.y", "a.u")]


def ring(folder: Path, fmu: Path, a: dict[str, float], b: dict[str, float]) -> Path:
    write_system(folder, fmu.parent, [Comp("a", fmu.name, CONNECTORS, a), Comp("b", fmu.name, CONNECTORS, b)], RING)
    return folder


def run(folder: Path, algorithm: str, steps: int, scenario: Path | None = None) -> tuple[dict[str, np.ndarray],
                                                                                          Execution]:
    ex = Execution(bind_system(load_system(folder)), algorithm, rate_hz=1 / H, record=["a.u", "a.x", "b.u"])
    if scenario is not None:
        ex.add_manipulator(ScenarioManipulator(load_scenario(scenario)))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(steps * H)
    return rec.result(), ex


def test_the_registry_offers_it_and_the_command_line_reads_the_registry() -> None:
    assert "gauss-seidel-iterative" in algorithm_registry.names()
    from openemss.orchestrator.cli.main import build_parser

    run_parser = build_parser()._subparsers._group_actions[0].choices["run"]  # type: ignore[union-attr]
    choices = next(a.choices for a in run_parser._actions if a.dest == "algorithm")
    assert tuple(choices) == algorithm_registry.names()


def test_algebraic_loop_sits_at_its_fixed_point_in_every_step(tmp_path: Path, state_fmu: Path) -> None:
    ka, kb, cb = 0.5, -0.5, 2.0
    folder = ring(tmp_path / "sys", state_fmu, {"k": ka, "c": 1.0}, {"k": kb, "c": cb})
    scenario = tmp_path / "ramp.yaml"  # c_a from 1 to 3 over 2 s: the fixed point moves every step
    scenario.write_text("events:\n  - from: 0.0\n    to: 2.0\n    ramp: {a.c: [1.0, 3.0]}\n")
    r, ex = run(folder, "gauss-seidel-iterative", 20, scenario)
    t = r["time_s"]
    ca = 1.0 + 2.0 * np.clip(t - H, 0.0, 2.0) / 2.0  # the c_a the step that ended at t used (set at t - h)
    fixed = (kb * ca + cb) / (1 - ka * kb)
    # tolerance: the convergence test's (rtol 1e-8) on values of order 1, times a few sweeps' margin
    assert np.max(np.abs(r["a.u"][1:] - fixed[1:])) < 1e-7
    assert np.max(np.abs(r["b.u"][1:] - (ka * r["a.u"][1:] + ca[1:]))) < 1e-7
    assert isinstance(ex.algorithm, IterativeGaussSeidel) and ex.algorithm.iterations[0] > 2
    plain, _ = run(folder, "gauss-seidel", 20, scenario)  # the same test fails without the iteration
    assert np.max(np.abs(plain["a.u"][1:] - fixed[1:])) > 1e-3


def test_dynamic_loop_follows_the_implicit_coupling_in_closed_form(tmp_path: Path, state_fmu: Path) -> None:
    ka, ca, g, kb, cb, n = 0.5, 1.0, 0.5, -0.5, 2.0, 20
    folder = ring(tmp_path / "sys", state_fmu, {"k": ka, "c": ca, "g": g}, {"k": kb, "c": cb})
    r, _ = run(folder, "gauss-seidel-iterative", n)
    # u_n = kb*(ka*u_n + ca + x_n + g*h*u_n) + cb (the outputs at the end of the step, x_{n+1} = x_n + g*h*u_n)
    d = 1.0 - ka * kb - kb * g * H
    alpha, beta = g * H * kb / d, g * H * (kb * ca + cb) / d
    steps = np.arange(n + 1)
    x = (0.0 + beta / alpha) * (1.0 + alpha) ** steps - beta / alpha
    assert np.max(np.abs(r["a.x"] - x)) < 1e-8  # a state stepped more than once per step would run ahead
    u = (kb * (ca + x[:-1]) + cb) / d  # the converged input of each step, recorded at its end
    assert np.max(np.abs(r["a.u"][1:] - u)) < 1e-7
    plain, _ = run(folder, "gauss-seidel", n)
    assert np.max(np.abs(plain["a.x"] - x)) > 1e-4


def test_a_loop_gain_above_one_fails_with_one_line(tmp_path: Path, state_fmu: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    folder = ring(tmp_path / "sys", state_fmu, {"k": 1.5, "c": 0.0}, {"k": 1.0, "c": 0.0})  # settles at 0
    scenario = tmp_path / "kick.yaml"
    scenario.write_text("events:\n  - at: 0.5\n    set: {a.c: 1.0}\n")
    with pytest.raises(CouplingError, match=r"loop a -> b did not converge in 50 sweeps in the step from t = 0.5 s"):
        run(folder, "gauss-seidel-iterative", 10, scenario)
    rc = main(["run", str(folder), "--algorithm", "gauss-seidel-iterative", "--scenario", str(scenario),
               "--stop-time", "1", "--rate", "10", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 3 and len(err) == 1 and "did not converge" in err[0] and ("a.u" in err[0] or "b.u" in err[0]), err
    assert len(read_timeseries(tmp_path / "out")) == 6  # what was recorded is kept: t = 0 to 0.5 s


def test_fmus_that_cannot_restore_their_state_are_refused(tmp_path: Path, fmu_dir: Path) -> None:
    folder = ring(tmp_path / "sys", fmu_dir / "LoopElement.fmu", {"c": 1.0}, {"c": 2.0})
    with pytest.raises(ConfigurationError, match="a, b in a loop cannot get and set its FMU state"):
        Execution(bind_system(load_system(folder)), "gauss-seidel-iterative")
    Execution(bind_system(load_system(folder)), "gauss-seidel")  # no loop iterated, no state needed


def test_loop_members_must_step_every_macro_step(tmp_path: Path, state_fmu: Path) -> None:
    folder = ring(tmp_path / "sys", state_fmu, {"c": 1.0}, {"c": 2.0})
    with pytest.raises(ConfigurationError, match="b in the loop a -> b must step every macro step"):
        Execution(bind_system(load_system(folder)), "gauss-seidel-iterative", multiples={"b": 2})
