"""The whole Munich mission as one container FMU (``emss export --container``) against our master.

Flies ``ssp/`` (or the system given) in our orchestrator at 20 Hz, Jacobi, until the FCS reports the
mission completed, then exports the same system as one FMU on fmpy's container runtime and runs that
with ``fmpy.simulate_fmu`` (the container applies no stop condition: it runs to the same time), and
prints the burned fuel of both at the end (the engine's ``fuel_burned_kg``), the altitude at 30 s, the
time each reports the mission completed, the end position and their differences, with the wall time of
each. Issue 16 point 7 asks for the fuel within 0.1 %, point 2 for the altitude at 30 s within 1 m. The
container runs in a child process, which leaves with ``os._exit`` (fmpy unloads the FMUs' libraries, see
tests/thirdparty.py). Nothing is asserted (DESIGN.md rule 12).

Run: ``python benchmarks/container_mission.py [SYSTEM] [--params X.ssv ...]`` (3 to 6 minutes).
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VARS = ["engine.fuel_burned_kg", "airframe.alt_m", "airframe.lat_deg", "airframe.lon_deg", "fcs.mission_completed"]

_CHILD = """
import json, os, sys
from fmpy import simulate_fmu
r = simulate_fmu(sys.argv[1], stop_time=float(sys.argv[2]), step_size=0.05, output_interval=0.05,
                 output=sys.argv[3:])
sys.stdout.write("@@" + json.dumps({k: [float(x) for x in r[k]] for k in ("time", *sys.argv[3:])}))
sys.stdout.flush()
os._exit(0)
"""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("system", nargs="?", type=Path, default=ROOT / "ssp")
    ap.add_argument("--params", type=Path, nargs="+", default=[], help="parameter sets (.ssv) to apply to both")
    args = ap.parse_args(argv)

    from openemss.orchestrator.fmu.build import ensure_built
    from openemss.orchestrator.fmu.export import export_container
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.observers import MemoryRecorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    if args.system.resolve() == (ROOT / "ssp").resolve():
        ensure_built(ROOT / "fmus", ROOT / "ssp" / "resources")
    bound = bind_system(load_system(args.system), list(args.params))
    ex = Execution(bound, algorithm="jacobi", record=VARS)
    ex.stop_when("fcs.mission_completed == 1")
    rec = MemoryRecorder()
    ex.add_observer(rec)
    t0 = time.perf_counter()
    ex.run(bound.definition.stop_time_s or 5000.0)
    ours_wall = time.perf_counter() - t0
    ours = rec.result()
    t_end = float(ours["time_s"][-1])
    with tempfile.TemporaryDirectory(prefix="emss-container-") as tmp:
        fmu = Path(tmp) / "system.fmu"
        export_container(bind_system(load_system(args.system), list(args.params)), fmu, step_size_s=0.05)
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-c", _CHILD, str(fmu), repr(t_end), *VARS], capture_output=True,
                              text=True, cwd=tmp)
        theirs_wall = time.perf_counter() - t0
    if "@@" not in proc.stdout:
        print(f"the container run failed: {proc.stderr.strip()[-1500:]}")
        return 1
    theirs = json.loads(proc.stdout.split("@@", 1)[1])
    k30 = int(round(30.0 / 0.05))
    fuel_a, fuel_b = float(ours["engine.fuel_burned_kg"][-1]), float(theirs["engine.fuel_burned_kg"][-1])
    print(f"{args.system} until the mission is completed (t = {t_end:.2f} s), 20 Hz, Jacobi")
    print(f"\n{'':<28}{'ours':>14}{'container':>14}{'difference':>14}")
    print("-" * 70)
    print(f"{'fuel burned [kg]':<28}{fuel_a:>14.3f}{fuel_b:>14.3f}{100 * (fuel_b - fuel_a) / fuel_a:>13.4f}%")
    alt_a, alt_b = float(ours["airframe.alt_m"][k30]), float(theirs["airframe.alt_m"][k30])
    print(f"{'altitude at 30 s [m]':<28}{alt_a:>14.3f}{alt_b:>14.3f}{alt_b - alt_a:>13.4f} m")
    done = []
    for run, t in ((ours, ours["time_s"]), (theirs, theirs["time"])):
        flags = [i for i, x in enumerate(run["fcs.mission_completed"]) if x > 0.5]
        done.append(float(t[flags[0]]) if flags else math.nan)
    print(f"{'mission completed at [s]':<28}{done[0]:>14.2f}{done[1]:>14.2f}{done[1] - done[0]:>13.2f} s")
    for v in ("airframe.lat_deg", "airframe.lon_deg"):
        a, b = float(ours[v][-1]), float(theirs[v][-1])
        print(f"{v + ' at the end':<28}{a:>14.6f}{b:>14.6f}{b - a:>14.2e}")
    print(f"{'wall time [s]':<28}{ours_wall:>14.1f}{theirs_wall:>14.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
