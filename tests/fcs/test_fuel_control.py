"""Fuel controller against a first-order engine with an analytic response.

The engine: corrected fan speed with one time constant,
tau dN1c/dt = G Wf - N1c (integrated exactly over each step with Wf held),
N1 = r N1c (r = 1/sqrt(theta2): hot day r > 1), Tt41 = T0 + kT Wf (static).
Tt41 answers a fuel step at once (~3000 K per kg/s at constant spool speed,
LHV / (W cp)), which is what bounds the Tt41 limiter gain.
With the PI zero on the engine pole (kp/ki = tau) the small-signal closed loop is
first order with time constant tau / (kp G): the analytic reference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from openemss.models.fcs.errors import ParameterError
from openemss.models.fcs.fuel_control import FuelController, FuelControlParams

TAU_S = 1.0
G_PCT_PER_KG_S = 400.0
DT_S = 0.05


@dataclass
class Engine:
    N1c_pct: float
    r: float = 1.0
    T0_K: float = 600.0
    kT_K_per_kg_s: float = 3000.0

    @property
    def N1_pct(self) -> float:
        return self.r * self.N1c_pct

    def Tt41_K(self, Wf: float) -> float:
        return self.T0_K + self.kT_K_per_kg_s * Wf

    def step(self, Wf: float, dt: float) -> None:
        a = math.exp(-dt / TAU_S)
        self.N1c_pct = a * self.N1c_pct + (1 - a) * G_PCT_PER_KG_S * Wf


def run(ctrl: FuelController, eng: Engine, delta: float, t_end: float) -> dict[str, list[float]]:
    h: dict[str, list[float]] = {k: [] for k in ("t", "Wf", "dWf", "N1c", "N1", "Tt41", "lim")}
    Wf = ctrl.Wf_cmd_kg_s
    for k in range(int(round(t_end / DT_S))):
        out = ctrl.step(DT_S, delta, eng.N1c_pct, eng.N1_pct, eng.Tt41_K(Wf))
        Wf = out.Wf_cmd_kg_s
        eng.step(Wf, DT_S)
        for key, v in (("t", (k + 1) * DT_S), ("Wf", Wf), ("dWf", out.dWf_kg_s), ("N1c", eng.N1c_pct),
                       ("N1", eng.N1_pct), ("Tt41", eng.Tt41_K(Wf)), ("lim", out.limiter)):
            h[key].append(v)
    return h


def trimmed(N1c_pct: float, **kw: float) -> tuple[FuelController, Engine]:
    Wf0 = N1c_pct / G_PCT_PER_KG_S
    return FuelController(FuelControlParams.from_file(**kw), Wf0_kg_s=Wf0), Engine(N1c_pct)


def test_small_step_follows_first_order_analytic_response() -> None:
    ctrl, eng = trimmed(80.0)
    p = ctrl.parameters
    assert p.kp_kg_s_pct / p.ki_kg_s2_pct == pytest.approx(TAU_S)
    step = 0.3  # % N1c: small enough that no increment hits stp_max
    run(ctrl, eng, 80.0 / p.k_delta_pct, 1.0)  # settled at trim: the PI's previous error is known
    h = run(ctrl, eng, (80.0 + step) / p.k_delta_pct, 5.0)
    assert max(abs(x) for x in h["dWf"]) < p.stp_max_kg_s
    tau_cl = TAU_S / (p.kp_kg_s_pct * G_PCT_PER_KG_S)
    # discrete-time loop (one step of delay) against the continuous first-order law: 6 % of the step
    err = max(abs((n - 80.0) - step * (1 - math.exp(-t / tau_cl))) for t, n in zip(h["t"], h["N1c"], strict=True))
    assert err < 0.06 * step
    assert h["N1c"][-1] == pytest.approx(80.0 + step, abs=1e-3 * step)


def test_large_step_is_rate_limited_and_reaches_steady_state() -> None:
    ctrl, eng = trimmed(40.0, Tt41_max_K=2000.0)
    p = ctrl.parameters
    Wf0 = ctrl.Wf_cmd_kg_s
    h = run(ctrl, eng, 0.95, 30.0)
    assert max(abs(x) for x in h["dWf"]) <= p.stp_max_kg_s * (1 + 1e-12)
    # while the clip binds, the command is the exact ramp Wf0 + k stp_max
    assert h["Wf"][9] == pytest.approx(Wf0 + 10 * p.stp_max_kg_s, rel=1e-12)
    assert h["N1c"][-1] == pytest.approx(95.0, abs=0.01)
    assert max(h["N1c"]) < 95.0 + 0.5  # overshoot after the ramp below 0.5 %


def test_decel_is_rate_limited_and_respects_minimum_fuel() -> None:
    ctrl, eng = trimmed(95.0, Tt41_max_K=2000.0)
    p = ctrl.parameters
    h = run(ctrl, eng, 0.0, 40.0)
    assert min(h["dWf"]) >= -p.stp_max_kg_s * (1 + 1e-12)
    assert min(h["Wf"]) >= p.Wf_min_kg_s - 1e-15
    assert h["Wf"][-1] == pytest.approx(p.Wf_min_kg_s)


def test_chop_to_idle_settles_at_the_flight_idle_speed_not_below() -> None:
    """Lever 0 with flight idle at 55 % N1c: the demand is floored, so the engine settles at idle,
    Wf = 55 / G on this first-order engine, instead of running down to Wf_min."""
    ctrl, eng = trimmed(95.0, Tt41_max_K=2000.0, N1c_idle_pct=55.0)
    p = ctrl.parameters
    h = run(ctrl, eng, 0.0, 40.0)
    assert min(h["dWf"]) >= -p.stp_max_kg_s * (1 + 1e-12)
    assert h["N1c"][-1] == pytest.approx(55.0, abs=0.01)
    assert h["Wf"][-1] == pytest.approx(55.0 / G_PCT_PER_KG_S, rel=1e-4)
    assert min(h["N1c"]) > 55.0 - 1.0  # undershoot of the deceleration below 1 %
    # above idle the lever law is untouched: 0.8 -> 80 %
    h = run(ctrl, eng, 0.8, 30.0)
    assert h["N1c"][-1] == pytest.approx(80.0, abs=0.01)


def test_Tt41_limit_bites_and_holds() -> None:
    """Full lever needs Tt41 = 600 + 3000 * 0.25 = 1350 K at 100 %: a 1250 K limit must hold it."""
    ctrl, eng = trimmed(60.0, Tt41_max_K=1250.0)
    h = run(ctrl, eng, 1.0, 40.0)
    assert h["lim"][-1] == "Tt41"
    assert h["Tt41"][-1] == pytest.approx(1250.0, abs=0.5)
    overshoot_K = max(h["Tt41"]) - 1250.0
    assert overshoot_K < 5.0  # stated tolerance: 5 K (0.4 %) above Tt41_max in a slam acceleration
    assert max(abs(x) for x in h["dWf"]) <= ctrl.parameters.stp_max_kg_s * (1 + 1e-12)


def test_N1_limit_bites_on_a_hot_day() -> None:
    """On a hot day N1 = 1.08 N1c: 100 % N1c would need N1 = 108 % > 103 %."""
    ctrl, eng = trimmed(60.0, Tt41_max_K=2000.0)
    eng.r = 1.08
    h = run(ctrl, eng, 1.0, 40.0)
    assert h["lim"][-1] == "N1"
    assert h["N1"][-1] == pytest.approx(103.0, abs=0.02)
    assert max(h["N1"]) - 103.0 < 0.3  # stated tolerance: 0.3 % above N1_max
    assert max(abs(x) for x in h["dWf"]) <= ctrl.parameters.stp_max_kg_s * (1 + 1e-12)


def test_parameters_by_name() -> None:
    ctrl = FuelController()
    assert ctrl.get_parameter("stp_max_kg_s") == pytest.approx(0.0015)
    ctrl.set_parameter("stp_max_kg_s", 0.001)
    assert ctrl.parameters.stp_max_kg_s == 0.001
    assert "k_delta_pct" in ctrl.parameter_names()
    with pytest.raises(ParameterError, match="valid names: k_delta_pct"):
        ctrl.get_parameter("stp_max")
    with pytest.raises(ParameterError, match=r"allowed range \[0.0, 1.0\]"):
        ctrl.set_parameter("stp_max_kg_s", -1.0)
    with pytest.raises(ParameterError, match="Wf_min_kg_s"):
        ctrl.set_parameter("Wf_min_kg_s", 5.0)
