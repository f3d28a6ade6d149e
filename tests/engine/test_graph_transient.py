"""Transient of any engine file (issue 31, point 6): against the steady graph, linear theory, conservation,
certification, and similarity.

Independent references:

* the steady off-design solver of the graph (shaft balances as equations, :meth:`.EngineGraph.solve`) is
  the end point of every settled transient;
* the shaft energy balance: the integral of a shaft's net power equals the change of its kinetic energy
  1/2 I omega^2;
* linear theory of the spool equation I omega d omega/dt = P_net: the late response to a small fuel step
  is first order with the slowest eigenvalue of the Jacobian of the accelerations; it scales with the
  inertias;
* 14 CFR 33.73(b): an engine goes from flight idle to 95 % of its rated take-off thrust in at most 5 s
  (here a fuel step from half thrust, which the certified schedule must also meet);
* scaling at constant cycle (Walsh & Fletcher ch. 4): a scaled engine's thrust and fuel flow scale by the
  factor, temperatures, pressures and SFC do not.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pytest

from openemss.models.engine.engine_file import EngineFileError, ShaftDef, read_engine_file, scale_engine
from openemss.models.engine.engine_graph import EngineGraph
from openemss.models.engine.graph_transient import GraphMatch, GraphTransient

SLS = (0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def hbtf() -> GraphTransient:
    return GraphTransient(EngineGraph("pycycle_hbtf"))


@pytest.mark.parametrize(("name", "cond"), [("larzac04", (3000.0, 0.5, 0.0)), ("pycycle_hbtf", (10668.0, 0.8, 0.0))])
def test_settles_to_the_steady_solution(name: str, cond: tuple[float, float, float]) -> None:
    g = EngineGraph(name)
    tr = GraphTransient(g)
    first = g.eng.elements[g.compressors[0]].attrs["shaft"]
    a = tr.steady(cond, ("N_rpm", 0.85 * g.eng.shafts[first].attrs["N_rpm"], first))
    Wf = 1.08 * a.Wf_kg_s
    t0 = time.perf_counter()
    hist = tr.simulate(a, lambda t: Wf, 20.0, 0.05)
    per_step_ms = (time.perf_counter() - t0) / (len(hist) - 1) * 1e3
    end = hist[-1]
    b = g.solve(*cond, demand=("Wf_kg_s", Wf), guess=None)
    for i, s in enumerate(tr.shafts):
        assert end.N_rpm[i] == pytest.approx(b.shafts[s]["N_rpm"], rel=1e-6), s
        assert abs(end.net_W[i]) < 1e-4 * g.ref[("P", s)], s
    assert end.Fn_N == pytest.approx(b.Fn_N, rel=1e-6)
    stations = tr.point(end).stations
    for k, st in b.stations.items():
        assert stations[k].Tt_K == pytest.approx(st.Tt_K, rel=1e-6), k
        assert stations[k].Pt_Pa == pytest.approx(st.Pt_Pa, rel=1e-6), k
    evals = sum(m.evaluations for m in hist[1:]) / (len(hist) - 1)
    print(f"{name}: Euler 50 ms, {evals:.2f} graph evaluations and {per_step_ms:.2f} ms per step; settled N "
          f"{[round(n, 1) for n in end.N_rpm]} rpm, steady {[round(b.shafts[s]['N_rpm'], 1) for s in tr.shafts]} rpm")


def test_shaft_energy_balance(hbtf: GraphTransient) -> None:
    a = hbtf.steady(SLS, ("N_rpm", 0.8 * 4666.1, "lp"))
    b = hbtf.steady(SLS, ("N_rpm", 0.9 * 4666.1, "lp"))
    dt = 0.002
    start = hbtf.match(0.0, SLS, a.N_rpm, b.Wf_kg_s, {}, a)      # the power right after the fuel step
    hist = hbtf.simulate(start, lambda t: b.Wf_kg_s, 1.0, dt, dt_internal_s=dt)
    for i, inertia in enumerate(hbtf.I_kg_m2):
        P = np.array([m.net_W[i] for m in hist])
        work = float(np.sum(P[:-1]) * dt)                     # each step's start power, as Euler takes it
        w0, w1 = (m.N_rpm[i] * math.pi / 30.0 for m in (hist[0], hist[-1]))
        dKE = 0.5 * inertia * (w1 * w1 - w0 * w0)
        assert abs(dKE) > 1e4                                   # the spool did take up energy
        assert work == pytest.approx(dKE, rel=2e-3), hbtf.shafts[i]


def _accel_jacobian(tr: GraphTransient, m: GraphMatch, d_rpm: float = 1.0) -> np.ndarray:
    n = len(tr.shafts)
    J = np.empty((n, n))
    for j in range(n):
        acc = []
        for sgn in (1.0, -1.0):
            N = list(m.N_rpm)
            N[j] += sgn * d_rpm
            acc.append(np.array(tr.match(0.0, m.cond, tuple(N), m.Wf_kg_s, m.settings, m).dN_dt_rpm_s))
        J[:, j] = (acc[0] - acc[1]) / (2.0 * d_rpm)
    return J


def _fitted_tau(tr: GraphTransient, cond: tuple[float, float, float]) -> tuple[float, float]:
    a = tr.steady(cond, ("N_rpm", 0.85 * tr.g.eng.shafts[tr.shafts[0]].attrs["N_rpm"], tr.shafts[0]))
    b = tr.steady(cond, ("Wf_kg_s", 1.02 * a.Wf_kg_s))
    tau_lin = float(max(-1.0 / np.linalg.eigvals(_accel_jacobian(tr, b)).real))
    dt = tau_lin / 100.0
    hist = tr.simulate(a, lambda t: b.Wf_kg_s, 5.5 * tau_lin, dt, dt_internal_s=dt)
    t = np.array([m.t_s for m in hist])
    e = np.array([b.N_rpm[0] - m.N_rpm[0] for m in hist])
    sel = (t > 3.0 * tau_lin) & (t < 5.0 * tau_lin)            # the slow mode alone
    return -1.0 / float(np.polyfit(t[sel], np.log(e[sel]), 1)[0]), tau_lin


def test_fuel_step_time_constant(hbtf: GraphTransient) -> None:
    tau_fit, tau_lin = _fitted_tau(hbtf, SLS)
    assert tau_fit == pytest.approx(tau_lin, rel=0.03)
    eng = hbtf.g.eng
    sh = {k: ShaftDef(k, MappingProxyType({**v.attrs, "I_kg_m2": 2.0 * v.attrs["I_kg_m2"]}), v.line)
          for k, v in eng.shafts.items()}
    tau2, _ = _fitted_tau(GraphTransient(EngineGraph(replace(eng, shafts=MappingProxyType(sh)))), SLS)
    assert tau2 == pytest.approx(2.0 * tau_fit, rel=0.03)
    # 14 CFR 33.73(b): to 95 % of take-off thrust within 5 s (a fuel step from half the thrust)
    top = hbtf.steady(SLS, ("Tt_K", 1587.0))
    half = hbtf.steady(SLS, ("Fn_N", 0.5 * top.Fn_N))
    hist = hbtf.simulate(half, lambda t: top.Wf_kg_s, 6.0, 0.05)
    t95 = next(m.t_s for m in hist if m.Fn_N >= 0.95 * top.Fn_N)
    assert t95 <= 5.0
    print(f"pycycle_hbtf SLS, 2 % fuel step at 85 % N1: tau fitted {tau_fit:.3f} s, linear {tau_lin:.3f} s, "
          f"inertias x2 {tau2:.3f} s; fuel step 50 -> 95 % take-off thrust in {t95:.2f} s (14 CFR 33.73: <= 5 s)")


@pytest.mark.parametrize("name", ["pycycle_hbtf", "larzac04", "pycycle_turboshaft", "pycycle_ab_turbojet"])
def test_thrust_scale_at_constant_cycle(name: str) -> None:
    eng = read_engine_file(name)
    s = 0.37
    g1, g2 = EngineGraph(eng), EngineGraph(scale_engine(eng, s))
    d1, d2 = g1.design(), g2.design()
    T = 0.93 * d1.elements[g1.main_burner]["Tt_exit_K"]
    for p1, p2 in ((d1, d2), (g1.solve(d1.alt_m, 0.9 * d1.Mach, demand=("Tt_K", T)),
                               g2.solve(d1.alt_m, 0.9 * d1.Mach, demand=("Tt_K", T)))):
        assert p2.Fn_N == pytest.approx(s * p1.Fn_N, rel=1e-9)
        assert p2.Wf_kg_s == pytest.approx(s * p1.Wf_kg_s, rel=1e-9)
        assert p2.W_kg_s == pytest.approx(s * p1.W_kg_s, rel=1e-9)
        assert p2.SFC_kg_N_s == pytest.approx(p1.SFC_kg_N_s, rel=1e-9)
        for k, st in p1.stations.items():
            assert p2.stations[k].Tt_K == pytest.approx(st.Tt_K, rel=1e-9), k
            assert p2.stations[k].Pt_Pa == pytest.approx(st.Pt_Pa, rel=1e-9), k
        for k, el in p1.elements.items():
            if "A_eff_m2" in el:
                assert p2.elements[k]["A_eff_m2"] == pytest.approx(s * el["A_eff_m2"], rel=1e-9), k


def test_scaled_spools_are_slower_by_the_square_root(hbtf: GraphTransient) -> None:
    tau1, _ = _fitted_tau(hbtf, SLS)
    tau4, _ = _fitted_tau(GraphTransient(EngineGraph(scale_engine(hbtf.g.eng, 4.0))), SLS)
    assert tau4 == pytest.approx(2.0 * tau1, rel=0.03)


def test_bad_input_is_one_line(tmp_path) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(EngineFileError, match=r"pycycle_ab_turbojet.yaml:\d+: shaft 'hp': I_kg_m2 is not given"):
        GraphTransient(EngineGraph("pycycle_ab_turbojet"))
    text = Path(read_engine_file("pycycle_ab_turbojet").file).read_text()
    f = tmp_path / "ab.yaml"
    f.write_text(text.replace("hp: {N_rpm: 8070.0}", "hp: {N_rpm: 8070.0, I_kg_m2: 3.0}").replace(
        "../maps/", str(Path(read_engine_file("larzac04").file).parents[1] / "maps") + "/"))
    with pytest.raises(EngineFileError, match=r"ab.yaml:\d+: element 'nozz': a variable-area nozzle .* area: fixed"):
        GraphTransient(EngineGraph(str(f)))
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(EngineFileError, match="thrust_scale=.* must be a finite number > 0"):
            scale_engine(read_engine_file("larzac04"), bad)
