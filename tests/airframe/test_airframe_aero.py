"""UPERA's geometry, handbook aerodynamics and generated JSBSim file.

References are hand calculations written out here from the textbook formulas
(numbers worked with a calculator from the data file's geometry), limiting
cases of the formulas, or JSBSim itself reading the file. Nothing is compared
with numbers the code printed once.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.airframe.adapter import FT, LBM, SLUG, Airframe
from openemss.models.airframe.aero import (
    aero_model,
    helmbold_slope,
    isa,
    korn_mcrit,
    geometric_model,
    lifting_form_factor,
    oswald_kroo,
    planform_efficiency_nita_scholz,
    skin_friction,
    wave_drag,
)
from openemss.models.airframe.aero_lateral import lateral
from openemss.models.airframe.geometry import load_geometry
from openemss.models.airframe.xmlgen import AIRCRAFT_FILE, aircraft_xml, sidecar_json

G = load_geometry()
A = aero_model()


# ---------------------------------------------------------------- geometry (SPEC.md figures)
def test_spec_figures() -> None:
    assert G.wing.span_m == 6.0
    assert G.wing.area_m2 == 11.2
    assert G.fuselage_length_m == 7.0
    assert G.mtom_kg == 2100.0 and G.oem_kg == 1500.0
    assert G.fuel_capacity_kg == G.mtom_kg - G.oem_kg
    assert G.mtom_kg / G.wing.area_m2 == pytest.approx(187.5)
    # thrust-to-weight 0.6 to 0.7 with the 13 kN engine
    assert 0.6 <= G.section("engine")["thrust_sls_N"] / (G.mtom_kg * 9.80665) <= 0.7


def test_planform_by_hand() -> None:
    # S = 11.2, b = 6, taper 0.5: c_r = 2S/(b(1+l)) = 2.4889 m, MAC = 2/3 c_r (1+l+l^2)/(1+l) = 1.9358 m,
    # y_MAC = b/6 (1+2l)/(1+l) = 1.3333 m (Raymer eqs. 7.5-7.6).
    assert G.wing.root_chord_m == pytest.approx(2.48889, rel=1e-5)
    assert G.wing.mac_m == pytest.approx(1.93580, rel=1e-5)
    assert G.wing.y_mac_m == pytest.approx(4.0 / 3.0)
    # chord integral over the whole half span = S/2
    assert G.wing.chord_integral_m2(0.0, 3.0) == pytest.approx(5.6)
    # leading-edge sweep from c/4 sweep: tan L_LE = tan 25 + (1-l)/(A(1+l)) = 0.46631 + 0.10370
    assert math.tan(G.wing.sweep(0.0)) == pytest.approx(0.57001, rel=1e-4)


def test_inertia_by_radii_of_gyration() -> None:
    ixx, iyy, izz = G.inertia_kg_m2(1500.0)
    assert ixx == pytest.approx(1500 * (6 * 0.25 / 2) ** 2)
    assert iyy == pytest.approx(1500 * (7 * 0.35 / 2) ** 2)
    assert izz == pytest.approx(1500 * (6.5 * 0.45 / 2) ** 2)


# ---------------------------------------------------------------- handbook formulas
def test_isa_sea_level_and_tropopause() -> None:
    # ICAO standard atmosphere table: 0 m 288.15 K 101325 Pa 1.2250 kg/m3 340.29 m/s;
    # 11000 m 216.65 K 22632 Pa 0.36392 kg/m3.
    T, p, rho, a, mu = isa(0.0)
    assert (T, p) == (288.15, 101325.0)
    assert rho == pytest.approx(1.2250, abs=1e-4)
    assert a == pytest.approx(340.29, abs=0.01)
    assert mu == pytest.approx(1.7894e-5, rel=1e-3)
    T, p, rho, _, _ = isa(11000.0)
    assert T == pytest.approx(216.65)
    assert p == pytest.approx(22632, rel=1e-4)
    assert rho == pytest.approx(0.36392, rel=1e-4)


def test_helmbold_limits() -> None:
    # Large aspect ratio: 2 pi A/(2 + A beta/eta) -> 2 pi eta / beta (2-D, Prandtl-Glauert).
    a = helmbold_slope(1e6, 0.0, 0.6)
    assert float(a) == pytest.approx(2 * math.pi * 0.95 / math.sqrt(1 - 0.36), rel=1e-4)
    # Small aspect ratio: slender-wing theory pi A / 2, independent of Mach.
    assert float(helmbold_slope(1e-4, 0.0, 0.0)) == pytest.approx(math.pi * 1e-4 / 2, rel=1e-3)
    assert float(helmbold_slope(1e-4, 0.0, 0.7)) == pytest.approx(math.pi * 1e-4 / 2, rel=1e-3)
    # UPERA's wing, by hand: A = 3.2143, tan(L_tmax) = tan 25 - 4/A (0.15)(0.5/1.5) = 0.40408,
    # A^2/0.95^2 = 11.4478, x (1 + 0.16329) = 13.3171, + 4 = 17.3171, sqrt = 4.16138;
    # 2 pi A / (2 + 4.16138) = 20.1960 / 6.16138 = 3.2778 /rad at M = 0.
    assert float(helmbold_slope(G.wing.aspect_ratio, G.wing.tan_sweep(0.4), 0.0)) == pytest.approx(3.2778, rel=1e-4)


def test_skin_friction_schlichting() -> None:
    # Prandtl-Schlichting turbulent flat plate 0.455/(log10 Re)^2.58 at Re = 1e7, M = 0:
    # 7^2.58 = 151.47 -> 0.0030039 (smooth plate: roughness far below cut-off). Blasius laminar at Re = 1e6: 1.328e-3.
    assert float(skin_friction(1e7, 0.0, 1.0, 1e-9, 0.0)) == pytest.approx(0.0030039, rel=1e-4)
    assert float(skin_friction(1e6, 0.0, 1.0, 1e-9, 1.0)) == pytest.approx(1.328e-3, rel=1e-9)
    # Compressibility factor (1 + 0.144 M^2)^-0.65 at M = 0.8: 0.9441
    r = float(skin_friction(1e7, 0.8, 1.0, 1e-9, 0.0) / skin_friction(1e7, 0.0, 1.0, 1e-9, 0.0))
    assert r == pytest.approx((1 + 0.144 * 0.64) ** -0.65)


def test_korn_and_lock() -> None:
    # Korn: kappa 0.87, t/c 0.10, sweep 25 deg, CL 0.3:
    # M_DD = 0.87/0.90631 - 0.1/0.82139 - 0.3/(10 x 0.74443) = 0.95994 - 0.12175 - 0.04030 = 0.79789;
    # M_cr = M_DD - 0.10772 = 0.69017.
    mcr = float(korn_mcrit(0.3, 0.10, math.radians(25), 0.87))
    assert mcr == pytest.approx(0.69017, abs=2e-5)
    # Lock: at M_DD the slope dCD/dM = 80 (M_DD - M_cr)^3 is 0.1 and CD_w = 20 (0.10772)^4 = 0.002693
    assert float(wave_drag(mcr + 0.10772, mcr)) == pytest.approx(0.002693, rel=1e-3)
    assert float(wave_drag(mcr - 0.01, mcr)) == 0.0


def test_oswald_kroo_by_hand() -> None:
    # Nita & Scholz planform: dl = -0.357 + 0.45 exp(-0.0375 x 25) = -0.18079; f(0.68079) = 0.004661;
    # u = 1/(1 + 0.004661 x 3.2143) = 0.98524. Kroo: s = 1 - 2 (0.8/6)^2 = 0.96444;
    # 1/e = 1/(0.98524 x 0.96444) + pi x 3.2143 x 0.38 x 0.012 = 1.052404 + 0.046047 -> e = 0.91037.
    assert planform_efficiency_nita_scholz(G.wing.aspect_ratio, 0.5, 25.0) == pytest.approx(0.98524, abs=5e-5)
    e = oswald_kroo(G.wing.aspect_ratio, 0.5, 25.0, 0.8 / 6.0, 0.012)
    assert e == pytest.approx(0.91037, abs=5e-5)
    # Limits: no viscous part and no fuselage leave the planform efficiency; more CD0, less e.
    assert oswald_kroo(G.wing.aspect_ratio, 0.5, 25.0, 0.0, 0.0) == pytest.approx(0.98524, abs=5e-5)
    assert oswald_kroo(G.wing.aspect_ratio, 0.5, 25.0, 0.0, 0.02) < 0.98524


def test_shevell_form_factor_by_hand() -> None:
    # Wing: t/c 0.10, c/4 sweep 25 deg (cos 0.906308). M 0.5: Z = 1.75 x 0.906308 / sqrt(1 - 0.25 x 0.821394)
    # = 1.586039/0.891433 = 1.779206 -> FF = 1 + 0.177921 + 0.01 = 1.187921; M 0: Z = 1.812616 -> 1.191262.
    assert float(lifting_form_factor(G.wing, 0.5)) == pytest.approx(1.187921, abs=2e-6)
    assert float(lifting_form_factor(G.wing, 0.0)) == pytest.approx(1.191262, abs=2e-6)
    # Unswept, incompressible: 1 + 2 t/c + 100 (t/c)^4 (Hoerner's thickness term at M 0)
    from openemss.models.airframe.geometry import Planform
    p = Planform(10.0, 10.0, 1.0, 0.0, 0.12, 0.4)
    assert float(lifting_form_factor(p, 0.0)) == pytest.approx(1 + 0.24 + 100 * 0.12 ** 4)


def test_cd0_buildup_magnitude() -> None:
    # Clean subsonic jets: CD0 between 0.010 and 0.025 on the wing area (Raymer table 12.3 equivalent
    # skin friction 0.0035 to 0.0045 x Swet/Sref). UPERA: Swet/Sref by hand about
    # (18.8 wing + 15.0 fuselage + 5.5 h-tail + 2.5 v-tail)/11.2 = 3.7 -> 0.013 to 0.017.
    g = geometric_model()
    for alt, m in ((0, 0.3), (7500, 0.8)):
        T, p, rho, a, mu = isa(alt)
        re = rho * m * a * G.wing.mac_m / mu
        assert 0.010 < float(g.cd0(m, re)) < 0.017
    # More Reynolds number, less friction
    assert float(g.cd0(0.5, 3e7)) < float(g.cd0(0.5, 5e6))
    # The calibrated CD0 is the build-up times its factor
    assert float(A.cd0(0.5, 1e7)) == pytest.approx(float(g.cd0(0.5, 1e7)) * A.corrections.cd0_factor)


def test_static_margin_positive_over_envelope() -> None:
    # Cm_alpha < 0 and neutral point aft of the CG from M 0 to 0.8 (stick fixed).
    for m in np.linspace(0.0, 0.8, 9):
        sm = float(A.static_margin(m))
        assert 0.03 < sm < 0.25, (m, sm)
    # Neutral point by the textbook formula (Nelson eq. 2.48 with the fuselage term):
    # h_n = h_ac - Cm_a,fus/a_wb + eta V_H a_t/a_wb (1 - deps/da), V_H about the CG.
    m = 0.3
    a_wb, a_t = float(A.a_wb(m)), float(A.a_h(m))
    h_ac = (G.x_wing_ac_m - G.x_mac_le_m) / G.wing.mac_m
    h_cg = G.raw["balance"]["cg_mac_fraction"]
    h_n = h_ac - A.cm_alpha_fus / a_wb + A.eta_h * G.tail_volume_h * a_t / a_wb * (1 - float(A.deps_dalpha(m)))
    # Margin referred to the wing-body slope; the code's -Cm_a/CL_a uses the whole aircraft's slope.
    assert (h_n - h_cg) * a_wb / float(A.cl_alpha(m)) == pytest.approx(float(A.static_margin(m)), rel=1e-9)


def test_lateral_directional_signs() -> None:
    lat = lateral(A)
    m, cl = 0.5, 0.3
    assert lat.cn_beta(m) > 0  # weathercock stable
    assert lat.cl_beta(m, cl) < 0  # dihedral effect stable
    assert lat.cy_beta(m) < 0
    assert lat.cl_p(m) < 0 and lat.cn_r(m) < 0  # damped
    assert lat.cl_da(m) > 0  # positive aileron rolls right
    assert lat.cn_dr(m) > 0  # positive rudder yaws right
    assert A.cm_de(m) < 0 < A.cl_de(m)  # trailing edge down: nose down, more lift
    assert A.cm_q(m) < 0


# ---------------------------------------------------------------- the JSBSim file
def test_committed_xml_is_generated() -> None:
    """The committed UPERA.xml and its openemss.json are exactly what xmlgen writes from aero.py and the geometry
    (regenerate with ``python -m openemss.models.airframe.xmlgen``)."""
    assert AIRCRAFT_FILE.read_text(encoding="utf-8") == aircraft_xml()
    assert (AIRCRAFT_FILE.parent / "openemss.json").read_text(encoding="utf-8") == sidecar_json()


def test_jsbsim_reads_mass_and_metrics() -> None:
    af = Airframe()
    af.start_air(3000.0, 150.0, 0.0, alpha_rad=0.05, fuel_kg=600.0)
    # 1e-7: JSBSim converts the file's KG with its own 5-digit factor 2.20462 lb/kg
    assert af.mass_kg == pytest.approx(2100.0, rel=1e-7)
    assert af.get_property("metrics/Sw-sqft") * FT ** 2 == pytest.approx(11.2, rel=1e-6)
    assert af.get_property("metrics/bw-ft") * FT == pytest.approx(6.0, rel=1e-6)
    assert af.get_property("propulsion/tank[0]/contents-lbs") * LBM == pytest.approx(600.0, rel=1e-9)
    iyy = af.get_property("inertia/iyy-slugs_ft2") * SLUG * FT ** 2
    # tank on the CG adds no inertia; 2e-4: JSBSim's KG*M2 to SLUG*FT2 factor has 5 digits
    assert iyy == pytest.approx(G.inertia_kg_m2(1500.0)[1], rel=2e-4)


def test_jsbsim_lift_equals_table_formula() -> None:
    """JSBSim's lift at a state equals q S CL from aero.py (the file is the formula, tabulated)."""
    af = Airframe()
    for alpha in (0.0, 0.05, 0.1):
        af.start_air(3000.0, 150.0, 0.0, alpha_rad=alpha, ground_elevation_m=0.0)
        mach = af.state().mach
        q = af.get_property("aero/qbar-psf") * 47.88026
        lift_n = af.get_property("forces/fwz-aero-lbs") * 4.4482216
        # alpha-dot of the initial frame is not zero; subtract its (tabulated) contribution
        adot = af.get_property("aero/coefficient/CLadot") * 4.4482216
        cl = (lift_n - adot) / (q * 11.2)
        assert cl == pytest.approx(float(A.cl_basic(alpha, mach)), rel=2e-3, abs=2e-4)
