"""Idle and sub-idle steady states of the Larzac 04 preset on the extended maps (models/engine/map_extension.py).

Independent references: monotonic trends of thrust, Tt4, N2 and fuel flow with N1 over a power sweep
(Walsh & Fletcher 2004, ch. 7); the handling bleed's schedule (SPEC.md and the reference engine: open
below about 60 % of the LP spool's corrected speed) and its effect, by the energy balance of the core
(bleeding 10 % of the HPC flow to the bypass at a given N1 needs more fuel, a hotter core exhaust and a
faster HP spool, and moves the HPC away from surge);
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
    """From maximum down to (below) idle every point converges and Fn, N2 and Wf fall with N1 throughout
    (the handling bleed's ramp is wide enough for that, offdesign.py); Tt4 on either side of the bleed's
    ramp (across it Tt4 rises at SLS: the bleed takes 10 % of the core flow past the turbines,
    test_handling_bleed_effect_on_the_sls_sweep)."""
    pts = _sweep(od, alt_m, Mach, [float(v) for v in np.arange(100.0, n1_min - 1e-9, -3.0)])
    for quantity in ("Fn_N", "N2_rpm", "Wf_kg_s"):
        v = [getattr(q, quantity) for q in pts]
        assert all(a > b for a, b in zip(v, v[1:], strict=False)), (quantity, v)
    for regime in (0.0, 0.1):
        seg = [q.Tt4_K for q in pts if q.handling_bleed_frac == pytest.approx(regime)]
        assert len(seg) >= 3
        assert all(a > b for a, b in zip(seg, seg[1:], strict=False)), (regime, seg)
    if alt_m > 0.0:                            # flight idle: net thrust crosses zero inside the sweep
        assert pts[0].Fn_N > 0.0 > pts[-1].Fn_N


def test_ground_idle_thrust_at_sls(od: TurbofanOffDesign) -> None:
    """A ground idle of 5 to 8 % of the 13 kN take-off thrust exists on the steady working line (N1 ~ 28-31 %)."""
    pts = _sweep(od, 0.0, 0.0, [100.0, 80.0, 60.0, 45.0, 35.0, 31.0, 28.0])
    frac = [q.Fn_N / pts[0].Fn_N for q in pts]
    assert any(0.05 <= f <= 0.08 for f in frac), frac
    idle = od.solve(0.0, 0.0, Fn_N=0.065 * pts[0].Fn_N, guess=pts[-1])
    assert 25.0 < idle.N1_pct < 35.0 and idle.N2_pct < 75.0 and idle.Tt4_K < 800.0


def test_handling_bleed_opens_at_60_pct_corrected_n1_in_a_steady_sweep(od: TurbofanOffDesign) -> None:
    """SLS sweep through N1c = 60 %: closed above 65 %, fully open (10 %) below 55 % (the steady schedule's
    10 % ramp), no jump in Fn beyond the bleed's own effect (no step across the ramp more than 4 times the
    largest step away from it)."""
    pts = _sweep(od, 0.0, 0.0, [75.0, 71.0, 68.0] + [float(v) for v in np.arange(67.0, 52.9, -0.5)])
    n1c = np.array([q.N1c_pct for q in pts])
    hb = np.array([q.handling_bleed_frac for q in pts])
    assert n1c.min() < 55.0 < 65.0 < n1c.max()
    assert np.all(hb[n1c > 65.0] == 0.0) and np.all(hb[n1c < 55.0] == pytest.approx(0.10))
    assert hb[np.argmin(np.abs(n1c - 60.0))] == pytest.approx(0.05)
    fine = slice(3, None)
    fn, n1f = np.array([q.Fn_N for q in pts])[fine], n1c[fine]
    steps = np.abs(np.diff(fn))
    away = steps[(n1f[1:] > 65.5) | (n1f[1:] < 54.5)]
    assert steps.max() < 4.0 * away.max()
    assert all(0.0 < q.SM_hpc < 1.0 and 0.0 < q.SM_fan < 1.0 for q in pts)


@pytest.mark.parametrize(("alt_m", "Mach", "dT_isa_K"), [(0.0, 0.0, 0.0), (0.0, 0.0, 25.0), (7500.0, 0.75, 0.0)])
def test_the_schedule_follows_corrected_speed(od: TurbofanOffDesign, alt_m: float, Mach: float,
                                              dT_isa_K: float) -> None:
    """At any flight condition the bleed is shut at N1c 65.5 % and open at 54.5 %, whatever the physical N1."""
    a = od.solve(alt_m, Mach, dT_isa_K, N1c_pct=65.5)
    b = od.solve(alt_m, Mach, dT_isa_K, N1c_pct=54.5, guess=a)
    assert a.handling_bleed_frac == 0.0 and b.handling_bleed_frac == pytest.approx(0.10)


def test_handling_bleed_effect_on_the_sls_sweep(od: TurbofanOffDesign) -> None:
    """The bleed (open below N1c 60 %, ramp 55-65 %) against the same engine with it shut, at the same N1 (SLS): more fuel,
    hotter core exhaust Tt7, faster HP spool and more HPC surge margin where it is open, nothing changed where
    it is closed; by the core's energy balance the fuel rises by about the bled fraction (10 %) of the core flow
    and more (the air is bled after it was compressed). Prints the table of the README."""
    shut = TurbofanOffDesign(od.dp, od.maps, handling_bleed_open_frac=0.0)
    print("\nSLS, N1 [%]: N2 [%], Tt7 [K], Wf [g/s], Fn [N], SM_hpc [-], bleed shut -> scheduled on N1c")
    ga = gb = None
    for n1 in (100.0, 80.0, 70.0, 65.0, 60.0, 55.0, 50.0, 40.0, 30.0):
        ga = shut.solve(N1_pct=n1, guess=ga)
        gb = od.solve(N1_pct=n1, guess=gb)
        print(f"{n1:5.1f}: {ga.N2_pct:6.2f} -> {gb.N2_pct:6.2f}, {ga.Tt7_K:6.1f} -> {gb.Tt7_K:6.1f}, "
              f"{1e3 * ga.Wf_kg_s:6.2f} -> {1e3 * gb.Wf_kg_s:6.2f}, {ga.Fn_N:7.0f} -> {gb.Fn_N:7.0f}, "
              f"{ga.SM_hpc:.3f} -> {gb.SM_hpc:.3f}")
        if n1 >= 65.0:
            assert gb.handling_bleed_frac == 0.0 and gb.Wf_kg_s == pytest.approx(ga.Wf_kg_s, rel=1e-8)
        elif n1 <= 55.0:
            assert gb.handling_bleed_frac == pytest.approx(0.10)
            assert 1.10 < gb.Wf_kg_s / ga.Wf_kg_s < 1.25
            assert gb.Tt7_K > ga.Tt7_K + 30.0 and gb.N2_pct > ga.N2_pct + 0.5 and gb.SM_hpc > ga.SM_hpc + 0.05
            assert gb.Fn_N == pytest.approx(ga.Fn_N, rel=0.03)


@pytest.mark.parametrize(("alt_m", "Mach"), [(0.0, 0.0), (2500.0, 0.5), (7500.0, 0.75)])
def test_idle_and_descent_thrust_with_the_bleed(od: TurbofanOffDesign, alt_m: float, Mach: float) -> None:
    """At the flight control's idle (N1c 40 %) the bleed is open: more fuel and a little more net thrust
    than shut (the bled air leaves through the bypass nozzle instead of the core's turbines)."""
    shut = TurbofanOffDesign(od.dp, od.maps, handling_bleed_open_frac=0.0)
    a = shut.solve(alt_m, Mach, N1c_pct=40.0)
    b = od.solve(alt_m, Mach, N1c_pct=40.0, guess=a)
    print(f"\nidle N1c 40 % at {alt_m:.0f} m, M {Mach}: Fn {a.Fn_N:.1f} -> {b.Fn_N:.1f} N, "
          f"Wf {1e3 * a.Wf_kg_s:.2f} -> {1e3 * b.Wf_kg_s:.2f} g/s, N2 {a.N2_pct:.1f} -> {b.N2_pct:.1f} %")
    assert b.handling_bleed_frac == pytest.approx(0.10) and b.Wf_kg_s > 1.1 * a.Wf_kg_s
    assert 0.0 < b.Fn_N - a.Fn_N < 0.05 * od.dp.Fn_N


