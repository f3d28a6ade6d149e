"""The FCS's inner loops are one source: compiled (numba, the FCS's step) and as plain Python (OPENEMSS_NO_JIT)
they give the same commands, bit for bit, over whole closed-loop flights.

Two flights on the 3-DoF aircraft of ``aircraft3dof.py`` (the FCS given its performance model), each in a
child process compiled and in one with ``OPENEMSS_NO_JIT=1``: the first 900 s of the Munich mission (take-off
roll, rotation, climb, turns and speed steps) and the impossible descent of ``test_mission_run.HOLD`` (a
planned hold at the fix flown at idle with the airbrake, the TECS's energy-rate limiting and airbrake law).
Every field of every step's output is hashed (the floats by their bits). The flights are closed loops, so a
difference in one last bit anywhere would grow into different trajectories and hashes.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent

_FLY = r"""
import hashlib, json, math, struct, sys
sys.path.insert(0, {here!r})
from aircraft3dof import Aircraft3Dof
from test_mission_run import DT, HOLD, N_SUB, ROOT, performance
from openemss.models.infra import jit
from openemss.models.fcs import inner_loops
from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.fcs import FlightControlSystem
from openemss.models.mission.geo import LatLon
from openemss.models.mission.mission import load_mission, parse_mission

def fly(m, ac, t_end):
    fcs = FlightControlSystem(m, Wf0_kg_s=0.012, performance=performance())
    h, k, airbrake_steps = hashlib.sha256(), 0, 0
    while not fcs.finished and k * DT < t_end:
        out = fcs.step(k * DT, DT, ac.state(), ac.engine())
        ac.airbrake_cmd = out.airbrake_norm
        for _ in range(N_SUB):
            ac.step(DT / N_SUB, out.elevator_norm, out.aileron_norm, out.steering_norm, out.brakes_norm,
                    out.Wf_cmd_kg_s)
        f = (out.elevator_norm, out.aileron_norm, out.rudder_norm, out.steering_norm, out.brakes_norm, out.lever_norm,
             out.Wf_cmd_kg_s, out.theta_cmd_rad, out.phi_cmd_rad, out.tas_cmd_m_s, out.airbrake_norm)
        h.update(struct.pack("11d", *f) + repr((out.gear_down, out.fuel_limiter, out.vnav_mode)).encode())
        airbrake_steps += bool(out.airbrake_norm > 0.0)
        k += 1
    return {{"hash": h.hexdigest(), "steps": k, "airbrake_steps": airbrake_steps,
             "holds": [h.reason for h in fcs.runner.holds]}}

m = load_mission(ROOT / "missions" / "munich.yaml")
rwy = m.sections[0]["runway"]
munich = fly(m, Aircraft3Dof(rwy.point(50.0), rwy.elevation_m, 0.0, rwy.heading_rad, rwy.elevation_m), 900.0)
a = isa(5000.0)
hold = fly(parse_mission(HOLD), Aircraft3Dof(LatLon.from_deg(48.10, 10.80), 5000.0, 0.5 * a.a_m_s, math.pi / 2,
                                             0.0, on_ground=False, theta=0.03, N1c=60.0), 3000.0)
print(json.dumps({{"compiled": jit.AVAILABLE and bool(inner_loops.inner_step.signatures), "munich": munich,
                  "hold": hold}}))
"""


def _fly(no_jit: bool) -> dict:
    env = dict(os.environ)
    env.pop("OPENEMSS_NO_JIT", None)
    if no_jit:
        env["OPENEMSS_NO_JIT"] = "1"
    res = subprocess.run([sys.executable, "-c", _FLY.format(here=str(HERE))], env=env, capture_output=True,
                         text=True, timeout=900)
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_inner_loops_compiled_equal_plain_python() -> None:
    """The same commands at every step of two closed-loop flights, compiled and not; the flights reach what they
    are for (the Munich climb past 900 s, the hold flown with the airbrake out)."""
    from openemss.models.infra import jit

    if not jit.AVAILABLE:
        pytest.skip("numba not importable")
    comp, plain = _fly(False), _fly(True)
    assert comp["compiled"] and not plain["compiled"]
    assert comp["munich"]["steps"] == 18000  # not finished within 900 s: flown to the end of the window
    assert comp["hold"]["airbrake_steps"] > 100 and comp["hold"]["holds"] == ["planned"]
    assert comp["munich"] == plain["munich"]
    assert comp["hold"] == plain["hold"]
