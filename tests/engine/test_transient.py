"""Transient turbofan: consistency with the steady state, and the physics of a fuel step.

Independent references: the steady off-design solution (a different set of equations:
shaft balances instead of spool accelerations) must be a fixed point of the transient and
its end state after a fuel step; the classical transient behaviour (Walsh & Fletcher ch. 8):
Tt4 overshoots during an acceleration and the HPC surge margin falls below its steady
values, both recover as the spools settle.
"""

from __future__ import annotations

import pytest

from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps
from openemss.models.engine.transient import TurbofanTransient


@pytest.fixture(scope="module")
def setup() -> tuple[TurbofanOffDesign, TurbofanTransient]:
    dp = design(load_params(preset_path("larzac04_sls")))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    return od, TurbofanTransient(od)


def test_steady_state_is_a_fixed_point(setup: tuple[TurbofanOffDesign, TurbofanTransient]) -> None:
    od, tr = setup
    a = od.solve(3000.0, 0.5, N1_pct=85.0)
    s = tr.state(0.0, a.N1_rpm, a.N2_rpm, a.Wf_kg_s, 3000.0, 0.5, guess=a)
    # shaft residuals 1e-9 of the design powers give accelerations of order 1e-3 rpm/s
    assert abs(s.dN1_dt_rpm_s) < 1e-2 and abs(s.dN2_dt_rpm_s) < 1e-2
    assert s.point.Fn_N == pytest.approx(a.Fn_N, rel=1e-8)


@pytest.mark.parametrize("method", ["heun", "euler"])
def test_fuel_step_accelerates_to_the_new_steady_state(setup: tuple[TurbofanOffDesign, TurbofanTransient],
                                                      method: str) -> None:
    od, tr = setup
    a = od.solve(N1_pct=80.0)
    b = od.solve(N1_pct=95.0, guess=a)
    hist = tr.simulate(a, lambda t: a.Wf_kg_s if t < 0.05 else b.Wf_kg_s, 3.0, 0.02, method=method)
    n1 = [h.point.N1_rpm for h in hist]
    assert all(y >= x - 1e-6 for x, y in zip(n1, n1[1:], strict=False))        # N1 never falls
    end = hist[-1].point
    assert end.N1_rpm == pytest.approx(b.N1_rpm, rel=1e-4) and end.N2_rpm == pytest.approx(b.N2_rpm, rel=1e-4)
    assert end.Fn_N == pytest.approx(b.Fn_N, rel=1e-3)
    assert max(h.point.Tt4_K for h in hist) > b.Tt4_K + 20.0                      # Tt4 overshoot
    assert min(h.point.SM_hpc for h in hist) < min(a.SM_hpc, b.SM_hpc) - 0.02     # transient SM loss
    assert hist[3].t_s == pytest.approx(0.06, abs=1e-15)                          # t = k dt


def test_deceleration_and_bad_input(setup: tuple[TurbofanOffDesign, TurbofanTransient]) -> None:
    od, tr = setup
    a = od.solve(N1_pct=95.0)
    b = od.solve(N1_pct=85.0, guess=a)
    hist = tr.simulate(a, lambda t: b.Wf_kg_s, 3.0, 0.02)
    assert hist[1].dN1_dt_rpm_s < 0.0 and hist[-1].point.N1_rpm == pytest.approx(b.N1_rpm, rel=1e-4)
    assert min(h.point.SM_hpc for h in hist) > 0.0
    with pytest.raises(OutOfRangeError, match="inertias"):
        TurbofanTransient(od, I_lp_kg_m2=0.0)


def test_distortion_switched_on_during_a_transient(setup: tuple[TurbofanOffDesign, TurbofanTransient]) -> None:
    """Switching a fan distortion on between two instants: same speeds and fuel, visible SM penalty."""
    from openemss.models.engine.distortion import Distortion
    od, tr = setup
    a = od.solve(N1_pct=95.0)
    s0 = tr.state(0.0, a.N1_rpm, a.N2_rpm, a.Wf_kg_s, guess=a)
    s1 = tr.state(0.05, a.N1_rpm, a.N2_rpm, a.Wf_kg_s, guess=s0, distortion=(Distortion(0.25, 0.1), None))
    s2 = tr.state(0.10, a.N1_rpm, a.N2_rpm, a.Wf_kg_s, guess=s1)
    assert s1.point.SM_fan < s0.point.SM_fan - 0.05
    assert s1.dN1_dt_rpm_s != pytest.approx(0.0, abs=1.0)       # the spools are no longer balanced
    assert s2.point.SM_fan == pytest.approx(s0.point.SM_fan, rel=1e-6)
