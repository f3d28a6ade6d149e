"""One name per quantity (issue 37 point 2): from the model through the FMU and the SSD to the results.

* An engine input fills the field of ``EngineInputs`` of its own name, an airframe output is the field of
  ``AirframeState`` of its own name, an FCS output read from the step's ``FcsOutput`` is its field of the same
  name: no renaming at the FMU's edge (the signal tables' accessors).
* Every connection of the shipped systems joins an output and an input of the same name.
* The quantities the issue found under two names each have one (no table, SSD or results column uses the
  old ones).
"""
from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from openemss.models.airframe.adapter import AirframeState
from openemss.models.airframe.airframe_signals import SIGNALS as AIRFRAME
from openemss.models.engine.engine_signals import SIGNALS as ENGINE
from openemss.models.engine.engine_signals import EngineInputs
from openemss.models.fcs.fcs import OUTPUT_SIGNALS, FcsOutput
from openemss.models.fcs.fcs_signals import SIGNALS as FCS

ROOT = Path(__file__).resolve().parent.parent
SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
#: The names the issue found for one quantity, and the one kept.
OLD_NAMES = {"thrust_N": "Fn_N", "gross_thrust_N": "Fg_N", "fuel_flow_kg_s": "Wf_kg_s",
             "fuel_flow_cmd_kg_s": "Wf_cmd_kg_s", "alt_msl_m": "alt_m", "isa_dev_K": "dT_isa_K",
             "trim_thrust_N": "trim_Fn_N", "start_fuel_flow_kg_s": "start_Wf_kg_s"}


def test_engine_inputs_are_the_model_fields_of_their_names() -> None:
    fields = {f.name for f in dataclasses.fields(EngineInputs)}
    inputs = [s for s in ENGINE if s.causality == "input"]
    assert all(s.accessor is None for s in inputs), [(s.name, s.accessor) for s in inputs if s.accessor]
    assert fields <= {s.name for s in inputs}


def test_airframe_outputs_are_the_state_fields_of_their_names() -> None:
    fields = {f.name for f in dataclasses.fields(AirframeState)} - {"time_s"}
    outputs = [s for s in AIRFRAME if s.causality == "output"]
    assert all(s.accessor is None for s in outputs), [(s.name, s.accessor) for s in outputs if s.accessor]
    assert fields <= {s.name for s in outputs}


def test_fcs_outputs_are_the_output_fields_of_their_names() -> None:
    """Every FCS output the FMU reads from the step's FcsOutput (accessor ``out.<field>``) is the field of its own
    name, and FcsOutput.signals() (the Python model's outputs) names them as the FMU does."""
    fields = {f.name for f in dataclasses.fields(FcsOutput)}
    read = {s.name: s.accessor.removeprefix("out.") for s in FCS
            if s.causality == "output" and s.accessor and s.accessor.startswith("out.")
            and s.accessor.count(".") == 1}
    assert read and all(name == field for name, field in read.items()), read
    assert set(read) <= fields
    assert set(read) <= set(OUTPUT_SIGNALS)
    fmu_outputs = {s.name for s in FCS if s.causality == "output"}
    shared = (set(OUTPUT_SIGNALS) & fields) - {"targets"}
    assert shared <= fmu_outputs, shared - fmu_outputs


@pytest.mark.parametrize("ssd", ["ssp/SystemStructure.ssd", "ssp/hybrid/SystemStructure.ssd"])
def test_connections_join_equal_names(ssd: str) -> None:
    root = ET.parse(ROOT / ssd).getroot()
    pairs = [(c.get("startConnector"), c.get("endConnector")) for c in root.iter(f"{SSD}Connection")]
    assert pairs and all(a == b for a, b in pairs), [p for p in pairs if p[0] != p[1]]
    used = {c.get("name") for c in root.iter(f"{SSD}Connector")}
    assert not used & set(OLD_NAMES)


def test_no_table_uses_an_old_name() -> None:
    names = {s.name for table in (ENGINE, AIRFRAME, FCS) for s in table}
    assert not names & set(OLD_NAMES)
    assert {"Fn_N", "Fg_N", "Wf_kg_s", "Wf_cmd_kg_s", "alt_m", "dT_isa_K", "mach"} <= names
    # the ISA deviation: the airframe publishes it, the engine and the flight control take it
    assert {(s.name, s.causality) for s in AIRFRAME if s.name == "dT_isa_K"} == {("dT_isa_K", "output")}
    assert all(any(s.name == "dT_isa_K" and s.causality == "input" for s in t) for t in (ENGINE, FCS))
