"""The recorders' cost per macro step on the Munich system's exchange vectors, without the FMUs.

Lays out the exchange vectors of ``ssp/`` exactly as a run does (the Execution's own layout, no FMU
instantiated), then times ``sample`` for 66 049 macro steps (the whole Munich mission at 20 Hz) and
``finish`` of each recorder, best of three, all in this process:

* ``csv, every connector``: the recorder and the columns ``emss run`` wrote before issue 17 (98 or
  more columns of text);
* ``csv``, ``parquet``, ``mat`` on ``emss run``'s columns today (outputs, and inputs not merely
  copying a connected output).

The vectors change between samples (one value per step), as in a run. The machine's speed is printed
with a fixed Python workload before and after (compare runs at equal calibration). Nothing asserted.

Run: ``python benchmarks/recorders.py [--steps N]``
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--steps", type=int, default=66049, help="macro steps (default: the Munich mission's)")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from mission import calibration_ms

    from openemss.orchestrator.fmu.build import ensure_built
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.timeseries import default_record, recorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    ensure_built(ROOT / "fmus", ROOT / "ssp" / "resources")
    bound = bind_system(load_system(ROOT / "ssp"))
    cal = calibration_ms()
    rows = []
    run = Execution(bound, record=default_record(bound, inputs=True))
    run.initialize(1.0)  # the run's layout of the exchange vectors (the FMUs instantiated, never stepped)
    default = set(default_record(bound))
    real = run.vectors["Real"].outputs
    for label, fmt, inputs in (("csv, every connector (before)", "csv", True), ("csv", "csv", False),
                               ("parquet (default)", "parquet", False), ("mat", "mat", False)):
        ex = SimpleNamespace(system=run.system, vectors=run.vectors, time_s=0.0,
                             signals=[s for s in run.signals if inputs or s.path in default])
        best = float("inf")
        size = 0
        for _ in range(3):
            work = Path(tempfile.mkdtemp(prefix="emss-bench-rec-"))
            try:
                rec = recorder(fmt, work)
                rec.start(ex)
                t0 = time.perf_counter()
                for k in range(args.steps):
                    real[k % len(real)] = k * 1e-3
                    rec.sample(k, k * 0.05)
                rec.finish(ex, None)
                best = min(best, time.perf_counter() - t0)
                size = sum(f.stat().st_size for f in work.rglob("*") if f.is_file())
            finally:
                shutil.rmtree(work, ignore_errors=True)
        rows.append((label, len(ex.signals) + 1, best, size))
    base = rows[0][2]
    print(f"recorders over {args.steps} macro steps of the Munich system's exchange vectors (best of 3)")
    print(f"{'recorder':<32}{'columns':>8}{'us/step':>10}{'ratio':>8}{'MB':>8}")
    for label, ncol, sec, size in rows:
        print(f"{label:<32}{ncol:>8}{1e6 * sec / args.steps:>10.2f}{sec / base:>8.3f}{size / 1e6:>8.1f}")
    print(f"machine speed: a fixed Python workload took {cal:.1f} ms before and {calibration_ms():.1f} ms after")
    run._finish(None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
