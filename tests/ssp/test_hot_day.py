"""A hot day is one value: the airframe's ``weather_dT_isa_K``, published as ``dT_isa_K`` to the engine and
the flight control (ssp/SystemStructure.ssd), so that all three fly the same atmosphere.

Checked against the ISA formulas of ISO 2533 (troposphere, written out here, independent of
``models/common/atmosphere.py``): with +20 K set once, the airframe's temperature and density, the
engine's fan-face temperature (from its corrected fan speed, N1c = N1 / sqrt(Tt2 / 288.15 K) on a
design point at sea-level static ISA) and the flight control's Mach/TAS conversion all see the
standard's temperature plus 20 K. A model that missed the deviation would be 20 K (7 %) off.

The pressure: JSBSim's atmosphere integrates the hydrostatic equation through the +20 K column from the
standard's sea-level pressure (checked here with that formula), while the engine and the flight control
take the standard's pressure at the altitude (``models/common/atmosphere.py``, the engine-performance
convention for a pressure altitude): on a +20 K day they differ by 0.35 % at 450 m (not by temperature).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

DT_K = 20.0
R_J_KG_K = 287.05287   # ISO 2533 gas constant of dry air
GAMMA = 1.4
G0 = 9.80665
T0_K, P0_PA, LAPSE_K_M = 288.15, 101325.0, 0.0065


R_EARTH_M = 6356766.0  # ISO 2533's radius for geopotential altitude


def isa_troposphere(h_m: np.ndarray, dT_K: float) -> tuple[np.ndarray, np.ndarray]:
    """Temperature [K] of ISO 2533's troposphere at geopotential altitude h with a temperature deviation, and
    the pressure [Pa] of that warmer column in hydrostatic equilibrium from the standard sea-level pressure."""
    T = T0_K + dT_K - LAPSE_K_M * h_m
    return T, P0_PA * (T / (T0_K + dT_K)) ** (G0 / (R_J_KG_K * LAPSE_K_M))


@pytest.fixture(scope="module")
def hot_day(project_system: Path, tmp_path_factory: pytest.TempPathFactory):  # noqa: ANN201
    import openemss

    out = tmp_path_factory.mktemp("hot_day") / "run"
    r = openemss.run(project_system, stop_time=40.0, set={"airframe.weather_dT_isa_K": DT_K}, out=out,
                     pre_run=False, post_run=False, warn=lambda line: None)
    assert r.status == "completed", r.error
    return r.df


def test_one_setting_reaches_every_model(hot_day) -> None:  # noqa: ANN001
    df = hot_day
    assert np.all(df["airframe.dT_isa_K"] == DT_K)
    h = df["airframe.alt_m"].to_numpy()
    T, p = isa_troposphere(R_EARTH_M * h / (R_EARTH_M + h), DT_K)  # JSBSim: geometric -> geopotential altitude
    # airframe (JSBSim's atmosphere): temperature, pressure and density of the +20 K day
    assert np.allclose(df["airframe.T_amb_K"], T, rtol=0, atol=1e-6)
    assert np.allclose(df["airframe.p_amb_Pa"], p, rtol=2e-5)
    assert np.allclose(df["airframe.rho_amb_kg_m3"], p / (R_J_KG_K * T), rtol=2e-5)
    a = np.sqrt(GAMMA * R_J_KG_K * T)
    assert np.allclose(df["airframe.mach"] * a, df["airframe.tas_m_s"], rtol=1e-3, atol=1e-3)


def test_engine_inlet_temperature(hot_day) -> None:  # noqa: ANN001
    df = hot_day
    T, _ = isa_troposphere(df["airframe.alt_m"].to_numpy(), DT_K)
    Tt2 = T * (1.0 + 0.5 * (GAMMA - 1.0) * df["airframe.mach"].to_numpy() ** 2)  # adiabatic intake
    Tt2_engine = 288.15 * (df["engine.N1_pct"] / df["engine.N1c_pct"]).to_numpy() ** 2
    # the engine flies the Mach of the previous exchange (one 0.05 s step late on the take-off roll) and real gas
    # (gamma(T) of air at 300 K: 1.4 within 0.1 %): 0.02 K found
    assert np.allclose(Tt2_engine, Tt2, rtol=0, atol=0.05), float(np.max(np.abs(Tt2_engine - Tt2)))
    assert float(Tt2_engine[0]) == pytest.approx(T0_K - LAPSE_K_M * float(df["airframe.alt_m"].iloc[0]) + DT_K,
                                                 abs=0.05)


def test_flight_control_airspeed_conversion(hot_day) -> None:  # noqa: ANN001
    df = hot_day
    h = df["airframe.alt_m"].to_numpy()
    # the FCS's outputs at t_k+1 come from its step at t_k, on the airframe's altitude at t_k (a row before)
    T, _ = isa_troposphere(np.concatenate([h[:1], h[:-1]]), DT_K)
    a = np.sqrt(GAMMA * R_J_KG_K * T)
    tas_cmd = df["fcs.tas_cmd_m_s"].to_numpy()
    moving = tas_cmd > 5.0
    assert moving.sum() > 100  # the take-off roll
    # mach_cmd is the commanded true airspeed as Mach at the flown altitude, in the hot day's speed of sound
    assert np.allclose(df["fcs.mach_cmd"].to_numpy()[moving] * a[moving], tas_cmd[moving], rtol=1e-9)
    assert not math.isclose(a[0], math.sqrt(GAMMA * R_J_KG_K * (T[0] - DT_K)), rel_tol=1e-2)
