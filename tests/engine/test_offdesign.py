"""Off-design matching of the turbofan: design-point recovery, conservation, physics of a power sweep.

Independent checks: simple analytic maps (defined here) and the shipped maps; the
design point must be recovered from another operating point (the matching equations
and the design calculation are separate code); mass and energy close to 1e-9; over
power sweeps at SLS and at 7500 m / Mach 0.75 thrust, Tt4, N2 and fuel flow rise with
N1 (the issue's physics criterion); the handling bleed opens where scheduled with no
jump in the results beyond the bleed's own effect.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.engine.combustion import h_fuel_liquid
from openemss.models.engine.cycle_design import DesignPoint, design, gas_of
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.errors import ConvergenceError, ModelError
from openemss.models.engine.map_scaled import TabulatedMap, tabulate_map
from openemss.models.engine.offdesign import OffDesignPoint, TurbofanMaps, TurbofanOffDesign, scaled_maps


class AnalyticCompressor:
    """Speed lines of a generic compressor about its design point (n = Nc/Nc_d, beta 0..1, design 0.5)."""

    def __init__(self, Wc: float, PR: float, eff: float, Nc: float) -> None:
        self.Wc, self.PR, self.eff, self.Nc = Wc, PR, eff, Nc

    def evaluate(self, Nc: float, beta: float) -> tuple[float, float, float]:
        n, b = Nc / self.Nc, beta - 0.5
        return (self.Wc * n ** 1.6 * (1.0 + 0.12 * b), 1.0 + (self.PR - 1.0) * n ** 2.2 * (1.0 - 0.35 * b),
                self.eff * (1.0 - 0.4 * (n - 1.0) ** 2 - 0.3 * b * b))


class AnalyticTurbine:
    """Flow saturating with pressure ratio (choking), efficiency falling off the design speed."""

    def __init__(self, Wc: float, PR: float, eff: float, Nc: float) -> None:
        self.Wc, self.PR, self.eff, self.Nc = Wc, PR, eff, Nc

    @staticmethod
    def _phi(PR: float) -> float:
        return 1.0 - math.exp(-2.5 * (PR - 1.0))

    def evaluate(self, Nc: float, PR: float) -> tuple[float, float]:
        n = Nc / self.Nc
        return self.Wc * self._phi(PR) / self._phi(self.PR), self.eff * (1.0 - 0.3 * (n - 1.0) ** 2)


@pytest.fixture(scope="module")
def dp() -> DesignPoint:
    return design(load_params(preset_path("larzac04_sls")))


def _grid(design_value: float, lo: float, hi: float, n: int) -> np.ndarray:
    """n nodes from lo to hi times the design value, the design value itself one of them (the tables pass
    through their nodes exactly, so the design point is recovered exactly)."""
    g = np.unique(np.append(np.linspace(lo, hi, n), 1.0)) * design_value
    return g


def tab_compressor(m: AnalyticCompressor) -> TabulatedMap:
    return tabulate_map(m.evaluate, _grid(m.Nc, 0.3, 1.2, 28), np.linspace(0.0, 1.0, 21), "compressor")


def tab_turbine(m: AnalyticTurbine) -> TabulatedMap:
    prs = np.unique(np.append(np.linspace(1.0, 1.0 + 2.5 * (m.PR - 1.0), 41), m.PR))
    return tabulate_map(m.evaluate, _grid(m.Nc, 0.3, 1.3, 31), prs, "turbine")


def analytic_maps(dp: DesignPoint) -> TurbofanMaps:
    """Analytic maps about the design point, tabulated (the gas path reads maps as tables)."""
    c = dp.components
    fo = c["fan_outer"]
    return TurbofanMaps(
        tab_compressor(AnalyticCompressor(dp.stations["2"].Wc_kg_s, fo.PR, fo.eta_is, fo.Nc_rpm)),
        tab_compressor(AnalyticCompressor(c["hpc"].Wc_kg_s, c["hpc"].PR, c["hpc"].eta_is, c["hpc"].Nc_rpm)),
        tab_turbine(AnalyticTurbine(c["hpt"].Wc_kg_s, c["hpt"].PR, c["hpt"].eta_is, c["hpt"].Nc_rpm)),
        tab_turbine(AnalyticTurbine(c["lpt"].Wc_kg_s, c["lpt"].PR, c["lpt"].eta_is, c["lpt"].Nc_rpm)))


def closure(od: OffDesignPoint, dp: DesignPoint, offtake_W: float = 0.0) -> tuple[float, float]:
    """Relative mass and energy residuals of the whole engine at an off-design point.

    In: air W0 ht0 and the fuel's energy Wf (LHV + h_fuel). Out: the two jets' enthalpy
    flows, overboard bleeds, mechanical losses (1 - eta_mech) P_turbine, shaft offtakes and
    the unreleased fuel energy (1 - eta_b) Wf LHV.
    """
    g, st, p, P = gas_of(dp.params), od.stations, dp.params, od.powers_W
    W_in = st["0"].W_kg_s + od.Wf_kg_s
    W_out = st["7"].W_kg_s + st["17"].W_kg_s + od.overboard_W_kg_s
    E_in = st["0"].H_W + od.Wf_kg_s * (g.LHV_J_kg + h_fuel_liquid(p.T_fuel_K, g))
    E_out = (st["7"].H_W + st["17"].H_W + od.overboard_H_W + (1 - p.eta_mech_hp) * P["hpt"]
             + (1 - p.eta_mech_lp) * P["lpt"] + offtake_W + (1 - p.eta_burner) * od.Wf_kg_s * g.LHV_J_kg)
    return (W_in - W_out) / W_in, (E_in - E_out) / E_in


def test_design_point_is_recovered_from_another_operating_point(dp: DesignPoint) -> None:
    od = TurbofanOffDesign(dp, analytic_maps(dp))
    part = od.solve(N1_pct=85.0)
    assert part.Fn_N < 0.8 * dp.Fn_N
    back = od.solve(Wf_kg_s=dp.Wf_kg_s, guess=part)
    assert back.residual_max < 1e-9
    assert back.stations["2"].W_kg_s == pytest.approx(27.64, rel=1e-7)
    assert back.N1_pct == pytest.approx(100.0, rel=1e-7) and back.N2_pct == pytest.approx(100.0, rel=1e-7)
    assert back.BPR == pytest.approx(1.13, rel=1e-7)
    assert back.Fn_N == pytest.approx(dp.Fn_N, rel=1e-7)
    assert back.Tt4_K == pytest.approx(1403.0, rel=1e-7)
    for k in ("3", "41", "5", "17"):
        assert back.stations[k].Pt_Pa == pytest.approx(dp.stations[k].Pt_Pa, rel=1e-6)


def test_offdesign_conserves_mass_and_energy(dp: DesignPoint) -> None:
    """Closure to 1e-9 (the shaft balances are solved to 1e-9 of the design powers, so the
    energy residual is of that order times P/E_in, far below)."""
    od = TurbofanOffDesign(dp, analytic_maps(dp)).solve(3000.0, 0.5, 5.0, N1_pct=90.0, customer_bleed_frac=0.03,
                                                        offtake_hp_W=20e3, offtake_lp_W=5e3)
    assert od.overboard_W_kg_s > 0.0
    dm, de = closure(od, dp, offtake_W=25e3)
    assert abs(dm) < 1e-9 and abs(de) < 1e-9


@pytest.mark.parametrize("alt_m, Mach", [(0.0, 0.0), (7500.0, 0.75)])
def test_power_sweep_is_monotonic_with_shipped_maps(dp: DesignPoint, alt_m: float, Mach: float) -> None:
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    pts: list[OffDesignPoint] = []
    guess = None
    for pct in np.arange(100.0, 54.0, -5.0):
        guess = od.solve(alt_m, Mach, N1_pct=float(pct), guess=guess)
        assert guess.residual_max < 1e-9
        pts.append(guess)
    # with the handling bleed shut (above its switch at N1c 60 %); across the switch see test_idle.py
    shut = [q for q in pts if q.handling_bleed_frac == 0.0]
    assert len(shut) >= 8
    for quantity in ("Fn_N", "Tt4_K", "N2_rpm", "Wf_kg_s"):
        v = [getattr(q, quantity) for q in shut]
        assert all(a > b for a, b in zip(v, v[1:], strict=False)), (quantity, v)
    assert all(0.0 < q.SM_hpc < 1.0 and 0.0 < q.SM_fan < 1.0 for q in pts)


def test_handling_bleed_switches_where_scheduled_without_jumps(dp: DesignPoint) -> None:
    """Threshold at 95 % corrected N1, ramp 2 %: the bleed opens over N1c 94-96 %; Fn stays continuous through
    the ramp."""
    od = TurbofanOffDesign(dp, analytic_maps(dp), handling_bleed_open_frac=0.08, handling_bleed_N1c_pct=95.0,
                           handling_bleed_ramp_pct=2.0)
    guess, rows = None, []
    for pct in np.linspace(100.0, 80.0, 41):
        guess = od.solve(N1_pct=float(pct), guess=guess)
        rows.append((guess.N1c_pct, guess.handling_bleed_frac, guess.Fn_N,
                     guess.stations["16"].Tt_K - guess.stations["13"].Tt_K))
    n1c = np.array([r[0] for r in rows])
    hb = np.array([r[1] for r in rows])
    assert np.all(hb[n1c > 96.0] == 0.0) and np.all(hb[n1c < 94.0] == pytest.approx(0.08))
    fn = np.array([r[2] for r in rows])
    steps = np.abs(np.diff(fn))
    # no step across the ramp is more than 3 times the largest step away from it
    away = steps[(n1c[1:] > 97.0) | (n1c[1:] < 93.0)]
    assert steps.max() < 3.0 * away.max()
    # the bleed air warms the bypass stream only where it flows
    dT = np.array([r[3] for r in rows])
    assert np.all(dT[hb == 0.0] == 0.0) and np.all(dT[hb > 0.0] > 0.0)


def test_power_settings_and_errors(dp: DesignPoint) -> None:
    od = TurbofanOffDesign(dp, analytic_maps(dp))
    a = od.solve(Fn_N=10e3)
    assert a.Fn_N == pytest.approx(10e3, rel=1e-8)
    b = od.solve(Tt4_K=a.Tt4_K, guess=a)
    assert b.Wf_kg_s == pytest.approx(a.Wf_kg_s, rel=1e-7)
    c = od.solve(N1c_pct=a.N1c_pct)
    assert c.Fn_N == pytest.approx(10e3, rel=1e-6)
    with pytest.raises(ModelError, match="exactly one power setting"):
        od.solve(Fn_N=1e3, Tt4_K=1000.0)
    with pytest.raises(ConvergenceError, match="fan_flow=.*power_setting="):
        od.solve(Fn_N=60e3)


def test_cold_start_far_from_design_uses_similarity_and_continuation(dp: DesignPoint) -> None:
    """A cold solve at altitude and part power converges (similarity start, continuation in the
    power setting) and agrees with the same point reached by a sweep."""
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    cold = od.solve(7500.0, 0.75, N1_pct=60.0)
    g = None
    for pct in (100.0, 90.0, 80.0, 70.0, 60.0):
        g = od.solve(7500.0, 0.75, N1_pct=pct, guess=g)
    assert cold.Fn_N == pytest.approx(g.Fn_N, rel=1e-7) and cold.N2_rpm == pytest.approx(g.N2_rpm, rel=1e-8)


def test_engine_with_booster_and_cooling_flows() -> None:
    """pyCycle's HBTF layout (booster, five HPC bleeds, HP offtake) at 35000 ft / M0.8: the design
    point is recovered from part power, and mass and energy close, with analytic maps."""
    dp = design(load_params(preset_path("pycycle_hbtf")))
    c = dp.components
    base = analytic_maps(dp)
    b = c["booster"]
    maps = TurbofanMaps(base.fan, base.hpc, base.hpt, base.lpt,
                        booster=tab_compressor(AnalyticCompressor(b.Wc_kg_s, b.PR, b.eta_is, b.Nc_rpm)))
    od = TurbofanOffDesign(dp, maps)
    cond = (dp.params.alt_m, 0.8, 0.0)
    part = od.solve(*cond, N1_pct=90.0)
    assert part.powers_W["booster"] > 0.0 and part.overboard_W_kg_s > 0.0
    dm, de = closure(part, dp, offtake_W=dp.params.offtake_hp_W)
    assert abs(dm) < 1e-9 and abs(de) < 1e-9
    back = od.solve(*cond, Wf_kg_s=dp.Wf_kg_s, guess=part)
    assert back.Fn_N == pytest.approx(dp.Fn_N, rel=1e-7) and back.N1_pct == pytest.approx(100.0, rel=1e-7)
    assert back.stations["24"].Pt_Pa == pytest.approx(dp.stations["24"].Pt_Pa, rel=1e-7)
    with pytest.raises(ModelError, match="booster map"):
        TurbofanOffDesign(dp, base)
