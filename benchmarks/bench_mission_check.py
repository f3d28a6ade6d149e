"""Wall time of ``emss mission check`` and where it goes: binding the system, the performance points (JSBSim
trims and engine matches), the check itself. Prints a table; asserts nothing (DESIGN.md, rule 12).

    python benchmarks/bench_mission_check.py [MISSION] [--repeat 3]

Each repeat builds a fresh performance model (no point kept from the last), as one ``emss mission check``
does; the engine's compiled kernels are cached on disk after the first run ever (about 10 s to compile).
"""
from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from openemss.models.mission.mission import load_mission
from openemss.orchestrator.fmu.build import PACKAGE_ROOT
from openemss.report import mission_check
from openemss.report.model_performance import ModelPerformance


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mission", nargs="?", type=Path, default=PACKAGE_ROOT / "missions" / "munich.yaml")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    counts = {"trim": 0, "engine": 0}
    point, solve = ModelPerformance.point, ModelPerformance._solve

    def counted_point(self, *a, **k):  # type: ignore[no-untyped-def]
        n = len(self._points)
        out = point(self, *a, **k)
        counts["trim"] += len(self._points) - n
        return out

    def counted_solve(self, *a, **k):  # type: ignore[no-untyped-def]
        n = len(self._engine)
        out = solve(self, *a, **k)
        counts["engine"] += len(self._engine) - n
        return out

    ModelPerformance.point, ModelPerformance._solve = counted_point, counted_solve  # type: ignore[method-assign]
    rows = []
    for _ in range(args.repeat):
        counts.update(trim=0, engine=0)
        t0 = time.perf_counter()
        components, values = mission_check._bind(PACKAGE_ROOT / "ssp", [], [])
        setup = mission_check.setup_from_system(components, values, "ssp")
        t1 = time.perf_counter()
        mission = load_mission(args.mission)
        check = mission_check.run_check(mission, setup)
        t2 = time.perf_counter()
        rows.append((t1 - t0, t2 - t1, counts["trim"], counts["engine"], len(check.sections)))
    print(f"emss mission check {args.mission.name}: {rows[0][4]} sections, {args.repeat} repeats")
    print(f"{'run':>4} {'bind system s':>14} {'check s':>9} {'trims':>6} {'engine points':>14}")
    for i, (b, c, nt, ne, _) in enumerate(rows):
        print(f"{i:>4} {b:>14.3f} {c:>9.3f} {nt:>6} {ne:>14}")
    bind, chk = statistics.median(r[0] for r in rows), statistics.median(r[1] for r in rows)
    print(f"median: bind {bind:.3f} s, check {chk:.3f} s (target: the whole command under 10 s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
