"""Engine model speed, this working tree against a git revision, in one process, interleaved.

The machine is shared and its load changes within seconds (up to 5x between the best and the
median of the same case), so a speed-up is only credible against a baseline measured
alongside. This script extracts the package of a git revision (default ``main``) to a temporary
folder (``git archive``) and imports it under another name (``openemss_base``; the engine
package imports itself relatively, and numba caches its kernels by module name, so both
coexist), then times both versions in alternating chunks of 100 steps, and prints best and
median per case and the ratio of the bests. Asserts nothing (DESIGN.md, rule 12).

Cases (Larzac 04 preset, 50 ms steps, explicit Euler, the default compiled path):

* ``mission``: ``bench_engine_fmu.py``'s mission-like profile (take-off, climb to 7500 m and
  Mach 0.75, cruise, idle descent, slam and chop, 300 s) with its fuel controller;
* ``held``: 5000 m, Mach 0.6, N1 90 %, inputs held (one match per step);
* ``changing``: the same with the fuel flow and altitude changing every step.

With ``--compile N`` it prints instead the first compile of each version (CPU seconds of a new process on an
empty kernel cache: the engine built, started and stepped three times), N alternating runs each.

    python benchmarks/bench_engine_versions.py [--rev main] [--rounds 30] [--compile N]
"""

from __future__ import annotations

import argparse
import importlib
import math
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_engine_fmu import _mission_inputs  # noqa: E402

_PACKAGES = ("orchestrator", "models", "fmus", "report", "study")
H, CHUNK, MISSION_STEPS = 0.05, 100, 6000


def _extract(rev: str, into: Path) -> None:
    """The package of `rev` as ``into/openemss_base`` (symlinks to the extracted folders)."""
    src = into / "src"
    src.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(src)], input=archive, check=True)
    pkg = into / "openemss_base"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    for name in _PACKAGES:
        if (src / name).is_dir():
            (pkg / name).symlink_to(src / name)


def _cases(E: Any) -> dict[str, Callable[[], None]]:
    """The three cases of one version (module ``engine_model`` E), each a function running the next chunk."""
    m = E.EngineModel("larzac04_sls")
    N1d, Wf_d = m.p.N1_rpm, m.dp.Wf_kg_s
    m.start(E.EngineInputs(m.od.solve(0.0, 0.0, N1_pct=60.0).Wf_kg_s, 0.0, 0.0))
    st = {"k": 0, "wf": m.state.Wf_kg_s}

    def mission() -> None:                     # bench_engine_fmu._mission_runner's fuel controller
        for _ in range(CHUNK):
            n1, alt, mach = _mission_inputs(H * (st["k"] % MISSION_STEPS))
            err = n1 - 100.0 * m.values[4] / N1d
            st["wf"] = max(0.15 * Wf_d, st["wf"] + max(-0.01 * Wf_d, min(0.02 * Wf_d, 0.004 * Wf_d * err)))
            m.step(H, E.EngineInputs(st["wf"], alt, mach))
            st["k"] += 1

    out = {"mission": mission}
    for changing in (False, True):
        mm = E.EngineModel("larzac04_sls")
        pt = mm.od.solve(5000.0, 0.6, N1_pct=90.0)
        mm.start(E.EngineInputs(pt.Wf_kg_s, 5000.0, 0.6))
        k = [0]

        def run(mm: Any = mm, pt: Any = pt, k: list[int] = k, changing: bool = changing) -> None:
            for _ in range(CHUNK):
                t = H * k[0]
                k[0] += 1
                mm.step(H, E.EngineInputs(pt.Wf_kg_s * (1.0 + 0.02 * math.sin(0.5 * t)), 5000.0 + 2.0 * t, 0.6)
                        if changing else E.EngineInputs(pt.Wf_kg_s, 5000.0, 0.6))

        out["changing" if changing else "held"] = run
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rev", default="main", help="git revision of the baseline (default main)")
    ap.add_argument("--rounds", type=int, default=30, help="chunks of 100 steps per case and version")
    ap.add_argument("--compile", type=int, default=0, metavar="N",
                    help="instead: the first compile of each version, N runs each on empty caches")
    a = ap.parse_args()
    if a.compile:
        compile_times(a.rev, a.compile)
        return
    with tempfile.TemporaryDirectory() as tmp:
        _extract(a.rev, Path(tmp))
        sys.path.insert(0, tmp)
        versions = {"old": _cases(importlib.import_module("openemss_base.models.engine.engine_model")),
                    "new": _cases(importlib.import_module("openemss.models.engine.engine_model"))}
        times: dict[str, dict[str, list[float]]] = {v: {c: [] for c in versions[v]} for v in versions}
        for _ in range(a.rounds):
            for case in ("mission", "held", "changing"):
                for v in ("old", "new"):                   # alternating: both see the same load
                    t0 = time.perf_counter()
                    versions[v][case]()
                    times[v][case].append((time.perf_counter() - t0) / CHUNK * 1e6)
    print(f"engine model, us per 50 ms step, {a.rounds} chunks of {CHUNK} steps per case, old and new alternating "
          f"in one process; old = {a.rev}, new = this working tree")
    print(f"{'case':12s}{'old best':>10s}{'new best':>10s}{'old median':>12s}{'new median':>12s}{'new/old best':>14s}")
    for case in ("mission", "held", "changing"):
        o, n = times["old"][case], times["new"][case]
        print(f"{case:12s}{min(o):10.1f}{min(n):10.1f}{statistics.median(o):12.1f}{statistics.median(n):12.1f}"
              f"{min(n) / min(o):14.3f}")


#: A child process's first compile: the engine built, started and stepped three times with an empty kernel cache.
_COMPILE = """
import os, sys, time, tempfile
sys.path.insert(0, sys.argv[1])
with tempfile.TemporaryDirectory() as cache:
    os.environ["OPENEMSS_JIT_CACHE"] = cache
    import importlib
    E = importlib.import_module(sys.argv[2] + ".models.engine.engine_model")
    m = E.EngineModel("larzac04_sls")
    u = E.EngineInputs(m.od.solve(5000.0, 0.6, N1_pct=90.0).Wf_kg_s, 5000.0, 0.6)
    m.start(u)
    for _ in range(3):
        m.step(0.05, u)
    print(time.process_time())
"""


def compile_times(rev: str, rounds: int) -> None:
    """Print the first compile [s of CPU] of `rev` and of this tree, each in a new process on an empty cache,
    alternating (``rounds`` each)."""
    with tempfile.TemporaryDirectory() as tmp:
        _extract(rev, Path(tmp))
        out: dict[str, list[float]] = {"old": [], "new": []}
        for _ in range(rounds):
            for v, pkg in (("old", "openemss_base"), ("new", "openemss")):
                res = subprocess.run([sys.executable, "-c", _COMPILE, tmp, pkg], check=True, capture_output=True,
                                     text=True)
                out[v].append(float(res.stdout.split()[-1]))
    print(f"first compile on an empty cache, s of CPU (engine built, started, three steps), {rounds} alternating "
          f"runs each; old = {rev}, new = this working tree")
    print(f"{'old best':>10s}{'new best':>10s}{'old median':>12s}{'new median':>12s}{'new/old best':>14s}")
    o, n = out["old"], out["new"]
    print(f"{min(o):10.1f}{min(n):10.1f}{statistics.median(o):12.1f}{statistics.median(n):12.1f}"
          f"{min(n) / min(o):14.3f}")


if __name__ == "__main__":
    main()
