"""Electric machines: energy balance, the loss model by hand, limits without overshoot.

References: the loss model of Larminie & Lowry (2012) sec. 6.5, written out here by hand; the
rated-point efficiency the parameter file states (95 %, losses split 50/30/10/10 %).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.electric.machine import RPM, ElectricMachine
from openemss.models.electric.params import MachineParams, load_section


@pytest.fixture(params=["hp_machine", "lp_machine"])
def m(request: pytest.FixtureRequest) -> ElectricMachine:
    return ElectricMachine(load_section(MachineParams, request.param))


def _loss_by_hand(p: MachineParams, P_W: float, n_rpm: float) -> float:
    w = n_rpm * math.pi / 30.0
    T = P_W / w
    return p.k_c_W_Nm2 * T ** 2 + p.k_i_W_s * w + p.k_w_W_s3 * w ** 3 + p.C_W


@pytest.mark.parametrize("frac", [-1.0, -0.5, -0.1, 0.1, 0.5, 1.0])
@pytest.mark.parametrize("n_frac", [0.6, 0.8, 1.0])
def test_shaft_equals_electrical_plus_losses(m: ElectricMachine, frac: float, n_frac: float) -> None:
    """P_shaft = P_elec + P_loss to round-off, losses as the formula by hand, generating and motoring."""
    n = m.p.n_max_rpm * n_frac
    pt = m.at_shaft(frac * m.shaft_limit_W(n), n)
    assert pt.P_shaft_W - pt.P_elec_W - pt.P_loss_W == pytest.approx(0.0, abs=1e-9 * abs(pt.P_shaft_W))
    assert pt.P_loss_W == pytest.approx(_loss_by_hand(m.p, pt.P_shaft_W, n), rel=1e-12)
    if frac > 0:
        assert pt.P_elec_W < pt.P_shaft_W      # a generator delivers less than it takes
    else:
        assert -pt.P_elec_W > -pt.P_shaft_W    # a motor draws more than it delivers


def test_rated_point_efficiency_is_the_stated_95_percent() -> None:
    """At the rated point (P_max at the design spool speed) the losses are the 5 % the file states."""
    for section, n_rpm in (("hp_machine", 22900.0), ("lp_machine", 17300.0)):
        p = load_section(MachineParams, section)
        loss = _loss_by_hand(p, p.P_max_W, n_rpm)
        assert loss / p.P_max_W == pytest.approx(0.05, rel=0.005), section


@pytest.mark.parametrize("P_el", [-30e3, -5e3, 1e3, 20e3, 35e3])
def test_at_elec_is_the_inverse_of_at_shaft(P_el: float) -> None:
    m = ElectricMachine(load_section(MachineParams, "lp_machine"))
    pt = m.at_elec(P_el, 16000.0)
    assert pt.P_elec_W == pytest.approx(P_el, rel=1e-10)
    assert m.at_shaft(pt.P_shaft_W, 16000.0).P_elec_W == pytest.approx(P_el, rel=1e-10)


def test_limits_hold_without_overshoot(m: ElectricMachine) -> None:
    """Torque below the corner speed, power above it; off outside the speed range; never beyond."""
    p = m.p
    corner = p.P_max_W / p.T_max_Nm / RPM
    for n in np.linspace(p.n_min_rpm, p.n_max_rpm, 41):
        for req in (-10 * p.P_max_W, 10 * p.P_max_W):
            pt = m.at_shaft(req, n)
            assert pt.limited
            assert abs(pt.T_Nm) <= p.T_max_Nm * (1 + 1e-12)
            assert abs(pt.P_shaft_W) <= p.P_max_W * (1 + 1e-12)
            expect = p.T_max_Nm * n * RPM if n < corner else p.P_max_W
            assert abs(pt.P_shaft_W) == pytest.approx(expect, rel=1e-12)
    for n in (0.5 * p.n_min_rpm, 1.1 * p.n_max_rpm):
        pt = m.at_shaft(p.P_max_W, n)
        assert pt.limited and pt.P_elec_W == 0.0 and pt.T_Nm == 0.0
