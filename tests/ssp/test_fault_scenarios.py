"""Faults injected by scenario files into the shipped coupled system (ssp/: engine, airframe, FCS FMUs),
on a short mission (take-off from EDDM 26R, then an orbit at 1000 m), through the README's command.

- Inlet distortion in the turn (scenarios/distortion_in_orbit.yaml's events, triggered here by the
  orbit of this mission): the run goes on to its end; while the distortion is on, the fan's surge
  margin is lower than just before (the parallel compressor model's penalty), and it recovers after.
- A runaway aileron (as scenarios/stuck_aileron.yaml): the aircraft is lost; the run stops with one
  line naming the component, the time and the cause, exit code 1, and every step recorded up to the
  fault stays on disk, with the summary written from it.
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import table
from openemss.orchestrator.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
MISSION = {
    "mission": {"name": "take-off and orbit"},
    "places": {"runways": {"EDDM_26R": {"threshold_lat_deg": 48.366887, "threshold_lon_deg": 11.821173,
                                        "heading_deg": 263.42, "elevation_m": 441.7, "length_m": 4000.0,
                                        "width_m": 60.0}},
               "waypoints": {"C": {"lat_deg": 48.33, "lon_deg": 11.60}}},
    "sections": [
        {"type": "Rolling", "runway": "EDDM_26R", "lever": 1.0, "rotate_cas_m_s": 62.0},
        {"type": "TakeOff", "runway": "EDDM_26R", "lever": 1.0, "pitch_deg": 10.0, "rotation_rate_deg_s": 3.0,
         "climb_speed": {"cas_m_s": 85.0}, "until_height_agl_m": 300.0},
        {"type": "Orbiting", "name": "orbit", "center": "C", "radius_m": 4000.0, "direction": "clockwise",
         "turns": 3, "altitude_m": 1200.0, "speed": {"mach": 0.35}},
    ],
}


@pytest.fixture()
def system(tmp_path: Path, project_fmus: dict[str, Path]) -> tuple[Path, Path]:
    """A copy of ssp/ with the session's FMUs, and a parameter set that flies the short mission."""
    copy = tmp_path / "ssp"
    shutil.copytree(ROOT / "ssp", copy, ignore=shutil.ignore_patterns("resources", "__pycache__", "*.py"))
    (copy / "resources").mkdir()
    for path in project_fmus.values():
        shutil.copy2(path, copy / "resources" / path.name)
    mission = tmp_path / "orbit.yaml"
    mission.write_text(yaml.safe_dump(MISSION))
    ssv = tmp_path / "mission.ssv"
    ssv.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet xmlns:ssv='
                   '"http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="m">'
                   f'<ssv:Parameters><ssv:Parameter name="fcs.mission_file"><ssv:String value="{mission}"/>'
                   '</ssv:Parameter></ssv:Parameters></ssv:ParameterSet>\n')
    return copy, ssv


def _read(run: Path) -> dict[str, np.ndarray]:
    return table(run)


def _scenario(shipped: str, tmp_path: Path, replace: dict[str, str]) -> Path:
    text = (ROOT / "scenarios" / shipped).read_text()
    for a, b in replace.items():
        assert a in text
        text = text.replace(a, b)
    out = tmp_path / shipped
    out.write_text(text)
    return out


def test_distortion_in_the_turn_costs_fan_surge_margin_and_the_run_goes_on(system: tuple[Path, Path],
                                                                           tmp_path: Path) -> None:
    folder, ssv = system
    # the shipped scenario's events, on this mission's orbit (section 2), cleared a minute into it
    scen = _scenario("distortion_in_orbit.yaml", tmp_path, {
        "when: fcs.section_index == 6": "when: fcs.section_index == 2",
        "when: fcs.section_index == 7\n": "when: fcs.section_index == 2\n    after: 60.0\n"})
    out = tmp_path / "run"
    assert main(["run", str(folder), "--params", str(ssv), "--scenario", str(scen), "--stop-time", "150",
                 "--out", str(out), "--no-post-run"]) == 0
    r = _read(out)
    t, sec, sm = r["time_s"], r["fcs.section_index"], r["engine.SM_fan"]
    assert t[-1] == pytest.approx(150.0)
    t_orbit = t[np.argmax(sec == 2)]
    on = (t >= t_orbit + 30.0 + 1.0) & (t < t_orbit + 60.0)
    before = (t >= t_orbit + 20.0) & (t < t_orbit + 30.0)
    after = (t >= t_orbit + 65.0)
    assert on.any() and before.any() and after.any()
    assert np.all(r["engine.distortion_on"][on] == 1.0) and np.all(r["engine.distortion_on"][before] == 0.0)
    assert sm[on].max() < sm[before].min() - 0.02  # an 8 % deficit on 90 deg costs margin (fraction)
    assert sm[after][-1] > sm[on].max()  # and it comes back when the distortion clears


def test_runaway_aileron_loses_the_aircraft_and_keeps_what_was_recorded(system: tuple[Path, Path], tmp_path: Path,
                                                                        capsys: pytest.CaptureFixture[str]) -> None:
    folder, ssv = system
    scen = _scenario("stuck_aileron.yaml", tmp_path, {"fcs.section_index == 3": "fcs.section_index == 2",
                                                      "from: 60.0": "from: 5.0", "to: 62.0": "to: 7.0"})
    out = tmp_path / "run"
    rc = main(["run", str(folder), "--params", str(ssv), "--scenario", str(scen), "--stop-time", "200",
               "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 3  # failed while stepping
    line = [e for e in err if e.startswith("emss run: error")]
    assert len(line) == 1 and "component 'airframe' failed in fmi2DoStep" in line[0] and "aircraft lost" in line[0]
    r = _read(out)
    t = r["time_s"]
    t_fault = t[np.argmax(r["fcs.section_index"] == 2)] + 5.0
    assert t[0] == 0.0 and np.all(np.diff(t) == pytest.approx(0.05))  # every step up to the loss, none missing
    assert t_fault < t[-1] < 200.0
    assert abs(r["airframe.aileron_norm"][-1] - 0.3) < 1e-12  # the runaway is in the record
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "aircraft lost" in s["error"]
    assert s["sim_time_s"] == pytest.approx(t[-1])
