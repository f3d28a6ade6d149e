"""summary.json math on synthetic runs, against analytic values.

Fuel: a constant flow W over a section of duration T burns exactly W*T; a linear ramp
a + b*t has the exact integral a*T + b*(t1^2 - t0^2)/2, and the held-before rule (each
sample's value held over the interval ending at it, as the engine's counter adds it) exceeds
it by exactly b*h*T/2. Landing: positions placed on a sphere of the WGS-84 equatorial radius,
which the summary measures in the WGS-84 tangent plane (they differ by under 0.5 %, metres
at the distances used, far inside the runway's margins).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from synthetic_runs import BOUNDS, H_S, WF_KG_S, N, Runs

from openemss.report.plugin import write_report
from openemss.report.rundata import load_mission, load_run
from openemss.report.summary import flag_stats, held_increments, summarize

T = np.arange(N) * H_S
R_M = 6_378_137.0


def _summary(folder: Path) -> dict:
    run = load_run(folder)
    return summarize(run, load_mission(run)[0])


def _east_lon(east_m: float, lat_deg: float = 48.0) -> float:
    return 11.0 + math.degrees(east_m / (R_M * math.cos(math.radians(lat_deg))))


def test_constant_fuel_flow_gives_flow_times_duration_per_section(tmp_path: Path) -> None:
    s = _summary(Runs(tmp_path).make())
    t1, t2, tend = T[BOUNDS[0]], T[BOUNDS[1]], T[-1]
    expected = [("roll", "Rolling", 0.0, t1, "completed"), ("lift-off", "TakeOff", t1, t2, "completed"),
                ("out to WP1", "WaypointFollowing", t2, tend, "active"), ("land", "Landing", None, None, "not reached")]
    assert [x["index"] for x in s["sections"]] == [0, 1, 2, 3]
    for sec, (name, typ, start, end, status) in zip(s["sections"], expected, strict=True):
        assert (sec["name"], sec["type"], sec["status"]) == (name, typ, status)
        assert sec["start_time_s"] == start and sec["end_time_s"] == end
        duration = 0.0 if start is None else end - start
        assert sec["duration_s"] == pytest.approx(duration, abs=1e-9)
        assert sec["fuel_burned_kg"] == pytest.approx(WF_KG_S * duration, rel=1e-12, abs=1e-12)
    assert s["fuel_burned_kg"] == pytest.approx(WF_KG_S * 60.0, rel=1e-12)
    assert s["fuel_flow_integral_kg"] == pytest.approx(WF_KG_S * 60.0, rel=1e-12)
    assert abs(s["fuel_balance_error_kg"]) < 1e-12
    assert sum(x["fuel_burned_kg"] for x in s["sections"]) == pytest.approx(s["fuel_flow_integral_kg"], rel=1e-12)
    # copied from the synthetic run.json (wall 2.0 s, factor 30 written by synthetic_runs.py): the summary
    # reports what the run recorded; nothing here times anything
    assert s["sim_time_s"] == pytest.approx(60.0) and s["wall_time_s"] == 2.0 and s["realtime_factor"] == 30.0
    assert s["max_Tt4_K"] == pytest.approx(1060.0) and s["max_Tt4_time_s"] == pytest.approx(60.0)
    assert s["mission_completed"] is False and s["mission"]["sections"] == 4


def test_linear_fuel_ramp_against_the_analytic_integral(tmp_path: Path) -> None:
    a, b = 0.05, 0.002  # [kg/s], [kg/s^2]
    ramp = {"engine.Wf_kg_s": a + b * T, "engine.fuel_burned_kg": a * T + b * T**2 / 2}
    s = _summary(Runs(tmp_path).make(columns=ramp))
    t0, t1 = T[BOUNDS[0]], T[BOUNDS[1]]
    exact = a * (t1 - t0) + b * (t1**2 - t0**2) / 2
    assert s["sections"][1]["fuel_burned_kg"] == pytest.approx(exact + b * H_S * (t1 - t0) / 2, rel=1e-12)
    # the counter holds the exact integral here: the balance error is the rule's, b*h*T/2
    assert s["fuel_balance_error_kg"] == pytest.approx(b * H_S * 60.0 / 2, rel=1e-9)


def test_held_increments_of_a_step_flow() -> None:
    t = np.array([0.0, 1.0, 3.0, 4.0])
    assert held_increments(t, np.array([9.0, 1.0, 2.0, 3.0])).tolist() == [1.0, 4.0, 3.0]


def test_completed_mission_marks_every_section_completed(tmp_path: Path) -> None:
    idx = np.where(T < 10, 0, np.where(T < 20, 1, np.where(T < 30, 2, np.where(T < 50, 3, 4))))
    done = (T >= 50).astype(float)
    s = _summary(Runs(tmp_path).make(columns={"fcs.section_index": idx, "fcs.mission_completed": done}))
    assert s["mission_completed"] is True
    assert [x["status"] for x in s["sections"]] == ["completed"] * 4
    assert s["sections"][3]["end_time_s"] == pytest.approx(50.0)


def test_flag_counts_first_time_and_duration() -> None:
    flag = np.zeros(N)
    flag[100:110] = 1
    flag[300] = 1
    st = flag_stats(T, flag)
    assert st == {"count": 2, "first_time_s": T[100], "duration_s": pytest.approx(11 * H_S)}
    assert flag_stats(T, np.zeros(N)) == {"count": 0, "first_time_s": None, "duration_s": 0.0}
    assert flag_stats(T, np.ones(N))["count"] == 1


def test_limits_from_engine_flags_and_the_fuel_controller(tmp_path: Path) -> None:
    surge = np.zeros(N)
    surge[100:110] = 1
    tt41 = np.full(N, 1200.0)
    tt41[600:700] = 1399.0  # within 0.25 % of the 1400 K limit
    s = _summary(Runs(tmp_path).make(columns={"engine.surge": surge, "fcs.Tt41_K": tt41}))
    lim = s["limits_hit"]
    assert lim["surge"]["count"] == 1 and lim["surge"]["first_time_s"] == pytest.approx(T[100])
    assert lim["flameout"]["count"] == 0 and lim["overspeed"]["count"] == 0
    assert lim["Tt41_limit"]["count"] == 1 and lim["Tt41_limit"]["first_time_s"] == pytest.approx(T[600])
    assert lim["Tt41_limit"]["limit"] == 1400.0 and lim["Tt41_limit"]["source"].startswith("inferred")
    assert lim["N1_limit"]["count"] == 0
    # an FCS that reports its limiter (fuel_limiter: 1 Tt41, 2 N1) is believed instead of the inference
    code = np.zeros(N)
    code[50:60] = 1
    code[70:75] = 2
    lim = _summary(Runs(tmp_path).make("flagged", columns={"fcs.fuel_limiter": code, "fcs.Tt41_K": tt41}))["limits_hit"]
    assert lim["Tt41_limit"] == {"count": 1, "first_time_s": pytest.approx(T[50]),
                                 "duration_s": pytest.approx(10 * H_S), "source": "fcs.fuel_limiter == 1"}
    assert lim["N1_limit"] == {"count": 1, "first_time_s": pytest.approx(T[70]),
                               "duration_s": pytest.approx(5 * H_S), "source": "fcs.fuel_limiter == 2"}


def _landing_columns(east_m: float, north_m: float = 0.0, gs_end: float = 0.1, airborne: bool = True) -> dict:
    lat = np.full(N, 48.0 + math.degrees(north_m / R_M))
    lon = np.full(N, _east_lon(east_m))
    on_ground = ((T < 15) | (T > 50)).astype(float) if airborne else np.ones(N)
    gs = np.full(N, 60.0)
    gs[-1] = gs_end
    return {"airframe.lat_deg": lat, "airframe.lon_deg": lon, "airframe.on_ground": on_ground, "airframe.gs_m_s": gs}


@pytest.mark.parametrize(("case", "kwargs", "landed"), [
    ("stopped on the runway", {"east_m": 1500.0}, True),
    ("100 m beside the centre line (width 45 m)", {"east_m": 1500.0, "north_m": 100.0}, False),
    ("beyond the runway's end (3000 m)", {"east_m": 3300.0}, False),
    ("still rolling at 5 m/s", {"east_m": 1500.0, "gs_end": 5.0}, False),
    ("never airborne", {"east_m": 1500.0, "airborne": False}, False),
])
def test_landed_means_airborne_then_stopped_on_a_runway(tmp_path: Path, case: str, kwargs: dict,
                                                        landed: bool) -> None:
    s = _summary(Runs(tmp_path).make(columns=_landing_columns(**kwargs)))
    assert s["landed"] is landed, case
    if landed:
        assert s["landing"]["runway"] == "RWY_09"
        assert s["landing"]["along_m"] == pytest.approx(1500.0, rel=5e-3)
        assert abs(s["landing"]["cross_m"]) < 1.0


def test_without_a_mission_the_sections_seen_are_listed_unnamed(tmp_path: Path) -> None:
    s = _summary(Runs(tmp_path).make(mission=None))
    assert s["mission"] is None and s["landed"] is False
    assert [(x["index"], x["name"], x["status"]) for x in s["sections"]] == [
        (0, None, "completed"), (1, None, "completed"), (2, None, "active")]


def test_failed_run_with_a_partial_last_line_is_summarized(tmp_path: Path) -> None:
    error = "engine: fmi2DoStep failed at t = 60 s"
    folder = Runs(tmp_path).make(info={"system": "synthetic", "status": "failed", "error": error},
                                 columns={"engine.Tt4_K": np.full(N, np.nan)})
    with open(folder / "timeseries.csv", "a") as f:
        f.write("60.05,1,0")  # killed while writing
    files = write_report(folder, plots=False)
    assert files[0].name == "summary.json"
    text = files[0].read_text()
    assert "NaN" not in text  # strict JSON: non-finite values are null
    s = json.loads(text)
    assert s["status"] == "failed" and "fmi2DoStep" in s["error"]
    assert s["sim_time_s"] == pytest.approx(60.0) and s["max_Tt4_K"] is None and s["wall_time_s"] is None
