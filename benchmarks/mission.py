"""Real-time factor of the whole coupled Munich mission, and where the time goes.

Runs ``ssp/`` (engine, airframe and FCS FMUs wired by the shipped SSD, the Munich mission of
``missions/munich.yaml``) in our orchestrator at 20 Hz, Jacobi, recording every connector to
``timeseries.csv`` as ``emss run`` does, and prints:

* the real-time factor of the run (simulated time / wall time), against the targets of issue 8
  (at least 100x, aiming at 200x), and the engine-less floor: the same system's cost without the
  engine's share, i.e. what the real-time factor would be with an engine that cost nothing;
* per component: time in ``fmi2DoStep``, in the batched gets and sets (the FMI calls into
  pythonfmu), µs per macro step and share of the wall time, and the batched sets the master left
  out per step because their values were those it had sent last;
* the orchestrator's own share: wall time minus everything spent inside the FMUs (transfers,
  recording, the loop itself);
* the recorders' cost per macro step (sampling and writing, the end of the run included; their
  ``start``, before the first step -- imports, the file's schema -- is printed apart, in ms, as the
  FMUs' set-up is), for every
  format of ``--formats`` (default ``csv,parquet``: the former default and today's), all attached to
  the same run and recording the same columns, so their ratio is free of the machine's load; the
  columns are ``emss run``'s default (outputs, and inputs not merely copying a connected output), or
  every connector with ``--record-inputs`` (the former default).

The set-up (instantiating the FMUs, the engine's steady start, compiling its kernels on a
first run) is timed apart and printed, not counted in the real-time factor.

A mission that does not complete still gives the figures up to where it stopped (the table says
so). ``--stop-time`` runs a part of the mission; ``--profile FILE`` writes a cProfile of the run
(read it with ``python -m pstats FILE`` or snakeviz). Nothing is asserted (DESIGN.md rule 12).

Run: ``python benchmarks/mission.py [--stop-time S] [--params X.ssv ...] [--record-every N]
[--formats csv,parquet,mat] [--record-inputs] [--profile FILE]``
"""
from __future__ import annotations

import argparse
import cProfile
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET_X, AIM_X = 100.0, 200.0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stop-time", type=float, help="stop time [s] (default: the SSD's, the whole mission)")
    ap.add_argument("--params", type=Path, nargs="+", default=[], help="parameter sets (.ssv) to apply")
    ap.add_argument("--record-every", type=int, default=1, help="record every N-th step (default 1)")
    ap.add_argument("--until", default="fcs.mission_completed == 1",
                    help="stop condition, as emss run --until (default: the mission completed; 'never' for none)")
    ap.add_argument("--profile", type=Path, help="write a cProfile of the run to this file")
    ap.add_argument("--formats", default="csv,parquet", help="recorders to attach, comma-separated (csv, parquet, mat)")
    ap.add_argument("--record-inputs", action="store_true",
                    help="record every connector (the former default) instead of emss run's default columns")
    ap.add_argument("--no-replay", action="store_true", help="skip JSBSim alone on the run's inputs")
    ap.add_argument("--repeat", type=int, default=3, help="replays of JSBSim alone, the best kept (default 3)")
    args = ap.parse_args(argv)

    from openemss.orchestrator.errors import EmssError
    from openemss.orchestrator.fmu.build import ensure_built
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.timeseries import default_record, recorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    ensure_built(ROOT / "fmus", ROOT / "ssp" / "resources")
    work = Path(tempfile.mkdtemp(prefix="emss-bench-mission-"))
    try:
        bound = bind_system(load_system(ROOT / "ssp"), list(args.params))
        ex = Execution(bound, algorithm="jacobi", record=default_record(bound, inputs=args.record_inputs))
        timed = {}
        for fmt in [f.strip() for f in args.formats.split(",") if f.strip()]:
            (work / fmt).mkdir()
            timed[fmt] = Timed(recorder(fmt, work / fmt, every=args.record_every))
            ex.add_observer(timed[fmt])
        if args.until.strip().lower() != "never":
            ex.stop_when(args.until)
        stop = args.stop_time if args.stop_time is not None else bound.definition.stop_time_s
        prof = cProfile.Profile() if args.profile else None
        error = ""
        cal_before = calibration_ms()
        t_init = time.perf_counter()
        ex.initialize(stop)  # instantiation, the engine's start, compiled kernels: not part of the run
        t0 = time.perf_counter()
        setup_s = t0 - t_init
        try:
            if prof is not None:
                prof.enable()
            ex.run(stop)
        except EmssError as exc:
            error = str(exc)
        finally:
            if prof is not None:
                prof.disable()
                prof.dump_stats(str(args.profile))
        wall = time.perf_counter() - t0
        sim = ex.time_s - ex.start_time_s
        _report(ex.stats(), sim, wall, setup_s, error)
        _report_recorders(timed, work, ex.k, len(ex.signals) + 1)
        if not args.no_replay:
            _report_replay(bound, work, timed, ex, wall, max(1, args.repeat))
        print(f"machine speed: a fixed Python workload took {cal_before:.1f} ms before the run and "
              f"{calibration_ms():.1f} ms after (compare runs at equal calibration)")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


class Timed:
    """An observer around a recorder, adding up the wall time of its sample and finish calls (``seconds``)
    and, apart, of its start before the first step (``start_seconds``)."""

    def __init__(self, inner: object) -> None:
        self.inner = inner
        self.seconds = 0.0
        self.start_seconds = 0.0

    def start(self, execution: object) -> None:
        t0 = time.perf_counter()
        self.inner.start(execution)
        self.start_seconds += time.perf_counter() - t0

    def sample(self, k: int, time_s: float) -> None:
        t0 = time.perf_counter()
        self.inner.sample(k, time_s)
        self.seconds += time.perf_counter() - t0

    def finish(self, execution: object, error: BaseException | None) -> None:
        t0 = time.perf_counter()
        self.inner.finish(execution, error)
        self.seconds += time.perf_counter() - t0


def _size(path: Path) -> int:
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file()) if path.is_dir() else path.stat().st_size


def _report_recorders(timed: dict[str, Timed], work: Path, steps: int, columns: int) -> None:
    if not timed:
        return
    print(f"\nrecorders, same run, {columns} columns, {steps} macro steps (perf_counter around each call: "
          "about 0.1 us of it is the timing itself)")
    print(f"{'format':<10}{'us/step':>10}{'ratio':>8}{'file MB':>10}{'start ms':>10}")
    base = next(iter(timed.values())).seconds
    for fmt, t in timed.items():
        files = [p for p in (work / fmt).iterdir()]
        size = sum(_size(p) for p in files) / 1e6
        print(f"{fmt:<10}{1e6 * t.seconds / max(steps, 1):>10.2f}{t.seconds / base if base else 0:>8.2f}{size:>10.2f}"
              f"{1e3 * t.start_seconds:>10.1f}")


def _report_replay(bound: object, work: Path, timed: dict[str, Timed], ex: object, wall_s: float,
                   repeat: int) -> None:
    """JSBSim alone on the run's recorded inputs (jsbsim_alone.py), in this process: the whole co-simulation's
    cost per macro step as a multiple of its flight dynamics', and each component's cost beyond its model."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from jsbsim_alone import replay
    fmt = next((f for f in ("parquet", "csv") if f in timed), None)
    if fmt is None:
        print("\nJSBSim alone: not replayed (record parquet or csv to replay the airframe's inputs)")
        return
    files = sorted((work / fmt).rglob(f"*.{fmt}"))
    r = replay(bound, files[0], ex.k, ex.step_size_s, repeat=repeat) if files else "no recorded file"
    if isinstance(r, str):
        print(f"\nJSBSim alone: not replayed ({r})")
        return
    steps = max(ex.k, 1)
    whole = wall_s / steps
    af = ex.stats().get("airframe", {})
    af_s = (af.get("do_step_s", 0.0) + af.get("get_s", 0.0) + af.get("set_s", 0.0)) / steps
    print(f"\nJSBSim alone on the run's airframe inputs, same process, best of {repeat} ({r.steps} steps; "
          f"fuel at the end {r.fuel_kg:.5f} kg, the run's {r.run_fuel_kg:.5f} kg)")
    print(f"{'what':<44}{'us/step':>10}{'x JSBSim':>10}")
    for name, sec in (("JSBSim (property nodes, FGFDMExec.run)", r.jsbsim_s), ("airframe model (adapter)", r.model_s),
                      ("airframe FMU (doStep+get+set, in the run)", af_s), ("whole co-simulation (wall)", whole)):
        print(f"{name:<44}{1e6 * sec:>10.1f}{sec / r.jsbsim_s:>10.2f}")
    print(f"the whole co-simulation costs {whole / r.jsbsim_s:.2f} times JSBSim alone (target 2.0); the airframe "
          f"FMU {1e6 * (af_s - r.model_s):.1f} us per step beyond its model")


def calibration_ms() -> float:
    """Time of a fixed pure-Python workload [ms] (best of 3): this VM's speed varies by a factor of about 2
    over minutes, so the real-time factor is printed with it, measured right before and after the run."""
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        x = 0.0
        for i in range(300_000):
            x = x * 0.999 + i * 1e-6
        best = min(best, time.perf_counter() - t0)
    return 1e3 * best


def _report(stats: dict[str, dict[str, float]], sim_s: float, wall_s: float, setup_s: float, error: str) -> None:
    steps = max((s["steps"] for s in stats.values()), default=0)
    print(f"Munich mission, ssp/ at 20 Hz (Jacobi), every connector recorded: {sim_s:.1f} s simulated "
          f"in {wall_s:.2f} s wall, {steps} macro steps (set-up before the first step: {setup_s:.2f} s, "
          "not counted)")
    if error:
        print(f"the run stopped early: {error}")
    print(f"\n{'where':<22}{'doStep s':>10}{'get+set s':>11}{'us/step':>10}{'share %':>9}{'sets left out':>15}")
    print("-" * 77)
    inside = 0.0
    for name, s in stats.items():
        fmi = s["do_step_s"] + s["get_s"] + s["set_s"]
        inside += fmi
        print(f"{name:<22}{s['do_step_s']:>10.3f}{s['get_s'] + s['set_s']:>11.3f}"
              f"{1e6 * fmi / max(steps, 1):>10.1f}{100 * fmi / wall_s:>9.1f}"
              f"{s.get('sets_skipped', 0) / max(s['steps'], 1):>10.2f}/step")
    own = wall_s - inside
    print(f"{'orchestrator':<22}{'':>10}{'':>11}{1e6 * own / max(steps, 1):>10.1f}{100 * own / wall_s:>9.1f}")
    print("-" * 77)
    rtf = sim_s / wall_s if wall_s > 0 else float("inf")
    engine = sum(s["do_step_s"] + s["get_s"] + s["set_s"] for n, s in stats.items() if n == "engine")
    floor = sim_s / (wall_s - engine) if wall_s > engine else float("inf")
    verdict = "met" if rtf >= TARGET_X else "NOT met"
    print(f"real-time factor {rtf:.1f}x: target {TARGET_X:.0f}x {verdict}"
          + (f", aim {AIM_X:.0f}x met" if rtf >= AIM_X else f" (aim {AIM_X:.0f}x)"))
    print(f"without the engine's share the same run would go at {floor:.1f}x (the other components' floor)")


if __name__ == "__main__":
    sys.exit(main())
