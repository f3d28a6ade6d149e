"""Design point of the turbofan and turbojet: presets against published data, conservation laws.

References: SPEC.md's Larzac 04 table (F_N 13.0 kN at 27.64 kg/s, OPR 10.4, BPR 1.13,
Tt4 1403 K) and Jane's published SFC of 73 kg/(kN h); the whole engine's mass and
energy balance closed to 1e-9 relative.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from openemss.models.engine.bleed import BleedSpec
from openemss.models.engine.combustion import h_fuel_liquid
from openemss.models.engine.cycle_design import DesignPoint, design, gas_of
from openemss.models.engine.design_params import (
    TurbofanParams,
    TurbojetParams,
    load_params,
    params_from_dict,
    preset_path,
)
from openemss.models.engine.errors import ModelError, OutOfRangeError
from openemss.models.engine.stations import TURBOFAN_STATIONS, TURBOJET_STATIONS

CONS = 1e-9


def test_larzac_preset_reproduces_published_design_point() -> None:
    """F_N within 1 % of 13.0 kN at 27.64 kg/s; SFC within 5 % of 73 kg/(kN h) (Jane's)."""
    d = design(load_params(preset_path("larzac04_sls")))
    assert d.W2_kg_s == 27.64
    assert d.Fn_N == pytest.approx(13.0e3, rel=0.01)
    assert d.SFC_kg_N_s * 3.6e6 == pytest.approx(73.0, rel=0.05)
    assert d.OPR == pytest.approx(10.4, rel=1e-5)
    assert d.BPR == 1.13 and d.Tt4_K == 1403.0
    assert d.ram_drag_N == 0.0 and d.Fg_N == d.Fn_N
    assert d.nozzles["core"].choked and d.nozzles["bypass"].choked


def test_reference_study_preset_meets_thrust_by_solving_mass_flow() -> None:
    p = load_params(preset_path("reference_study"))
    assert p.W2_kg_s is None and p.Fn_target_N == 13.0e3
    d = design(p)
    assert d.Fn_N == pytest.approx(13.0e3, rel=1e-9)
    assert d.OPR == pytest.approx(11.22, rel=1e-12) and d.BPR == 1.16
    # same thrust, higher OPR, more bypass: lower SFC than the Larzac preset
    assert d.SFC_kg_N_s < design(load_params(preset_path("larzac04_sls"))).SFC_kg_N_s


def _everything_on() -> TurbofanParams:
    """A turbofan with every loss, bleed and offtake active, in flight."""
    p = load_params(preset_path("larzac04_sls"))
    assert isinstance(p, TurbofanParams)
    return replace(p, alt_m=5000.0, Mach=0.7, dT_isa_K=10.0, handling_bleed_frac=0.06,
                   customer_bleed_frac=0.02, bypass_bleed_frac=0.01, offtake_hp_W=30e3, offtake_lp_W=5e3,
                   eta_burner=0.99, T_fuel_K=320.0, PR_booster=1.3, eta_booster=0.87, dPqP_24_25=0.01,
                   bleeds=p.bleeds + (BleedSpec("cool_lpt", 0.01, 0.5, 0.5, "lpt", 1.0),))


def _closure(d: DesignPoint) -> tuple[float, float]:
    """Relative mass and energy residuals of the whole engine."""
    g = gas_of(d.params)
    st = d.stations
    out_streams = [st["7"]] + ([st["17"]] if "17" in st else [])
    overboard = [d.bleeds[b.name] for b in _specs(d) if b.sink == "overboard"]
    if "bypass_overboard" in d.bleeds:
        overboard.append(d.bleeds["bypass_overboard"])
    W_in = st["0"].W_kg_s + d.Wf_kg_s
    W_out = sum(s.W_kg_s for s in out_streams + overboard)
    E_in = st["0"].H_W + d.Wf_kg_s * (g.LHV_J_kg + h_fuel_liquid(d.params.T_fuel_K, g))
    E_out = (sum(s.H_W for s in out_streams + overboard) + d.mech_loss_W + d.offtake_W
             + d.heat_unreleased_W)
    return (W_in - W_out) / W_in, (E_in - E_out) / E_in


def _specs(d: DesignPoint) -> list[BleedSpec]:
    p = d.params
    s = list(p.bleeds)
    if isinstance(p, TurbofanParams) and p.customer_bleed_frac > 0:
        s.append(BleedSpec("customer", p.customer_bleed_frac))
    return s


def test_turbofan_conserves_mass_and_energy() -> None:
    d = design(_everything_on())
    dm, de = _closure(d)
    assert abs(dm) < CONS and abs(de) < CONS
    assert set(d.stations) == set(TURBOFAN_STATIONS)
    # fuel is carried through: fuel in the core nozzle flow equals the fuel flow
    assert d.stations["7"].W_fuel_kg_s == pytest.approx(d.Wf_kg_s, rel=1e-12)
    # the handling bleed went to the bypass: 16 is warmer than 13 and carries more flow
    assert d.stations["16"].Tt_K > d.stations["13"].Tt_K
    assert d.ram_drag_N == pytest.approx(d.W2_kg_s * d.free.V0_m_s)
    assert d.Fn_N == pytest.approx(d.Fg_N - d.ram_drag_N)


def test_turbofan_shaft_power_balances() -> None:
    p = _everything_on()
    d = design(p)
    c = d.components
    assert p.eta_mech_hp * c["hpt"].power_W == pytest.approx(c["hpc"].power_W + p.offtake_hp_W, rel=1e-10)
    lp = c["fan_outer"].power_W + c["fan_inner"].power_W + c["booster"].power_W
    assert p.eta_mech_lp * c["lpt"].power_W == pytest.approx(lp + p.offtake_lp_W, rel=1e-10)


def test_turbojet_conserves_mass_and_energy_and_meets_thrust() -> None:
    p = TurbojetParams(name="tj", alt_m=3000.0, Mach=0.5, Fn_target_N=20e3, PR_c=12.0, eta_c=0.84,
                       Tt4_K=1450.0, eta_burner=0.99, dPqP_burner=0.04, eta_t=0.88, eta_mech=0.99,
                       offtake_W=40e3, dPqP_jetpipe=0.01, Cv=0.98, Cd=0.97,
                       bleeds=(BleedSpec("cust", 0.03), BleedSpec("cool", 0.05, sink="hpt"),
                               BleedSpec("mid", 0.02, 0.3, 0.5, "hpt", 0.0)))
    d = design(p)
    assert d.Fn_N == pytest.approx(20e3, rel=1e-9)
    dm, de = _closure(d)
    assert abs(dm) < CONS and abs(de) < CONS
    assert set(d.stations) == set(TURBOJET_STATIONS)


def test_design_values_for_map_scaling() -> None:
    d = design(load_params(preset_path("larzac04_sls")))
    c = d.components
    # at SLS ISA the fan face is at reference conditions: corrected = physical
    assert c["fan_outer"].Wc_kg_s + c["fan_inner"].Wc_kg_s == pytest.approx(27.64 * 0.995 ** -1, rel=1e-12)
    assert c["fan_outer"].Nc_rpm == pytest.approx(17300.0)
    assert c["hpc"].Nc_rpm < 22900.0 and c["hpc"].PR == pytest.approx(10.4 / (2.05 * 0.99), rel=1e-6)
    assert c["hpt"].PR > 1.0 and c["lpt"].PR > 1.0
    out = d.to_dict()
    json.dumps(out)
    assert out["Fn_N"] == d.Fn_N and out["stations"]["4"]["Tt_K"] == 1403.0


def test_bad_parameters_are_reported(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="unknown parameter 'PR_fann'"):
        params_from_dict({"engine": "turbofan", "W2_kg_s": 10.0, "PR_fann": 2.0})
    with pytest.raises(OutOfRangeError, match="exactly one"):
        params_from_dict({"engine": "turbojet"})
    f = tmp_path / "bad.json"
    f.write_text("{\n  'x': 1\n}")
    with pytest.raises(ModelError, match="bad.json:2: invalid JSON"):
        load_params(f)
    with pytest.raises(ModelError, match="design of 'tj': nozzle: .* below the ambient .*reverse flow"):
        design(TurbojetParams(name="tj", Fn_target_N=1e3, PR_c=8.0, eta_c=0.6, eta_t=0.6, Tt4_K=1000.0))
    with pytest.raises(ModelError, match="the turbine cannot drive its load"):
        design(TurbojetParams(name="tj", W2_kg_s=1.0, PR_c=20.0, eta_c=0.5, eta_t=0.5, Tt4_K=1300.0))
