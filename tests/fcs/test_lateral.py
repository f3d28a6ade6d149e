"""Roll, heading and yaw-damper laws on a roll-mode model with an analytic reference.

Model: pdot = -p / tau_r + L_da aileron (qbar/qbar_ref), phidot = p,
psidot = g tan(phi) / V, with tau_r = 0.3 s and L_da = 6 rad/s^2 (a full aileron gives
the steady roll rate 1.8 rad/s = 100 deg/s). With the gains of data/lateral.yaml the
closed roll loop is phi'' + (1/tau_r + L k_p) phi' + L k_phi phi = L k_phi phi_c
(integral neglected): omega = 2.68 rad/s, zeta = 0.9, i.e. overshoot below 1 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.fcs.lateral import LateralController, LateralState

TAU_R, L_DA, G, V = 0.3, 6.0, 9.80665, 150.0
DT = 0.01


def simulate(ctrl: LateralController, t_end: float, **cmd: float) -> dict[str, np.ndarray]:
    phi = p = psi = 0.0
    qbar = ctrl.parameters.qbar_ref_Pa
    log: dict[str, list[float]] = {"t": [], "phi": [], "psi": [], "ail": []}
    for k in range(int(t_end / DT)):
        x = LateralState(phi, 0.0, psi, psi, p, G * math.sin(phi) / V, 0.0, V, qbar)
        out = ctrl.step(DT, x, **cmd)
        p += (-p / TAU_R + L_DA * out.aileron) * DT
        phi += p * DT
        psi += G * math.tan(phi) / V * DT
        for key, v in (("t", k * DT), ("phi", phi), ("psi", psi), ("ail", out.aileron)):
            log[key].append(v)
    return {k: np.array(v) for k, v in log.items()}


def test_roll_step_matches_second_order_design() -> None:
    ctrl = LateralController()
    pr = ctrl.parameters
    wn = math.sqrt(L_DA * pr.k_phi_1_rad)
    zeta = (1 / TAU_R + L_DA * pr.k_p_s_rad) / (2 * wn)
    assert zeta == pytest.approx(0.9, abs=0.01)
    h = simulate(ctrl, 6.0, phi_cmd_rad=math.radians(20.0))
    assert h["phi"].max() < math.radians(20.0) * 1.03  # 3 %: the integral adds a little to the 0.2 % of zeta = 0.9
    t90 = h["t"][np.argmax(h["phi"] > 0.9 * math.radians(20.0))]
    assert t90 < 2.0  # the second-order design reaches 90 % in 1.4 s
    assert abs(h["phi"][-1] - math.radians(20.0)) < math.radians(0.2)


def test_heading_change_at_bank_limit_without_overshoot() -> None:
    ctrl = LateralController()
    h = simulate(ctrl, 120.0, heading_cmd_rad=math.radians(90.0))
    assert np.abs(h["phi"]).max() <= ctrl.parameters.phi_max_rad * 1.02
    assert h["psi"].max() < math.radians(90.0 + 2.0)
    assert abs(h["psi"][-1] - math.radians(90.0)) < math.radians(0.1)


def test_heading_takes_the_shorter_way() -> None:
    ctrl = LateralController()
    assert ctrl.phi_for_heading(math.radians(350.0), math.radians(10.0)) < 0.0
    assert ctrl.phi_for_heading(math.radians(10.0), math.radians(350.0)) > 0.0


def test_turn_coordination_and_sideslip_signs() -> None:
    ctrl = LateralController()
    phi = math.radians(30.0)
    r_c = G * math.sin(phi) / V
    base = dict(phi_rad=phi, theta_rad=0.0, psi_rad=0.0, chi_rad=0.0, p_rad_s=0.0, tas_m_s=V,
                qbar_Pa=ctrl.parameters.qbar_ref_Pa)
    coordinated = ctrl.step(DT, LateralState(r_rad_s=r_c, beta_rad=0.0, **base), phi_cmd_rad=phi)
    assert coordinated.rudder == pytest.approx(0.0, abs=1e-12)
    # yawing faster than coordinated: nose-left rudder; wind from the right (beta > 0): nose-right rudder
    assert ctrl.step(DT, LateralState(r_rad_s=2 * r_c, beta_rad=0.0, **base), phi_cmd_rad=phi).rudder < 0.0
    assert ctrl.step(DT, LateralState(r_rad_s=r_c, beta_rad=0.05, **base), phi_cmd_rad=phi).rudder > 0.0
