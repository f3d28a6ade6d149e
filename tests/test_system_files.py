"""The system files the project ships cannot drift from the FMUs they wire.

For every SystemStructure.ssd under ssp/ and examples/, the FMUs are built
from their slaves, and each connector is compared with the FMU's
modelDescription.xml: it must exist, with the causality, type and unit the
FMU declares (pythonfmu writes no unit attribute; the unit is then read from
the variable's description, "[unit]", which our house style requires).
"""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from fmpy import read_model_description

from openemss.orchestrator.build import ensure_built
from openemss.orchestrator.ssp import load_system
from openemss.orchestrator.system import bind_system

ROOT = Path(__file__).resolve().parent.parent
SYSTEMS = sorted(p.parent for base in ("ssp", "examples") for p in (ROOT / base).rglob("SystemStructure.ssd"))


def _slaves_for(system: Path) -> Path:
    """Where the slaves of a system live: its own fmus/ folder, else the project's."""
    return system / "fmus" if (system / "fmus").is_dir() else ROOT / "fmus"


@pytest.mark.parametrize("system", SYSTEMS, ids=[str(s.relative_to(ROOT)) for s in SYSTEMS])
def test_every_connector_matches_its_fmu(system: Path, tmp_path: Path) -> None:
    copy = tmp_path / "system"
    shutil.copytree(system, copy, ignore=shutil.ignore_patterns("resources", "fmus", "__pycache__"))
    ensure_built(_slaves_for(system), copy / "resources")
    sysdef = load_system(copy)
    checked = 0
    for comp in sysdef.components:
        md = read_model_description(str(comp.source_path), validate=False)
        variables = {v.name: v for v in md.modelVariables}
        for k in comp.connectors:
            assert k.name in variables, f"{comp.name}.{k.name} is not in {comp.source}"
            v = variables[k.name]
            assert k.kind == v.causality, f"{comp.name}.{k.name}: {k.kind} vs {v.causality}"
            if k.type_name is not None:
                assert k.type_name == v.type, f"{comp.name}.{k.name}: {k.type_name} vs {v.type}"
            described = re.search(r"\[([^\]]+)\]\s*$", v.description or "")
            fmu_unit = v.unit or (described.group(1) if described else None)
            if k.unit is not None and fmu_unit not in (None, "-"):
                assert k.unit == fmu_unit, f"{comp.name}.{k.name}: unit {k.unit} vs {fmu_unit}"
            checked += 1
    assert checked > 0
    bind_system(sysdef)  # and the whole system binds (connections, parameters)


def test_the_shipped_coupled_system_takes_off(tmp_path: Path) -> None:
    """ssp/: engine, airframe and flight control FMUs wired by the generated SSD take off from
    EDDM 26R under the Munich mission (the mission's first seconds: roll and lift-off)."""
    from openemss.orchestrator.execution import Execution
    from openemss.orchestrator.observers import MemoryRecorder

    copy = tmp_path / "ssp"
    shutil.copytree(ROOT / "ssp", copy, ignore=shutil.ignore_patterns("resources", "__pycache__"))
    ensure_built(ROOT / "fmus", copy / "resources")
    ex = Execution(bind_system(load_system(copy)), record=["airframe.on_ground", "airframe.alt_agl_m",
                                                          "airframe.tas_m_s", "engine.thrust_N"])
    assert ex.rate_hz == 20.0  # from the SSD
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(30.0)
    r = rec.result()
    assert r["airframe.on_ground"][0] == 1 and r["airframe.on_ground"][-1] == 0  # it left the runway
    assert r["airframe.alt_agl_m"][-1] > 20.0 and r["airframe.tas_m_s"][-1] > 60.0
    assert r["engine.thrust_N"].max() > 10_000.0  # take-off thrust of a 13 kN engine
