"""Engine FMU speed: cost of one 50 ms engine step, in the FMU as our orchestrator runs it and in Python.

Targets: issue 5, under 150 microseconds per 50 ms step (the engine alone at 300x real time);
issue 18 point 5, the model at most 25 us per step on the mission-like profile. Prints a table (median and best of several repeats, microseconds per step) and a
cProfile summary of where the time of a step goes; asserts nothing (DESIGN.md, rule 12).

Cases (Larzac 04 preset, explicit Euler, one internal step):

* ``mission, compiled cycle`` / ``mission, compiled iteration`` / ``mission, compiled step``: the
  mission-like profile of :func:`_mission_inputs` (take-off, climb to 7500 m and Mach 0.75,
  cruise, idle descent, slam and chop) with a rate-limited fuel controller, on the compiled gas
  path driven by the Python chord iteration, with the iteration compiled as well
  (:mod:`.jit_solve`) in the Python step, and with the whole step compiled (:mod:`.jit_step`, the
  default); all three give the same outputs (printed); they run in turn, repeat by repeat, so
  that they see the same load (the plain-Python gas path runs without numba only,
  ``OPENEMSS_NO_JIT=1``, in a process of its own);

* ``model, inputs held``: at 5000 m, Mach 0.6, N1 90 %, constant inputs (steady cruise): one
  gas-path match per step (at the new spool speeds);
* ``model, inputs changing``: fuel flow and altitude change every step (a fuel controller,
  a climb): two matches per step (the derivative at the step start with the new inputs, then
  the end state);
* ``FMU in our orchestrator``: the built ``Engine.fmu`` in a one-component SSP system, run by
  :class:`openemss.orchestrator.master.execution.Execution` (Jacobi, 20 Hz), inputs held at their
  start values, timed by the master's per-slave timers (doStep, gets and sets, as ``mission.py``); the
  difference to ``model, inputs held`` is the FMI and slave overhead.

    python benchmarks/bench_engine_fmu.py [--repeat 5] [--steps 200]
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import pstats
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from openemss.models.engine.engine_model import EngineInputs, EngineModel

ROOT = Path(__file__).resolve().parents[1]
ALT_M, MACH, H = 5000.0, 0.6, 0.05


def _model_runner(changing: bool, steps: int) -> tuple[EngineModel, object]:
    m = EngineModel("larzac04_sls")
    pt = m.od.solve(ALT_M, MACH, N1_pct=90.0)
    m.start(EngineInputs(pt.Wf_kg_s, ALT_M, MACH))
    k0 = [0]

    def run() -> None:
        for k in range(k0[0], k0[0] + steps):
            t = H * k
            if changing:
                m.step(H, EngineInputs(pt.Wf_kg_s * (1.0 + 0.02 * math.sin(0.5 * t)), ALT_M + 2.0 * t, MACH))
            else:
                m.step(H, EngineInputs(pt.Wf_kg_s, ALT_M, MACH))
        k0[0] += steps

    run()                                                       # warm: Jacobian cached
    return m, run


def _mission_inputs(t: float) -> tuple[float, float, float]:
    """(N1 demand [%], altitude [m], Mach [-]) of the mission-like profile at time t [s], 300 s in all:
    take-off roll and initial climb (0-40 s), climb to 7500 m accelerating to Mach 0.75 (40-150 s), cruise
    (150-210 s), idle descent to 1500 m (210-260 s), slam to 100 % and chop to idle at 1500 m (260-300 s)."""
    if t < 40.0:
        return 100.0, 3.0 * max(0.0, t - 25.0), min(0.3, 0.012 * t)
    if t < 150.0:
        f = (t - 40.0) / 110.0
        return 98.0, 45.0 + f * (7500.0 - 45.0), 0.3 + f * 0.45
    if t < 210.0:
        return 91.0 + 0.5 * math.sin(0.7 * t), 7500.0, 0.75
    if t < 260.0:
        f = (t - 210.0) / 50.0
        return 62.0, 7500.0 - f * 6000.0, 0.75 - f * 0.25
    return (100.0 if t < 275.0 else 62.0), 1500.0, 0.5


def _mission_runner(steps: int, compiled_iteration: bool = True,
                    compiled_step: bool = True) -> tuple[EngineModel, object]:
    """The engine flown through :func:`_mission_inputs` by a fuel controller as the FCS's: the fuel flow moves
    toward the N1 demand by at most 2 % (up) and 1 % (down) of design fuel flow per 50 ms step, not below
    15 %; `compiled_iteration` False: the compiled cycle driven by the Python chord iteration (as before the
    iteration was compiled); `compiled_step` False: the Python step around the compiled iteration (as before
    the step was compiled, :mod:`.jit_step`)."""
    m = EngineModel("larzac04_sls")
    m.tr.compiled_iteration = compiled_iteration
    m.compiled_step = compiled_step and compiled_iteration
    N1d, Wf_d = m.p.N1_rpm, m.dp.Wf_kg_s
    pt = m.od.solve(0.0, 0.0, N1_pct=60.0)
    m.start(EngineInputs(pt.Wf_kg_s, 0.0, 0.0))
    wf = [pt.Wf_kg_s]

    def run() -> None:
        for k in range(steps):
            n1, alt, mach = _mission_inputs(H * k)
            err = n1 - 100.0 * m.values[4] / N1d
            wf[0] = max(0.15 * Wf_d, wf[0] + max(-0.01 * Wf_d, min(0.02 * Wf_d, 0.004 * Wf_d * err)))
            m.step(H, EngineInputs(wf[0], alt, mach))

    return m, run


def _time(run: object, steps: int, repeat: int) -> tuple[float, float]:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run()                                                   # type: ignore[operator]
        out.append((time.perf_counter() - t0) / steps)
    return statistics.median(out), min(out)


def _fmu_case(steps: int, repeat: int) -> tuple[float, float] | str:
    try:
        sys.path.insert(0, str(ROOT / "tests"))
        from openemss.orchestrator.fmu.build import ensure_built
        from openemss.orchestrator.master.execution import Execution
        from openemss.orchestrator.ssp.read import load_system
        from openemss.orchestrator.ssp.system import bind_system
        from systems import Comp, write_system
    except ImportError as exc:                                  # pragma: no cover
        return f"not run: {exc}"
    tmp = Path(tempfile.mkdtemp(prefix="bench_engine_fmu_"))
    try:
        (fmu,) = ensure_built(ROOT / "fmus", tmp / "fmus", names=["engine"])
        m = EngineModel("larzac04_sls")
        pt = m.od.solve(ALT_M, MACH, N1_pct=90.0)
        folder = tmp / "system"
        (folder / "resources").mkdir(parents=True)
        shutil.copy2(fmu, folder / "resources" / fmu.name)
        comp = Comp("engine", fmu.name, [("Fn_N", "output", "Real"), ("N1_rpm", "output", "Real")],
                    {"alt_m": ALT_M, "mach": MACH, "start_Wf_kg_s": float(pt.Wf_kg_s)})
        write_system(folder, fmu.parent, [comp], [], copy_fmus=False)
        warm = 20                                               # steps before the timing starts

        class _Window:
            """The FMU's doStep, gets and sets [s] after the first `warm` steps, by the master's own per-slave
            timers (as ``mission.py``): neither the set-up and initialisation, which vary more from run to run
            than a few hundred steps take, nor the first steps (the compiled step taking over) are in it."""

            def __init__(self) -> None:
                self.ex: Any = None
                self.t0 = 0.0

            def _busy(self) -> float:
                st = self.ex.stats()["engine"]
                return st["do_step_s"] + st["get_s"] + st["set_s"]

            def start(self, execution: Any) -> None:
                self.ex = execution

            def sample(self, k: int, time_s: float) -> None:
                if k == warm:
                    self.t0 = self._busy()

            def finish(self, execution: Any, error: BaseException | None) -> None:
                self.t1 = self._busy()

        def run(n: int) -> float:
            w = _Window()
            ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="jacobi")
            ex.add_observer(w)
            ex.run((n + warm) * H)
            return (w.t1 - w.t0) / n

        out = [run(steps) for _ in range(repeat)]
        return statistics.median(out), min(out)
    finally:
        pass                                                    # the library stays loaded: keep its files


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--steps", type=int, default=200)
    a = ap.parse_args()
    rows = []
    n_mis = int(round(300.0 / H))
    t0 = time.perf_counter()
    m, run = _mission_runner(2)
    run()                                                       # type: ignore[operator]
    t_first = time.perf_counter() - t0
    finals = []
    cases = (("mission, compiled cycle", False, False), ("mission, compiled iteration", True, False),
             ("mission, compiled step", True, True))
    meds: dict[str, list[float]] = {c[0]: [] for c in cases}
    for k in range(max(1, a.repeat // 2)):
        for name, it, step in cases:               # in turn: they see the same load
            m, run = _mission_runner(n_mis, it, step)
            meds[name].append(_time(run, n_mis, 1)[0])
            if k == 0:
                finals.append(list(m.values))
    rows += [(name, statistics.median(meds[name]), min(meds[name])) for name, *_ in cases]
    for name, changing in (("model, inputs held", False), ("model, inputs changing", True)):
        m, run = _model_runner(changing, a.steps)
        med, best = _time(run, a.steps, a.repeat)
        rows.append((name, med, best))
    fmu = _fmu_case(a.steps, a.repeat)
    print(f"one 50 ms engine step (target 150 us); mission-like profile: {n_mis} steps (300 s), "
          f"other cases {a.steps} steps x {a.repeat} repeats")
    print(f"first engine built and stepped in this process: {t_first:.2f} s (kernel compiled or loaded "
          "from the cache)")
    print(f"{'case':<28} {'median us':>10} {'best us':>10} {'x real time':>12}")
    for name, med, best in rows:
        print(f"{name:<28} {med * 1e6:10.0f} {best * 1e6:10.0f} {H / med:12.0f}")
    print(f"compiled iteration / Python iteration on the compiled cycle: {rows[1][1] / rows[0][1]:.3f} "
          f"(speed-up {rows[0][1] / rows[1][1]:.1f} x); "
          f"compiled step / Python step around the compiled iteration: {rows[2][1] / rows[1][1]:.3f} "
          f"(speed-up {rows[1][1] / rows[2][1]:.1f} x; best {rows[2][2] / rows[1][2]:.3f})")
    same = max(abs(x - y) for x, y in zip(finals[0], finals[1], strict=True))
    same_step = max(abs(x - y) for x, y in zip(finals[1], finals[2], strict=True))
    print(f"outputs at the end of the mission-like profile, largest difference: compiled iteration vs Python "
          f"iteration {same:.3g}, compiled step vs Python step {same_step:.3g}")
    if isinstance(fmu, tuple):
        print(f"{'FMU in our orchestrator':<28} {fmu[0] * 1e6:10.0f} {fmu[1] * 1e6:10.0f} {H / fmu[0]:12.0f}")
    else:
        print(f"FMU in our orchestrator: {fmu}")
    m, run = _model_runner(True, a.steps)
    prof = cProfile.Profile()
    prof.enable()
    run()                                                       # type: ignore[operator]
    prof.disable()
    s = io.StringIO()
    pstats.Stats(prof, stream=s).sort_stats("tottime").print_stats(12)
    print("\ncProfile, model with inputs changing (tottime, top 12):")
    print("\n".join(line for line in s.getvalue().splitlines() if line.strip())[:4000])


if __name__ == "__main__":
    main()
