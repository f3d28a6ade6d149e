"""Idle and sub-idle steady states of the Larzac 04 preset on the extended maps (models/engine/map_extension.py).

Independent references: monotonic trends of thrust, Tt4, N2 and fuel flow with N1 over a power sweep
(Walsh & Fletcher 2004, ch. 7); the handling bleed's schedule (SPEC.md: open below about 60 % N2);
the order of magnitude of ground-idle thrust of a turbofan, 5 to 8 % of take-off thrust (stated in the
issue; Walsh & Fletcher 2004, ch. 7 and 8, idle settings). Tolerances are stated at each assertion.
"""

from __future__ import annotations

import numpy as np
import pytest

from openemss.models.engine.cycle_design import DesignPoint, design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.offdesign import OffDesignPoint, TurbofanOffDesign, scaled_maps


@pytest.fixture(scope="module")
def od() -> TurbofanOffDesign:
    dp: DesignPoint = design(load_params(preset_path("larzac04_sls")))
    return TurbofanOffDesign(dp, scaled_maps(dp))


def _sweep(od: TurbofanOffDesign, alt_m: float, Mach: float, n1: list[float]) -> list[OffDesignPoint]:
    pts, guess = [], None
    for pct in n1:
        guess = od.solve(alt_m, Mach, N1_pct=pct, guess=guess)
        assert guess.residual_max < 1e-9
        pts.append(guess)
    return pts


@pytest.mark.parametrize(("alt_m", "Mach", "n1_min"), [(0.0, 0.0, 28.0), (7500.0, 0.75, 34.0)])
def test_power_sweep_from_idle_to_max_is_monotonic(od: TurbofanOffDesign, alt_m: float, Mach: float,
                                                   n1_min: float) -> None:
    """From maximum down to (below) idle every point converges and Fn, Tt4, N2, Wf fall with N1."""
    pts = _sweep(od, alt_m, Mach, [float(v) for v in np.arange(100.0, n1_min - 1e-9, -3.0)])
    for quantity in ("Fn_N", "Tt4_K", "N2_rpm", "Wf_kg_s"):
        v = [getattr(q, quantity) for q in pts]
        assert all(a > b for a, b in zip(v, v[1:], strict=False)), (quantity, v)
    if alt_m > 0.0:                            # flight idle: net thrust crosses zero inside the sweep
        assert pts[0].Fn_N > 0.0 > pts[-1].Fn_N


def test_ground_idle_thrust_at_sls(od: TurbofanOffDesign) -> None:
    """A ground idle of 5 to 8 % of the 13 kN take-off thrust exists on the steady working line (N1 ~ 28-31 %)."""
    pts = _sweep(od, 0.0, 0.0, [100.0, 80.0, 60.0, 45.0, 35.0, 31.0, 28.0])
    frac = [q.Fn_N / pts[0].Fn_N for q in pts]
    assert any(0.05 <= f <= 0.08 for f in frac), frac
    idle = od.solve(0.0, 0.0, Fn_N=0.065 * pts[0].Fn_N, guess=pts[-1])
    assert 25.0 < idle.N1_pct < 35.0 and idle.N2_pct < 75.0 and idle.Tt4_K < 800.0


def test_handling_bleed_opens_at_60_pct_n2_in_a_steady_sweep(od: TurbofanOffDesign) -> None:
    """SLS sweep through N2 = 60 %: closed above 61 %, fully open (10 %) below 59 %, no jump in Fn beyond
    the bleed's own effect (no step across the ramp more than 4 times the largest step away from it)."""
    pts = _sweep(od, 0.0, 0.0, [30.0, 26.0, 23.0] + [float(v) for v in np.arange(22.0, 17.9, -0.25)])
    n2 = np.array([q.N2_pct for q in pts])
    hb = np.array([q.handling_bleed_frac for q in pts])
    assert n2.min() < 59.0 < 61.0 < n2.max()
    assert np.all(hb[n2 > 61.0] == 0.0) and np.all(hb[n2 < 59.0] == pytest.approx(0.10))
    fine = slice(3, None)
    fn, n2f = np.array([q.Fn_N for q in pts])[fine], n2[fine]
    steps = np.abs(np.diff(fn))
    away = steps[(n2f[1:] > 62.0) | (n2f[1:] < 58.0)]
    assert steps.max() < 4.0 * away.max()
