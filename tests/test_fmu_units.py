"""FMI units of the project's FMUs (issue 16 point 1), read back with fmpy, and SSP unit conversion
against them.

Every Real variable of the engine, airframe and FCS FMUs declares an FMI ``unit`` that its
UnitDefinitions define with base-unit exponents (FMI 2.0 section 2.2.2). The expected exponents and
factors are written here from the SI brochure (BIPM, 9th ed., tables 2 to 4 and 8: N = kg m s-2,
Pa = kg m-1 s-2, W = kg m2 s-3; 1 rpm = 2 pi / 60 rad/s; 1 deg = pi / 180 rad; 1 % = 0.01), not taken
from the code that writes them.
"""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

# (exponents kg, m, s, A, K, mol, cd, rad; factor), transcribed from the SI brochure
PUBLISHED = {
    "N": ((1, 1, -2, 0, 0, 0, 0, 0), 1.0), "Pa": ((1, -1, -2, 0, 0, 0, 0, 0), 1.0),
    "W": ((1, 2, -3, 0, 0, 0, 0, 0), 1.0), "kg/s": ((1, 0, -1, 0, 0, 0, 0, 0), 1.0),
    "K": ((0, 0, 0, 0, 1, 0, 0, 0), 1.0), "m/s": ((0, 1, -1, 0, 0, 0, 0, 0), 1.0),
    "rpm": ((0, 0, -1, 0, 0, 0, 0, 1), 2 * math.pi / 60), "deg": ((0, 0, 0, 0, 0, 0, 0, 1), math.pi / 180),
    "%": ((0, 0, 0, 0, 0, 0, 0, 0), 0.01), "kg/m3": ((1, -3, 0, 0, 0, 0, 0, 0), 1.0),
    "kg/(N s)": ((0, -1, 1, 0, 0, 0, 0, 0), 1.0), "rad/s": ((0, 0, -1, 0, 0, 0, 0, 1), 1.0),
}
BASE = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
# a quantity of each FMU and the unit its name promises
EXPECTED = {"Engine": {"Fn_N": "N", "Pt3_Pa": "Pa", "N1_rpm": "rpm", "offtake_hp_W": "W", "Tt41_K": "K",
                       "SFC_kg_N_s": "kg/(N s)", "N1_pct": "%", "OPR": "1"},
            "Airframe": {"lat_deg": "deg", "tas_m_s": "m/s", "rho_amb_kg_m3": "kg/m3", "p_rad_s": "rad/s",
                         "mach": "1"},
            "Fcs": {"Wf_cmd_kg_s": "kg/s", "N1c_pct": "%", "tecs.lever_min": "1"}}


@pytest.mark.parametrize("name", ["Engine", "Airframe", "Fcs"])
def test_every_real_variable_has_a_defined_si_unit(project_fmus: dict[str, Path], name: str) -> None:
    fmu = project_fmus[name.lower()]
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    defs = {u.name: u for u in md.unitDefinitions}
    reals = [v for v in md.modelVariables if v.type == "Real"]
    assert reals and all(v.unit in defs for v in reals), [v.name for v in reals if v.unit not in defs]
    byname = {v.name: v for v in reals}
    for var, unit in EXPECTED[name].items():
        assert byname[var].unit == unit, var
    for unit, (exps, factor) in PUBLISHED.items():
        if unit in defs:
            b = defs[unit].baseUnit
            assert tuple(getattr(b, k) for k in BASE) == exps, unit
            assert b.factor == pytest.approx(factor, rel=1e-15) and b.offset == 0.0, unit
    one = defs["1"].baseUnit
    assert all(getattr(one, k) == 0 for k in BASE) and one.factor == 1.0


def test_ssp_unit_conversion_uses_the_fmus_units(project_fmus: dict[str, Path], fmu_dir: Path,
                                                 tmp_path: Path) -> None:
    """A connection from the engine's ``N1_rpm`` (rpm, defined only in the engine FMU's UnitDefinitions)
    to a Gain input declared in rad/s, and from ``N1_pct`` (%) to one declared dimensionless, is converted
    by the orchestrator with the FMU's factor: y = N1 * 2 pi / 60 and N1_pct / 100. A connection to an
    input of another dimension (rpm into K) is refused naming both units."""
    from openemss.orchestrator.errors import EmssError
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.observers import MemoryRecorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system
    from openemss.orchestrator.ssp.write import SystemBuilder

    res = tmp_path / "resources"
    res.mkdir()
    shutil.copy(project_fmus["engine"], res / "Engine.fmu")
    shutil.copy(fmu_dir / "Gain.fmu", res / "Gain.fmu")

    def system(target_unit: str, exps: dict[str, int]) -> Path:
        s = SystemBuilder("units").experiment(0.0, 0.1, 0.05)
        s.unit(target_unit, **exps)
        eng = s.component("engine", "resources/Engine.fmu")
        eng.connector("N1_rpm", "output", "Real").connector("N1_pct", "output", "Real")
        s.component("w", "resources/Gain.fmu").connector("u_real", "input", "Real", target_unit)
        s.component("p", "resources/Gain.fmu").connector("u_real", "input", "Real", "1")
        s.connect("engine.N1_rpm", "w.u_real").connect("engine.N1_pct", "p.u_real")
        folder = tmp_path / target_unit.replace("/", "_")
        shutil.copytree(res, folder / "resources")
        s.units.setdefault("1", {"factor": 1.0, "offset": 0.0})
        s.write(folder)
        return folder

    ex = Execution(bind_system(load_system(system("rad/s", {"s": -1, "rad": 1}))), algorithm="jacobi",
                   record=["engine.N1_rpm", "engine.N1_pct", "w.y_real", "p.y_real"])
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(0.1)
    r = rec.result()
    assert r["engine.N1_rpm"][-1] > 1000.0
    assert r["w.y_real"][-1] == pytest.approx(r["engine.N1_rpm"][-2] * 2 * math.pi / 60, rel=1e-12)
    assert r["p.y_real"][-1] == pytest.approx(r["engine.N1_pct"][-2] / 100.0, rel=1e-12)
    with pytest.raises(EmssError, match="rpm.*K|K.*rpm"):
        bind_system(load_system(system("K", {"K": 1})))
