"""Engine dynamics (issue 5): the transient against the steady solver, linear theory and conservation.

Independent references:

* the steady off-design solver (shaft balances as equations) is the end point of every
  settled transient (0.1 % asked; the match tolerance gives far better);
* linear theory of the spool equation I omega d omega/dt = P_net(omega, Wf): the time
  constants are -1/lambda of the eigenvalues of the 2x2 Jacobian of the accelerations,
  each spool's own one I omega / (-dP_net/d omega); they scale with the inertias;
* the shaft energy balance: the integral of the spool's net power equals the change of
  its rotational kinetic energy 1/2 I omega^2;
* the parallel compressor model: zero deficit is the clean engine, the margin falls with
  the deficit, and the critical sector angle of Reid (1969): for a given deficit the loss
  of surge pressure ratio grows with the sector angle up to about 60 deg and not beyond.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.engine.distortion import Distortion
from openemss.models.engine.engine_model import BleedValve, EngineInputs, EngineModel
from openemss.models.engine.transient import TurbofanTransient


@pytest.fixture(scope="module")
def model() -> EngineModel:
    return EngineModel("larzac04_sls")


def test_settles_to_the_steady_solution(model: EngineModel) -> None:
    a = model.od.solve(3000.0, 0.5, N1_pct=80.0)
    b = model.od.solve(3000.0, 0.5, N1_pct=92.0, guess=a)
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(a.Wf_kg_s, 3000.0, 0.5))
    u = EngineInputs(b.Wf_kg_s, 3000.0, 0.5)
    for _ in range(160):                                        # 8 s at 50 ms, > 10 time constants
        m.step(0.05, u)
    for name, ref in (("N1_rpm", b.N1_rpm), ("N2_rpm", b.N2_rpm), ("Fn_N", b.Fn_N), ("Tt4_K", b.Tt4_K),
                      ("SM_hpc", b.SM_hpc)):
        assert m.value(name) == pytest.approx(ref, rel=1e-3), name     # the 0.1 %
    assert m.value("N1_rpm") == pytest.approx(b.N1_rpm, rel=1e-6)      # what it actually reaches
    assert not any(m.flags)


def _accel_jacobian(tr: TurbofanTransient, pt, d: float = 1.0) -> np.ndarray:  # type: ignore[no-untyped-def]
    """d(dN/dt)/dN [1/s] at a steady point, by central differences of 1 rpm."""
    J = np.empty((2, 2))
    for j in range(2):
        acc = []
        for sgn in (1.0, -1.0):
            N = [pt.N1_rpm, pt.N2_rpm]
            N[j] += sgn * d
            s = tr.state(0.0, N[0], N[1], pt.Wf_kg_s, guess=pt)
            acc.append(np.array([s.dN1_dt_rpm_s, s.dN2_dt_rpm_s]))
        J[:, j] = (acc[0] - acc[1]) / (2.0 * d)
    return J


def _fitted_tau(model: EngineModel, I_scale: float) -> tuple[float, float]:
    """(time constant fitted to the simulated N1 response of a 2 % fuel step, slow linear time constant)."""
    od = model.od
    tr = TurbofanTransient(od, od.p.I_lp_kg_m2 * I_scale, od.p.I_hp_kg_m2 * I_scale)
    a = od.solve(N1_pct=85.0)
    b = od.solve(Wf_kg_s=1.02 * a.Wf_kg_s, guess=a)
    lam = np.linalg.eigvals(_accel_jacobian(tr, b))
    tau_lin = float(max(-1.0 / lam.real))
    hist = tr.simulate(a, lambda t: b.Wf_kg_s, 6.0 * tau_lin, 0.005 * I_scale, method="heun")
    t = np.array([h.t_s for h in hist])
    e = np.array([b.N1_rpm - h.point.N1_rpm for h in hist])
    sel = (t > 3.0 * tau_lin) & (t < 5.5 * tau_lin)    # the slow mode alone (the fast one, ~0.19 s, has died)
    slope = np.polyfit(t[sel], np.log(e[sel]), 1)[0]
    return -1.0 / slope, tau_lin


def test_fuel_step_time_constant_from_the_inertias(model: EngineModel) -> None:
    tau_fit, tau_lin = _fitted_tau(model, 1.0)
    # the late response is first order with the slow eigenvalue of the linearised spools
    assert tau_fit == pytest.approx(tau_lin, rel=0.02)
    # each spool alone: tau = I omega / (-dP/d omega) = -1 / (d(dN/dt)/dN)
    od = model.od
    tr = TurbofanTransient(od)
    b = od.solve(N1_pct=85.0)
    J = _accel_jacobian(tr, b)
    s = tr.state(0.0, b.N1_rpm + 1.0, b.N2_rpm, b.Wf_kg_s, guess=b)
    omega = b.N1_rpm * math.pi / 30.0
    dP_domega = s.net_lp_W / (math.pi / 30.0)                     # net power per rad/s, from P = 0 at b
    assert -1.0 / J[0, 0] == pytest.approx(od.p.I_lp_kg_m2 * omega / -dP_domega, rel=0.01)
    # doubling both inertias doubles the time constant
    tau2, _ = _fitted_tau(model, 2.0)
    assert tau2 == pytest.approx(2.0 * tau_fit, rel=0.03)
    print(f"fuel step +2 % at SLS N1 85 %: tau fitted {tau_fit:.3f} s, linear {tau_lin:.3f} s, "
          f"LP alone {-1.0 / J[0, 0]:.3f} s, HP alone {-1.0 / J[1, 1]:.3f} s; inertias x2: {tau2:.3f} s")


def test_shaft_energy_balance_over_a_transient(model: EngineModel) -> None:
    od = model.od
    tr = TurbofanTransient(od)
    a = od.solve(N1_pct=80.0)
    b = od.solve(N1_pct=90.0, guess=a)
    dt = 0.005
    hist = tr.simulate(a, lambda t: b.Wf_kg_s, 2.0, dt, method="heun")
    for I, key, N in ((tr.I_lp, "net_lp_W", "N1_rpm"), (tr.I_hp, "net_hp_W", "N2_rpm")):
        P = np.array([getattr(h, key) for h in hist])
        work = float(np.sum(0.5 * (P[1:] + P[:-1])) * dt)          # trapezoid, as Heun integrates
        w0, w1 = (getattr(h.point, N) * math.pi / 30.0 for h in (hist[0], hist[-1]))
        dKE = 0.5 * I * (w1 * w1 - w0 * w0)
        assert work == pytest.approx(dKE, rel=2e-3), key


CORNERS = [(0.0, 0.0), (0.0, 0.8), (4000.0, 0.6), (8000.0, 0.8), (8000.0, 0.5)]


@pytest.mark.parametrize(("alt_m", "mach"), CORNERS)
def test_slam_and_chop_across_the_envelope(alt_m: float, mach: float) -> None:
    m = EngineModel("larzac04_sls")
    idle = m.od.solve(alt_m, mach, N1c_pct=64.0)      # above the handling bleed's switch (N1c 59-61 %)
    top = m.od.solve(alt_m, mach, N1_pct=100.0, guess=idle) if alt_m < 8000.0 or mach > 0.6 else \
        m.od.solve(alt_m, mach, N1_pct=95.0, guess=idle)
    m.start(EngineInputs(idle.Wf_kg_s, alt_m, mach))
    seen = [False] * len(m.flags)
    for k in range(240):                                        # slam for 6 s, chop for 6 s
        u = EngineInputs(top.Wf_kg_s if k < 120 else idle.Wf_kg_s, alt_m, mach)
        m.step(0.05, u)                                          # never raises
        seen = [x or y for x, y in zip(seen, m.flags, strict=True)]
        if k == 119:
            assert m.value("N1_rpm") == pytest.approx(top.N1_rpm, rel=0.01)
    assert m.value("N1_rpm") == pytest.approx(idle.N1_rpm, rel=0.02)
    assert not m.flags[3]                                        # matched at the end
    print(f"slam/chop at {alt_m:.0f} m, M {mach}: flags seen (surge, flameout, overspeed, failed, "
          f"fuel_limited) = {seen}, events {m.events}, failures {m.failures}")


def test_extreme_inputs_hold_the_last_state(model: EngineModel) -> None:
    logs: list[str] = []
    m = EngineModel("larzac04_sls", logger=logs.append)
    m.start(EngineInputs(0.15, 0.0, 0.3))
    before = list(m.values)
    m.step(0.05, EngineInputs(0.15, 0.0, 5.0))                   # Mach beyond the atmosphere model
    assert m.flags[3] and m.values[4] == before[4] and logs
    m.step(0.05, EngineInputs(0.0, 0.0, 0.3))                    # fuel cut: flameout flag, no crash
    assert m.flags[1]
    m.step(0.05, EngineInputs(0.15, 0.0, 0.3, distortion_on=True, distortion_sector_deg=400.0,
                              distortion_dPt_frac=0.9))  # clipped
    m.step(0.05, EngineInputs(0.15, 0.0, 0.3))
    assert not m.flags[3]                                        # matched again


def test_zero_distortion_is_the_clean_engine(model: EngineModel) -> None:
    m1, m2 = EngineModel("larzac04_sls"), EngineModel("larzac04_sls")
    u1 = EngineInputs(0.2, 2000.0, 0.4)
    u2 = EngineInputs(0.2, 2000.0, 0.4, distortion_on=True, distortion_sector_deg=90.0, distortion_dPt_frac=0.0)
    m1.start(u1)
    m2.start(u2)
    for _ in range(10):
        m1.step(0.05, EngineInputs(0.22, 2000.0, 0.4))
        m2.step(0.05, EngineInputs(0.22, 2000.0, 0.4, distortion_on=True, distortion_sector_deg=90.0))
    # same engine to the matching tolerance (1e-8 on the residuals); the spool accelerations are
    # differences of powers of about 1 MW, so 1e-8 of that is about 1e-3 rpm/s
    acc = [23, 24]
    keep = [i for i in range(len(m1.values)) if i not in acc]
    np.testing.assert_allclose(np.array(m2.values)[keep], np.array(m1.values)[keep], rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(np.array(m2.values)[acc], np.array(m1.values)[acc], atol=1e-2)


def test_surge_margin_falls_monotonically_with_the_deficit(model: EngineModel) -> None:
    od = model.od
    clean = od.solve(N1_pct=90.0)
    sm = [clean.SM_fan]
    for dpt in np.linspace(0.01, 0.12, 12):
        sm.append(od.solve(N1_pct=90.0, distortion_fan=Distortion(0.25, float(dpt)), guess=clean).SM_fan)
    assert all(b < a for a, b in zip(sm, sm[1:], strict=False))
    hot = [od.solve(N1_pct=90.0, distortion_hpc=Distortion(0.25, 0.0, dT), guess=clean).SM_hpc
           for dT in (0.0, 10.0, 20.0, 40.0)]
    assert all(b < a for a, b in zip(hot, hot[1:], strict=False))


def test_critical_sector_angle() -> None:
    """Reid (1969), ASME 69-GT-29; Cumpsty, Compressor Aerodynamics, ch. 9; Walsh & Fletcher sec. 5.2.6:
    the loss of surge pressure ratio for a given deficit grows with the spoiled sector angle up to a
    critical angle of about 60 deg and stays constant beyond. Parallel compressor with the spoiled
    sector on its surge line, both sectors discharging to the same pressure: the compressor's surge
    pressure ratio (exit over clean-face total pressure) against the clean compressor's."""
    from scipy.optimize import brentq

    from openemss.models.engine.cycle_design import design
    from openemss.models.engine.design_params import load_params, preset_path
    from openemss.models.engine.offdesign import scaled_maps

    dp = design(load_params(preset_path("larzac04_sls")))
    fan = scaled_maps(dp).fan
    face = dp.stations["2"]
    N = dp.p.N1_rpm if hasattr(dp, "p") else dp.params.N1_rpm          # type: ignore[attr-defined]
    Nc = N / math.sqrt(face.Tt_K / 288.15)
    beta_s = brentq(lambda b: fan.surge_margin(Nc, b), 0.0, 1.0)      # the clean surge point
    PR_surge = fan.evaluate(Nc, beta_s)[1]
    loss = {}

    def exits(d: Distortion, b_clean: float, b_spoiled: float) -> tuple[float, float]:
        """Exit total pressures [Pa] of the clean and the spoiled sector (the parallel compressor model by hand:
        the spoiled sector's inlet Pt lower by the attenuated deficit, the same Tt and corrected speed)."""
        pe_c = face.Pt_Pa * fan.evaluate(Nc, b_clean)[1]
        pe_s = face.Pt_Pa * (1.0 - d.attenuation * d.dPt_frac) * fan.evaluate(Nc, b_spoiled)[1]
        return pe_c, pe_s

    for deg in (15.0, 30.0, 45.0, 60.0, 90.0, 120.0, 180.0):
        d = Distortion(deg / 360.0, 0.10)
        # spoiled sector at surge; the clean sector at the beta giving the same exit pressure
        spoiled_exit = exits(d, beta_s, beta_s)[1]
        b_clean = brentq(lambda b, d=d, pe=spoiled_exit: exits(d, b, beta_s)[0] - pe, 0.0, 1.09)
        pe_c, pe_s = exits(d, b_clean, beta_s)
        assert pe_c == pytest.approx(pe_s, rel=1e-9)
        loss[deg] = 1.0 - pe_s / face.Pt_Pa / PR_surge
    crit = loss[60.0]
    assert loss[15.0] < loss[30.0] < loss[45.0] < crit                  # grows below the critical angle
    for deg in (90.0, 120.0, 180.0):
        assert loss[deg] == pytest.approx(crit, rel=1e-6)               # and no further beyond it
    assert crit == pytest.approx(0.10, rel=1e-6)                       # the full deficit
    assert loss[30.0] == pytest.approx(0.5 * crit, rel=1e-6)


def test_handling_bleed_hysteresis_no_chattering() -> None:
    """Corrected N1 swept through the switching speed with a dither inside the band: one opening, one
    closing; the valve strokes at its rate."""
    valve = BleedValve.from_file(threshold_N1c_pct=70.0, band_pct=2.0, stroke_s=0.5, open_frac=0.10)
    m = EngineModel("larzac04_sls", valve=valve)
    lo = m.od.solve(N1_pct=60.0)
    hi = m.od.solve(N1_pct=80.0, guess=lo)
    m.start(EngineInputs(lo.Wf_kg_s))
    assert m.valve_open_cmd and lo.N1c_pct < 69.0
    cmds, pos, n1c = [], [], []
    for k in range(400):                                          # 20 s: up, hold, down
        t = 0.05 * k
        ramp = min(1.0, t / 6.0) if t < 10.0 else max(0.0, 1.0 - (t - 10.0) / 6.0)
        dither = 0.01 * lo.Wf_kg_s * math.sin(2.0 * math.pi * t / 0.4)
        m.step(0.05, EngineInputs(lo.Wf_kg_s + ramp * (hi.Wf_kg_s - lo.Wf_kg_s) + dither))
        cmds.append(m.valve_open_cmd)
        pos.append(m.valve_pos)
        n1c.append(m.value("N1c_pct"))
    switches = sum(1 for a, b in zip(cmds, cmds[1:], strict=False) if a != b)
    assert max(n1c) > 71.5 and min(n1c[200:]) < 69.0
    assert switches == 2
    assert max(abs(b - a) for a, b in zip(pos, pos[1:], strict=False)) <= 0.05 / 0.5 + 1e-12
    opened = [k for k in range(1, 400) if cmds[k] != cmds[k - 1]]
    assert n1c[opened[0]] > 71.0 - 0.5 and n1c[opened[1]] < 69.0 + 0.5      # switched at the band's edges


def test_linearised_step_start_agrees_with_the_matched_one() -> None:
    """The fuel-sensitivity shortcut at the step start (no extra match) against matching the gas path
    there again: a +-2 % fuel oscillation with a climb, N1 and thrust within 1e-5 (the shortcut's error
    is second order in the fuel change, 1e-4 relative per step, and the spools filter it)."""
    fast, exact = EngineModel("larzac04_sls"), EngineModel("larzac04_sls", linear_input_frac=0.0)
    pt = fast.od.solve(5000.0, 0.6, N1_pct=90.0)
    for m in (fast, exact):
        m.start(EngineInputs(pt.Wf_kg_s, 5000.0, 0.6))
    for k in range(100):
        t = 0.05 * k
        u = EngineInputs(pt.Wf_kg_s * (1.0 + 0.02 * math.sin(2.0 * t)), 5000.0 + 2.0 * t, 0.6)
        fast.step(0.05, u)
        exact.step(0.05, u)
        for name in ("N1_rpm", "N2_rpm", "Fn_N"):
            assert fast.value(name) == pytest.approx(exact.value(name), rel=1e-5), (k, name)


def test_limits_are_flags_and_events() -> None:
    """Overspeed (N1 above a lowered limit) and flameout (FAR below a raised lean limit) in a slam and
    a chop: flags and counted events with a log line each, no exception."""
    from openemss.models.engine.engine_model import EngineLimits

    logs: list[str] = []
    m = EngineModel("larzac04_sls", limits=EngineLimits.from_file(N1_max_pct=95.0, FAR_lean=0.012), logger=logs.append)
    idle = m.od.solve(4000.0, 0.6, N1_pct=65.0)
    top = m.od.solve(4000.0, 0.6, N1_pct=100.0, guess=idle)
    m.start(EngineInputs(top.Wf_kg_s, 4000.0, 0.6))
    assert m.flags[2] and not m.flags[1]                         # 100 % > 95 %: overspeed at the start
    seen = False
    for _ in range(100):                                         # chop: FAR falls below 0.012 on the way
        m.step(0.05, EngineInputs(idle.Wf_kg_s, 4000.0, 0.6))  # down (at the fuel system's decel rate)
        seen = seen or m.flags[1]
    assert seen
    assert not m.flags[2]                                        # back under the limit
    assert m.events >= 2 and any("flameout" in s for s in logs) and any("overspeed" in s for s in logs)


@pytest.mark.parametrize(("alt_m", "mach"), [(8000.0, 0.0), (0.0, 0.8)])
def test_fuel_ramps_idle_to_max_and_back(alt_m: float, mach: float) -> None:
    """5 s ramps from idle (N1 60 %) to maximum (corrected N1 100 % or N1 100 %, whichever needs less fuel:
    N1 90.5 % at 8000 m, Mach 0; N1 100 % at sea level, Mach 0.8) and back: matched at every step, at the top within 1.5 % of the steady N1 (the spools lag a ramp by
    about one time constant, 0.4 s, i.e. 8 % of its span), no limit reached."""
    m = EngineModel("larzac04_sls")
    idle = m.od.solve(alt_m, mach, N1_pct=60.0)
    top = m.od.solve(alt_m, mach, N1c_pct=100.0)
    if top.N1_pct > 100.0:                      # the physical speed limits first (high ram temperature)
        top = m.od.solve(alt_m, mach, N1_pct=100.0)
    m.start(EngineInputs(idle.Wf_kg_s, alt_m, mach))
    for k in range(240):
        f = min(1.0, k / 100.0) if k < 120 else max(0.0, 1.0 - (k - 120) / 100.0)
        m.step(0.05, EngineInputs(idle.Wf_kg_s + f * (top.Wf_kg_s - idle.Wf_kg_s), alt_m, mach))
        assert not any(m.flags), (k, m.flags)
        if k == 119:
            assert m.value("N1_rpm") == pytest.approx(top.N1_rpm, rel=0.015)
    assert m.value("N1_rpm") < 1.15 * idle.N1_rpm


def test_deep_chop_at_altitude_runs_down_on_the_fuel_system_stops() -> None:
    """A chop from 85 % N1 to a fuel flow far below idle (0.012 kg/s) at 7500 m, Mach 0.75 (the Munich
    mission's top of descent): the burned fuel flow falls at the fuel system's decel rate, never below
    the minimum-flow stop on the previous step's Pt3, and the spools run down monotonically to a steady
    sub-idle on the extended maps, without a failed match."""
    m = EngineModel("larzac04_sls")
    # the stops in this design's units (0.32 of its design Wf/Pt3, 0.38 of its design fuel flow per s)
    assert m.Wf_Pt3_min_kg_s_Pa == pytest.approx(8e-8, rel=0.02)
    assert m.Wf_decel_max_kg_s2 == pytest.approx(0.1, rel=0.02)
    pt = m.od.solve(7500.0, 0.75, N1_pct=85.0)
    m.start(EngineInputs(pt.Wf_kg_s, 7500.0, 0.75))
    wf_prev, pt3_prev, n1_prev = m.value("Wf_kg_s"), m.value("Pt3_Pa"), m.value("N1_pct")
    for _ in range(1200):                                        # 60 s
        m.step(0.05, EngineInputs(0.012, 7500.0, 0.75))
        wf, n1 = m.value("Wf_kg_s"), m.value("N1_pct")
        assert wf >= wf_prev - m.Wf_decel_max_kg_s2 * 0.05 - 1e-12
        assert wf >= m.Wf_Pt3_min_kg_s_Pa * pt3_prev - 1e-12
        assert n1 <= n1_prev + 1e-9
        wf_prev, pt3_prev, n1_prev = wf, m.value("Pt3_Pa"), n1
    assert m.failures == 0 and not m.flags[3]
    assert 30.0 < n1 < 60.0 and abs(m.state.dN1_dt_rpm_s) < 1.0  # settled below flight idle
