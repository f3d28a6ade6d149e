"""A third-party importer (libcosim, via libcosimpy) reads our SSD and FMUs as we do.

libcosim's fixed-step algorithm is a Jacobi scheme: every slave steps from the
inputs set at the start of the step, then outputs are transferred. Our Jacobi
master must give the same trajectories to within 1e-9 on the same system files
(same FMUs, same parameter bindings: inline on a component and an .ssv file on
the system). libcosim runs in a child process (see thirdparty.py).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from thirdparty import require_libcosim, run_isolated

RATE_HZ = 50.0
STEPS = 200


def libcosim_run(system: Path, names: list[str]) -> dict[str, np.ndarray]:
    out = run_isolated("libcosim_run", system=str(system), variables=names, steps=STEPS,
                       step_ns=int(round(1e9 / RATE_HZ)))
    return {n: np.array(v) for n, v in out["values"].items()}


def test_libcosim_and_our_jacobi_master_agree(oscillator: Path) -> None:
    require_libcosim()
    names = ["mass1.x1_m", "mass1.v1_m_s", "mass2.x2_m", "mass2.f_c_N"]
    bound = bind_system(load_system(oscillator))
    ex = Execution(bound, rate_hz=RATE_HZ, algorithm="jacobi")
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(STEPS / RATE_HZ)
    ours = rec.result()
    theirs = libcosim_run(oscillator, names)
    # The bindings took effect in both: mass1 starts from the inline x1_start_m = 0.1 m.
    assert ours["mass1.x1_m"][0] == pytest.approx(0.1)
    for n in names:
        diff = np.max(np.abs(ours[n][1:] - theirs[n]))
        assert diff < 1e-9, (n, diff)
    # and something actually moved: not two flat lines agreeing
    assert np.ptp(theirs["mass2.x2_m"]) > 1e-3


def test_linear_transformation_agrees_with_libcosim(tmp_path: Path, fmu_dir: Path) -> None:
    """libcosim applies ssc:LinearTransformation on connections (it converts no units, so none are used here)."""
    require_libcosim()
    from test_ssp_features import connection, final, gain, make, system_xml

    lin = '<ssc:LinearTransformation factor="3.0" offset="1.0"/>'
    xml = system_xml(gain("a", u_real=2.0) + gain("b") + gain("c"),
                     connection("a.y_real", "b.u_real", lin) + connection("b.y_real", "c.u_real", lin))
    folder = make(tmp_path, fmu_dir, xml)
    theirs = run_isolated("libcosim_run", system=str(folder), variables=["b.u_real", "c.u_real"], steps=3,
                          step_ns=100_000_000)["values"]
    ours = final(folder, "b.u_real", "c.u_real")
    assert theirs["b.u_real"][-1] == ours["b.u_real"] == pytest.approx(7.0)   # 3*2 + 1
    assert theirs["c.u_real"][-1] == ours["c.u_real"] == pytest.approx(22.0)  # 3*7 + 1
