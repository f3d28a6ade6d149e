"""The engine FMU alone on a whole mission's recorded inputs, layer by layer: where its in-mission step goes.

The Munich mission is run once (``emss run``, its default columns), or a finished run is given (``--run
DIR``). The engine FMU of that run's system is then stepped alone, open loop, in this process, over the
inputs it had in the run (the recorded outputs its connected inputs come from, at every 50 ms step: with
Jacobi, the step from t_k takes the samples at t_k), with the run's parameters. One instance takes every
step, so the trajectory is the mission's (the fuel burned at the end is printed beside the run's: the
same number to the last digit, when the replay is faithful); each step is timed in one of four ways, in
turn (step k by way k mod 4, the rounds shifting the assignment), so every way sees every phase of the
mission:

* ``model``: the engine model's ``step_array`` (``EngineModel``, the compiled step), the inputs written
  into its array as the FMU's ``do_step`` writes them;
* ``slave``: the FMU slave's ``do_step`` (``fmus/engine.py``, the Python pythonfmu calls), without the
  FMI C layer;
* ``fmi2DoStep``: the master's ``Slave.do_step`` (fmi2DoStep through pythonfmu's C layer), as in a run;
* ``fmi2DoStep, caches flushed``: the same, after touching ``--flush-mb`` MB of memory between two steps
  (untimed), the way the airframe and the FCS evict the engine's data between two of its steps in the
  coupled run.

The FMU is driven by the master's own :class:`.Slave` (its FMI calls); the inputs are set with one
fmi2SetReal before every step (untimed). The slave object is found in this
interpreter by its class (pythonfmu runs it here): a benchmark's reach into the FMU, never the master's.
Columns: us per step (mean over the steps timed that way, best of ``--rounds``) and the ratio to
``model``. The coupled mission's own figure, the engine's ``doStep`` among the other FMUs, is
``benchmarks/mission.py``'s. Nothing is asserted (DESIGN.md rule 12).

Run: ``python benchmarks/bench_engine_replay.py [--run DIR] [--rounds 2] [--flush-mb 4]``
"""
from __future__ import annotations

import argparse
import gc
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
H = 0.05
WAYS = ("model", "slave", "fmi2DoStep", "fmi2DoStep, caches flushed")


def record_run(work: Path) -> Path:
    """Run the project's Munich mission (``emss run``); returns the run's folder."""
    out = work / "run"
    print("recording the mission: emss run ssp --no-post-run ...", flush=True)
    proc = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli.main", "run", str(ROOT / "ssp"),
                           "--out", str(out), "--no-post-run"], cwd=ROOT, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"bench_engine_replay: the recording run failed: {proc.stderr.strip()}")
    return out


def engine_inputs(run: Path, component: str) -> tuple[Any, list[Any], np.ndarray, list[Any], float]:
    """(the component's model, its connected input variables, their values per step (n, k), its parameter
    assignments, the run's fuel burned [kg]) of a recorded run."""
    from openemss.orchestrator.recording.timeseries import read_timeseries
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    meta = json.loads((run / "run.json").read_text(encoding="utf-8"))
    bound = bind_system(load_system(Path(meta["system"])), [Path(f) for f in meta.get("parameter_files", [])])
    names = [c.name for c in bound.components]
    if component not in names:
        raise SystemExit(f"bench_engine_replay: the run's system has no component '{component}'")
    i = names.index(component)
    table = read_timeseries(run)
    links = [ln for ln in bound.links if ln.target == i]
    cols = []
    for ln in links:
        col = f"{names[ln.source]}.{ln.source_var.name}"
        if col not in table.data:
            raise SystemExit(f"bench_engine_replay: the run did not record {col} (the source of "
                             f"{component}.{ln.target_var.name})")
        cols.append(ln.affine.scale * np.asarray(table.data[col], dtype=float) + ln.affine.offset)
    params = [p for p in bound.parameters if p.component == i]
    fuel = float(table.data[f"{component}.fuel_burned_kg"][-1])
    return bound.components[i], [ln.target_var for ln in links], np.column_stack(cols), params, fuel


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--run", type=Path, help="a finished emss run (default: run the Munich mission now)")
    ap.add_argument("--component", default="engine", help="the engine's component name (default engine)")
    ap.add_argument("--rounds", type=int, default=2, help="replays of the whole mission (default 2)")
    ap.add_argument("--flush-mb", type=float, default=4.0, help="memory touched between steps (default 4 MB)")
    args = ap.parse_args(argv)
    from openemss.orchestrator.fmu.build import ensure_built
    from openemss.orchestrator.master.slave import FmuLog, Slave

    ensure_built(ROOT / "fmus", ROOT / "ssp" / "resources")  # the shipped system's FMUs from today's sources
    with tempfile.TemporaryDirectory() as tmp:
        run = args.run or record_run(Path(tmp))
        model, inputs, u, params, fuel_run = engine_inputs(run, args.component)
        kind = model.model_description.coSimulation.modelIdentifier
        junk = np.ones(max(1, int(args.flush_mb * 1e6) // 8))
        best = dict.fromkeys(WAYS, np.inf)
        buf = np.empty(len(inputs))
        for r in range(args.rounds):
            before = {id(o) for o in gc.get_objects() if type(o).__name__ == kind}
            fmu = Slave(model, FmuLog.shared())  # the master's own FMI calls
            fmu.instantiate()
            fmu.bind_io("Real", "set", inputs, buf)
            fmu.setup_experiment(0.0, None)
            for p in params:
                fmu.set_value(p.variable, p.value)
            buf[:] = u[0]
            fmu.set_inputs()
            fmu.enter_initialization_mode()
            fmu.exit_initialization_mode()
            slave = next(o for o in gc.get_objects() if type(o).__name__ == kind and id(o) not in before)
            total, count = np.zeros(len(WAYS)), np.zeros(len(WAYS))
            pc = time.perf_counter
            for k in range(u.shape[0] - 1):
                buf[:] = u[k]
                fmu.set_inputs()
                way = (k + r) % len(WAYS)
                if way == 0:  # the slave's do_step without its checks and its event count
                    uin = slave.model_inputs()  # untimed
                    t0 = pc()
                    slave._model.step_array(H, uin)
                    t1 = pc()
                    slave._yi[0] = slave._model.events
                elif way == 1:
                    t0 = pc()
                    slave.do_step(k * H, H)
                    t1 = pc()
                else:
                    if way == 3:
                        junk.sum()
                    t0 = pc()
                    fmu.do_step(k * H, H)
                    t1 = pc()
                total[way] += t1 - t0
                count[way] += 1
            fuel = fmu.get_value(model.variables["fuel_burned_kg"])
            for w, name in enumerate(WAYS):
                best[name] = min(best[name], total[w] / count[w] * 1e6)
            fmu.terminate()
            fmu.free()
        print(f"{args.component} FMU alone on the recorded inputs of {run}: {u.shape[0] - 1} steps of {H} s, "
              f"inputs {', '.join(v.name for v in inputs)}; best of {args.rounds} rounds")
        print(f"fuel burned at the end: replay {fuel!r} kg, the run {fuel_run!r} kg "
              f"({'the same' if fuel == fuel_run else 'DIFFERENT: the replay is not the run'})")
        print(f"\n{'way':30s} {'us/step':>8s} {'ratio':>6s}")
        print("-" * 46)
        for name in WAYS:
            print(f"{name:30s} {best[name]:8.1f} {best[name] / best['model']:6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
