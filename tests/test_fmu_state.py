"""Real FMU state in FMPy (issue 34 point 1): the project's four FMUs save and restore everything.

The check is the uninterrupted run itself, in a host that is not ours (FMPy's ``FMU2Slave``): run to t1,
``fmi2GetFMUstate``, run on to t2 and read every output, ``fmi2SetFMUstate``, run to t2 again on the same
inputs: every output must be identical, bit for bit (a state that restored only the FMI variables, as
pythonfmu's own does, gives the t2 outputs of a run that went on from t2). The same through
``fmi2SerializeFMUstate``/``fmi2DeSerializeFMUstate`` where the model description declares it, and where
it does not, the serialization call must fail (never OK with nothing behind it).
"""
from __future__ import annotations

import math
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

H_S = 0.05
N1, N2 = 200, 120  # steps to t1, then from t1 to t2

#: Per FMU, the inputs at step k (varied, so that the state moves): name -> value
INPUTS: dict[str, Callable[[int], dict[str, float]]] = {
    "airframe": lambda k: {"Fn_N": 14000.0 + 10.0 * k, "brakes_norm": 0.0,
                           "elevator_norm": -0.15 if k > 260 else 0.0, "Wf_kg_s": 0.2},
    "engine": lambda k: {"Wf_cmd_kg_s": 0.12 + 0.0005 * k, "mach": min(0.002 * k, 0.3),
                         "fuel_kg": 500.0},
    "fcs": lambda k: {"tas_m_s": min(0.3 * k, 70.0), "gs_m_s": min(0.3 * k, 70.0), "mass_kg": 5000.0,
                      "rho_amb_kg_m3": 1.2, "N1_pct": 60.0 + 0.05 * k},
    "electric": lambda k: {"N1_rpm": 8000.0 + 10.0 * k, "N2_rpm": 20000.0 + 20.0 * k, "lever_norm": 0.3,
                           "pulse_load_W": 20000.0 if 150 < k < 260 else 0.0},
}


class Host:
    """One FMU in FMPy, stepped with its inputs of :data:`INPUTS`."""

    def __init__(self, fmu: Path, name: str, tmp: Path) -> None:
        self.md = read_model_description(str(fmu))
        self.unzip = extract(str(fmu), unzipdir=str(tmp / name))
        self.vr = {v.name: v for v in self.md.modelVariables}
        self.inputs = INPUTS[name]
        self.outs = {t: [v.valueReference for v in self.md.modelVariables if v.causality == "output" and v.type == t]
                     for t in ("Real", "Integer", "Boolean", "String")}
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.k = 0

    def run(self, n: int) -> None:
        for _ in range(n):
            for name, value in self.inputs(self.k).items():
                v = self.vr[name]
                assert v.causality == "input", name
                self.fmu.setReal([v.valueReference], [value])
            self.fmu.doStep(self.k * H_S, H_S)
            self.k += 1

    def outputs(self) -> tuple[list, ...]:
        f = self.fmu
        return (f.getReal(self.outs["Real"]), f.getInteger(self.outs["Integer"]),
                f.getBoolean(self.outs["Boolean"]), f.getString(self.outs["String"]))

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.unzip, ignore_errors=True)


def _same(a: tuple[list, ...], b: tuple[list, ...]) -> bool:
    """Bit for bit (NaN equal to NaN at the same place)."""
    return all(len(x) == len(y) and all(p == q or (isinstance(p, float) and math.isnan(p) and math.isnan(q))
                                        for p, q in zip(x, y, strict=True)) for x, y in zip(a, b, strict=True))


@pytest.mark.parametrize("name", ["airframe", "engine", "fcs", "electric"])
def test_restored_state_reproduces_the_uninterrupted_run(project_fmus: dict[str, Path], tmp_path: Path,
                                                         name: str) -> None:
    host = Host(project_fmus[name], name, tmp_path)
    try:
        assert host.md.coSimulation.canGetAndSetFMUstate
        host.run(N1)
        at_t1 = host.outputs()
        state = host.fmu.getFMUstate()
        host.run(N2)
        at_t2 = host.outputs()
        assert not _same(at_t1, at_t2), "the outputs do not move: the test would prove nothing"
        host.fmu.setFMUstate(state)
        assert _same(host.outputs(), at_t1)
        host.k = N1
        host.run(N2)
        assert _same(host.outputs(), at_t2)
        if host.md.coSimulation.canSerializeFMUstate:
            data = host.fmu.serializeFMUstate(state)
            host.run(5)
            restored = host.fmu.deSerializeFMUstate(data)
            host.fmu.setFMUstate(restored)
            assert _same(host.outputs(), at_t1)
            host.k = N1
            host.run(N2)
            assert _same(host.outputs(), at_t2)
            host.fmu.freeFMUstate(restored)
        else:
            with pytest.raises(FMICallException):
                host.fmu.serializeFMUstate(state)
        host.fmu.freeFMUstate(state)
    finally:
        host.close()


@pytest.mark.parametrize("name", ["airframe", "engine", "fcs", "electric"])
def test_serialized_state_goes_on_in_another_instance(project_fmus: dict[str, Path], tmp_path: Path,
                                                      name: str) -> None:
    """fmi2SerializeFMUstate in one instance, fmi2DeSerializeFMUstate and fmi2SetFMUstate in another (its own
    extraction, fresh from initialization): stepped on with the same inputs, it gives the first instance's
    uninterrupted outputs bit for bit. Bytes that are not a state of the FMU are refused at the set."""
    a = Host(project_fmus[name], name, tmp_path / "a")
    b = Host(project_fmus[name], name, tmp_path / "b")
    try:
        assert a.md.coSimulation.canSerializeFMUstate
        a.run(N1)
        state = a.fmu.getFMUstate()
        data = a.fmu.serializeFMUstate(state)
        a.fmu.freeFMUstate(state)
        a.run(N2)
        at_t2 = a.outputs()
        b.run(7)  # somewhere else
        restored = b.fmu.deSerializeFMUstate(data)
        b.fmu.setFMUstate(restored)
        b.fmu.freeFMUstate(restored)
        b.k = N1
        b.run(N2)
        assert _same(b.outputs(), at_t2)
        bad = b.fmu.deSerializeFMUstate(bytes(data[: len(data) // 2]))
        with pytest.raises(FMICallException):
            b.fmu.setFMUstate(bad)
    finally:
        a.close()
        b.close()
