"""End to end through the real FMUs (issue 8): the shipped system ssp/ (engine model FMU with the
Larzac 04 preset, UPERA airframe FMU, FCS FMU) flies a shortened mission with the README's command:
take-off from EDDM 26R, out to one waypoint west of the airport, then the ILS approach to runway 08L
and a full stop. Checked against independent facts: the mission completes and the aircraft stops on
the runway it was told to land on (its surveyed threshold and heading, from missions/munich.yaml),
and the fuel burned equals the integral of the recorded fuel flow (mass conservation: the engine's
counter integrates the same flow over each step, so they agree to round-off)."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import table
from openemss.models.fcs.geo import LatLon
from openemss.models.fcs.mission import load_mission
from openemss.orchestrator.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


def _short_mission(path: Path) -> Path:
    munich = yaml.safe_load((ROOT / "missions" / "munich.yaml").read_text())
    mission = {
        "mission": {"name": "EDDM circuit: 26R departure, ILS 08L"},
        "places": {"runways": munich["places"]["runways"],
                   "waypoints": {"W": {"lat_deg": 48.40, "lon_deg": 11.48}}},
        "sections": [munich["sections"][0], munich["sections"][1],
                     {"type": "WaypointFollowing", "name": "out to W", "waypoints": ["W"], "altitude_m": 1000.0,
                      "speed": {"cas_m_s": 90.0}},
                     {"type": "Landing", "name": "ILS 08L and full stop", "runway": "EDDM_08L",
                      "approach_altitude_m": 1000.0, "approach_speed": {"cas_m_s": 68.0}}],
    }
    path.write_text(yaml.safe_dump(mission, sort_keys=False))
    return path


def test_take_off_one_waypoint_and_landing_through_the_real_fmus(tmp_path: Path,
                                                                  project_fmus: dict[str, Path]) -> None:
    copy = tmp_path / "ssp"
    shutil.copytree(ROOT / "ssp", copy, ignore=shutil.ignore_patterns("resources", "__pycache__", "*.py"))
    (copy / "resources").mkdir()
    for path in project_fmus.values():
        shutil.copy2(path, copy / "resources" / path.name)
    mission = _short_mission(tmp_path / "circuit.yaml")
    out = tmp_path / "run"
    assert main(["run", str(copy), "--set", f"fcs.mission_file={mission}", "--stop-time", "2000",
                 "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "completed" and s["mission_completed"] is True and s["landed"] is True
    assert s["sim_time_s"] < 2000.0  # ended by the mission's completion, not the stop time
    assert [x["status"] for x in s["sections"]] == ["completed"] * 4
    # stopped on 08L, within its length and half its width, by the runway's own geometry
    rwy = load_mission(mission).sections[3]["runway"]
    data = table(out)
    lat, lon = float(data["airframe.lat_deg"][-1]), float(data["airframe.lon_deg"][-1])
    along, cross = rwy.local(LatLon.from_deg(lat, lon))
    assert 0.0 < along < rwy.length_m and abs(cross) < rwy.width_m / 2
    assert s["landing"]["runway"] in ("EDDM_08L", "EDDM_26R")  # one strip, named from either end
    # fuel: the engine's counter against the integral of the recorded fuel flow (held over each step)
    t, wf, burned = data["time_s"], data["engine.Wf_kg_s"], data["engine.fuel_burned_kg"]
    integral = float(np.sum(wf[1:] * np.diff(t)))
    assert burned[-1] - burned[0] == pytest.approx(integral, rel=1e-9)
    assert s["fuel_burned_kg"] == pytest.approx(integral, rel=1e-9) and integral > 10.0
