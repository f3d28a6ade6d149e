"""summary.json's conformance (report/conformance.py) on synthetic runs with hand-computed answers.

The synthetic run (synthetic_runs.py) is given an altitude that climbs at 20 m/s from 500 m from
t = 15 s to 1000 m at t = 40 s, then holds 1000 m but for a dip of 25 m (a half sine from 45 to 50 s),
and climbs 5 m over the last 2 s. Its section 2 (from t = 25 s, still active at the end, t = 60 s)
targets 1000 m and Mach 0.4 and flies Mach 0.3. So the altitude enters the 10 m band at 990 m,
t = 39.5 s (14.5 s after the section's start), is settled (1 m) at 39.95 s, dips to 975 m: the worst
deviation after the capture is -25 m, and it ends at 1005 m, 5 m high. The Mach never gets within
0.005 of its target: no capture, -0.1 at the end. A HOLD (vertical mode 5) from
30 s to 40 s is one hold of 10 s that climbed 100 m. The ILS: a localizer captured 200 m right of the
centre line (south of runway 09) and flown to 30 m left of it is an overshoot of 30 m; the glide slope
captured at 1000 m, below the path, then flown to 4 m above it, is an overshoot of 4 m. The positions
are placed in the runway's tangent plane (geo.from_local_ne), where the summary measures them.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from synthetic_runs import H_S, N, Runs

from openemss.models.mission.geo import LatLon, from_local_ne
from openemss.report.rundata import load_mission, load_run
from openemss.report.summary import summarize

T = np.arange(N) * H_S


def _summary(folder: Path) -> dict:
    run = load_run(folder)
    return summarize(run, load_mission(run)[0])


def _altitude() -> np.ndarray:
    h = np.where(T < 40.0, 500.0 + 20.0 * np.maximum(T - 15.0, 0.0), 1000.0)
    dip = (T > 45.0) & (T < 50.0)
    h = np.where(dip, 1000.0 - 25.0 * np.sin(np.pi * (T - 45.0) / 5.0), h)
    return np.where(T > 58.0, 1000.0 + 2.5 * (T - 58.0), h)


def test_section_targets_against_the_flown_altitude_and_speed(tmp_path: Path) -> None:
    s = _summary(Runs(tmp_path).make(columns={"airframe.alt_m": _altitude()}))
    assert s["sections"][0]["conformance"] is None and s["sections"][1]["conformance"] is None
    c = s["sections"][2]["conformance"]
    a, v = c["altitude"], c["speed"]
    assert a["target_m"] == 1000.0 and a["constraint_at"] == "end"
    assert a["achieved_m"] == pytest.approx(1005.0) and a["error_at_end_m"] == pytest.approx(5.0)
    assert a["time_to_capture_s"] == pytest.approx(14.5, abs=1e-9)
    assert a["worst_after_capture_m"] == pytest.approx(-25.0)
    assert v == {"kind": "mach", "target": 0.4, "achieved": pytest.approx(0.3), "error_at_end": pytest.approx(-0.1),
                 "time_to_capture_s": None, "worst_after_capture": None}
    assert s["holds"] == [] and s["ils"] is None  # no vnav_mode or ils_phase recorded


def test_a_hold_is_reported_with_its_section_and_duration(tmp_path: Path) -> None:
    mode = np.where((T >= 30.0) & (T <= 40.0 + 1e-9), 5.0, 1.0)
    s = _summary(Runs(tmp_path).make(columns={"fcs.vnav_mode": mode}))
    assert len(s["holds"]) == 1
    h = s["holds"][0]
    assert (h["section"], h["name"]) == (2, "out to WP1")
    assert h["start_time_s"] == pytest.approx(30.0) and h["end_time_s"] == pytest.approx(40.0)
    assert h["duration_s"] == pytest.approx(10.0) and h["height_lost_m"] == pytest.approx(-100.0)


def test_ils_capture_altitude_and_overshoots(tmp_path: Path) -> None:
    """On the approach to runway 09 (threshold 48 N 11 E, elevation 500 m, glide path 3 deg over 15 m at the
    threshold): from 12 km out to 10 km, LOC from t = 40 s (200 m right, ramping to 30 m left by 50 s), GS from
    t = 45 s at 1000 m: the glide path there is 15 + (12000 - 2000 x 5/20) tan 3 deg = 617 m above the runway,
    1117 m, so the glide slope is captured from below."""
    tan_gs = math.tan(0.05236)
    along = -12000.0 + 2000.0 * np.clip((T - 40.0) / 20.0, 0.0, 1.0)  # [m] from the threshold, < 0 before it
    cross = np.interp(T, [40.0, 50.0], [200.0, -30.0])  # right of the centre line (south for heading 90)
    thr = LatLon.from_deg(48.0, 11.0)
    pts = [from_local_ne(thr, -c, a, 500.0) for a, c in zip(along, cross, strict=True)]  # north = -cross, east = along
    lat, lon = np.array([p.lat_deg for p in pts]), np.array([p.lon_deg for p in pts])
    h_gp = 500.0 + 15.0 - along * tan_gs
    i45 = int(round(45.0 / H_S))
    alt = np.where(T < 45.0, 1000.0, h_gp + np.interp(T, [45.0, 55.0], [1000.0 - h_gp[i45], 4.0]))
    phase = np.where(T < 40.0, 2.0, np.where(T < 45.0, 3.0, 4.0))
    s = _summary(Runs(tmp_path).make(columns={"fcs.ils_phase": phase, "airframe.lat_deg": lat,
                                              "airframe.lon_deg": lon, "airframe.alt_m": alt}))
    ils = s["ils"]
    assert ils["runway"] == "RWY_09" and ils["approach_altitude_m"] == 1000.0
    assert ils["loc_capture_time_s"] == pytest.approx(40.0)
    assert ils["loc_capture_xtk_m"] == pytest.approx(200.0, abs=1e-3)
    assert ils["loc_overshoot_m"] == pytest.approx(30.0, abs=1e-3)
    assert ils["gs_capture_time_s"] == pytest.approx(45.0) and ils["gs_capture_altitude_m"] == pytest.approx(1000.0)
    assert ils["gs_capture_error_m"] == pytest.approx(0.0, abs=1e-9)
    assert 1000.0 - h_gp[i45] < 0.0  # captured from below
    assert ils["gs_overshoot_m"] == pytest.approx(4.0, abs=1e-3)
