"""Fuel controller closed loop with the engine model (models/engine: Larzac 04 preset,
quasi-steady transient with spool inertias), integrated here with Heun at 20 Hz.

Stated tolerances: in a slam acceleration (lever 0 -> 1 in one step from 80 % N1, SLS)
Tt41 never exceeds Tt41_max by more than 2 K and N1 never exceeds N1_max by more than
0.2 %; every fuel-flow step is within stp_max; the limited quantity settles at its limit
within 0.5 K / 0.05 %.
"""

from __future__ import annotations

import pytest

transient = pytest.importorskip("openemss.models.engine.transient")

from openemss.models.engine.cycle_design import design  # noqa: E402
from openemss.models.engine.design_params import load_params, preset_path  # noqa: E402
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps  # noqa: E402
from openemss.models.fcs.fuel_control import FuelController, FuelControlParams  # noqa: E402

DT = 0.05


@pytest.fixture(scope="module")
def engine():
    dp = design(load_params(preset_path("larzac04_sls")))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    return od, transient.TurbofanTransient(od), od.solve(0.0, 0.0, N1_pct=80.0)


def slam(engine, t_end: float, **params: float) -> dict[str, list[float]]:
    od, tr, start = engine
    fc = FuelController(FuelControlParams.from_file(**params), Wf0_kg_s=start.Wf_kg_s)
    N1, N2 = start.N1_rpm, start.N2_rpm
    s = tr.state(0.0, N1, N2, start.Wf_kg_s, guess=start)
    h: dict[str, list] = {"T41": [], "N1": [], "dWf": [], "lim": []}
    for k in range(int(round(t_end / DT))):
        out = fc.step(DT, 1.0, s.point.N1c_pct, s.point.N1_pct, s.point.T41_K)
        wf = out.Wf_cmd_kg_s
        s0 = tr.state(k * DT, N1, N2, wf, guess=s)
        p = tr.state((k + 1) * DT, N1 + DT * s0.dN1_dt_rpm_s, N2 + DT * s0.dN2_dt_rpm_s, wf, guess=s0)
        N1 += 0.5 * DT * (s0.dN1_dt_rpm_s + p.dN1_dt_rpm_s)
        N2 += 0.5 * DT * (s0.dN2_dt_rpm_s + p.dN2_dt_rpm_s)
        s = tr.state((k + 1) * DT, N1, N2, wf, guess=p)
        for key, v in (("T41", s.point.T41_K), ("N1", s.point.N1_pct), ("dWf", out.dWf_kg_s), ("lim", out.limiter)):
            h[key].append(v)
    return h


def test_Tt41_limit_on_the_engine_model(engine) -> None:
    h = slam(engine, 10.0, Tt41_max_K=1250.0)
    stp = FuelControlParams.from_file().stp_max_kg_s
    assert max(abs(x) for x in h["dWf"]) <= stp * (1 + 1e-12)
    assert max(h["T41"]) <= 1250.0 + 2.0
    assert h["lim"][-1] == "Tt41" and abs(h["T41"][-1] - 1250.0) < 0.5


def test_N1_limit_on_the_engine_model(engine) -> None:
    h = slam(engine, 20.0, N1_max_pct=96.0)
    stp = FuelControlParams.from_file().stp_max_kg_s
    assert max(abs(x) for x in h["dWf"]) <= stp * (1 + 1e-12)
    assert max(h["N1"]) <= 96.0 + 0.2
    assert h["lim"][-1] == "N1" and abs(h["N1"][-1] - 96.0) < 0.05
