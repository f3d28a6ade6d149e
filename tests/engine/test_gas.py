"""Tests of gas properties and burner balance (models/engine/thermo.py, gas.py, combustion.py).

Every reference below is either a published table or correlation (cited where
it is used, with its tolerance and why), a conservation law, or an exact
mathematical identity checked by an independent computation (numerical
quadrature, an element balance written out here). Nothing is compared with
output of the code captured once.
"""

from __future__ import annotations

import json
import math

import pytest
from scipy.integrate import quad

from openemss.models.engine import combustion, gas
from openemss.models.engine.errors import ModelError, OutOfRangeError
from openemss.models.engine.gas import T_MAX_K, T_MIN_K, GasModel
from openemss.models.engine.thermo import DATA_FILE, T_REF_K, load_thermo_data

G = gas.DEFAULT_GAS
DATA = load_thermo_data()
R_U = DATA.gas_constant_J_molK
FARS = (0.0, 0.01, 0.02, 0.04, G.FAR_stoich)


# --------------------------------------------------------------------------- data file
def _d(field: str) -> float:
    return float(field.replace("D", "E"))


def test_json_numbers_equal_the_verbatim_nasa_record_lines() -> None:
    """The JSON numbers are exactly those of the thermo.inp lines kept beside them.

    The lines are NASA's fixed format (NASA/TP-2002-211556 appendix A; NASA
    RP-1311 part 2): molar mass in columns 53-65 and Hf in 66-80 of line 2;
    per interval a line with T_min, T_max in columns 1-22, then two lines of
    D16.9 fields: a1..a5; a6, a7, (blank), b1, b2.
    """
    raw = json.loads(DATA_FILE.read_text(encoding="utf-8"))
    for name, rec in raw["species"].items():
        lines = rec["thermo_inp_record"]
        assert lines[0][:18].strip() == rec["thermo_inp_name"]
        assert float(lines[1][52:65]) == rec["molar_mass_g_mol"], name
        assert float(lines[1][65:80]) == rec["Hf298_J_mol"], name
        for k, iv in enumerate(rec["intervals"]):
            t, c1, c2 = lines[2 + 3 * k: 5 + 3 * k]
            assert (float(t[0:11]), float(t[11:22])) == (iv["T_min_K"], iv["T_max_K"]), name
            a = [_d(c1[16 * j:16 * j + 16]) for j in range(5)] + [_d(c2[0:16]), _d(c2[16:32])]
            assert a == iv["a"], (name, k)
            assert [_d(c2[48:64]), _d(c2[64:80])] == iv["b"], (name, k)


@pytest.mark.parametrize("name", [n for n in sorted(DATA.species) if DATA.species[n].T_min_K <= T_REF_K])
def test_enthalpy_at_298K_equals_heat_of_formation_in_record_header(name: str) -> None:
    """H(298.15 K) from the coefficients reproduces the header's Hf to 1 J/mol.

    Hf is a separate number in the NASA record, so this catches a wrong
    coefficient or constant of the interval holding 298.15 K. ('Air' starts at
    300 K and is checked against our mixture instead.)
    """
    sp = DATA.species[name]
    assert R_U * sp.H_R(T_REF_K) == pytest.approx(sp.Hf298_J_mol, abs=1.0)


@pytest.mark.parametrize("name", [n for n in sorted(DATA.species) if len(DATA.species[n].intervals) > 1])
def test_species_functions_continuous_at_interval_break(name: str) -> None:
    """NASA fits are constrained to meet at 1000 K; a mistyped coefficient breaks that.

    Tolerances: cp/R to 1e-6 relative, H/R to 1e-3 K and S/R to 1e-6 (the jumps
    of correct data are < 5e-5 K and < 2e-8; a one-digit typo gives far more).
    """
    sp = DATA.species[name]
    lo, hi = sp.intervals[0], sp.intervals[1]
    T = lo.T_max_K
    pieces = []
    for iv in (lo, hi):
        a1, a2, a3, a4, a5, a6, a7 = iv.a
        pieces.append((
            a1 / T**2 + a2 / T + a3 + a4 * T + a5 * T**2 + a6 * T**3 + a7 * T**4,
            -a1 / T + a2 * math.log(T) + a3 * T + a4 * T**2 / 2 + a5 * T**3 / 3
            + a6 * T**4 / 4 + a7 * T**5 / 5 + iv.b[0],
            -a1 / (2 * T**2) - a2 / T + a3 * math.log(T) + a4 * T + a5 * T**2 / 2
            + a6 * T**3 / 3 + a7 * T**4 / 4 + iv.b[1],
        ))
    (c1, h1, s1), (c2, h2, s2) = pieces
    assert c2 == pytest.approx(c1, rel=1e-6)
    assert h2 == pytest.approx(h1, abs=1e-3)
    assert s2 == pytest.approx(s1, abs=1e-6)


def test_loader_reports_missing_file_with_its_path(tmp_path) -> None:
    missing = tmp_path / "nope.json"
    with pytest.raises(ModelError, match="nope.json"):
        load_thermo_data(missing)


# ------------------------------------------------------------------- published values
# Ideal-gas cp [kJ/(kg K)] and gamma of dry air, NBS Circular 564 (Hilsenrath et al.,
# "Tables of Thermal Properties of Gases", 1955), as tabulated by Ohio University,
# ME321 "Specific Heat Capacities of Air" (www.ent.ohiou.edu/~thermo). Tolerances:
# cp 0.2 % = table rounding (up to 0.05 %) + 1955-vs-current data (about 0.1 %);
# gamma 0.001 = rounding 0.0005 + the same cp difference (0.0003 in gamma).
NBS_AIR = [
    (250, 1.003, 1.401), (300, 1.005, 1.400), (350, 1.008, 1.398), (400, 1.013, 1.395),
    (450, 1.020, 1.391), (500, 1.029, 1.387), (550, 1.040, 1.381), (600, 1.051, 1.376),
    (650, 1.063, 1.370), (700, 1.075, 1.364), (750, 1.087, 1.359), (800, 1.099, 1.354),
    (900, 1.121, 1.344), (1000, 1.142, 1.336),
]


@pytest.mark.parametrize("T_K, cp_kJ_kgK, gamma_ref", NBS_AIR)
def test_air_cp_and_gamma_match_nbs_circular_564(T_K: float, cp_kJ_kgK: float, gamma_ref: float) -> None:
    assert gas.cp(T_K) == pytest.approx(cp_kJ_kgK * 1e3, rel=2e-3)
    assert gas.gamma(T_K) == pytest.approx(gamma_ref, abs=1e-3)


def test_gamma_of_air_at_300K_is_1_400() -> None:
    assert gas.gamma(300.0) == pytest.approx(1.400, abs=0.002)


def test_gas_constant_of_air_matches_standard_atmosphere() -> None:
    """R of dry air 287.05287 J/(kg K) (ISO 2533:1975, ICAO Doc 7488).

    Tolerance 0.01 %: the standard atmosphere uses R* = 8.31432 J/(mol K) and
    M = 28.9644 g/mol, the NASA data 8.31451 and the Gordon (1982) composition.
    """
    assert gas.R() == pytest.approx(287.05287, rel=1e-4)


# NIST Chemistry WebBook, nitrogen, gas-phase Shomate coefficients A..E fitted to
# NIST-JANAF (Chase 1998), cp = A + B t + C t^2 + D t^3 + E/t^2 [J/(mol K)], t = T/1000.
# NASA's N2 comes from Gurvich (1978); the two data sets and the Shomate fit agree to
# a few 0.01 %, so the tolerance is 0.1 %.
SHOMATE_N2 = [
    ((100.0, 500.0), (28.98641, 1.853978, -9.647459, 16.63537, 0.000117)),
    ((500.0, 2000.0), (19.50583, 19.88705, -8.598535, 1.369784, 0.527601)),
    ((2000.0, 6000.0), (35.51872, 1.128728, -0.196103, 0.014662, -4.553760)),
]


@pytest.mark.parametrize("T_K", [200, 300, 400, 600, 800, 1000, 1200, 1500, 1800, 2000, 2200])
def test_nitrogen_cp_matches_nist_janaf(T_K: float) -> None:
    A, B, C, D, E = next(c for (lo, hi), c in SHOMATE_N2 if lo <= T_K <= hi)
    t = T_K / 1000.0
    cp_ref = A + B * t + C * t**2 + D * t**3 + E / t**2
    assert R_U * DATA.species["N2"].cp_R(T_K) == pytest.approx(cp_ref, rel=1e-3)


@pytest.mark.parametrize("T_K", [300, 400, 600, 800, 1000, 1200, 1500, 1800, 2000, 2200])
def test_air_mixture_matches_nasa_air_record(T_K: float) -> None:
    """Our dry-air mixture against NASA's own 'Air' record (Gordon 1982 composition).

    The record is a separate NASA fit for the same air, so this checks our
    composition and mixing: cp and h(T) - h(300 K) to 0.01 %, molar mass to 1e-6.
    """
    air = DATA.species["Air"]
    R_air = R_U / air.molar_mass_kg_mol
    assert G.molar_mass_air_kg_mol == pytest.approx(air.molar_mass_kg_mol, rel=1e-6)
    assert gas.cp(T_K) == pytest.approx(R_air * air.cp_R(T_K), rel=1e-4)
    if T_K > 300:
        dh_ref = R_air * (air.H_R(T_K) - air.H_R(300.0))
        assert gas.h(T_K) - gas.h(300.0) == pytest.approx(dh_ref, rel=1e-4)


# Walsh & Fletcher, "Gas Turbine Performance", 2nd ed. (2004), formulae F3.23/F3.24:
# cp [kJ/(kg K)] = sum A_i TZ^i + FAR/(1+FAR) sum B_i TZ^i, TZ = T/1000, for dry air
# and kerosene combustion products, 200 K to 2000 K.
WF_A = (0.992313, 0.236688, -1.852148, 6.083152, -8.893933, 7.097112, -3.234725, 0.794571, -0.081873)
WF_B = (-0.718874, 8.747481, -15.863157, 17.254096, -10.233795, 3.081778, -0.361112, -0.003919)


@pytest.mark.parametrize("FAR", [0.0, 0.01, 0.02, 0.03, 0.05])
@pytest.mark.parametrize("T_K", [200, 300, 500, 800, 1000, 1200, 1500, 1800, 2000])
def test_cp_matches_walsh_fletcher_polynomial(T_K: float, FAR: float) -> None:
    """Tolerance 0.2 % for air (fit residuals, data vintage); 0.3 % for products,
    because W&F's kerosene H/C is not stated and y from 1.8 to 2.0 moves cp of
    products at FAR 0.03 by about +-0.2 % against our C12H23."""
    tz = T_K / 1000.0
    cp_wf = sum(a * tz**i for i, a in enumerate(WF_A))
    cp_wf += FAR / (1 + FAR) * sum(b * tz**i for i, b in enumerate(WF_B))
    assert gas.cp(T_K, FAR) == pytest.approx(cp_wf * 1e3, rel=2e-3 if FAR == 0.0 else 3e-3)


def test_default_lhv_agrees_with_nasa_heats_of_formation() -> None:
    """C12H23(L) + 17.75 O2 -> 12 CO2 + 11.5 H2O(g) at 298.15 K with the data file's
    Hf gives 43.03 MJ/kg; the default LHV (43.1 MJ/kg) must agree within 0.5 %."""
    sp = DATA.species
    lhv = -(12 * sp["CO2"].Hf298_J_mol + 11.5 * sp["H2O"].Hf298_J_mol
            - sp["Jet-A(L)"].Hf298_J_mol) / sp["Jet-A(L)"].molar_mass_kg_mol
    assert G.LHV_J_kg == pytest.approx(lhv, rel=5e-3)


# ----------------------------------------------------------- composition (element balance)
def _products_per_kg_air(FAR: float) -> dict[str, float]:
    """Moles per kg of dry air after burning FAR kg of C12H23, written out independently."""
    sp = DATA.species
    x = DATA.air_mole_fractions
    M_air = sum(x[s] * sp[s].molar_mass_kg_mol for s in x)
    n = {s: x[s] / M_air for s in x}
    n["H2O"] = 0.0
    m = FAR / sp["Jet-A(L)"].molar_mass_kg_mol          # mol C12H23 per kg air
    n["CO2"] += 12 * m
    n["H2O"] += 11.5 * m
    n["O2"] -= 17.75 * m
    return n


@pytest.mark.parametrize("FAR", FARS)
def test_composition_matches_element_balance(FAR: float) -> None:
    ref = _products_per_kg_air(FAR)
    got = G.mole_numbers(FAR)
    for s, n in ref.items():
        assert got[s] * (1 + FAR) == pytest.approx(n, rel=1e-12, abs=1e-12), s
    assert sum(G.mass_fractions(FAR).values()) == pytest.approx(1.0, rel=1e-12)
    assert G.R(FAR) == pytest.approx(R_U * sum(ref.values()) / (1 + FAR), rel=1e-12)


def test_stoichiometric_far_leaves_no_oxygen() -> None:
    assert _products_per_kg_air(G.FAR_stoich)["O2"] == pytest.approx(0.0, abs=1e-12)
    assert 0.067 < G.FAR_stoich < 0.069


# -------------------------------------------------------------------- consistency laws
T_GRID = [200.0, 213.7, 250.0, 298.15, 300.0, 450.0, 700.0, 999.99, 1000.0, 1000.01, 1350.0,
          1700.0, 2000.0, 2199.99, 2200.0]


@pytest.mark.parametrize("FAR", FARS)
def test_h_and_phi_are_integrals_of_cp(FAR: float) -> None:
    """h(T2) - h(T1) = int cp dT and phi(T2) - phi(T1) = int cp/T dT, by scipy quad.

    Relative tolerance 1e-9 (quadrature error is far smaller); h and phi vanish at 298.15 K.
    """
    assert gas.h(T_REF_K, FAR) == pytest.approx(0.0, abs=1e-6)
    assert gas.phi(T_REF_K, FAR) == pytest.approx(0.0, abs=1e-9)
    for T1, T2 in [(200.0, 1000.0), (1000.0, 2200.0), (288.15, 1403.0), (600.0, 610.0)]:
        kw = dict(points=[1000.0] if T1 < 1000.0 < T2 else None, epsabs=0.0, epsrel=1e-12)
        dh = quad(lambda T: gas.cp(T, FAR), T1, T2, **kw)[0]
        dphi = quad(lambda T: gas.cp(T, FAR) / T, T1, T2, **kw)[0]
        assert gas.h(T2, FAR) - gas.h(T1, FAR) == pytest.approx(dh, rel=1e-9)
        assert gas.phi(T2, FAR) - gas.phi(T1, FAR) == pytest.approx(dphi, rel=1e-9)


@pytest.mark.parametrize("FAR", FARS)
def test_derivatives_by_finite_difference(FAR: float) -> None:
    """dh/dT = cp and dphi/dT = cp/T by central differences (step 0.01 K, rel. 1e-7)."""
    for T in (210.0, 400.0, 900.0, 1100.0, 1600.0, 2190.0):
        d = 0.01
        assert (gas.h(T + d, FAR) - gas.h(T - d, FAR)) / (2 * d) == pytest.approx(gas.cp(T, FAR), rel=1e-7)
        assert (gas.phi(T + d, FAR) - gas.phi(T - d, FAR)) / (2 * d) == pytest.approx(
            gas.cp(T, FAR) / T, rel=1e-7)


@pytest.mark.parametrize("FAR", FARS)
def test_inverses_round_trip_to_1e_6_K(FAR: float) -> None:
    for T in T_GRID + [200.0 + 13.1 * k for k in range(153)]:
        assert gas.T_from_h(gas.h(T, FAR), FAR) == pytest.approx(T, abs=1e-6)
        assert gas.T_from_phi(gas.phi(T, FAR), FAR) == pytest.approx(T, abs=1e-6)
        assert gas.T_from_h(gas.h(T, FAR), FAR, T_guess_K=1800.0) == pytest.approx(T, abs=1e-6)


@pytest.mark.parametrize("FAR", [0.0, 0.025])
def test_isentropic_temperature(FAR: float) -> None:
    """phi(T2) - phi(T1) = R ln(p2/p1); compression then expansion returns to T1;
    with cp evaluated by quadrature of cp/T between the two temperatures."""
    T1, pr = 288.15, 10.4
    T2 = gas.T_isentropic(T1, pr, FAR)
    lhs = quad(lambda T: gas.cp(T, FAR) / T, T1, T2, epsabs=0.0, epsrel=1e-12)[0]
    assert lhs == pytest.approx(gas.R(FAR) * math.log(pr), rel=1e-9)
    assert gas.T_isentropic(T2, 1 / pr, FAR) == pytest.approx(T1, abs=1e-6)


@pytest.mark.parametrize("Tt_K, Mach, FAR", [(288.15, 0.0, 0.0), (288.15, 0.5, 0.0), (250.0, 0.8, 0.0),
                                           (1400.0, 0.3, 0.025), (900.0, 1.0, 0.02)])
def test_static_from_total(Tt_K: float, Mach: float, FAR: float) -> None:
    """Energy h(Tt) - h(T) = V^2/2 with V = M a(T) (rel. 1e-9); isentropic p/pt from
    phi; and, for air near ambient where cp is nearly constant, the perfect-gas
    results T = Tt/(1 + (g-1)/2 M^2), p/pt = (T/Tt)^(g/(g-1)) to 0.02 %."""
    T, p_pt = gas.static_from_total(Tt_K, Mach, FAR)
    V2 = Mach**2 * gas.gamma(T, FAR) * gas.R(FAR) * T
    assert gas.h(Tt_K, FAR) - gas.h(T, FAR) == pytest.approx(V2 / 2, rel=1e-9, abs=1e-9)
    assert gas.phi(T, FAR) - gas.phi(Tt_K, FAR) == pytest.approx(gas.R(FAR) * math.log(p_pt), rel=1e-9, abs=1e-12)
    if Tt_K < 300.0:
        g = gas.gamma(0.5 * (T + Tt_K))
        assert T == pytest.approx(Tt_K / (1 + (g - 1) / 2 * Mach**2), rel=2e-4)
        assert p_pt == pytest.approx((T / Tt_K) ** (g / (g - 1)), rel=2e-4)


def test_adiabatic_mixing_conserves_enthalpy() -> None:
    """Air and products mixed at equal T give products at the mixed FAR, same T:
    m1 h(T, 0) + m2 h(T, f2) = (m1 + m2) h(T, f_mix)."""
    m1, m2, f2, T = 0.3, 1.0, 0.03, 1200.0
    f_mix = (m2 * f2 / (1 + f2)) / (m1 + m2 / (1 + f2))
    assert m1 * gas.h(T) + m2 * gas.h(T, f2) == pytest.approx((m1 + m2) * gas.h(T, f_mix), rel=1e-12)


# ---------------------------------------------------------------------------- burner
def _H_abs(moles: dict[str, float], T_K: float) -> float:
    return sum(n * R_U * DATA.species[s].H_R(T_K) for s, n in moles.items())


@pytest.mark.parametrize("Tt3_K, Tt4_K, FAR_in, T_fuel_K", [
    (600.0, 1403.0, 0.0, T_REF_K), (300.0, 1000.0, 0.0, 400.0), (800.0, 2000.0, 0.0, 250.0),
    (1100.0, 1500.0, 0.015, T_REF_K),
])
def test_burner_conserves_absolute_enthalpy(Tt3_K: float, Tt4_K: float, FAR_in: float,
                                            T_fuel_K: float) -> None:
    """With eta_b = 1 and the LHV that the data's heats of formation imply, the
    burner FAR closes the balance of absolute enthalpies (heats of formation
    included, written out here per species) to 1e-9 of the heat released."""
    sp = DATA.species
    M_f = sp["Jet-A(L)"].molar_mass_kg_mol
    lhv = -(12 * sp["CO2"].Hf298_J_mol + 11.5 * sp["H2O"].Hf298_J_mol - sp["Jet-A(L)"].Hf298_J_mol) / M_f
    model = GasModel(LHV_J_kg=lhv)
    far4 = combustion.far_burner(Tt3_K, Tt4_K, 1.0, FAR_in, T_fuel_K, gas=model)
    H_in = _H_abs(_products_per_kg_air(FAR_in), Tt3_K) + (far4 - FAR_in) / M_f * R_U * sp["Jet-A(L)"].H_R(T_fuel_K)
    H_out = _H_abs(_products_per_kg_air(far4), Tt4_K)
    assert H_out - H_in == pytest.approx(0.0, abs=1e-9 * (far4 - FAR_in) * lhv)
    assert combustion.T_burner_exit(Tt3_K, far4, 1.0, FAR_in, T_fuel_K, gas=model) == pytest.approx(
        Tt4_K, abs=1e-6)


def test_burner_efficiency_scales_fuel() -> None:
    """Less efficient combustion needs proportionally more fuel (exactly, at T_fuel = 298.15 K,
    since only eta_b * LHV enters): f(eta) * (eta LHV - h_fuel(T4)) is invariant."""
    f1, f2 = combustion.far_burner(600.0, 1400.0, 1.0), combustion.far_burner(600.0, 1400.0, 0.95)
    assert f2 > f1
    hf4 = (1 + f1) * gas.h(1400.0, f1) - gas.h(1400.0)           # = f1 * h_fuel(T4)
    hf4 /= f1
    assert f2 * (0.95 * G.LHV_J_kg - hf4) == pytest.approx(f1 * (G.LHV_J_kg - hf4), rel=1e-12)


# ------------------------------------------------------------------------ range checks
@pytest.mark.parametrize("T_K", [T_MIN_K - 1e-6, T_MAX_K + 1e-6, float("nan"), float("inf"), -5.0])
@pytest.mark.parametrize("fn", [gas.cp, gas.h, gas.phi, gas.gamma])
def test_temperature_out_of_range_raises_value_error_naming_range(fn, T_K: float) -> None:
    with pytest.raises(OutOfRangeError) as info:
        fn(T_K, 0.01)
    assert isinstance(info.value, ValueError)
    msg = str(info.value)
    assert repr(T_K) in msg and "200.0 K to 2200.0 K" in msg


@pytest.mark.parametrize("FAR", [-1e-9, G.FAR_stoich * 1.0001, float("nan")])
def test_far_out_of_range_raises(FAR: float) -> None:
    for fn in (gas.cp, gas.h, gas.phi):
        with pytest.raises(OutOfRangeError, match=f"FAR={FAR!r}.*0 to 0.0681"):
            fn(1000.0, FAR)
    with pytest.raises(OutOfRangeError):
        gas.R(FAR)


def test_inverse_out_of_range_raises() -> None:
    with pytest.raises(OutOfRangeError, match="h_J_kg=3000000.0 J/kg"):
        gas.T_from_h(3.0e6, 0.02)
    with pytest.raises(OutOfRangeError, match="phi_J_kgK"):
        gas.T_from_phi(-500.0)


def test_burner_limits_raise() -> None:
    with pytest.raises(OutOfRangeError, match="beyond the stoichiometric"):
        combustion.far_burner(250.0, 2200.0, 0.8)
    with pytest.raises(OutOfRangeError, match="eta_b"):
        combustion.far_burner(600.0, 1400.0, 0.0)
    with pytest.raises(OutOfRangeError, match="must exceed"):
        combustion.far_burner(1400.0, 600.0)
    with pytest.raises(OutOfRangeError, match="Jet-A"):
        combustion.far_burner(600.0, 1400.0, 1.0, 0.0, 600.0)     # fuel data end at 550 K
