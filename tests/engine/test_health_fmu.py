"""The engine FMU's health parameters (tunable): a degraded start and a change between steps give what the Python
model gives with :meth:`EngineModel.set_health` (the same computation: round-off, 1e-9), and a value out of range
fails the step with one line."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import open_slave
from openemss.models.engine.engine_model import OUTPUTS, EngineInputs, EngineModel
from openemss.models.engine.health import HealthDeltas, health_parameters

H = 0.05
OUT = [n for n, _ in OUTPUTS]
START = HealthDeltas(hpc_eta_frac=-0.02, hpt_Wc_frac=0.01)
LATER = HealthDeltas(hpc_eta_frac=-0.04, fan_Wc_frac=-0.02, lpt_eta_frac=-0.01)
U = EngineInputs(0.15, 3000.0, 0.5)


def test_fmu_health_matches_the_model(project_fmus: dict[str, Path]) -> None:
    n, switch = 40, 20
    m = EngineModel("larzac04_sls")
    m.set_health(START)
    m.start(U, N1_pct=80.0)
    start = list(m.values)
    ref = []
    for k in range(n):
        if k == switch:
            m.set_health(LATER)
        m.step(H, U)
        ref.append(list(m.values))
    clean = EngineModel("larzac04_sls")
    clean.start(U, N1_pct=80.0)
    slave, vr = open_slave(project_fmus["engine"], "engine")
    names = list(health_parameters(START))
    slave.setReal([vr["start_N1_pct"]], [80.0])
    slave.setReal([vr[x] for x in names], list(health_parameters(START).values()))
    slave.setReal([vr[x] for x in ("Wf_cmd_kg_s", "alt_m", "mach")], [U.Wf_cmd_kg_s, U.alt_m, U.mach])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    got = []
    for k in range(n):
        if k == switch:
            slave.setReal([vr[x] for x in names], list(health_parameters(LATER).values()))
        slave.doStep(currentCommunicationPoint=k * H, communicationStepSize=H)
        got.append(slave.getReal([vr[x] for x in OUT]))
    # out of range: the step fails (fmi2Error), it does not fly on with a wrong engine
    slave.setReal([vr["health_hpc_eta_frac"]], [0.5])
    with pytest.raises(Exception, match="fmi2DoStep|doStep|Error"):
        slave.doStep(currentCommunicationPoint=n * H, communicationStepSize=H)
    slave.fmi2FreeInstance(slave.component)
    np.testing.assert_allclose(np.array(got), np.array(ref), rtol=1e-9, atol=1e-9)
    i4 = OUT.index("Tt4_K")
    assert start[i4] > clean.values[i4] + 5.0         # the degraded engine runs hotter at the same N1
