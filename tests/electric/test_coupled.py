"""The engine and the electrical system coupled in a steady state, against a hand calculation.

At a fixed flight condition and fan speed the two are iterated to a common steady state: the engine's
off-design point with the electrical system's shaft powers, the electrical system at the engine's spool
speeds (its machines' losses and limits depend on them). Checked by hand:

* the shaft balances from the engine's station enthalpy flows with the port powers of the electrical
  system: eta_mech (H_in - H_out)_turbine = (H_out - H_in)_compressors + P_port on each spool;
* the machines' loss model (Larminie & Lowry) at the engine's speeds: the LP motor draws the boost plus
  its losses, the HP generator takes the avionics load plus its losses, and the battery supplies the
  difference: P_batt = load - P_elec_hp - P_elec_lp.
"""
from __future__ import annotations

import math

import pytest

from openemss.models.electric.system import OUTPUTS, ElectricSystem
from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps

IDX = {name: i for i, (name, _, _) in enumerate(OUTPUTS)}


def _H(st, k: str) -> float:  # type: ignore[no-untyped-def]
    return st[k].W_kg_s * st[k].ht_J_kg


def _loss(p, P_W: float, n_rpm: float) -> float:  # type: ignore[no-untyped-def]
    w = n_rpm * math.pi / 30.0
    return p.k_c_W_Nm2 * (P_W / w) ** 2 + p.k_i_W_s * w + p.k_w_W_s3 * w ** 3 + p.C_W


def test_coupled_steady_state_by_hand() -> None:
    dp = design(load_params(preset_path("larzac04_sls")))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    s = ElectricSystem({"battery.soc0": 0.8})
    pt = od.solve(3000.0, 0.5, N1_pct=90.0)
    base_Wf = pt.Wf_kg_s
    P_hp = P_lp = 0.0
    for _ in range(30):  # fixed point: electric at the engine's speeds, engine with the electric's ports
        for k in range(200):  # machines past their ramps: a steady climb with boost
            v = s.step(k * 0.05, 0.05, pt.N1_rpm, pt.N2_rpm, 1.0, False, 5.0)
        new = (v[IDX["offtake_hp_W"]], v[IDX["offtake_lp_W"]])
        if abs(new[0] - P_hp) < 1e-6 and abs(new[1] - P_lp) < 1e-6:
            break
        P_hp, P_lp = new
        pt = od.solve(3000.0, 0.5, N1_pct=90.0, offtake_hp_W=P_hp, offtake_lp_W=P_lp, guess=pt)
    else:
        pytest.fail("the coupled steady state did not converge")
    p, st = od.p, pt.stations
    # the engine's shaft balances from its stations, with the electrical system's port powers
    P_hpc = _H(st, "3") - _H(st, "25")
    P_hpt = _H(st, "4") + (st["44"].W_kg_s - st["4"].W_kg_s) * st["3"].ht_J_kg - _H(st, "44")
    P_fan = _H(st, "13") + _H(st, "21") - _H(st, "2")
    P_lpt = _H(st, "45") - _H(st, "5")
    assert p.eta_mech_hp * P_hpt == pytest.approx(P_hpc + P_hp, rel=1e-8)
    assert p.eta_mech_lp * P_lpt == pytest.approx(P_fan + P_lp, rel=1e-8)
    # the machines by hand at the engine's speeds: LP delivers the boost, HP carries the avionics
    boost, load = s.ems.p.boost_W, s.loads.p.avionics_W
    assert P_lp == pytest.approx(-boost, rel=1e-12)
    lp_elec = -boost - _loss(s.lp.p, -boost, pt.N1_rpm)
    assert v[IDX["lp_elec_W"]] == pytest.approx(lp_elec, rel=1e-10)
    assert P_hp - load - _loss(s.hp.p, P_hp, pt.N2_rpm) == pytest.approx(0.0, abs=1e-6)
    assert v[IDX["hp_elec_W"]] == pytest.approx(load, rel=1e-10)
    assert v[IDX["battery_W"]] == pytest.approx(load - load - lp_elec, rel=1e-10)
    # and the boost saves fuel at the same fan speed (the HP offtake is 2 % of it)
    assert pt.Wf_kg_s < base_Wf
