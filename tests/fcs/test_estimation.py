"""The TECS's airspeed-rate estimate (models/fcs/estimation.py) on synthetic flights with known answers.

* The air path's direction from the attitude: in a level coordinated turn the angle of attack is
  atan(tan(theta)/cos(phi)) and the path horizontal; wings level it is the pitch.
* A steady level turn at constant speed (positions on a circle, as an FMU measures them): the rate is
  zero, though the centripetal acceleration is 17 m/s^2; the heading alone as the path direction reads
  the nose's alpha sin(phi) inside the turn as a speed change.
* A straight acceleration: the rate is the acceleration.
* White noise on the airspeed: the output noise is the complementary filter's, about sigma/tau,
  instead of the raw difference's sigma sqrt(2)/h.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.fcs.atmosphere import G0_M_S2
from openemss.models.fcs.estimation import AirspeedRateEstimator, air_path_direction

H = 0.05


def test_air_path_direction_from_the_attitude() -> None:
    # wings level, climbing at 3 deg with 4 deg of angle of attack, heading 30 deg: along the heading, up 3 deg
    n, e, u = air_path_direction(0.0, math.radians(7.0), math.radians(30.0), 0.0, math.radians(3.0))
    c3, s3 = math.cos(math.radians(3)), math.sin(math.radians(3))
    assert (n, e, u) == pytest.approx((c3 * math.cos(math.radians(30)), c3 * math.sin(math.radians(30)), s3), abs=1e-12)
    # level right turn, 60 deg bank, pitch 3 deg: alpha = atan(tan(3 deg)/cos(60 deg)); the path is horizontal
    # and, the nose pointing into the turn, lies to the left of the heading
    phi, theta = math.radians(60.0), math.radians(3.0)
    n, e, u = air_path_direction(phi, theta, 0.0, 0.0, 0.0)
    assert u == pytest.approx(0.0, abs=1e-12) and math.hypot(n, e) == pytest.approx(1.0, abs=1e-12)
    alpha = math.atan(math.tan(theta) / math.cos(phi))
    # the body x axis projected on the horizontal and the velocity differ by the azimuth
    # atan2(sin(alpha) sin(phi), cos(alpha) cos(theta) + sin(alpha) cos(phi) sin(theta)) (rotation by hand)
    expect = -math.atan2(math.sin(alpha) * math.sin(phi), math.cos(alpha) * math.cos(theta)
                         + math.sin(alpha) * math.cos(phi) * math.sin(theta))
    assert math.atan2(e, n) == pytest.approx(expect, abs=1e-12)
    assert math.degrees(-expect) > 4.0  # 5 deg: the error of taking the heading for the path


def _turn(tau_s: float, use_heading_only: bool = False) -> np.ndarray:
    """Level right turn at 164 m/s and 2 g (phi 60 deg), positions on the circle differenced as the FMU does."""
    V, phi = 164.0, math.radians(60.0)
    R = V * V / (G0_M_S2 * math.tan(phi))
    w = V / R
    theta = math.radians(3.0)
    alpha = math.atan(math.tan(theta) / math.cos(phi))
    drift = math.atan2(math.sin(alpha) * math.sin(phi), math.cos(alpha) * math.cos(theta)
                       + math.sin(alpha) * math.cos(phi) * math.sin(theta))  # the nose inside the turn, as above
    est = AirspeedRateEstimator(tau_s)
    out = []
    for k in range(400):
        t0, t1 = (k - 1) * H, k * H
        # mean velocity over the step from two positions on the circle (centre east of the start)
        p0 = (R * math.sin(w * t0), R * (1 - math.cos(w * t0)))
        p1 = (R * math.sin(w * t1), R * (1 - math.cos(w * t1)))
        vn, ve = (p1[0] - p0[0]) / H, (p1[1] - p0[1]) / H
        chi = w * t1
        psi = chi + drift
        if use_heading_only:
            out.append(est.step(H, V, vn, ve, 0.0, 0.0, 0.0, psi, 0.0, 0.0))
        else:
            out.append(est.step(H, V, vn, ve, 0.0, phi, theta, psi, 0.0, 0.0))
    return np.array(out[5:])


def test_steady_turn_reads_no_speed_change() -> None:
    got = _turn(10.0)
    assert np.max(np.abs(got)) < 2e-3  # of 17 m/s^2 centripetal acceleration
    # the heading as the path direction (wings level attitude): the nose's 5 deg into the turn reads
    # about a_c sin(5 deg) = 1.5 m/s^2 of acceleration
    wrong = _turn(10.0, use_heading_only=True)
    assert np.min(wrong[:20]) > 1.0


def test_straight_acceleration_is_the_rate() -> None:
    a = 0.8
    est = AirspeedRateEstimator(10.0)
    out = []
    for k in range(2000):  # 100 s = 10 tau: the start's error of a h decays as exp(-t/tau)
        t = k * H
        v_mean = 100.0 + a * (t - 0.5 * H)  # the step's mean velocity, from positions
        out.append(est.step(H, 100.0 + a * t, v_mean, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    assert out[-1] == pytest.approx(a, rel=1e-6)
    assert est.tas_m_s == pytest.approx(100.0 + a * 2000 * H, abs=1e-3)


@pytest.mark.parametrize("tau_s", [2.0, 10.0])
def test_airspeed_noise_is_filtered(tau_s: float) -> None:
    """Steady flight, airspeed with white noise sigma: output = (V - V_e)/tau, V_e the first-order low-pass of
    V; for white noise its standard deviation is sigma / tau sqrt(1 + h/(2 tau)) / sqrt(1 - h/(2 tau)) ~
    sigma / tau (the low-pass keeps a fraction h/(2 tau) of the variance). Within 5 % over 40000 samples."""
    rng = np.random.default_rng(1)
    sigma = 1.0
    est = AirspeedRateEstimator(tau_s)
    out = [est.step(H, 150.0 + sigma * x, 150.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
           for x in rng.standard_normal(40000)]
    sd = float(np.std(out[2000:]))
    r = H / (2.0 * tau_s)
    assert sd == pytest.approx(sigma / tau_s * math.sqrt((1 + r) / (1 - r)), rel=0.05)
    assert sd < sigma * math.sqrt(2.0) / H / 50.0  # the raw difference: sigma sqrt(2)/h = 28 m/s^2
