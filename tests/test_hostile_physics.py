"""The hostile corpus, physics that cannot happen (issue 33 point 2).

Each case builds its system in tmp_path (the project's SSD with the FMUs built for this session, or a
small system of one or two of them) and asserts the behaviour:

* fuel: an empty tank at the start is refused (one line naming the fuel); a tank that runs dry flames
  the engine out (the run fails with one line, summary.json says when and why) and the fuel the engine
  burned is the fuel that left the tank (checked on the recorded flows, independently of the counters);
  an engine whose fuel_kg no host connects is not limited; an airframe asked for fuel its tank does not
  hold refuses;
* mass: fuel beyond the tank, a negative fuel or added mass refused at the airframe's start naming the
  parameter; a take-off mass above the maximum warned before flying and flagged in summary.json;
* start: the aircraft starts on the mission's departure runway (another runway, another airport); one set
  away from it (another airport, the wrong direction, in the air) is refused naming both positions; an air start below the ground is
  refused by the airframe; a ground run off the runway's end fails with the distance and speeds.
"""
from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from test_hostile_runs import assert_one_line

from conftest import ROOT, table
from openemss.models.mission.geo import LatLon
from openemss.orchestrator.cli.main import main
from systems import Comp, write_system

FMU_NAMES = {"engine": "Engine.fmu", "airframe": "Airframe.fmu", "fcs": "Fcs.fmu"}
MUNICH = ROOT / "missions" / "munich.yaml"


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    rc = main(list(argv))
    return rc, [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]


@pytest.fixture()
def munich(tmp_path: Path, project_fmus: dict[str, Path]) -> Path:
    """The project's system (ssp/SystemStructure.ssd) with this session's FMUs, in tmp_path."""
    folder = tmp_path / "sys"
    (folder / "resources").mkdir(parents=True)
    shutil.copy2(ROOT / "ssp" / "SystemStructure.ssd", folder / "SystemStructure.ssd")
    for name, fmu in FMU_NAMES.items():
        shutil.copy2(project_fmus[name], folder / "resources" / fmu)
    return folder


def _mission(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    """A copy of the Munich mission with `old` replaced by `new` (asserting it was there)."""
    text = MUNICH.read_text(encoding="utf-8")
    assert text.count(old) >= count, old
    path = tmp_path / "mission.yaml"
    path.write_text(text.replace(old, new, count), encoding="utf-8")
    return path


# -- fuel -----------------------------------------------------------------------------------------
def test_zero_fuel_is_refused_before_flying(munich: Path, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    """No fuel on board: the airframe (whose tank feeds the engine) refuses to start, naming the parameter."""
    rc, err = _run(capsys, "run", str(munich), "--set", "airframe.fuel0_kg=0", "--out", str(tmp_path / "out"),
                   "--no-pre-run")
    assert_one_line(rc, err, "component 'airframe'", "fmi2ExitInitializationMode", "fuel0_kg = 0",
                    "no fuel on board")


def test_tank_running_dry_flames_the_engine_out(munich: Path, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    fuel0 = 1.5  # kg: about 15 s of the take-off run
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(munich), "--set", f"airframe.fuel0_kg={fuel0}", "--out", str(out),
                   "--stop-time", "120", "--no-pre-run", "--format", "csv")
    line = assert_one_line(rc, err, "component 'engine'", "flame-out at t = ", "fuel tank empty")
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["status"] == "failed" and "flame-out" in summary["error"]
    t_out = float(re.search(r"flame-out at t = ([0-9.]+) s", line).group(1))  # type: ignore[union-attr]
    assert summary["flameout"]["time_s"] == pytest.approx(t_out, abs=1e-9)
    assert summary["flameout"]["cause"].startswith("fuel starvation")
    data = table(out)
    t, h = data["time_s"], 0.05
    wf, tank, burned = data["engine.Wf_kg_s"], data["airframe.fuel_kg"], data["engine.fuel_burned_kg"]
    assert t[-1] == pytest.approx(t_out) and wf[-1] == 0.0 and data["engine.Fn_N"][-1] == 0.0
    assert data["engine.flameout_cause"][-1] == 2 and not np.any(data["engine.flameout_cause"][:-1])
    # conservation, from the recorded flows: the tank lost what the engine published (the airframe burns a
    # sample's flow over the next step, Jacobi), never went below zero, and the engine's counter is the same
    # fuel but for the one-step lag of the coupling: the start flow (burned by the tank over the first step)
    assert np.all(tank >= 0.0) and tank[-1] < wf[-2] * h
    assert fuel0 - tank[-1] == pytest.approx(float(np.sum(wf[:-1])) * h, abs=1e-9)
    assert burned[-1] == pytest.approx(float(np.sum(wf[1:])) * h, abs=1e-9)
    assert fuel0 - tank[-1] - burned[-1] == pytest.approx(wf[0] * h, abs=1e-9)


def _engine_alone(tmp_path: Path, project_fmus: dict[str, Path], params: dict[str, float]) -> Path:
    folder = tmp_path / "sys"
    shutil.copy2(project_fmus["engine"], tmp_path / "Engine.fmu")
    write_system(folder, tmp_path, [Comp("engine", "Engine.fmu",
                                         [("fuel_kg", "input", "Real"), ("Wf_kg_s", "output", "Real"),
                                          ("fuel_burned_kg", "output", "Real"), ("Fn_N", "output", "Real"),
                                          ("flameout_cause", "output", "Integer")],
                                         {"start_N1_pct": 80.0, **params})], [], stop_time=2.0)
    return folder


def test_engine_without_a_tank_is_not_limited(tmp_path: Path, project_fmus: dict[str, Path],
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """A host that connects no tank leaves fuel_kg at its start value: the engine burns as commanded."""
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(_engine_alone(tmp_path, project_fmus, {})), "--out", str(out),
                   "--format", "csv")
    assert rc == 0, err
    data = table(out)
    assert not np.any(data["engine.flameout_cause"]) and np.all(data["engine.Fn_N"] > 1000.0)
    assert data["engine.fuel_burned_kg"][-1] == pytest.approx(float(np.sum(data["engine.Wf_kg_s"][1:])) * 0.05)


def test_engine_on_a_small_tank_burns_no_more_than_it_holds(tmp_path: Path, project_fmus: dict[str, Path],
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    """fuel_kg held at 0.05 kg (nobody takes it off): the engine burns at most that, then flames out."""
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(_engine_alone(tmp_path, project_fmus, {"fuel_kg": 0.05})), "--out", str(out),
                   "--format", "csv")
    assert_one_line(rc, err, "flame-out at t = ", "fuel tank empty")
    data = table(out)
    burned = data["engine.fuel_burned_kg"]
    assert burned[-1] <= 0.05 and data["engine.flameout_cause"][-1] == 2 and data["engine.Fn_N"][-1] == 0.0
    assert burned[-1] > 0.05 - 2 * data["engine.Wf_kg_s"][-2] * 0.05  # it stopped within a step's metered fuel


def test_airframe_refuses_a_flow_its_tank_cannot_give(tmp_path: Path, project_fmus: dict[str, Path],
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    shutil.copy2(project_fmus["airframe"], tmp_path / "Airframe.fmu")
    write_system(folder, tmp_path, [Comp("airframe", "Airframe.fmu", [("fuel_kg", "output", "Real")],
                                         {"fuel0_kg": 0.01, "Wf_kg_s": 1.0})], [], stop_time=1.0)
    rc, err = _run(capsys, "run", str(folder), "--out", str(tmp_path / "out"))
    assert_one_line(rc, err, "component 'airframe'", "tank empty", "0.01 kg")


# -- mass -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(("setting", "fragments"), [
    ("airframe.fuel0_kg=700", ("fuel0_kg = 700", "600 kg")),
    ("airframe.fuel0_kg=-1", ("fuel0_kg = -1", "from 0")),
    ("airframe.added_mass_kg=-5", ("added_mass_kg = -5", "from 0")),
])
def test_impossible_loading_is_refused_by_the_airframe(munich: Path, tmp_path: Path, setting: str,
                                                       fragments: tuple[str, ...],
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = _run(capsys, "run", str(munich), "--set", setting, "--out", str(tmp_path / "out"), "--no-pre-run")
    assert_one_line(rc, err, "component 'airframe'", *fragments)


def test_above_mtow_is_warned_before_flying_and_flagged(munich: Path, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    rc = main(["run", str(munich), "--set", "airframe.added_mass_kg=1200", "fcs.mission_file=" + str(MUNICH),
               "--out", str(out), "--stop-time", "2"])
    err = capsys.readouterr().err
    assert rc == 0, err
    warned = [ln for ln in err.splitlines() if "maximum take-off mass" in ln]
    assert len(warned) == 1 and "3300.0 kg" in warned[0] and "57.1 %" in warned[0], err
    mass = json.loads((out / "summary.json").read_text(encoding="utf-8"))["mass"]
    assert mass["mtow_kg"] == 2100.0 and mass["takeoff_kg"] == pytest.approx(1500.0 + 600.0 + 1200.0, abs=0.1)
    assert "57.1 %" in mass["above_mtow"]


def test_full_tank_is_at_mtow_not_above(munich: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(munich), "--out", str(out), "--stop-time", "1", "--no-pre-run")
    assert rc == 0, err
    mass = json.loads((out / "summary.json").read_text(encoding="utf-8"))["mass"]
    assert mass["takeoff_kg"] == pytest.approx(2100.0, abs=0.1) and mass["above_mtow"] is None


# -- start ----------------------------------------------------------------------------------------
def test_air_start_below_the_ground_is_refused_by_the_airframe(munich: Path, tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = _run(capsys, "run", str(munich), "--set", "airframe.start_on_runway=false", "airframe.alt0_m=100",
                   "--out", str(tmp_path / "out"), "--no-pre-run")
    line = assert_one_line(rc, err, "component 'airframe'", "below the ground", "alt0_m = 100", "ground_elevation_m")
    assert "engine" not in line.partition(":")[2]


@pytest.mark.parametrize(("old", "new", "runway"), [
    # the other runway of EDDM: 26L, 2.3 km south of 26R
    ("runway: EDDM_26R, lever: 1.0, rotate_cas_m_s", "runway: EDDM_26L, lever: 1.0, rotate_cas_m_s", "EDDM_26L"),
    # another airport: the departure runway moved to Frankfurt's 25C threshold
    ("threshold_lat_deg: 48.366887, threshold_lon_deg: 11.821173, heading_deg: 263.42,\n               elevation_m: 441.7",
     "threshold_lat_deg: 50.0451, threshold_lon_deg: 8.5869, heading_deg: 249.0,\n               elevation_m: 100.0",
     "EDDM_26R"),
])
def test_the_aircraft_starts_where_the_mission_departs(munich: Path, tmp_path: Path, old: str, new: str, runway: str,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 32 point 5: the mission is the one source of the start; the airframe starts on its departure runway
    (the flight control's outputs departure_*), at rest on its threshold, and rolls along it."""
    from openemss.models.mission.mission import load_mission

    mission = _mission(tmp_path, old, new)
    rwy = load_mission(mission).runway(runway)
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(munich), "--set", f"fcs.mission_file={mission}", "--out", str(out),
                   "--no-pre-run", "--stop-time", "15", "--format", "csv")
    assert rc == 0, err
    data = table(out)
    lat, lon = data["airframe.lat_deg"], data["airframe.lon_deg"]
    assert lat[0] == pytest.approx(rwy.threshold.lat_deg, abs=1e-6) and lon[0] == pytest.approx(
        rwy.threshold.lon_deg, abs=1e-6)
    assert data["airframe.alt_m"][0] == pytest.approx(rwy.elevation_m + 0.93, abs=0.1)  # the CG on its wheels
    assert np.all(data["airframe.on_ground"] > 0.5) and data["airframe.gs_m_s"][-1] > 10.0
    along, cross = rwy.local(LatLon.from_deg(lat[-1], lon[-1]))
    assert along > 50.0 and abs(cross) < 2.0  # rolled along its centre line


def test_start_set_away_from_the_missions_departure_is_an_error(munich: Path, tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    """Start parameters given away from the mission's departure runway (Frankfurt's 25C for a Munich mission) win
    over the mission's, and the flight control refuses the start naming both positions."""
    rc, err = _run(capsys, "run", str(munich), "--set", "airframe.lat0_deg=50.0451", "airframe.lon0_deg=8.5869",
                   "--out", str(tmp_path / "out"), "--no-pre-run", "--stop-time", "5")
    assert_one_line(rc, err, "component 'fcs'", "the mission starts with section 0 (Rolling",
                    "but the aircraft starts at", "50.04510 N 8.58690 E", "48.36")


def test_start_facing_the_wrong_way_is_an_error(munich: Path, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = _run(capsys, "run", str(munich), "--set", "airframe.heading0_deg=83.42", "--out", str(tmp_path / "out"),
                   "--no-pre-run", "--stop-time", "5")
    assert_one_line(rc, err, "component 'fcs'", "heading 180.0 deg off the runway's")


def test_mission_from_the_runway_but_aircraft_in_the_air_is_an_error(munich: Path, tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = _run(capsys, "run", str(munich), "--set", "airframe.start_on_runway=false", "airframe.alt0_m=1500",
                   "--out", str(tmp_path / "out"), "--no-pre-run", "--stop-time", "5")
    assert_one_line(rc, err, "component 'fcs'", "in the air, not on the ground")


def test_ground_run_off_the_runway_end_says_so(munich: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """The take-off roll at lever 0.3: the aircraft runs out of runway on the ground below its rotation speed (a
    ground roll longer than the runway was reported as a "wingtip strike" on the grass)."""
    mission = _mission(tmp_path, "runway: EDDM_26R, lever: 1.0, rotate_cas_m_s: 62",
                       "runway: EDDM_26R, lever: 0.3, rotate_cas_m_s: 62")
    out = tmp_path / "out"
    rc, err = _run(capsys, "run", str(munich), "--set", f"fcs.mission_file={mission}", "--out", str(out),
                   "--no-pre-run", "--stop-time", "400", "--format", "csv")
    line = assert_one_line(rc, err, "component 'fcs'", "ran off the far end of runway EDDM_26R (4000 m long)",
                           "without lifting off", "rotation at 62 m/s")
    data = table(out)
    assert np.all(data["airframe.on_ground"] > 0.5)  # it never lifted off
    cas = float(re.search(r"on the ground at ([0-9.]+) m/s calibrated", line).group(1))  # type: ignore[union-attr]
    assert 0.0 < cas < 62.0
