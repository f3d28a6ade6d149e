"""Fuel starvation (models/engine/fuel_supply.py): the engine burns no fuel the tank does not give.

The tank is played here by the test, as an airframe under a Jacobi master plays it (it takes the fuel flow the
engine published at the start of a step off during that step) or under a Gauss-Seidel master that steps it after
the engine (the flow published at the end of the step); the reference is that bookkeeping, not the engine's
counter.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.engine.engine_model import EngineInputs, EngineModel
from openemss.models.engine.engine_signals import EO, FUEL_UNLIMITED_KG
from openemss.models.engine.errors import FlameoutError
from openemss.models.engine.fuel_supply import FuelSupply

H = 0.05  # [s]


def test_available_is_the_tank_less_what_it_still_owes() -> None:
    s = FuelSupply()
    assert s.available_kg(10.0, 0.0, 0.2) == pytest.approx(9.8)   # first reading: the owed step
    assert s.ref_kg == 10.0
    # a tank that lags by more than a step (it shows 10 kg still) cannot give more than 10 kg less what was burned
    assert s.available_kg(10.0, 3.0, 0.2) == pytest.approx(7.0)
    assert FuelSupply().available_kg(FUEL_UNLIMITED_KG, 5.0, 0.2) > 1e11  # no tank connected: not limited
    assert FuelSupply().available_kg(math.nan, 0.0, 0.0) == -math.inf  # nothing known: nothing delivered
    # a first reading of 0 kg is a tank not fed yet (FMPy's SSP runner starts every input at 0), not an empty one
    s = FuelSupply()
    assert s.available_kg(0.0, 0.0, 0.2) == math.inf and s.ref_kg is None
    assert s.available_kg(5.0, 0.3, 0.2) == pytest.approx(4.8) and s.ref_kg == pytest.approx(5.3)


@pytest.fixture(scope="module")
def started() -> EngineModel:
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(Wf_cmd_kg_s=0.0, alt_m=500.0, mach=0.2), N1_pct=80.0)
    return m


@pytest.mark.parametrize("master", ["jacobi", "gauss-seidel"])
def test_tank_running_dry_flames_out_and_conserves_fuel(master: str) -> None:
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(Wf_cmd_kg_s=0.0, alt_m=500.0, mach=0.2), N1_pct=80.0)
    wf0 = m.values[EO.Wf_kg_s]
    uin = np.array([wf0, 500.0, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 90.0, 0.0, 0.0])
    fuel0 = tank = 0.5                          # [kg]: about 4 s at 80 % N1
    supply, steps = FuelSupply(), 0
    while steps < 1000:
        published = m.values[EO.Wf_kg_s]
        if supply.starves(m, tank, wf0, H):
            tank -= m.values[EO.Wf_kg_s] * H if master == "gauss-seidel" else published * H
            break
        m.step_array(H, uin)
        tank -= published * H if master == "jacobi" else m.values[EO.Wf_kg_s] * H
        assert tank >= 0.0, steps
        steps += 1
    assert m.flamed_out and m.flags[1] and m.values[EO.Fn_N] == 0.0 and m.values[EO.Wf_kg_s] == 0.0
    assert "fuel tank empty" in m.flamed_out and f"t = {m.t_s:.6g} s" in m.flamed_out
    assert 0.0 <= tank < 2 * wf0 * H                                    # empty, to within the step(s) held back
    lag = wf0 * H if master == "jacobi" else 0.0                        # the first step's flow (Jacobi)
    assert fuel0 - tank == pytest.approx(m.fuel_burned_kg + lag, abs=1e-12)
    with pytest.raises(FlameoutError, match="cannot be stepped on"):
        m.step_array(H, uin)


def test_enough_fuel_changes_nothing(started: EngineModel) -> None:
    """A tank that can give the step leaves the step alone (the metered flow is what the step burns)."""
    m = started
    wf = m.values[EO.Wf_kg_s]
    metered = m.metered_fuel_kg_s(wf, H)
    assert metered == pytest.approx(wf, rel=1e-12)
    assert not FuelSupply().starves(m, 100.0, wf, H)
    assert not m.flamed_out
