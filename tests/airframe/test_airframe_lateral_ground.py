"""Lateral-directional modes, ground handling (brakes, steering, gear), atmosphere parameters.

Modes are identified from pulse and step responses and compared with the
textbook approximations (Nelson ch. 5); ground handling with Coulomb friction.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import curve_fit

from openemss.models.airframe.adapter import FT, SLUG, Airframe
from openemss.models.airframe.aero import aero_model, isa
from openemss.models.airframe.aero_lateral import lateral
from openemss.models.airframe.trim import trim_level

A = aero_model()
LAT = lateral(A)
G = A.geom
G0 = 9.80665
S, B = G.wing.area_m2, G.wing.span_m


@pytest.fixture(scope="module")
def af() -> Airframe:
    return Airframe()


def _inertia(af: Airframe, axis: str) -> float:
    return af.get_property(f"inertia/i{axis}-slugs_ft2") * SLUG * FT ** 2


def test_dutch_roll_identified_from_rudder_pulse(af: Airframe) -> None:
    """Rudder pulse at 3000 m, Mach 0.5; fit of beta(t) over 12 s. Against Nelson's dutch-roll
    approximation (eqs. 5.70-5.71): w^2 = (Y_b N_r - N_b Y_r + u N_b)/u, zeta = -(Y_b + u N_r)/(2 w u).
    w within 10 %; zeta within 35 %: the approximation drops the coupling with roll, which
    a large dihedral effect (Cl_beta -0.10) makes strong."""
    r = trim_level(3000.0, 0.5, airframe=af)
    n = int(15 * af.rate_hz)
    t, beta = np.empty(n), np.empty(n)
    for k in range(n):
        af.set_surfaces(rudder=0.1 if k * af.dt_s < 0.5 else 0.0)
        af.step(af.dt_s)
        s = af.state()
        t[k], beta[k] = s.time_s, s.beta_rad
    m = t >= 0.6

    def model(x, amp, sig, w, ph, c, d):  # type: ignore[no-untyped-def]
        return amp * np.exp(-sig * x) * np.cos(w * x + ph) + c + d * x

    p, _ = curve_fit(model, t[m] - 0.6, beta[m], p0=[0.01, 0.5, 4.0, 0.0, 0.0, 0.0], maxfev=20000)
    wn = math.hypot(p[1], p[2])
    zeta = p[1] / wn
    mach, u, q, mass = r.mach, r.tas_m_s, r.qbar_Pa, r.mass_kg
    izz = _inertia(af, "zz")
    y_b = float(LAT.cy_beta(mach)) * q * S / mass
    n_b = float(LAT.cn_beta(mach)) * q * S * B / izz
    n_r = float(LAT.cn_r(mach)) * q * S * B ** 2 / (2 * u * izz)
    y_r = float(LAT.cy_r(mach)) * q * S * B / (2 * u * mass)
    w_hand = math.sqrt((y_b * n_r - n_b * y_r + u * n_b) / u)
    z_hand = -(y_b + u * n_r) / (2 * w_hand * u)
    print(f"dutch roll: identified w_n {wn:.2f} rad/s, zeta {zeta:.3f}; approximation {w_hand:.2f} rad/s, "
          f"zeta {z_hand:.3f}")
    assert zeta > 0.0  # damped
    assert wn == pytest.approx(w_hand, rel=0.10)
    assert zeta == pytest.approx(z_hand, rel=0.35)


def test_roll_rate_from_aileron_step(af: Airframe) -> None:
    """Aileron step of 0.2 (3 deg) at 3000 m, Mach 0.5: the steady roll rate of the one-degree-of-
    freedom roll mode is p = -(Cl_da da / Cl_p) 2V/b (Nelson eq. 5.9). 10 %: adverse yaw and the
    dutch roll couple in."""
    r = trim_level(3000.0, 0.5, airframe=af)
    p = []
    for _ in range(int(3 * af.rate_hz)):
        af.set_surfaces(aileron=0.2)
        af.step(af.dt_s)
        p.append(af.state().p_rad_s)
    da = 0.2 * math.radians(G.raw["aileron"]["max_deg"])
    p_ss = -float(LAT.cl_da(r.mach)) * da / float(LAT.cl_p(r.mach)) * 2 * r.tas_m_s / B
    p_sim = float(np.mean(p[int(1.5 * af.rate_hz):]))
    print(f"roll: steady p {p_sim:.3f} rad/s, one-DOF approximation {p_ss:.3f} rad/s")
    assert p_sim > 0  # positive aileron rolls right
    assert p_sim == pytest.approx(p_ss, rel=0.10)


def test_brakes_stop_the_aircraft(af: Airframe) -> None:
    """Accelerate to 30 m/s, cut the thrust, full brakes. JSBSim's full brake gives the friction
    coefficient mu = static_friction (FGLGear::ComputeBrakeForceCoefficient). Hand calculation
    with the load transfer to the (unbraked) nose wheel, moments about the CG at height h:
    N_m (x_m - x_cg) + mu N_m h = N_n (x_cg - x_n), N_m + N_n = W -> decel = (mu N_m + mu_roll N_n)/m.
    10 %: drag, the struts' pitch and the build-up of braking neglected."""
    af.start_runway(48.366886, 11.821172, 263.4, 453.0)
    af.set_thrust(13000.0)
    while af.state().gs_m_s < 30.0:
        af.step(0.05)
    af.set_thrust(0.0)
    af.set_brakes(1.0)
    v0, t0 = af.state().gs_m_s, af.time_s
    while af.state().gs_m_s > 1.0 and af.time_s - t0 < 30.0:
        af.step(0.05)
    decel = (v0 - af.state().gs_m_s) / (af.time_s - t0)
    gr = G.section("gear")
    mu, mu_roll = gr["static_friction"], gr["rolling_friction"]
    h = -gr["contact_z_m"] - gr["main_static_deflection_m"]
    a_m, a_n = gr["main_aft_of_cg_m"], G.x_cg_m - gr["nose_x_m"]
    main_share = a_n / (a_n + a_m + mu * h)
    hand = (mu * main_share + mu_roll * (1 - main_share)) * G0
    print(f"braking: mean deceleration {decel:.2f} m/s^2, hand {hand:.2f} m/s^2 (main wheels {main_share:.0%})")
    assert decel == pytest.approx(hand, rel=0.10)
    assert af.state().on_ground


def test_nose_wheel_steering_turns(af: Airframe) -> None:
    af.start_runway(48.366886, 11.821172, 263.4, 453.0)
    af.set_thrust(3000.0)
    af.step(3.0)
    psi0 = af.state().psi_rad
    af.set_steering(0.5)
    af.step(3.0)
    turn = math.degrees((af.state().psi_rad - psi0 + math.pi) % (2 * math.pi) - math.pi)
    assert turn > 5.0  # steering > 0 turns right (heading increases)


def test_gear_retracts_and_adds_drag(af: Airframe) -> None:
    af.start_air(3000.0, 120.0, 0.0, alpha_rad=0.06, gear_down=True, ground_elevation_m=0.0)
    assert af.get_property("gear/gear-pos-norm") == 1.0
    d_down = af.get_property("aero/coefficient/CDgear")
    af.set_gear(False)
    af.step(2.5)
    assert af.get_property("gear/gear-pos-norm") == pytest.approx(0.5, abs=0.01)  # 5 s full travel
    af.step(3.0)
    assert af.get_property("gear/gear-pos-norm") == 0.0
    assert af.get_property("aero/coefficient/CDgear") == 0.0 < d_down


@pytest.mark.parametrize("wind", [(0.0, -10.0, 0.0), (6.0, 8.0, 0.0), (-3.0, 4.0, 1.0)])
def test_isa_deviation_and_wind(wind: tuple[float, float, float]) -> None:
    """The air start's airspeed, sideslip and angle of attack are relative to the air mass, and the
    ground velocity is air velocity + wind (vector sum, checked in north/east components)."""
    af = Airframe(dT_isa_K=15.0, wind_ned_m_s=wind)
    s0 = af.start_air(5000.0, 150.0, 90.0, alpha_rad=0.05, ground_elevation_m=0.0)
    assert s0.tas_m_s == pytest.approx(150.0, abs=1e-6) and abs(s0.beta_rad) < 1e-9  # at time zero already
    af.step(af.dt_s)
    s = af.state()
    assert s.T_amb_K == pytest.approx(isa(5000.0)[0] + 15.0, abs=0.05)
    assert s.tas_m_s == pytest.approx(150.0, abs=0.05)
    assert abs(s.beta_rad) < 1e-3 and s.alpha_rad == pytest.approx(0.05, abs=1e-3)
    v_n = af.get_property("velocities/v-north-fps") * FT
    v_e = af.get_property("velocities/v-east-fps") * FT
    # eastbound: air velocity (0, 150 cos(gamma)) with gamma ~ 0
    assert v_n == pytest.approx(wind[0], abs=0.1)
    assert v_e == pytest.approx(150.0 + wind[1], abs=0.1)


def test_turbulence_is_seeded() -> None:
    def run(seed: int) -> float:
        af = Airframe(turbulence_severity=4, turbulence_wind_20ft_m_s=10.0, seed=seed)
        r = trim_level(1000.0, 0.4, airframe=af)
        af.start_air(1000.0, r.tas_m_s, 0.0, alpha_rad=r.alpha_rad, elevator=r.elevator, Fn_N=r.Fn_N,
                     ground_elevation_m=0.0)
        af.step(10.0)
        return af.state().phi_rad

    a, b = run(1), run(1)
    assert a == b
    assert abs(a) > 1e-4  # the turbulence does something
