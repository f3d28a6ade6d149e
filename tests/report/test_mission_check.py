"""``emss mission check`` and the check ``emss run`` prints (report/mission_check.py) on the project's system.

* The performance of the shipped models within the fuel controller's limits: with the Tt41 limit
  lowered to 1250 K the maximum thrust is where the engine reaches it, the corrected fan speed
  found independently with Brent's method on the engine model.
* A mission with a descent of 4000 m over 15 km (26.7 %: no idle descent of a jet makes that) is
  named infeasible with its numbers; the exit code counts the infeasible sections; --json.
* The fuel on board (airframe.fuel0_kg) against the mission's fuel estimate.
* A mission's winds aloft the airframe does not fly are reported.
* emss run prints the findings before it starts (the plugin's pre_run), a system without a
  mission gets none; bad input is one line.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from scipy.optimize import brentq

from openemss.orchestrator.cli.main import main
from openemss.report.mission_check import pre_run

ROOT = Path(__file__).resolve().parents[2]
STEEP = """mission: {name: steep descent}
places:
  runways:
    EDDM_26R: {threshold_lat_deg: 48.366887, threshold_lon_deg: 11.821173, heading_deg: 263.42,
               elevation_m: 441.7, length_m: 4000.0, width_m: 60.0}
  waypoints:
    A: {lat_deg: 48.330, lon_deg: 11.460}
    B: {lat_deg: 48.600, lon_deg: 11.650}
    C: {lat_deg: 48.600, lon_deg: 11.852}
sections:
  - {type: Rolling, runway: EDDM_26R, lever: 1.0, rotate_cas_m_s: 62.0}
  - {type: TakeOff, runway: EDDM_26R, climb_speed: {cas_m_s: 85.0}, until_height_agl_m: 300.0}
  - {type: WaypointFollowing, fly_by: true, waypoints: [A, B], altitude_m: 5000.0, speed: {mach: 0.5}}
  - {type: WaypointFollowing, fly_by: true, name: steep descent, waypoints: [C], altitude_m: 1000.0,
     speed: {mach: 0.5}}
"""


@pytest.fixture(scope="module")
def system(project_system: Path) -> Path:
    """The project's system with this session's FMUs (conftest.project_system)."""
    return project_system


@pytest.fixture()
def steep(tmp_path: Path) -> Path:
    f = tmp_path / "steep.yaml"
    f.write_text(STEEP)
    return f


def _one_line_error(capsys: pytest.CaptureFixture[str], *words: str) -> None:
    err = [line for line in capsys.readouterr().err.strip().splitlines() if not line.startswith(("built:", "up to"))]
    assert len(err) == 1 and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err


def test_maximum_thrust_stops_at_the_tt41_limit() -> None:
    from openemss.models.engine.design_params import load_params, preset_path
    from openemss.report.model_performance import FuelControlLimits, ModelPerformance

    limits = FuelControlLimits(k_delta_pct=100.0, N1c_idle_pct=40.0, Tt41_max_K=1250.0, N1_max_pct=103.0,
                               Wf_min_kg_s=0.012, Wf_max_kg_s=0.4, lever_min=0.4, lever_max=1.0)
    perf = ModelPerformance(load_params(preset_path("larzac04_sls")), limits)
    alt, mach = 2500.0, 0.6
    hi = perf.max_point(alt, mach)
    od = perf._em.od  # the engine model itself, solved with another method for the same condition
    n1c = brentq(lambda x: od.solve(alt, mach, 0.0, N1c_pct=x).T41_K - 1250.0, 60.0, 100.0, xtol=1e-6)
    assert hi.T41_K <= 1250.0 and hi.N1c_pct == pytest.approx(n1c, abs=0.05)
    assert od.solve(alt, mach, 0.0, N1c_pct=100.0).T41_K > 1250.0  # the limit did bind
    idle = perf.idle_point(alt, mach)
    assert idle.Wf_kg_s >= 0.012 * (1 - 1e-6) and idle.N1c_pct >= 40.0 - 1e-6
    p = perf.point(alt, mach, 2000.0)
    assert p.thrust_max_N == hi.Fn_N and p.thrust_idle_N == idle.Fn_N and p.drag_N > 0.0


def test_check_names_the_infeasible_descent(system: Path, steep: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["mission", "check", str(steep), "--system", str(system)])
    out = capsys.readouterr().out
    assert code == 1  # one infeasible section
    line = next(li for li in out.splitlines() if "steep descent:" in li)
    assert "descent 5000 -> 1000 m over" in line and "infeasible" in line
    assert "at idle with the airbrake planned up to 50 % at M 0.50" in line
    assert "checked in" in out and "engine larzac04_sls, 2100 kg" in out
    assert main(["mission", "check", str(steep), "--system", str(system), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    s = d["sections"][3]
    assert s["verdict"] == "infeasible" and d["counts"]["infeasible"] == 1
    assert s["required_gradient"] < s["achievable_gradient"] < 0.0  # both descents, the required steeper
    assert s["needed_distance_m"] > s["distance_m"] > 0.0
    assert -s["required_gradient"] == pytest.approx(4000.0 / s["distance_m"])


def test_fuel_on_board_and_weather_not_flown(system: Path, steep: Path, tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    windy = tmp_path / "windy.yaml"
    windy.write_text(STEEP + "wind: {layers: [{alt_m: 0, from_deg: 270, speed_kt: 20}]}\n")
    code = main(["mission", "check", str(windy), "--system", str(system), "--set", "airframe.fuel0_kg=5"])
    out = capsys.readouterr().out
    assert code == 1  # findings: the descent and the fuel (counted in the table)
    assert "kg are on board: infeasible" in out and "1505 kg at the start" in out
    assert "the mission gives winds aloft" in out and "the airframe flies none (still air)" in out
    code = main(["mission", "check", str(windy), "--system", str(system), "--set", f"airframe.weather_file={windy}"])
    out = capsys.readouterr().out
    assert "the mission gives winds aloft" not in out and "wind 20 kt in 1 layer(s)" in out


def test_pre_run_hook(system: Path, steep: Path, oscillator: Path) -> None:
    comps = {"fcs": system / "resources" / "Fcs.fmu", "engine": system / "resources" / "Engine.fmu",
             "airframe": system / "resources" / "Airframe.fmu"}
    lines = pre_run(comps, {"fcs.mission_file": str(steep), "engine.preset": "larzac04_sls"})
    assert any("section 3 (WaypointFollowing 'steep descent')" in li and "infeasible" in li for li in lines)
    assert lines[-1].startswith("mission check: 1 infeasible")
    assert pre_run({"mass1": next(oscillator.glob("**/*.fmu"))}, {}) == []


def test_emss_run_prints_the_check_first(system: Path, steep: Path, tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(system), "--stop-time", "0.2", "--out", str(tmp_path / "o"), "--no-post-run",
                 "--set", f"fcs.mission_file={steep}"]) == 0
    err = capsys.readouterr().err
    assert "emss run: warning: mission check: section 3 (WaypointFollowing 'steep descent')" in err
    assert main(["run", str(system), "--stop-time", "0.2", "--out", str(tmp_path / "p"), "--no-post-run",
                 "--no-pre-run", "--set", f"fcs.mission_file={steep}"]) == 0
    assert "mission check" not in capsys.readouterr().err


@pytest.mark.parametrize(("args", "words"), [
    (["{tmp}/none.yaml"], ("cannot read the mission file",)),
    (["{steep}", "--set", "airframe.nothing=1"], ("--set", "airframe.nothing")),
    (["{steep}", "--set", "airframe.fuel0_kg=lots"], ("not a valid Real value",)),
    (["{steep}", "--margin", "-5"], ("--margin -5",)),
])
def test_bad_input_is_one_line(system: Path, steep: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                               args: list[str], words: tuple[str, ...]) -> None:
    argv = [a.format(tmp=tmp_path, steep=steep) for a in args]
    assert main(["mission", "check", *argv, "--system", str(system)]) == 2
    _one_line_error(capsys, "emss mission: error:", *words)
