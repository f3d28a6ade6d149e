"""The FMUs' outputs in Initialization Mode are their initial values (fmus/initial_outputs.py).

FMI 2.0 lets a master read outputs in Initialization Mode; fmpy's container runtime exchanges once there
and never again before the first step, so what an FMU shows there is what its neighbours first step on.
Driven here through fmpy's FMU2Slave alone (in a child process, tests/thirdparty.py)."""
from __future__ import annotations

from pathlib import Path

import pytest

from openemss.models.mission.mission import departure_runway, load_mission
from thirdparty import run_isolated

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def resources() -> Path:
    from openemss.orchestrator.fmu.build import ensure_built

    ensure_built(ROOT / "fmus", ROOT / "ssp" / "resources")
    return ROOT / "ssp" / "resources"


def test_the_airframe_shows_its_runway_start_in_initialization_mode(resources: Path) -> None:
    """Before leaving Initialization Mode the airframe shows the aircraft on the mission's departure runway
    (its elevation, a positive mass and air density), not placeholders, and the same values after leaving."""
    rwy = departure_runway(load_mission(ROOT / "missions" / "munich.yaml"))
    names = ["alt_m", "lat_deg", "mass_kg", "rho_amb_kg_m3"]
    r = run_isolated("fmpy_initialization_outputs", fmu=str(resources / "Airframe.fmu"), outputs=names, inputs={})
    alt, lat, mass, rho = r["entered"]
    assert r["entered"] == r["exited"]
    assert lat == pytest.approx(rwy.threshold.lat_deg, abs=1e-3)
    assert alt == pytest.approx(rwy.elevation_m, abs=2.0)  # the gear's height above the runway
    assert mass > 1000.0 and 1.0 < rho < 1.225  # above sea level: less dense than ISA at 0 m


def test_the_engine_start_follows_the_flight_condition_set_in_initialization_mode(resources: Path) -> None:
    """The engine's steady start at 60 % N1 is computed for the flight condition held when its outputs are
    read: at its input starts (sea level, static) first, then, after the altitude is set to 2000 m, at that
    altitude, with less thrust (lower density: at the same N1 the mass flow falls about as the density
    ratio, ISA 0.822 at 2000 m) and less fuel flow; leaving Initialization Mode keeps that start."""
    names = ["Fn_N", "Wf_kg_s", "N1_pct"]
    r = run_isolated("fmpy_initialization_outputs", fmu=str(resources / "Engine.fmu"), outputs=names,
                     inputs={"alt_m": 2000.0})
    (fn0, wf0, n10), (fn1, wf1, n11) = r["entered"], r["after_set"]
    assert n10 == pytest.approx(60.0) and n11 == pytest.approx(60.0)
    assert fn0 > 0.0 and 0.7 < fn1 / fn0 < 0.95
    assert wf1 < wf0
    assert r["exited"] == r["after_set"]
