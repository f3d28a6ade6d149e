"""Design points against pyCycle's published benchmarks (another open code, Apache-2.0).

Source: OpenMDAO/pyCycle, commit 65faca6c95506122812f74a3e66079266327d95e,
``example_cycles/tests/benchmark_simple_turbojet.py`` (DESIGN point of
``example_cycles/simple_turbojet.py``) and ``example_cycles/tests/benchmark_hbtf.py``
(DESIGN point of ``example_cycles/high_bypass_turbofan.py``). The expected numbers are
transcribed in ``data/pycycle_benchmarks.json``; the same inputs, converted to SI, are
the presets ``pycycle_simple_turbojet.json`` and ``pycycle_hbtf.json``, whose notes
say how each pyCycle input maps onto ours.

Tolerance 1 % (the issue's requirement) on thrust, mass flow, TSFC, fuel-air ratio,
turbine pressure ratios and Tt3. What remains is thermodynamics: pyCycle evaluates
CEA chemical equilibrium (the turbojet through CEA-generated tables), so its products
dissociate a little and its species data are JANAF-based, while ours are NASA Glenn
polynomials of frozen, complete combustion products. Measured (commit of this test):

=============  =========  =========  =========  ========  =========  ========
case           W          TSFC       Fg         FAR       turb. PR   Tt3
=============  =========  =========  =========  ========  =========  ========
turbojet       +0.29 %    -0.12 %    (target)   -0.41 %   +0.63 %    +0.20 %
HBTF           +0.34 %    -0.19 %    +0.20 %    -0.53 %   +0.23/0.55 %  +0.001 %
=============  =========  =========  =========  ========  =========  ========

Off-design (point OD0 of the same benchmark file: SLS, 11000 lbf, on pyCycle's AXI5
compressor and LPT2269 turbine maps, shipped in ``models/engine/maps/`` and scaled at the
design point as pyCycle does): W +0.20 %, OPR -0.16 %, FAR -0.26 %, N -0.31 %, TSFC
-0.07 %, Tt3 -0.02 %.

The fuel's heating value is not a thermo difference but a convention: pyCycle adds the
fuel with zero enthalpy on CEA's absolute scale, i.e. with the heat of formation of its
elements, which releases 44.85 MJ/kg from C12H23 (computed in
:func:`test_pycycle_effective_heating_value`), against 43.1 MJ/kg for liquid Jet-A.
With 43.1 MJ/kg the TSFC would differ by about +4 % (:func:`test_heating_value_convention_matters`).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from openemss.models.engine.cycle_design import DesignPoint, design
from openemss.models.engine.design_params import load_params, preset_path, replace
from openemss.models.engine.gas import DEFAULT_GAS

REF = json.loads((Path(__file__).parent / "data" / "pycycle_benchmarks.json").read_text())["cases"]
LBF_N = 4.4482216152605
LBM_KG = 0.45359237
R_PER_K = 1.8
TOL = 0.01


def _pyc_units(d: DesignPoint) -> dict[str, float]:
    out = {"W": d.W2_kg_s / LBM_KG, "OPR": d.OPR, "FAR": d.stations["4"].FAR, "Fg": d.Fg_N / LBF_N,
           "TSFC": d.SFC_kg_N_s * 3600.0 * LBF_N / LBM_KG, "Tt3": d.stations["3"].Tt_K * R_PER_K}
    c = d.components
    if "turbine" in c:
        out["turb_PR"] = c["turbine"].PR
    else:
        out["hpt_PR"], out["lpt_PR"] = c["hpt"].PR, c["lpt"].PR
    return out


def _compare(case: str, preset: str) -> None:
    ours = _pyc_units(design(load_params(preset_path(preset))))
    ref = {k: v for k, v in REF[case].items() if k not in ("file", "point", "conditions")}
    print(f"\npyCycle {REF[case]['file']} ({REF[case]['point']}) vs openEMSS")
    print(f"{'quantity':>8} {'pyCycle':>14} {'openEMSS':>14} {'diff %':>8}")
    for k, v in ref.items():
        print(f"{k:>8} {v:14.6f} {ours[k]:14.6f} {100 * (ours[k] / v - 1):8.3f}")
    for k, v in ref.items():
        assert ours[k] == pytest.approx(v, rel=TOL), k


def test_simple_turbojet_design_matches_pycycle() -> None:
    _compare("simple_turbojet", "pycycle_simple_turbojet")


def test_high_bypass_turbofan_design_matches_pycycle() -> None:
    _compare("hbtf", "pycycle_hbtf")


def test_simple_turbojet_offdesign_matches_pycycle() -> None:
    """OD0: the design's nozzle area and scaled maps, net thrust 11000 lbf at SLS."""
    from openemss.models.engine.offdesign_turbojet import TurbojetOffDesign, scaled_turbojet_maps
    dp = design(load_params(preset_path("pycycle_simple_turbojet")))
    cm, tm, beta = scaled_turbojet_maps(dp)
    r = TurbojetOffDesign(dp, cm, tm, beta).solve(0.0, 1e-6, Fn_N=11000.0 * LBF_N)
    ours = {"W": r.stations["2"].W_kg_s / LBM_KG, "OPR": r.OPR, "FAR": r.stations["4"].FAR, "Nmech": r.N_rpm,
            "Fg": r.Fg_N / LBF_N, "TSFC": r.SFC_kg_N_s * 3600.0 * LBF_N / LBM_KG, "Tt3": r.stations["3"].Tt_K * R_PER_K}
    ref = REF["simple_turbojet_OD0"]
    print(f"\npyCycle {ref['file']} (OD0) vs openEMSS")
    for k, v in ours.items():
        print(f"{k:>8} {ref[k]:14.6f} {v:14.6f} {100 * (v / ref[k] - 1):8.3f}")
    for k, v in ours.items():
        assert v == pytest.approx(ref[k], rel=TOL), k


def test_pycycle_effective_heating_value() -> None:
    """The presets' LHV: -(12 hf(CO2) + 11.5 hf(H2O))/M(C12H23) from the NASA Glenn data, to 1 J/kg."""
    data = DEFAULT_GAS.data
    sp, Ru = data.species, data.gas_constant_J_molK
    M_C = sp["CO2"].molar_mass_kg_mol - sp["O2"].molar_mass_kg_mol
    M_H = (sp["H2O"].molar_mass_kg_mol - sp["O2"].molar_mass_kg_mol / 2) / 2
    lhv = -(12 * sp["CO2"].H_R(298.15) + 11.5 * sp["H2O"].H_R(298.15)) * Ru / (12 * M_C + 23 * M_H)
    for name in ("pycycle_simple_turbojet", "pycycle_hbtf"):
        assert load_params(preset_path(name)).LHV_J_kg == pytest.approx(lhv, abs=1.0)
    assert lhv == pytest.approx(44.85e6, rel=1e-3)


def test_heating_value_convention_matters() -> None:
    """With liquid Jet-A's 43.1 MJ/kg instead, TSFC rises by about the LHV ratio (4 %)."""
    p = load_params(preset_path("pycycle_simple_turbojet"))
    a, b = design(p), design(replace(p, LHV_J_kg=43.1e6))
    assert b.SFC_kg_N_s / a.SFC_kg_N_s == pytest.approx(p.LHV_J_kg / 43.1e6, rel=0.01)
