"""Any communication step in a host that is not ours (issue 34 point 5): the airframe FMU alone in FMPy.

JSBSim flies whole frames; a step that is not a whole number of frames of 1/rate_hz (100 Hz, FMPy's default
of a 500th of the stop time, odd sizes) used to fail the FMU. The checks are closed forms, not our own runs:
on the runway with the brakes set, a constant fuel flow burns ``Wf * t`` from the tank (every frame, the
shorter ones included), and the airbrake, commanded fully out from rest, moves at the rate limit written in
the aircraft file (``UPERA.xml``): its position is ``rate * t`` until it is out, which holds only if the
actuator was built with the frame it is flown with (JSBSim's components take it when the aircraft loads).
"""
from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

ROOT = Path(__file__).resolve().parents[2]
UPERA_XML = ROOT / "models" / "airframe" / "jsbsim" / "aircraft" / "UPERA" / "UPERA.xml"
WF_KG_S = 0.2


def _airbrake_rate_per_s() -> float:
    """The airbrake actuator's rate limit [1/s], read from the aircraft file."""
    for act in ET.parse(UPERA_XML).getroot().iter("actuator"):
        if act.get("name") == "fcs/airbrake-actuator":
            return float(act.findtext("rate_limit"))
    raise AssertionError("no airbrake actuator in UPERA.xml")


class Alone:
    """The airframe FMU in FMPy's FMU2Slave, at rest on its runway, brakes set, airbrake commanded out."""

    def __init__(self, fmu: Path, unzip: Path) -> None:
        self.md = read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.s = FMU2Slave(guid=self.md.guid, unzipDirectory=str(unzip),
                           modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="airframe")
        self.s.instantiate()
        self.s.setupExperiment(startTime=0.0)
        self.s.enterInitializationMode()
        self.s.exitInitializationMode()
        self.s.setReal([self.vr[n] for n in ("Wf_kg_s", "brakes_norm", "airbrake_norm")], [WF_KG_S, 1.0, 1.0])
        self.fuel0_kg = self.get("fuel_kg")
        self.t_s = 0.0

    def get(self, name: str) -> float:
        return self.s.getReal([self.vr[name]])[0]

    def steps(self, sizes: list[float]) -> None:
        for h in sizes:
            self.s.doStep(self.t_s, h)
            self.t_s += h

    def close(self) -> None:
        self.s.terminate()
        self.s.freeInstance()


@pytest.fixture(scope="module")
def unzipped(project_fmus: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = tmp_path_factory.mktemp("airframe_any_step")
    return project_fmus["airframe"], Path(extract(str(project_fmus["airframe"]), unzipdir=str(folder / "x")))


@pytest.mark.parametrize("step_s", [0.05, 0.01, 0.0123, 0.002, 1.0 / 30.0, 0.07, 0.1])
def test_any_fixed_step_flies_the_closed_forms(unzipped: tuple[Path, Path], step_s: float) -> None:
    fmu, unzip = unzipped
    rate = _airbrake_rate_per_s()
    a = Alone(fmu, unzip)
    try:
        n = int(np.ceil(1.2 / step_s - 1e-9))  # about 1.2 s: the airbrake (rate 2/3 per s) still moving
        a.steps([step_s] * n)
        t = n * step_s
        assert a.fuel0_kg - a.get("fuel_kg") == pytest.approx(WF_KG_S * t, abs=1e-9)
        assert a.get("airbrake_pos_norm") == pytest.approx(min(1.0, rate * t), abs=1e-9)
        assert a.get("airbrake_pos_norm") < 1.0  # still moving: the check above measured the rate
    finally:
        a.close()


def test_steps_of_changing_sizes_keep_the_time(unzipped: tuple[Path, Path]) -> None:
    """A first step that fixes the frames (100 Hz: 0.005 s), then sizes that are not whole frames of it: the
    remainder is one shorter frame, so the fuel burned is still ``Wf * t`` to the rounding."""
    fmu, unzip = unzipped
    a = Alone(fmu, unzip)
    try:
        sizes = [0.01] * 10 + [0.0123, 0.05, 0.0071, 0.031, 1e-4, 0.2]
        a.steps(sizes)
        assert a.fuel0_kg - a.get("fuel_kg") == pytest.approx(WF_KG_S * sum(sizes), abs=1e-9)
    finally:
        a.close()


def test_fmpy_default_experiment_runs(unzipped: tuple[Path, Path], tmp_path: Path) -> None:
    """FMPy's simulate_fmu with its defaults (no DefaultExperiment step: a 500th of the stop time)."""
    fmu, _ = unzipped
    copy = tmp_path / fmu.name
    shutil.copy(fmu, copy)
    r = simulate_fmu(str(copy), output=["fuel_kg", "alt_agl_m"])
    assert r["time"][-1] == pytest.approx(1.0)
    assert len(r) > 100
    assert np.all(np.isfinite(r["fuel_kg"]))
