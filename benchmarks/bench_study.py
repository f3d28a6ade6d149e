"""Study speed-up on Dask: the same study of N cases on a LocalCluster of 1 and of 2 worker processes.

Each case is ``emss run`` in its worker's warm case process (openemss.study.warm: the FMUs reset between
cases); the study's wall time includes starting the cluster and each worker's case process (imports, FMU
loading). Prints a table: workers, wall time, the sum of the cases' own times, the speed-up over one worker,
the cases' time split into set-up, stepping and writing (study.csv's columns, summed) and the share of the
workers' time spent stepping (sum of stepping / (wall x workers)); asserts nothing (DESIGN.md, rule 12).
Targets: at least 1.8x with 2 workers on a 2-core machine (issue 9); at least 85 % stepping (issue 35).

Systems:

* ``ssp`` (default): the project's engine + airframe + FCS system taking off from EDDM
  (``--stop-time`` seconds of the Munich mission), four engines: presets larzac04_sls and
  reference_study, each starting at N1 60 % and 65 %;
* ``oscillator``: the two-mass oscillator example, N masses, 400 s each at 100 Hz Gauss-Seidel
  (stable; Jacobi at 20 Hz grows without bound over such runs).

    python benchmarks/bench_study.py [--system ssp|oscillator] [--cases 4] [--stop-time 40] [--work DIR]
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from openemss.study.plan import expand_cases
from openemss.study.runner import run_cases
from openemss.study.spec import load_study

ROOT = Path(__file__).resolve().parents[1]


def study_file(folder: Path, system: str, cases: int, stop_time_s: float) -> Path:
    if system == "ssp":
        n1 = ", ".join(str(60.0 + 5.0 * i) for i in range((cases + 1) // 2))
        text = (f"study: bench_ssp\nsystem: {ROOT / 'ssp'}\nstop_time_s: {stop_time_s}\n"
                f"grid:\n  engine.preset: [larzac04_sls, reference_study]\n  engine.start_N1_pct: [{n1}]\n")
    else:
        masses = ", ".join(str(1.0 + 0.5 * i) for i in range(cases))
        text = (f"study: bench_oscillator\nsystem: {ROOT / 'examples' / 'oscillator'}\n"
                f"stop_time_s: {stop_time_s}\nrate_hz: 100\nalgorithm: gauss-seidel\nrecord_every: 100\n"
                f"grid:\n  mass1.m1_kg: [{masses}]\n")
    path = folder / f"{system}.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--system", choices=("ssp", "oscillator"), default="ssp")
    ap.add_argument("--cases", type=int, default=4, help="number of cases (default 4)")
    ap.add_argument("--stop-time", type=float, default=None,
                    help="simulated time per case [s] (default: 40 for ssp, 400 for the oscillator)")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2], help="worker counts to compare")
    ap.add_argument("--work", type=Path, help="keep the study folders here (default: a temporary folder)")
    args = ap.parse_args(argv)
    stop = args.stop_time if args.stop_time is not None else (40.0 if args.system == "ssp" else 400.0)
    work = args.work or Path(tempfile.mkdtemp(prefix="bench_study_"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        cases = expand_cases(load_study(study_file(work, args.system, args.cases, stop)))[:args.cases]
        print(f"study: {len(cases)} cases of {args.system}, {stop:g} s simulated each; {os.cpu_count()} cores; "
              f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
        rows = []
        for n in args.workers:
            out = work / f"workers{n}"
            shutil.rmtree(out, ignore_errors=True)
            t0 = time.perf_counter()
            res = run_cases(cases, out, workers=n, stream=open(os.devnull, "w"))  # noqa: SIM115
            wall = time.perf_counter() - t0
            bad = [k for k, r in res.results.items() if r.status != "completed"]
            case_s = sum(r.process_time_s or 0.0 for r in res.results.values())
            split = [sum(getattr(r, k) or 0.0 for r in res.results.values())
                     for k in ("setup_s", "stepping_s", "writing_s")]
            rows.append((n, wall, case_s, split, res.stepping_fraction or 0.0, bad))
            print(f"  {n} worker(s): {wall:.1f} s wall", flush=True)
        base = rows[0][1]
        head = (f"{'workers':>7} {'cases':>5} {'wall s':>8} {'sum of case s':>13} {'speed-up':>8} {'setup s':>8} "
                f"{'stepping s':>10} {'writing s':>9} {'stepping %':>10}  failed")
        print(head)
        print("-" * len(head))
        for n, wall, case_s, (su, st, wr), frac, bad in rows:
            print(f"{n:>7} {len(cases):>5} {wall:>8.1f} {case_s:>13.1f} {base / wall:>7.2f}x {su:>8.1f} {st:>10.1f} "
                  f"{wr:>9.1f} {100 * frac:>10.1f}  {', '.join(bad) or '-'}")
        print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    finally:
        if args.work is None:
            shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
