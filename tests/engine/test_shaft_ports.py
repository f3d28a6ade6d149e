"""Shaft power ports (issue 18, point 2): signed offtake/assist on both spools, with limits.

Independent references:

* the steady shaft balance by hand, from the stations' enthalpy flows (not from the
  powers the cycle reports): eta_mech (H_in - H_out)_turbine = (H_out - H_in)_compressors + P_X,
  i.e. turbine power = (compressor power + P_X) / eta_mech, with an offtake (P_X > 0) and an
  assist (P_X < 0);
* the spool equation: at fixed speeds and fuel flow the gas path does not depend on the
  port, so a port power P_X changes the acceleration by exactly -P_X / (I omega) * 30/pi;
* energy: the whole engine's energy closes with the port's power as a flow out (offtake)
  or in (assist); over a transient with an assist the integral of the spool's net power
  equals the change of its kinetic energy 1/2 I omega^2;
* the limits: a port beyond its limit acts exactly as one at the limit, is flagged and logged.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_offdesign import closure

from openemss.models.engine import shaft
from openemss.models.engine.cycle_design import DesignPoint, design
from openemss.models.engine.design_params import replace
from openemss.models.engine.engine_model import FLAGS, OUTPUTS, EngineInputs, EngineLimits, EngineModel
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.offdesign import TurbofanOffDesign
from openemss.models.engine.transient import TurbofanTransient

P_PORT_W = 150e3          # a port power of 4 % (HP) to 6 % (LP) of the design spool powers
_LIMITED = [n for n, _ in FLAGS].index("shaft_power_limited")


def _H(st, k: str) -> float:  # type: ignore[no-untyped-def]
    return st[k].W_kg_s * st[k].ht_J_kg


@pytest.mark.parametrize("spool", ["hp", "lp"])
@pytest.mark.parametrize("P_X", [P_PORT_W, -P_PORT_W, 0.0])
def test_steady_shaft_balance_by_hand(larzac_od: TurbofanOffDesign, spool: str, P_X: float) -> None:
    """Turbine power = (compressor power + P_X) / eta_mech from the stations (enthalpy flows), 1e-8."""
    od = larzac_od
    kw = {"offtake_hp_W": P_X if spool == "hp" else 0.0, "offtake_lp_W": P_X if spool == "lp" else 0.0}
    pt = od.solve(3000.0, 0.5, N1_pct=90.0, **kw)
    p, st = od.p, pt.stations
    assert pt.handling_bleed_frac == 0.0 and not p.PR_booster > 1.0     # no bleed to the bypass, no booster
    # HP: the HPC compresses W25 to station 3 (its cooling bleeds leave at the exit, at ht3); the HPT takes
    # station 4 and the cooling air (W44 - W4, at ht3) down to station 44
    P_hpc = _H(st, "3") - _H(st, "25")
    P_hpt = _H(st, "4") + (st["44"].W_kg_s - st["4"].W_kg_s) * st["3"].ht_J_kg - _H(st, "44")
    # LP: the fan takes W2 to stations 13 (bypass) and 21 (core); the LPT has no cooling air
    P_fan = _H(st, "13") + _H(st, "21") - _H(st, "2")
    P_lpt = _H(st, "45") - _H(st, "5")
    assert P_hpt == pytest.approx((P_hpc + kw["offtake_hp_W"]) / p.eta_mech_hp, rel=1e-8)
    assert P_lpt == pytest.approx((P_fan + kw["offtake_lp_W"]) / p.eta_mech_lp, rel=1e-8)
    assert pt.powers_W[f"port_{spool}"] == P_X
    assert pt.powers_W["mech_lp"] == pytest.approx((1.0 - p.eta_mech_lp) * P_lpt, rel=1e-8)


def test_an_offtake_needs_more_fuel_an_assist_less(larzac_od: TurbofanOffDesign) -> None:
    od = larzac_od
    base = od.solve(3000.0, 0.5, N1_pct=90.0)
    take = od.solve(3000.0, 0.5, N1_pct=90.0, offtake_lp_W=P_PORT_W, guess=base)
    give = od.solve(3000.0, 0.5, N1_pct=90.0, offtake_lp_W=-P_PORT_W, guess=base)
    assert give.Wf_kg_s < base.Wf_kg_s < take.Wf_kg_s
    assert give.Tt4_K < base.Tt4_K < take.Tt4_K


@pytest.mark.parametrize("P_X", [P_PORT_W, -P_PORT_W])
def test_energy_closes_with_the_port(larzac_od: TurbofanOffDesign, larzac_dp: DesignPoint, P_X: float) -> None:
    """Whole engine: air and fuel energy in = jets, overboard, losses and the port's power out (1e-9)."""
    od = larzac_od
    dp = larzac_dp
    pt = od.solve(3000.0, 0.5, N1_pct=90.0, offtake_hp_W=0.4 * P_X, offtake_lp_W=0.6 * P_X)
    dm, de = closure(pt, dp, offtake_W=P_X)
    assert abs(dm) < 1e-9 and abs(de) < 1e-9


@pytest.mark.parametrize("P_X", [P_PORT_W, -P_PORT_W])
def test_a_port_moves_only_the_shaft_residuals(larzac_od: TurbofanOffDesign, P_X: float) -> None:
    """At the same gas path a port's power moves only the two shaft residuals, by exactly -P_X / P_ref."""
    od = larzac_od
    pt = od.solve(3000.0, 0.5, N1_pct=85.0)
    x = np.array(pt.x)
    extras = (0.0, 0.3 * P_X, P_X)
    r_py = od._cycle(x, (3000.0, 0.5, 0.0), ("Wf_kg_s", pt.Wf_kg_s), extras)[0]
    r0 = od._cycle(x, (3000.0, 0.5, 0.0), ("Wf_kg_s", pt.Wf_kg_s), (0.0, 0.0, 0.0))[0]
    assert np.array_equal(r_py[:6], r0[:6])
    assert r_py[6] - r0[6] == pytest.approx(-0.3 * P_X / od.ref["P_hp"], abs=1e-12)
    assert r_py[7] - r0[7] == pytest.approx(-P_X / od.ref["P_lp"], abs=1e-12)


def test_spool_balance_compiled_and_plain_are_one_function() -> None:
    spool, kind = shaft.term_arrays()
    P = np.array([3.6e6, 3.5e6, -80e3, 2.4e6, 1.3e6, 1.0e6, 0.0, 120e3])
    eta = np.array([0.99, 0.98])
    out = []
    for f in (shaft.spool_balance, getattr(shaft.spool_balance, "py_func", shaft.spool_balance)):
        net, loss = np.empty(2), np.empty(2)
        f(P, spool, kind, eta, net, loss)
        out.append((net.copy(), loss.copy()))
    # by hand: HP 0.99*3.6e6 - 3.5e6 + 80e3 = 144e3; LP 0.98*2.4e6 - 1.3e6 - 1.0e6 - 120e3 = -68e3
    for net, loss in out:
        assert net == pytest.approx([144e3, -68e3], rel=1e-12)
        assert loss == pytest.approx([0.01 * 3.6e6, 0.02 * 2.4e6], rel=1e-12)
    assert np.array_equal(out[0][0], out[1][0])


def test_shaft_functions_take_signed_ports() -> None:
    assert shaft.turbine_power_required([1.0e6], -100e3, 0.98) == pytest.approx(0.9e6 / 0.98)
    assert shaft.net_power(0.9e6 / 0.98, [1.0e6], -100e3, 0.98) == pytest.approx(0.0, abs=1e-6)
    with pytest.raises(OutOfRangeError, match="leaves no power for the turbine"):
        shaft.turbine_power_required([1.0e6], -1.0e6)
    with pytest.raises(OutOfRangeError, match="must be finite"):
        shaft.net_power(1.0, [1.0], math.nan)


def test_design_with_an_assist(larzac_dp: DesignPoint) -> None:
    """A design point with an LP motor: the LPT delivers (P_fan - P_assist) / eta_mech."""
    dp = larzac_dp
    p = replace(dp.params, offtake_lp_W=-P_PORT_W)
    d = design(p)
    c = d.components
    fan = c["fan_outer"].power_W + c["fan_inner"].power_W + c["booster"].power_W
    assert c["lpt"].power_W == pytest.approx((fan - P_PORT_W) / p.eta_mech_lp, rel=1e-12)
    assert d.Fn_N > 0.99 * dp.Fn_N


@pytest.mark.parametrize("spool", ["hp", "lp"])
def test_port_changes_the_acceleration_by_the_spool_equation(larzac_od: TurbofanOffDesign, spool: str) -> None:
    """Same speeds and fuel: dN/dt(P_X) - dN/dt(0) = -P_X / (I omega) * 30/pi, the gas path unchanged."""
    od = larzac_od
    tr = TurbofanTransient(od)
    pt = od.solve(3000.0, 0.5, N1_pct=85.0)
    kw = {f"offtake_{spool}_W": -P_PORT_W}
    s0 = tr.state(0.0, pt.N1_rpm, pt.N2_rpm, pt.Wf_kg_s, 3000.0, 0.5, guess=pt)
    s1 = tr.state(0.0, pt.N1_rpm, pt.N2_rpm, pt.Wf_kg_s, 3000.0, 0.5, guess=s0, **kw)  # type: ignore[arg-type]
    I, N, a0, a1 = (tr.I_hp, pt.N2_rpm, s0.dN2_dt_rpm_s, s1.dN2_dt_rpm_s) if spool == "hp" else \
        (tr.I_lp, pt.N1_rpm, s0.dN1_dt_rpm_s, s1.dN1_dt_rpm_s)
    omega = N * math.pi / 30.0
    assert a1 - a0 == pytest.approx(P_PORT_W / (I * omega) * 30.0 / math.pi, rel=1e-5)
    assert s1.point.Fn_N == pytest.approx(s0.point.Fn_N, rel=1e-7)


def test_energy_of_a_spool_run_up_by_an_assist(larzac_od: TurbofanOffDesign) -> None:
    """LP motor switched on at fixed fuel: the integral of the net power (turbine, fan, losses and the
    motor) equals the change of 1/2 I omega^2 (Heun's trapezoid, 2e-3), and N1 rises."""
    od = larzac_od
    tr = TurbofanTransient(od)
    a = od.solve(N1_pct=80.0)
    dt, n = 0.005, 300
    kw = {"offtake_lp_W": -P_PORT_W}
    s = tr.state(0.0, a.N1_rpm, a.N2_rpm, a.Wf_kg_s, guess=a, **kw)  # type: ignore[arg-type]
    N1, N2, hist = a.N1_rpm, a.N2_rpm, [s]
    for k in range(n):
        t1 = (k + 1) * dt
        pr = tr.state(t1, N1 + dt * s.dN1_dt_rpm_s, N2 + dt * s.dN2_dt_rpm_s, a.Wf_kg_s, guess=s, **kw)  # type: ignore[arg-type]
        N1 += 0.5 * dt * (s.dN1_dt_rpm_s + pr.dN1_dt_rpm_s)
        N2 += 0.5 * dt * (s.dN2_dt_rpm_s + pr.dN2_dt_rpm_s)
        s = tr.state(t1, N1, N2, a.Wf_kg_s, guess=s, **kw)  # type: ignore[arg-type]
        hist.append(s)
    assert N1 > a.N1_rpm + 50.0
    P = np.array([h.net_lp_W for h in hist])
    work = float(np.sum(0.5 * (P[1:] + P[:-1])) * dt)
    w0, w1 = a.N1_rpm * math.pi / 30.0, N1 * math.pi / 30.0
    assert work == pytest.approx(0.5 * tr.I_lp * (w1 * w1 - w0 * w0), rel=2e-3)


# ----------------------------------------------------------------------------------- limits in time
@pytest.mark.parametrize(("name", "value", "applied"), [
    ("offtake_lp_W", 250e3, 100e3), ("offtake_lp_W", -250e3, -50e3), ("offtake_hp_W", 250e3, 120e3),
    ("offtake_hp_W", -250e3, -80e3), ("offtake_lp_W", math.nan, 0.0)])
def test_a_port_beyond_its_limit_is_clipped_and_flagged(name: str, value: float, applied: float) -> None:
    lim = EngineLimits.from_file(offtake_lp_max_W=100e3, assist_lp_max_W=50e3, offtake_hp_max_W=120e3, assist_hp_max_W=80e3)
    logs: list[str] = []
    runs = {}
    for key, v in (("over", value), ("at", applied)):
        m = EngineModel("larzac04_sls", limits=lim, logger=logs.append)
        m.start(EngineInputs(0.2, 3000.0, 0.5))
        u = EngineInputs(0.2, 3000.0, 0.5, **{name: v})
        for _ in range(10):
            m.step(0.05, u)
        runs[key] = (list(m.values), list(m.flags), m.events)
    (v_over, f_over, ev_over), (v_at, f_at, _) = runs["over"], runs["at"]
    assert v_over == v_at                                                 # acts exactly as the limit
    out = "offtake_hp_applied_W" if name == "offtake_hp_W" else "offtake_lp_applied_W"
    assert v_over[[n for n, _ in OUTPUTS].index(out)] == applied
    assert f_over[_LIMITED] and ev_over == 1 and any("shaft ports" in s for s in logs)
    assert not f_at[_LIMITED]                                             # at the limit: not clipped


def test_limits_are_checked() -> None:
    with pytest.raises(OutOfRangeError, match="assist_lp_max_W"):
        EngineLimits.from_file(assist_lp_max_W=-1.0)
