"""Cost of one 50 ms FCS step: the Python FlightControlSystem, the FMU's adapter code, the built FMU.

Rows, all in this one process, the aircraft level at 1000 m, 130 m/s, on a waypoint leg
(TECS, L1 guidance, pitch, lateral and fuel control all running):

* ``FlightControlSystem.step``: the model alone, given a prebuilt ``AircraftState``.
* ``Fcs slave, no FMI``: the slave class of ``fmus/fcs.py`` called directly in Python
  (``set_real`` of the 18 inputs, ``do_step``, ``get_real`` of the 15 Real outputs): what
  the FMU does per step beyond the model (measured state from the inputs, ground track
  from successive positions, outputs cached), without pythonfmu's C layer.
* ``FMU via fmpy``: the built ``Fcs.fmu`` through fmpy's raw ctypes functions with prebuilt
  arrays: one fmi2SetReal (18 inputs), one fmi2SetBoolean, fmi2DoStep, one fmi2GetReal
  (15 outputs), one fmi2GetBoolean (2), one fmi2GetInteger. The floor of a master calling
  the FMU the way ours and fmpy's do.

Each row is the best of ``--repeat`` runs of ``--steps`` steps with the garbage collector
off; the position moves along the leg so the guidance does real work. Nothing is asserted.

Run ``python benchmarks/bench_fcs_fmu.py [--steps 2000] [--repeat 5] [--no-fmu]``.
"""
from __future__ import annotations

import argparse
import gc
import math
import shutil
import sys
import tempfile
import time
from ctypes import c_double, c_int, c_uint
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
H = 0.05
SECTION = ("  - {type: WaypointFollowing, name: bench leg, waypoints: [WP2, WP3], altitude_m: 1000.0,\n"
           "     speed: {tas_m_s: 130.0}}\n")


def _best(setup, steps: int, repeat: int) -> float:  # type: ignore[no-untyped-def]
    """Best time per step [us] of ``setup()(steps)`` over ``repeat`` runs (the set-up, a fresh
    controller started from its initial state, is not timed)."""
    best = float("inf")
    for _ in range(repeat):
        fn = setup()
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
    p.add_argument("--steps", type=int, default=2000, help="50 ms steps per run (default 2000, at most 2400)")
    p.add_argument("--repeat", type=int, default=5, help="runs per row, best kept (default 5)")
    p.add_argument("--no-fmu", action="store_true", help="skip building and timing the FMU")
    args = p.parse_args(argv)

    from openemss.fmus.fcs import INPUTS, OUTPUTS, Fcs
    from openemss.models.fcs.fcs import FlightControlSystem
    from openemss.models.mission.mission import load_mission
    from openemss.models.fcs.state import AircraftState, EngineState
    from openemss.models.mission.geo import destination

    work = Path(tempfile.mkdtemp(prefix="bench_fcs_"))
    try:
        text = (ROOT / "missions" / "munich.yaml").read_text(encoding="utf-8")
        mission_file = work / "bench.yaml"
        mission_file.write_text(text[: text.index("sections:")] + "sections:\n" + SECTION, encoding="utf-8")
        mission = load_mission(mission_file)
        hdg = math.radians(240.0)  # 20 km out, flying towards WP 2
        start = destination(mission.waypoint("WP2"), hdg - math.pi, 20000.0)
        V = 130.0
        # positions along the leg, one per step (precomputed: not part of any row)
        path = [destination(start, hdg, V * H * k) for k in range(args.steps + 1)]
        rho = 1.112
        eng = EngineState(80.0, 82.0, 1200.0)

        def state(k: int) -> AircraftState:
            return AircraftState(path[k], 1000.0, V, math.nan, 0.0, V * math.cos(hdg), V * math.sin(hdg), hdg, 0.0,
                                 0.03, 0.0, 0.0, 0.0, 0.0, 0.5 * rho * V * V, 2000.0, False)

        states = [state(k) for k in range(args.steps)]
        rows: list[tuple[str, float, str]] = []

        def model():  # type: ignore[no-untyped-def]
            step = FlightControlSystem(mission, Wf0_kg_s=0.2).step

            def run(n: int) -> None:
                for k in range(n):
                    step(k * H, H, states[k], eng)
            return run

        rows.append(("FlightControlSystem.step", _best(model, args.steps, args.repeat), "the model alone"))

        def adapter():  # type: ignore[no-untyped-def]
            s = Fcs(instance_name="bench", resources=str(ROOT))
            s.mission_file = str(mission_file)
            s.Wf0_kg_s = 0.2
            vr = {v.name: k for k, v in s.vars.items()}
            names = [n for n, _ in INPUTS]
            base = {n: 0.0 for n in names} | {"alt_m": 1000.0, "tas_m_s": V, "gs_m_s": V, "psi_rad": hdg,
                                              "theta_rad": 0.03, "rho_amb_kg_m3": rho, "mass_kg": 2000.0,
                                              "N1_pct": 80.0, "N1c_pct": 82.0, "Tt41_K": 1200.0}
            in_vr, values = [vr[n] for n in names], [base[n] for n in names]
            i_lat, i_lon = names.index("lat_deg"), names.index("lon_deg")
            out_vr = [vr[n] for n, _ in OUTPUTS]
            s.on_ground = False
            s.exit_initialization_mode()
            set_real, do_step, get_real = s.set_real, s.do_step, s.get_real

            def run(n: int) -> None:
                for k in range(n):
                    values[i_lat], values[i_lon] = path[k].lat_deg, path[k].lon_deg
                    set_real(in_vr, values)
                    do_step(k * H, H)
                    get_real(out_vr)
            return run

        rows.append(("Fcs slave, no FMI", _best(adapter, args.steps, args.repeat),
                     "slave class in Python: set_real, do_step, get_real"))

        fmu_note = ""
        if not args.no_fmu:
            try:
                rows.append(_fmu_row(work, args, mission_file, path, INPUTS, V, hdg, rho))
            except Exception as exc:  # report and go on: the Python rows still mean something
                fmu_note = f"FMU row skipped: {type(exc).__name__}: {exc}"
    finally:
        shutil.rmtree(work, ignore_errors=True)

    print(f"FCS, one 50 ms step on a waypoint leg at 1000 m; Python {sys.version.split()[0]}, "
          f"{args.steps} steps, best of {args.repeat}")
    print(f"{'row':26s} {'us/step':>9} {'x model':>8} {'x real time':>12}  note")
    print(f"{'-' * 26} {'-' * 9} {'-' * 8} {'-' * 12}  {'-' * 40}")
    base = rows[0][1]
    for name, us, note in rows:
        print(f"{name:26s} {us:9.1f} {us / base:8.2f} {H * 1e6 / us:12.0f}  {note}")
    if fmu_note:
        print(fmu_note)
    return 0


def _fmu_row(work: Path, args: argparse.Namespace, mission_file: Path, path: list, inputs: tuple,
             V: float, hdg: float, rho: float) -> tuple[str, float, str]:
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave

    from openemss.orchestrator.fmu.build import ensure_built

    (fmu,) = ensure_built(ROOT / "fmus", work, names=["fcs"], force=True)
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzip = work / "unzipped"
    shutil.unpack_archive(str(fmu), str(unzip), "zip")
    names = [n for n, _ in inputs]
    base = {n: 0.0 for n in names} | {"alt_m": 1000.0, "tas_m_s": V, "gs_m_s": V, "psi_rad": hdg,
                                      "theta_rad": 0.03, "rho_amb_kg_m3": rho, "mass_kg": 2000.0, "N1_pct": 80.0,
                                      "N1c_pct": 82.0, "Tt41_K": 1200.0}
    outs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    in_vr = (c_uint * len(names))(*[vr[n] for n in names])
    in_val = (c_double * len(names))(*[base[n] for n in names])
    i_lat, i_lon = names.index("lat_deg"), names.index("lon_deg")
    b_vr, b_val = (c_uint * 1)(vr["on_ground"]), (c_int * 1)(0)
    out_vr, out_val = (c_uint * len(outs))(*[vr[n] for n in outs]), (c_double * len(outs))()
    ob_vr, ob_val = (c_uint * 2)(vr["gear_down"], vr["mission_completed"]), (c_int * 2)()
    oi_vr, oi_val = (c_uint * 1)(vr["section_index"]), (c_int * 1)()
    slaves = []

    def fmu_steps():  # type: ignore[no-untyped-def]
        s = FMU2Slave(guid=md.guid, unzipDirectory=str(unzip), modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=f"fcs{len(slaves)}")
        slaves.append(s)
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        s.setString([vr["mission_file"]], [str(mission_file)])
        s.setReal([vr["Wf0_kg_s"]], [0.2])
        s.enterInitializationMode()
        s.exitInitializationMode()
        comp = s.component
        set_real, set_bool, do_step = s.fmi2SetReal, s.fmi2SetBoolean, s.fmi2DoStep
        get_real, get_bool, get_int = s.fmi2GetReal, s.fmi2GetBoolean, s.fmi2GetInteger
        def run(n: int) -> None:
            for k in range(n):
                in_val[i_lat], in_val[i_lon] = path[k].lat_deg, path[k].lon_deg
                set_real(comp, in_vr, len(names), in_val)
                set_bool(comp, b_vr, 1, b_val)
                do_step(comp, k * H, H, 1)
                get_real(comp, out_vr, len(outs), out_val)
                get_bool(comp, ob_vr, 2, ob_val)
                get_int(comp, oi_vr, 1, oi_val)
        return run

    us = _best(fmu_steps, args.steps, args.repeat)
    for s in slaves:  # terminate and free; keep the library loaded (unloading pythonfmu is unsafe)
        s.terminate()
        s.fmi2FreeInstance(s.component)
    return ("FMU via fmpy", us, f"built Fcs.fmu, raw fmi2 calls; {len(names)} + 1 in, {len(outs)} + 3 out")


if __name__ == "__main__":
    sys.exit(main())
