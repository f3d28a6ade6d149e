"""The electrical system's FMU: valid, every variable with its unit, parameters tunable by name, and the
shipped hybrid scenarios naming variables that exist."""
from __future__ import annotations

from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from conftest import assert_house_style, open_slave
from openemss.models.electric.system import ElectricSystem
from openemss.orchestrator.scenarios.manipulators import load_scenario

ROOT = Path(__file__).resolve().parents[2]


def test_fmu_is_valid_and_described(project_fmus: dict[str, Path]) -> None:
    fmu = project_fmus["electric"]
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    assert_house_style(md)
    names = {v.name for v in md.modelVariables}
    assert set(ElectricSystem().parameter_names()) <= names   # every parameter, by its dotted name
    assert {"offtake_hp_W", "offtake_lp_W", "added_mass_kg", "soc", "N1_rpm", "N2_rpm", "on_ground"} <= names


def _run(fmu: Path, n_parallel: int, boost_W: float) -> dict[str, float]:
    """Five seconds of take-off roll at fixed spool speeds; the outputs at the end."""
    slave, vr = open_slave(fmu, f"e{n_parallel}")
    try:
        slave.enterInitializationMode()
        slave.setInteger([vr["battery.n_parallel"]], [n_parallel])
        slave.setReal([vr["ems.boost_W"], vr["N1_rpm"], vr["N2_rpm"], vr["lever_norm"]],
                      [boost_W, 17000.0, 22000.0, 1.0])
        slave.setBoolean([vr["on_ground"]], [True])
        slave.exitInitializationMode()
        for k in range(100):
            slave.doStep(k * 0.05, 0.05)
        names = ["added_mass_kg", "offtake_lp_W", "soc"]
        return dict(zip(names, slave.getReal([vr[n] for n in names]), strict=True))
    finally:
        slave.fmi2FreeInstance(slave.component)


def test_parameters_act_through_the_fmu(project_fmus: dict[str, Path]) -> None:
    """A bigger pack weighs its strings more (8.0 kg per string, by hand); a boost set by name is flown."""
    a = _run(project_fmus["electric"], 4, 30000.0)
    b = _run(project_fmus["electric"], 5, 30000.0)
    assert b["added_mass_kg"] - a["added_mass_kg"] == pytest.approx(82 * 0.070 * 1.25, rel=1e-12)
    assert a["offtake_lp_W"] == pytest.approx(-30000.0, rel=1e-12)
    assert a["soc"] < b["soc"] < 0.9                    # the same energy from a bigger pack


@pytest.mark.parametrize("name", ["pulse_load_7500m.yaml", "climb_boost.yaml"])
def test_hybrid_scenarios_name_existing_variables(name: str, project_fmus: dict[str, Path]) -> None:
    variables = {f"{comp}.{v.name}" for comp, slave in (("electric", "electric"), ("engine", "engine"),
                                                         ("fcs", "fcs"), ("airframe", "airframe"))
                 for v in read_model_description(str(project_fmus[slave])).modelVariables}
    events = load_scenario(ROOT / "scenarios" / name)
    assert events
    for e in events:
        assert e.path in variables, e.path
        if e.when is not None:
            assert e.when.path in variables, e.when.path
