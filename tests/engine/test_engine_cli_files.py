"""``emss engine design | point | sweep`` on engine files (issue 31 point 7): the same commands as on parameter files,
with each map's operating point; bad input one line and a non-zero exit.

Independent checks: at the design point each map sits on the point its file declares (pyCycle's AXI5 defaults:
relative speed 1.0, R-line 2.0; LPT2269: PR 6.0); a point at the design's speed and flight condition is the design
point again; a power setting is met; a sweep of the design thrust at a constant cycle scales the mass flow and fuel
flow with the thrust and keeps the SFC (similarity: every extensive quantity is proportional to the mass flow).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main

HP_W = 745.69987158227


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_design_of_an_engine_file_with_its_maps(capsys: pytest.CaptureFixture[str]) -> None:
    d = _json(capsys, ["engine", "design", "pycycle_turboshaft", "--json"])
    assert d["name"] == "pyCycle single_spool_turboshaft" and d["OPR"] == pytest.approx(13.5, rel=1e-12)
    assert d["shafts"]["lp"]["net_W"] == pytest.approx(4000.0 * HP_W, rel=1e-9)
    assert set(d["stations"]) == {"2", "3", "4", "45", "5"}
    assert d["maps"]["comp"]["Nc_map_rel"] == pytest.approx(1.0, abs=1e-12)
    assert d["maps"]["comp"]["Rline"] == pytest.approx(2.0, abs=1e-9)
    assert d["maps"]["comp"]["surge_margin"] > 0.0
    for t in ("turb", "pt"):
        assert d["maps"][t]["PR_map"] == pytest.approx(6.0, abs=1e-9)
    assert main(["engine", "design", "pycycle_turboshaft"]) == 0
    text = capsys.readouterr().out
    assert "R-line/PRmap" in text and "design point" in text


def test_point_round_trip_and_power_setting(capsys: pytest.CaptureFixture[str]) -> None:
    d = _json(capsys, ["engine", "design", "pycycle_ab_turbojet", "--json"])
    p = _json(capsys, ["engine", "point", "pycycle_ab_turbojet", "--alt-m", "0", "--mach", "1e-6", "--N1-pct", "100",
                       "--json"])
    assert p["Fn_N"] == pytest.approx(d["Fn_N"], rel=1e-7)
    assert p["stations"]["4"]["Tt_K"] == pytest.approx(d["stations"]["4"]["Tt_K"], rel=1e-7)
    wet = _json(capsys, ["engine", "point", "pycycle_ab_turbojet", "--mach", "0.8", "--Tt4-K", "1316.67",
                         "--far", "ab=0.02", "--json"])
    assert wet["elements"]["ab"]["Wf_kg_s"] == pytest.approx(
        0.02 * wet["stations"]["5"]["W_kg_s"] / (1 + wet["stations"]["5"]["FAR"]), rel=1e-12)
    s = _json(capsys, ["engine", "point", "pycycle_turboshaft", "--mach", "0.1", "--power-W", "2.5e6", "--shaft",
                       "lp", "--json"])
    assert s["shafts"]["lp"]["net_W"] == pytest.approx(2.5e6, rel=1e-7)
    assert s["shafts"]["lp"]["N_rpm"] == 5000.0


def test_sweep_of_design_thrust_is_similar(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "s"
    r = _json(capsys, ["engine", "sweep", "pycycle_ab_turbojet", "--vary", "design.Fn_N", "40000", "80000",
                       "--out", str(out), "--json"])
    a, b = r["rows"]
    assert a["Fn_N"] == pytest.approx(40000.0, rel=1e-9) and b["Fn_N"] == pytest.approx(80000.0, rel=1e-9)
    assert b["W_kg_s"] / a["W_kg_s"] == pytest.approx(2.0, rel=1e-7)
    assert b["SFC_kg_N_s"] == pytest.approx(a["SFC_kg_N_s"], rel=1e-7)
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert [float(x["design.Fn_N"]) for x in rows] == [40000.0, 80000.0] and (out / "sweep.png").stat().st_size > 0
    assert main(["engine", "sweep", "pycycle_ab_turbojet", "--vary", "comp.PR", "12", "--out", str(out)]) == 2
    assert "already holds sweep.csv" in capsys.readouterr().err


@pytest.mark.parametrize("argv, words", [
    (["engine", "point", "pycycle_turboshaft", "--power-W", "1e6", "--shaft", "nope"], "no shaft 'nope'"),
    (["engine", "point", "pycycle_turboshaft", "--N1-pct", "90", "--far", "burner=0.01"], "other than the main"),
    (["engine", "point", "pycycle_ab_turbojet", "--N1-pct", "90", "--far", "ab=x"], "is not a number"),
    (["engine", "point", "--preset", "larzac04_sls", "--power-W", "1e6"], "only for an engine file"),
    (["engine", "design", "nope.txt"], "not an engine file"),
    (["engine", "design", "larzac04", "--preset", "larzac04_sls"], "not both"),
    (["engine", "design", "missing_dir/e.yaml"], "does not exist"),
    (["engine", "sweep", "larzac04", "--vary", "hpc.nope", "1"], "has no attribute 'nope'"),
    (["engine", "sweep", "larzac04", "--vary", "hpc.PR", "0.5"], "outside the allowed range"),
    (["engine", "sweep", "larzac04", "--vary", "hpc.map", "1"], "only numbers can be varied"),
    (["engine", "sweep", "larzac04"], "at least one value"),
])
def test_bad_input_is_one_line(argv: list[str], words: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2  # bad input (exit codes: README)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and "Traceback" not in err
