"""Cost of one 50 ms airframe step (six JSBSim steps at 120 Hz): bare JSBSim, the SI adapter, the FMU.

Issue 6's target: under 100 us per 50 ms step inside the FMU. Rows, all in this one
process on UPERA cruising at 5000 m, Mach 0.6 (trimmed, gear up):

* ``JSBSim run() x 6``: ``FGFDMExec.run`` six times, nothing else. The floor.
* ``adapter step``: :meth:`Airframe.step` (0.05 s), which also writes the fuel tank
  before each JSBSim step (fuel flow non-zero).
* ``adapter step + I/O``: what the FMU's ``do_step`` does: seven input setters,
  ``step`` and ``values()`` (all 25 outputs read and converted to SI).
* ``FMU via fmpy``: the built ``Airframe.fmu`` through fmpy's raw ctypes functions with
  prebuilt arrays: one fmi2SetReal (8 inputs), one fmi2SetBoolean (gear), fmi2DoStep,
  one fmi2GetReal (23 outputs), one fmi2GetBoolean. This is the floor of any master
  that calls the FMU the way ours and fmpy's do.

Each row is the best of ``--repeat`` runs of ``--steps`` steps with the garbage
collector off. Nothing is asserted; the verdict is printed.

Run ``python benchmarks/bench_airframe.py [--steps 2000] [--repeat 5] [--no-fmu]``.
"""
from __future__ import annotations

import argparse
import gc
import os
import shutil
import sys
import tempfile
import time
from ctypes import c_double, c_int, c_uint
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
H = 0.05
TARGET_US = 100.0


def _best(fn, steps: int, repeat: int) -> float:  # type: ignore[no-untyped-def]
    """Best time per call [us] of ``fn(steps)`` over ``repeat`` runs."""
    best = float("inf")
    for _ in range(repeat):
        gc.collect()
        gc.disable()
        t0 = time.perf_counter()
        fn(steps)
        dt = time.perf_counter() - t0
        gc.enable()
        best = min(best, dt / steps * 1e6)
    return best


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=2000, help="50 ms steps per run (default 2000)")
    p.add_argument("--repeat", type=int, default=5, help="runs per row, best kept (default 5)")
    p.add_argument("--no-fmu", action="store_true", help="skip building and timing the FMU")
    args = p.parse_args(argv)

    from openemss.models.airframe.adapter import Airframe
    from openemss.models.airframe.trim import trim_level

    af = Airframe()
    r = trim_level(5000.0, 0.6, airframe=af)

    def reset() -> None:
        af.start_air(5000.0, r.tas_m_s, 0.0, alpha_rad=r.alpha_rad, elevator=r.elevator, Fn_N=r.Fn_N,
                     fuel_kg=600.0)
        af.set_fuel_flow(0.1)

    rows: list[tuple[str, float, str]] = []
    reset()
    run = af.fdm.run

    def bare(n: int) -> None:
        for _ in range(n):
            for _ in range(6):
                run()

    rows.append(("JSBSim run() x 6", _best(bare, args.steps, args.repeat), "the floor"))
    reset()

    def step(n: int) -> None:
        for _ in range(n):
            af.step(H)

    rows.append(("adapter step", _best(step, args.steps, args.repeat), "Airframe.step(0.05), fuel tank written"))
    reset()

    def step_io(n: int) -> None:
        for _ in range(n):
            af.set_surfaces(0.0, r.elevator, 0.0)
            af.set_flaps(0.0)
            af.set_gear(False)
            af.set_brakes(0.0, 0.0)
            af.set_steering(0.0)
            af.set_thrust(r.Fn_N)
            af.set_fuel_flow(0.1)
            af.step(H)
            af.values()

    rows.append(("adapter step + I/O", _best(step_io, args.steps, args.repeat), "what the FMU's do_step does"))

    fmu_note = ""
    if not args.no_fmu:
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        from openemss.orchestrator.fmu.build import ensure_built

        work = Path(tempfile.mkdtemp(prefix="bench_airframe_"))
        try:
            (fmu,) = ensure_built(ROOT / "fmus", work, names=["airframe"], force=True)
            md = read_model_description(str(fmu))
            vr = {v.name: v.valueReference for v in md.modelVariables}
            unzip = work / "unzipped"
            shutil.unpack_archive(str(fmu), str(unzip), "zip")
            s = FMU2Slave(guid=md.guid, unzipDirectory=str(unzip), modelIdentifier=md.coSimulation.modelIdentifier,
                          instanceName="airframe")
            s.instantiate()
            s.setupExperiment(startTime=0.0)
            s.setBoolean([vr["start_on_runway"], vr["gear_down"]], [False, False])
            s.setReal([vr["alt0_m"], vr["tas0_m_s"], vr["elevator_norm"], vr["Fn_N"], vr["Wf_kg_s"]],
                      [5000.0, r.tas_m_s, r.elevator, r.Fn_N, 0.1])
            s.enterInitializationMode()
            s.exitInitializationMode()
            ins = ["aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "brakes_norm", "steering_norm",
                   "Fn_N", "Wf_kg_s"]
            outs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
            in_vr = (c_uint * len(ins))(*[vr[n] for n in ins])
            in_val = (c_double * len(ins))(0.0, r.elevator, 0.0, 0.0, 0.0, 0.0, r.Fn_N, 0.1)
            b_vr = (c_uint * 1)(vr["gear_down"])
            b_val = (c_int * 1)(0)
            out_vr = (c_uint * len(outs))(*[vr[n] for n in outs])
            out_val = (c_double * len(outs))()
            ob_vr = (c_uint * 1)(vr["on_ground"])
            ob_val = (c_int * 1)()
            set_real, set_bool = s.fmi2SetReal, s.fmi2SetBoolean
            do_step, get_real, get_bool = s.fmi2DoStep, s.fmi2GetReal, s.fmi2GetBoolean
            comp = s.component
            t = [0.0]

            def fmu_steps(n: int) -> None:
                for _ in range(n):
                    set_real(comp, in_vr, len(ins), in_val)
                    set_bool(comp, b_vr, 1, b_val)
                    do_step(comp, t[0], H, 1)
                    t[0] += H
                    get_real(comp, out_vr, len(outs), out_val)
                    get_bool(comp, ob_vr, 1, ob_val)

            rows.append(("FMU via fmpy", _best(fmu_steps, args.steps, args.repeat),
                         f"built Airframe.fmu, raw fmi2 calls; {len(ins)} + 1 in, {len(outs)} + 1 out"))
            s.terminate()
            s.freeInstance()
        except Exception as exc:  # report and go on: the Python rows still mean something
            fmu_note = f"FMU row skipped: {type(exc).__name__}: {exc}"
        finally:
            shutil.rmtree(work, ignore_errors=True)

    import jsbsim

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"UPERA airframe, one 50 ms step = 6 JSBSim steps at 120 Hz; jsbsim {jsbsim.__version__}, "
          f"Python {sys.version.split()[0]}, {args.steps} steps, best of {args.repeat}, load {load:.2f}")
    print(f"{'row':22s} {'us/step':>9} {'us/JSBSim step':>15} {'x real time':>12}  note")
    print(f"{'-' * 22} {'-' * 9} {'-' * 15} {'-' * 12}  {'-' * 40}")
    for name, us, note in rows:
        print(f"{name:22s} {us:9.1f} {us / 6:15.2f} {H * 1e6 / us:12.0f}  {note}")
    if fmu_note:
        print(fmu_note)
    fmu = [us for name, us, _ in rows if name == "FMU via fmpy"]
    verdict = fmu[0] if fmu else rows[2][1]
    where = "inside the FMU" if fmu else "adapter with I/O (FMU not timed)"
    print(f"target: < {TARGET_US:.0f} us per 50 ms step {where}: {verdict:.1f} us -> "
          f"{'met' if verdict < TARGET_US else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
