"""The FCS alone over a whole mission: its inputs recorded in one coupled run, replayed into the FCS.

The Munich mission is run once (``emss run --record fcs.lat_deg,...,fcs.on_ground``: the FCS's 19
inputs at every 50 ms step, and its parameters from ``run.json``), or a recorded run is given
(``--run DIR``, a folder of ``emss run`` holding its time series with the FCS's inputs, as ``--record-inputs``
records them, and ``run.json``). The FCS is then
stepped alone over those inputs, open loop, in this process: the FMU's slave class of
``fmus/fcs.py`` called directly (``set_real`` of the inputs, ``set_boolean`` of ``on_ground``,
``do_step``, ``get_real`` of the outputs), without pythonfmu's C layer and without the engine and
the airframe in between, so the figure is steady on a loaded machine, where the mission's is not.
The FCS flies the same sections at the same instants as in the run (its inputs are the run's), so
every section type, the VNAV plans and the approach and landing are in the figure with their share
of the mission's time.

Rows, each the best of ``--repeat`` replays, run interleaved (row by row, ``--repeat`` rounds), the
garbage collector off while timing:

* ``outer loops every step``: ``guidance.outer_period_s = 0``, the navigation sections' logic, L1
  guidance and vertical path at every step, as before issue 14 point 8;
* ``as shipped``: the parameters of the run (``guidance.outer_period_s`` at its default, 0.2 s);
* ``REV, as shipped`` with ``--baseline REV``: the same replay with the FCS of git revision ``REV``
  of this repository (its ``models/`` and ``fmus/``, exported with ``git archive``), in a child
  process, interleaved with the rows above: the before/after of a change on the same inputs.

Columns: µs per step of the replay loop (the slave's ``do_step`` with its gets and sets in Python), in
CPU time of the replaying process (``time.process_time``: the time spent waiting for a core on a shared
machine is not counted, what the other processes do to the caches is), and that time as a ratio to the
first row. The set-up (loading the mission, the VNAV's first
plans) is not timed. ``--steps N`` replays the first N steps only. Nothing is asserted
(DESIGN.md rule 12). The real-time mission figure (``benchmarks/mission.py``) times the FMU's
``fmi2DoStep`` and its gets and sets through pythonfmu's C layer, with the other models' work
between two FCS steps; it is about 1.2 to 1.4 times this replay's figure.

For instruction counts, which do not depend on the load, run a replay under callgrind:
``valgrind --tool=callgrind python benchmarks/bench_fcs_replay.py --run DIR --replay-only ROW``
(see benchmarks/README.md).

Run: ``python benchmarks/bench_fcs_replay.py [--run DIR] [--repeat 3] [--steps N] [--baseline REV]``
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
H = 0.05
ROWS = {"every": ("outer loops every step", {"guidance.outer_period_s": 0.0}), "shipped": ("as shipped", {})}


def record_run(work: Path) -> Path:
    """Run the project's Munich mission with every FCS variable recorded; returns the run's folder."""
    from openemss.fmus.fcs import INPUTS

    out = work / "run"
    inputs = ",".join(f"fcs.{name}" for name, _ in INPUTS) + ",fcs.on_ground"
    cmd = [sys.executable, "-m", "openemss.orchestrator.cli", "run", str(ROOT / "ssp"), "--out", str(out),
           "--record", inputs, "--until", "fcs.mission_completed == 1", "--no-post-run"]
    print("recording the FCS's inputs: emss run ssp --record fcs.<inputs> --no-post-run ...", flush=True)
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"bench_fcs_replay: the recording run failed: {done.stderr.strip().splitlines()[-1:]}")
    return out


def load_run(run: Path) -> tuple[list[float], list[list[float]], list[bool], dict[str, float], dict]:
    """(times, Real inputs per step in the order of fmus.fcs.INPUTS, on_ground per step, the FCS's parameters,
    run.json) of a recorded run."""
    from openemss.fmus.fcs import INPUTS
    from openemss.orchestrator.recording.timeseries import TimeSeriesError, read_timeseries

    if not (run / "run.json").is_file():
        raise SystemExit(f"bench_fcs_replay: --run {run}: no run.json; give the folder of a finished emss run")
    meta = json.loads((run / "run.json").read_text(encoding="utf-8"))
    params = {k[4:]: v for k, v in meta.get("parameters", {}).items() if k.startswith("fcs.")}
    try:
        data = read_timeseries(run).floats()  # any format emss run writes (Parquet by default)
    except TimeSeriesError as exc:
        raise SystemExit(f"bench_fcs_replay: --run {run}: {exc}") from None
    missing = [n for n in ["time_s", "fcs.on_ground", *(f"fcs.{name}" for name, _ in INPUTS)] if n not in data]
    if missing:
        raise SystemExit(f"bench_fcs_replay: --run {run} lacks FCS inputs ({', '.join(missing[:3])}); record them "
                         "(emss run --record-inputs, or --record fcs.<inputs>)")
    t = data["time_s"].tolist()
    u = [list(row) for row in zip(*(data[f"fcs.{name}"].tolist() for name, _ in INPUTS), strict=True)]
    g = (data["fcs.on_ground"] > 0.5).tolist()
    return t, u, g, params, meta


def replay(run: Path, row: str, steps: int | None) -> float:
    """One replay of ``run`` with the parameters of ``row`` (a key of ROWS); returns µs per step."""
    from openemss.fmus.fcs import INPUTS, OUTPUTS, Fcs

    t, u, g, params, _ = load_run(run)
    n = len(t) if steps is None else min(steps, len(t))
    s = Fcs(instance_name="replay", resources=str(ROOT))
    vr = {v.name: k for k, v in s.vars.items()}
    for name, value in (params | ROWS[row][1]).items():  # as the master sets them, before the initialization
        if "." in name:
            s.set_real([vr[name]], [value])  # a gain: pythonfmu's variable, through its setter
        elif name in vr:
            setattr(s, name, value)  # a parameter of the FMU itself (Wf0_kg_s, ...)
    s.exit_initialization_mode()
    in_vr, out_vr, og_vr = [vr[k] for k, _ in INPUTS], [vr[k] for k, _ in OUTPUTS], [vr["on_ground"]]
    set_real, set_bool, do_step, get_real = s.set_real, s.set_boolean, s.do_step, s.get_real
    gc.collect()
    gc.disable()
    t0 = time.process_time()  # CPU time of this process: the replay is single-threaded, and waiting for a
    for k in range(n):           # core on a loaded machine is not counted
        set_real(in_vr, u[k])
        set_bool(og_vr, [g[k]])
        do_step(t[k], H)
        get_real(out_vr)
    dt = time.process_time() - t0
    gc.enable()
    return 1e6 * dt / n


def _export(rev: str, work: Path) -> Path:
    """``models/``, ``fmus/`` and ``missions/`` of git revision ``rev``, importable as ``openemss``; returns
    the folder to put first on ``sys.path``."""
    src = work / f"rev-{rev.replace('/', '_')}"
    archive = work / "rev.tar"
    with open(archive, "wb") as f:
        done = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "models", "fmus", "missions"], stdout=f,
                              stderr=subprocess.PIPE, text=False)
    if done.returncode != 0:
        raise SystemExit(f"bench_fcs_replay: --baseline {rev}: {done.stderr.decode().strip()}")
    with tarfile.open(archive) as tar:
        tar.extractall(src / "openemss", filter="data")
    (src / "openemss" / "__init__.py").write_text("", encoding="utf-8")
    return src


def _child(run: Path, row: str, steps: int | None, path: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(path))
    cmd = [sys.executable, str(Path(__file__)), "--run", str(run), "--replay-only", row,
           "--root", str(path / "openemss")]
    if steps is not None:
        cmd += ["--steps", str(steps)]
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise SystemExit(f"bench_fcs_replay: the baseline's replay failed: {done.stderr.strip()[-400:]}")
    return float(done.stdout.split()[-1])


def main(argv: list[str] | None = None) -> int:
    global ROOT
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--run", type=Path, help="the folder of a finished emss run of the mission, every connector "
                                             "recorded (the default); default: record one")
    ap.add_argument("--repeat", type=int, default=3, help="rounds, best kept (default 3)")
    ap.add_argument("--steps", type=int, help="replay the first N steps only (default: all)")
    ap.add_argument("--baseline", metavar="REV", help="also replay the FCS of this git revision (e.g. main)")
    ap.add_argument("--replay-only", choices=sorted(ROWS), help=argparse.SUPPRESS)
    ap.add_argument("--root", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.root is not None:  # a child replaying an exported revision: its mission file and data
        ROOT = args.root
    if args.replay_only:
        print(f"{replay(args.run, args.replay_only, args.steps):.3f}")
        return 0
    work = Path(tempfile.mkdtemp(prefix="emss-bench-fcs-"))
    try:
        run = args.run if args.run is not None else record_run(work)
        t, _, _, params, meta = load_run(run)
        n = len(t) if args.steps is None else min(args.steps, len(t))
        base_path = _export(args.baseline, work) if args.baseline else None
        rows = list(ROWS) + (["baseline"] if base_path is not None else [])
        best = {r: float("inf") for r in rows}
        for _ in range(max(args.repeat, 1)):
            for r in rows:
                us = _child(run, "shipped", args.steps, base_path) if r == "baseline" else replay(run, r, args.steps)
                best[r] = min(best[r], us)
        stats = meta.get("step_statistics", {}).get("fcs")
        print(f"\nFCS alone over {n} steps of 50 ms ({t[n - 1]:.1f} s) of the recorded mission "
              f"({run}); best of {args.repeat}, interleaved; parameters {params or 'the defaults'}")
        print(f"{'row':40s} {'us/step':>9} {'x first':>8}")
        print(f"{'-' * 40} {'-' * 9} {'-' * 8}")
        first = best[rows[0]]
        for r in rows:
            name = f"{args.baseline}, as shipped" if r == "baseline" else ROWS[r][0]
            print(f"{name:40s} {best[r]:9.1f} {best[r] / first:8.2f}")
        if stats and stats.get("steps"):
            fmi = stats["do_step_s"] + stats["get_s"] + stats["set_s"]
            print(f"(in the recording run, coupled, through FMI: doStep {1e6 * stats['do_step_s'] / stats['steps']:.1f}"
                  f" + get/set {1e6 * (stats['get_s'] + stats['set_s']) / stats['steps']:.1f} = "
                  f"{1e6 * fmi / stats['steps']:.1f} us/step)")
        print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
