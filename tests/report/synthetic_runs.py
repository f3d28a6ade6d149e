"""Synthetic results folders (timeseries.csv, run.json, mission) for the report tests.

A helper module rather than a conftest.py: `from conftest import ...` elsewhere in tests/ means
tests/conftest.py, which a second conftest module would shadow. Use :class:`Runs`.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

#: A small valid mission: runway 09 (heading 90 deg, 3000 m x 45 m), one waypoint, four sections.
MISSION = """\
mission: {name: test mission}
places:
  runways:
    RWY_09: {threshold_lat_deg: 48.0, threshold_lon_deg: 11.0, heading_deg: 90.0, elevation_m: 500.0,
             length_m: 3000.0, width_m: 45.0}
  waypoints:
    WP1: {lat_deg: 48.05, lon_deg: 11.10}
sections:
  - {type: Rolling, name: roll, runway: RWY_09, rotate_cas_m_s: 60.0}
  - {type: TakeOff, name: lift-off, runway: RWY_09, climb_speed: {cas_m_s: 80.0}}
  - {type: WaypointFollowing, name: out to WP1, waypoints: [WP1], altitude_m: 1000.0, speed: {mach: 0.4}}
  - {type: Landing, name: land, runway: RWY_09, approach_altitude_m: 1000.0, approach_speed: {cas_m_s: 65.0}}
"""

H_S = 0.05          # sample interval [s]
N = 1201            # samples: 0 to 60 s
BOUNDS = (200, 500)  # samples at which section 1 and section 2 start (t = 10 s, 25 s)
WF_KG_S = 0.12      # constant fuel flow [kg/s]


def write_run(folder: Path, columns: dict[str, np.ndarray], info: dict | None = None,
              mission: str | None = MISSION) -> Path:
    """Write a results folder as emss run does: timeseries.csv (time_s first), run.json, mission copy."""
    folder.mkdir(parents=True, exist_ok=True)
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    np.savetxt(folder / "timeseries.csv", data, delimiter=",", fmt="%.15g", header=",".join(names), comments="")
    (folder / "run.json").write_text(json.dumps(info if info is not None else {
        "system": "synthetic", "status": "completed", "wall_time_s": 2.0, "realtime_factor": 30.0,
        "parameters": {"fcs.fuel_control.Tt41_max_K": 1400.0, "fcs.fuel_control.N1_max_pct": 103.0}}))
    if mission is not None:
        (folder / "mission.yaml").write_text(mission)
    return folder


def base_columns() -> dict[str, np.ndarray]:
    """60 s of a mission: sections 0, 1, 2 (starting at 0, 10, 25 s), constant fuel flow, flying east
    from the runway threshold at 50 m/s, airborne from 15 s."""
    k = np.arange(N)
    t = k * H_S
    idx = np.where(k < BOUNDS[0], 0, np.where(k < BOUNDS[1], 1, 2))
    east_m = 50.0 * t
    lat = np.full(N, 48.0)
    lon = 11.0 + np.degrees(east_m / (6_378_137.0 * np.cos(np.radians(48.0))))
    return {
        "time_s": t,
        "fcs.section_index": idx,
        "fcs.mission_completed": np.zeros(N),
        "fcs.alt_cmd_m": np.full(N, 1000.0),
        "fcs.mach_cmd": np.full(N, 0.4),
        "fcs.Tt41_K": np.full(N, 1200.0),
        "fcs.N1_pct": np.full(N, 90.0),
        "engine.Wf_kg_s": np.full(N, WF_KG_S),
        "engine.fuel_burned_kg": WF_KG_S * t,
        "engine.Tt4_K": 1000.0 + t,
        "engine.N1_pct": np.full(N, 90.0),
        "engine.N2_pct": np.full(N, 95.0),
        "engine.surge": np.zeros(N),
        "engine.flameout": np.zeros(N),
        "engine.overspeed": np.zeros(N),
        "airframe.lat_deg": lat,
        "airframe.lon_deg": lon,
        "airframe.alt_m": 500.0 + np.maximum(t - 15.0, 0.0) * 10.0,
        "airframe.mach": np.full(N, 0.3),
        "airframe.gs_m_s": np.full(N, 50.0),
        "airframe.on_ground": (t < 15.0).astype(float),
        "airframe.phi_rad": np.zeros(N),
        "airframe.theta_rad": np.full(N, 0.05),
        "airframe.psi_rad": np.full(N, np.pi / 2),
    }


class Runs:
    """Synthetic results folders under ``root``: ``Runs(tmp_path).make(name, columns={...}, info=..., mission=...)``;
    ``columns`` replace or add columns of :func:`base_columns` (``None`` drops one), ``info`` and
    ``mission`` replace run.json and the mission text."""

    def __init__(self, root: Path) -> None:
        self.root = root

    def make(self, name: str = "run", columns: dict[str, np.ndarray | None] | None = None,
             info: dict | None = None, mission: str | None = MISSION) -> Path:
        cols = base_columns()
        for path, value in (columns or {}).items():
            if value is None:
                cols.pop(path, None)
            else:
                cols[path] = value
        return write_run(self.root / name, cols, info, mission)
