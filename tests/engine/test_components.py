"""Engine components against hand calculations, published tables and conservation laws.

Independent references: cp integrated numerically with scipy.integrate.quad
(instead of the closed-form h and phi of gas.py), the perfect-gas relations at
300 K where air's gamma is 1.400 to 4 digits, the ISA tables of ISO 2533, the
MIL-E-5008B law, and closure of mass and energy flows (1e-9 relative).
"""

from __future__ import annotations

import math

import pytest
from scipy.integrate import quad

from openemss.models.engine import gas
from openemss.models.engine.atmosphere import free_stream, isa
from openemss.models.engine.bleed import BleedSpec, stage_fractions
from openemss.models.engine.burner import burner_to_temperature, burner_with_fuel
from openemss.models.engine.combustion import h_fuel_liquid
from openemss.models.engine.compressor import compressor, efficiency_poly_to_isentropic
from openemss.models.engine.duct import duct
from openemss.models.engine.errors import ModelError, OutOfRangeError
from openemss.models.engine.flow import flow_TP, mix, static_at_mach
from openemss.models.engine.inlet import inlet, ram_recovery_mil_e_5008b
from openemss.models.engine.nozzle import convergent_nozzle, ideal_nozzle
from openemss.models.engine.shaft import net_power, spool_acceleration, turbine_power_required
from openemss.models.engine.splitter import splitter
from openemss.models.engine.turbine import Cooling, turbine, turbine_for_power

CONS = 1e-9   # relative closure of mass and energy (the brief's requirement)


def dh_quad(T1: float, T2: float, FAR: float = 0.0) -> float:
    """Enthalpy difference [J/kg] by numerical integration of cp."""
    return quad(lambda T: gas.cp(T, FAR), T1, T2, epsabs=0, epsrel=1e-12)[0]


def ds_quad(T1: float, T2: float, FAR: float = 0.0) -> float:
    """Entropy-function difference [J/(kg K)] by numerical integration of cp/T."""
    return quad(lambda T: gas.cp(T, FAR) / T, T1, T2, epsabs=0, epsrel=1e-12)[0]


# ------------------------------------------------------------------ atmosphere
@pytest.mark.parametrize("alt_m, T_K, P_Pa", [
    (0.0, 288.15, 101325.0), (1000.0, 281.65, 89874.6), (5000.0, 255.65, 54019.9),
    (11000.0, 216.65, 22632.06), (15000.0, 216.65, 12044.57), (20000.0, 216.65, 5474.889),
    (25000.0, 221.65, 2511.02)])
def test_isa_matches_iso_2533_table(alt_m: float, T_K: float, P_Pa: float) -> None:
    """ISO 2533 / US 1976 table values (geopotential altitude); 5e-6: the tables' rounding
    and the 7th digit of R (287.05287 vs 287.0531 J/(kg K) in some printings)."""
    a = isa(alt_m)
    assert a.T_K == pytest.approx(T_K, abs=1e-9)
    assert a.P_Pa == pytest.approx(P_Pa, rel=5e-6)


def test_isa_deviation_changes_temperature_not_pressure() -> None:
    a, b = isa(3000.0), isa(3000.0, 15.0)
    assert b.T_K - a.T_K == pytest.approx(15.0) and b.P_Pa == a.P_Pa
    with pytest.raises(OutOfRangeError, match="altitude 40000.0 m"):
        isa(40000.0)


def test_free_stream_totals_close_to_perfect_gas() -> None:
    """At 216.65 K air has gamma = 1.401: Tt/T = 1 + 0.2 M^2 and Pt/P = (Tt/T)^3.5 within 0.1 %."""
    fr = free_stream(11000.0, 0.8)
    assert fr.Tt0_K / fr.amb.T_K == pytest.approx(1.128, rel=1e-3)
    assert fr.Pt0_Pa / fr.amb.P_Pa == pytest.approx(1.128 ** 3.5, rel=1e-3)
    # energy: ht0 = h(T) + V^2/2 exactly
    assert gas.h(fr.Tt0_K) - gas.h(fr.amb.T_K) == pytest.approx(0.5 * fr.V0_m_s ** 2, rel=1e-10)


# ---------------------------------------------------------------------- inlet
@pytest.mark.parametrize("M, eta", [(0.0, 1.0), (0.8, 1.0), (1.0, 1.0), (1.5, 1 - 0.075 * 0.5 ** 1.35),
                                    (2.0, 0.925), (3.0, 1 - 0.075 * 2 ** 1.35)])
def test_mil_e_5008b(M: float, eta: float) -> None:
    assert ram_recovery_mil_e_5008b(M) == pytest.approx(eta, rel=1e-15)


def test_inlet_recovery_and_adiabatic() -> None:
    fs0 = flow_TP(10.0, 300.0, 1e5)
    fs2 = inlet(fs0, 2.0, 0.98)
    assert fs2.Pt_Pa == pytest.approx(1e5 * 0.98 * 0.925) and fs2.Tt_K == 300.0 and fs2.W_kg_s == 10.0


# ----------------------------------------------------------------- compressor
@pytest.mark.parametrize("PR, eta", [(1.5, 0.9), (4.0, 0.85), (20.0, 0.82)])
def test_compressor_against_integrated_cp(PR: float, eta: float) -> None:
    """Isentropic exit from int cp/T dT = R ln PR; actual work = ideal work / eta; power = W dh."""
    fs = flow_TP(20.0, 288.15, 101325.0)
    c = compressor(fs, PR, eta)
    T_is = gas.T_isentropic(288.15, PR)
    assert ds_quad(288.15, T_is) == pytest.approx(gas.R() * math.log(PR), rel=1e-10)
    assert dh_quad(288.15, T_is) / dh_quad(288.15, c.out.Tt_K) == pytest.approx(eta, rel=1e-9)
    assert c.power_W == pytest.approx(20.0 * dh_quad(288.15, c.out.Tt_K), rel=1e-9)
    assert c.out.Pt_Pa == pytest.approx(101325.0 * PR, rel=1e-15)
    # polytropic efficiency definition and its inverse
    assert c.eta_poly == pytest.approx(gas.R() * math.log(PR) / ds_quad(288.15, c.out.Tt_K), rel=1e-9)
    assert efficiency_poly_to_isentropic(c.eta_poly, PR, 288.15) == pytest.approx(eta, rel=1e-9)


def test_compressor_hand_calculation_perfect_gas() -> None:
    """Low PR at 288 K (cp 1004-1010 J/(kg K)): the perfect-gas formula agrees within 0.2 %."""
    c = compressor(flow_TP(1.0, 288.15, 101325.0), 1.5, 0.88)
    T2 = 288.15 * (1 + (1.5 ** (0.4 / 1.4) - 1) / 0.88)
    assert c.out.Tt_K == pytest.approx(T2, rel=2e-3)


def test_compressor_bleeds_conserve_mass_and_energy() -> None:
    fs = flow_TP(12.0, 350.0, 2.2e5)
    fP, fw = stage_fractions(2, 4, 5.0)
    assert (fP, fw) == (pytest.approx((5.0 ** 0.5 - 1) / 4.0), 0.5)
    specs = (BleedSpec("handling", 0.1, fP, fw, "bypass"), BleedSpec("customer", 0.02),
             BleedSpec("cool", 0.05, sink="hpt"))
    c = compressor(fs, 5.0, 0.84, specs)
    W_out = c.out.W_kg_s - c.bleeds[1].W_kg_s - c.bleeds[2].W_kg_s      # exit bleeds leave at 3 -> 31
    assert fs.W_kg_s - W_out - sum(b.W_kg_s for b in c.bleeds) == pytest.approx(0.0, abs=CONS * fs.W_kg_s)
    H_out = W_out * c.out.ht_J_kg + sum(b.H_W for b in c.bleeds)
    assert (fs.H_W + c.power_W - H_out) / c.power_W == pytest.approx(0.0, abs=CONS)
    # the interstage bleed has half the work: power saved = W_b (ht3 - ht_b)
    unbled = compressor(fs, 5.0, 0.84)
    assert unbled.power_W - c.power_W == pytest.approx(
        0.1 * 12.0 * (c.out.ht_J_kg - c.bleeds[0].ht_J_kg) + 0.07 * 12.0 * 0.0, rel=1e-12)
    assert c.bleeds[0].Pt_Pa == pytest.approx(2.2e5 * 5.0 ** 0.5, rel=1e-12)


def test_compressor_rejects_bad_input() -> None:
    with pytest.raises(OutOfRangeError, match="PR"):
        compressor(flow_TP(1.0, 300.0, 1e5), 0.5, 0.8)
    with pytest.raises(OutOfRangeError, match="eta_is"):
        compressor(flow_TP(1.0, 300.0, 1e5), 2.0, 1.2)
    with pytest.raises(OutOfRangeError, match="sink"):
        BleedSpec("x", 0.1, sink="nowhere")


# ----------------------------------------------------- splitter, duct, mixing
def test_splitter_duct_mix() -> None:
    fs = flow_TP(27.64, 372.0, 2.2e5)
    core, byp = splitter(fs, 1.13)
    assert core.W_kg_s + byp.W_kg_s == pytest.approx(27.64, rel=1e-15)
    assert byp.W_kg_s / core.W_kg_s == pytest.approx(1.13, rel=1e-14)
    assert duct(fs, 0.02).Pt_Pa == pytest.approx(2.2e5 * 0.98)
    hot = flow_TP(3.0, 1200.0, 2.0e5, 0.02)
    m = mix([fs, hot])
    assert m.W_kg_s == pytest.approx(30.64) and m.Pt_Pa == fs.Pt_Pa
    assert m.W_fuel_kg_s == pytest.approx(hot.W_fuel_kg_s, rel=1e-14)
    assert (m.H_W - fs.H_W - hot.H_W) / m.H_W == pytest.approx(0.0, abs=CONS)


# ---------------------------------------------------------------------- burner
def test_burner_energy_and_mass_balance() -> None:
    fs3 = flow_TP(12.0, 620.0, 1.05e6)
    b = burner_to_temperature(fs3, 1403.0, 0.995, 0.05, 300.0)
    assert b.out.W_kg_s == pytest.approx(fs3.W_kg_s + b.Wf_kg_s, rel=1e-15)
    assert b.out.Pt_Pa == pytest.approx(1.05e6 * 0.95)
    fuel_energy = b.Wf_kg_s * (gas.DEFAULT_GAS.LHV_J_kg + h_fuel_liquid(300.0))
    closure = fs3.H_W + fuel_energy - b.out.H_W - b.heat_unreleased_W
    assert closure / fuel_energy == pytest.approx(0.0, abs=CONS)
    # the same balance with enthalpies from numerically integrated cp (independent of gas.h)
    lhs = b.out.W_kg_s * dh_quad(298.15, 1403.0, b.out.FAR)
    rhs = fs3.W_kg_s * dh_quad(298.15, 620.0) + b.Wf_kg_s * (0.995 * 43.1e6 + h_fuel_liquid(300.0))
    assert lhs == pytest.approx(rhs, rel=1e-9)
    # inverse: burning that fuel flow gives back Tt4
    b2 = burner_with_fuel(fs3, b.Wf_kg_s, 0.995, 0.05, 300.0)
    assert b2.out.Tt_K == pytest.approx(1403.0, abs=1e-6)


# --------------------------------------------------------------------- turbine
def test_turbine_for_power_closed_form() -> None:
    fs4 = flow_TP(13.0, 1400.0, 1.0e6, 0.022)
    t = turbine_for_power(fs4, 4.0e6, 0.88)
    assert t.power_W == pytest.approx(4.0e6, rel=1e-12)
    # efficiency from integrated cp: isentropic exit where int cp/T = -R ln PR
    T_is = gas.T_isentropic(1400.0, 1.0 / t.PR, 0.022)
    assert ds_quad(T_is, 1400.0, 0.022) == pytest.approx(gas.R(0.022) * math.log(t.PR), rel=1e-10)
    assert dh_quad(t.out.Tt_K, 1400.0, 0.022) / dh_quad(T_is, 1400.0, 0.022) == pytest.approx(0.88, rel=1e-9)
    assert (fs4.H_W - t.out.H_W - t.power_W) / t.power_W == pytest.approx(0.0, abs=CONS)


def test_turbine_with_cooling_conserves_mass_and_energy() -> None:
    fs4 = flow_TP(13.0, 1400.0, 1.0e6, 0.022)
    cool = [Cooling(flow_TP(0.8, 620.0, 1.05e6), 1.0), Cooling(flow_TP(0.4, 620.0, 1.05e6), 0.0),
            Cooling(flow_TP(0.3, 620.0, 1.05e6), 0.5)]
    t = turbine_for_power(fs4, 4.0e6, 0.88, cool)
    assert t.power_W == pytest.approx(4.0e6, rel=1e-11)
    W_in = fs4.W_kg_s + sum(c.flow.W_kg_s for c in cool)
    assert t.out.W_kg_s == pytest.approx(W_in, rel=1e-15)
    assert t.out.W_fuel_kg_s == pytest.approx(fs4.W_fuel_kg_s, rel=1e-14)
    H_in = fs4.H_W + sum(c.flow.H_W for c in cool)
    assert (H_in - t.out.H_W - t.power_W) / t.power_W == pytest.approx(0.0, abs=CONS)
    # rotor inlet 41 mixes the inlet cooling (frac_P = 1) only
    assert t.rotor_in.W_kg_s == pytest.approx(13.8) and t.rotor_in.Tt_K < 1400.0
    # exit cooling does no work: same PR without it needs the same power minus nothing
    t0 = turbine(fs4, t.PR, 0.88, cool[:1] + cool[2:])
    assert t0.power_W == pytest.approx(t.power_W, rel=1e-12)
    with pytest.raises(OutOfRangeError, match="cannot enter"):
        turbine(fs4, 2.0, 0.88, [Cooling(flow_TP(0.1, 620.0, 0.9e6), 1.0)])


# ---------------------------------------------------------------------- nozzle
def test_nozzle_choked_perfect_gas_hand_calculation() -> None:
    """Air between 250 K and 300 K: gamma 1.400-1.401, so p*/pt = (2/2.4)^3.5 and T*/Tt = 1/1.2 to 5e-4."""
    fs = flow_TP(10.0, 300.0, 3.0e5)
    n = convergent_nozzle(fs, 101325.0)
    assert n.choked
    assert n.throat.Ps_Pa / fs.Pt_Pa == pytest.approx((2 / 2.4) ** 3.5, rel=5e-4)
    assert n.throat.Ts_K / 300.0 == pytest.approx(1 / 1.2, rel=5e-4)
    assert n.throat.Mach == pytest.approx(1.0, abs=1e-9)
    # continuity, energy, thrust definition
    assert n.throat.rho_kg_m3 * n.throat.V_m_s * n.A_eff_m2 == pytest.approx(10.0, rel=1e-12)
    assert gas.h(n.throat.Ts_K) + 0.5 * n.throat.V_m_s ** 2 == pytest.approx(fs.ht_J_kg, abs=1e-6 * 3e5)
    assert n.Fg_N == pytest.approx(10.0 * n.throat.V_m_s + (n.throat.Ps_Pa - 101325.0) * n.A_eff_m2, rel=1e-14)
    # perfect-gas flow function: W sqrt(Tt)/(A Pt) = sqrt(gamma/R) (1.2)^-3
    ff = math.sqrt(1.4 / gas.R()) * 1.2 ** -3.0
    assert 10.0 * math.sqrt(300.0) / (n.A_eff_m2 * 3.0e5) == pytest.approx(ff, rel=5e-4)


def test_nozzle_unchoked_and_coefficients() -> None:
    fs = flow_TP(10.0, 300.0, 1.5e5)
    n = convergent_nozzle(fs, 101325.0, Cv=0.98, Cd=0.95)
    assert not n.choked and n.throat.Ps_Pa == 101325.0
    V = math.sqrt(2 * dh_quad(n.throat.Ts_K, 300.0))
    assert n.throat.V_m_s == pytest.approx(V, rel=1e-9)
    assert n.Fg_N == pytest.approx(0.98 * 10.0 * V, rel=1e-9)
    assert n.A_geom_m2 == pytest.approx(n.A_eff_m2 / 0.95)
    ci = ideal_nozzle(flow_TP(10.0, 300.0, 3.0e5), 101325.0, 0.99)
    assert ci.Fg_N == pytest.approx(0.99 * 10.0 * ci.V_ideal_m_s)
    assert ci.Fg_N > convergent_nozzle(flow_TP(10.0, 300.0, 3.0e5), 101325.0, 0.99).Fg_N
    with pytest.raises(OutOfRangeError, match="reverse flow"):
        convergent_nozzle(flow_TP(1.0, 300.0, 0.9e5), 101325.0)


def test_static_at_mach_consistent() -> None:
    fs = flow_TP(5.0, 500.0, 2e5, 0.01)
    s = static_at_mach(fs, 0.5)
    assert s.Mach == pytest.approx(0.5, rel=1e-9)


# ----------------------------------------------------------------------- shaft
def test_shaft_balance() -> None:
    P_T = turbine_power_required([1.0e6, 0.5e6], 50e3, 0.99)
    assert P_T == pytest.approx(1.55e6 / 0.99)
    assert net_power(P_T, [1.0e6, 0.5e6], 50e3, 0.99) == pytest.approx(0.0, abs=1e-6)
    # dN/dt = P / (I omega) in rad/s^2, converted to rpm/s
    assert spool_acceleration(1000.0, 30000.0 / math.pi, 0.1) == pytest.approx(1000.0 / (0.1 * 1000.0) * 30 / math.pi)
    with pytest.raises(ModelError):
        turbine_power_required([1.0], 0.0, 1.5)
