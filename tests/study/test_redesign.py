"""The reference study's pieces: the cycle sweep's choice of engine, and the two-engine comparison."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path, replace
from openemss.orchestrator.ssp.read import read_ssv
from openemss.study.case import CaseResult
from openemss.study.compare import compare_engines
from openemss.study.redesign import BASELINE, REDESIGNED, cycle_redesign, parse_redesign
from openemss.study.spec import StudyError, load_study


def test_sweep_picks_the_lowest_sfc_engine_at_equal_thrust(tmp_path: Path, engine_system: Path) -> None:
    p = tmp_path / "r.yaml"
    p.write_text(f"study: r\nsystem: {engine_system}\nredesign:\n  preset: reference_study\n"
                 "  bpr: [0.5, 1.16, 2.0]\n  opr: [9.0, 11.22, 20.0]\n", encoding="utf-8")
    study = load_study(p)
    variants, info = cycle_redesign(study, parse_redesign(study), tmp_path / "out")
    # At fixed Tt4 and component efficiencies, SFC falls with bypass ratio and with overall pressure ratio in
    # this range (Walsh & Fletcher, Gas Turbine Performance, 2004, figs. 6.10 and 6.12): the corner wins.
    assert info["redesigned"]["BPR"] == 2.0 and info["redesigned"]["OPR"] == pytest.approx(20.0, rel=1e-9)
    ref = load_params(preset_path("reference_study"))
    assert info["baseline"]["BPR"] == ref.BPR
    # SPEC.md: every design of the sweep meets the reference's thrust through its own design mass flow
    assert info["redesigned"]["Fn_N"] == pytest.approx(ref.Fn_target_N, rel=1e-6)
    assert info["baseline"]["Fn_N"] == pytest.approx(ref.Fn_target_N, rel=1e-6)
    assert info["design_point_SFC_change_pct"] < 0.0
    assert [v.name for v in variants] == [BASELINE, REDESIGNED]
    base, new = dict(variants[0].values), dict(variants[1].values)
    assert base == {"engine.preset": "reference_study"}
    assert new["engine.design_override"] is True and new["engine.design_BPR"] == 2.0
    # the redesigned engine, as the FMU will size it from its design_* parameters, has that SFC
    fields = {k.split(".design_")[1]: v for k, v in new.items() if ".design_" in k and "override" not in k}
    assert design(replace(ref, Fn_target_N=None, **fields)).SFC_kg_N_s == pytest.approx(
        info["redesigned"]["SFC_kg_N_s"], rel=1e-9)
    values, _ = read_ssv(tmp_path / "out" / "cycle" / "redesigned_engine.ssv")
    assert {v.name: v.value for v in values}["engine.design_W2_kg_s"] == pytest.approx(new["engine.design_W2_kg_s"])
    with open(tmp_path / "out" / "cycle" / "carpet.csv", newline="") as f:
        assert len(list(csv.DictReader(f))) == 9
    assert (tmp_path / "out" / "cycle" / "carpet.png").stat().st_size > 0


def test_redesign_block_is_validated(tmp_path: Path, engine_system: Path) -> None:
    p = tmp_path / "r.yaml"
    p.write_text(f"study: r\nsystem: {engine_system}\nredesign:\n  preset: nope\n", encoding="utf-8")
    with pytest.raises(StudyError, match=r"r.yaml:4: field 'redesign.preset': got the text 'nope'; allowed: "):
        parse_redesign(load_study(p))


def _series(path: Path, rate_kg_s: float, t_end_s: float, section_from_s: float) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time_s", "engine.fuel_burned_kg", "engine.Wf_kg_s", "engine.Tt4_K", "fcs.section_index"])
        for k in range(int(t_end_s * 10) + 1):
            t = k / 10
            w.writerow([t, rate_kg_s * t, rate_kg_s, 1200.0, int(t >= section_from_s)])


def test_engines_compared_at_the_last_common_time_unless_both_completed(tmp_path: Path) -> None:
    _series(tmp_path / "cases" / "b" / "timeseries.csv", 0.20, 100.0, 50.0)
    _series(tmp_path / "cases" / "r" / "timeseries.csv", 0.15, 80.0, 40.0)
    results = {"b": CaseResult("b", "completed"), "r": CaseResult("r", "failed")}
    res = compare_engines(tmp_path, {"baseline": "b", "redesigned": "r"}, results,
                          {"design_point_SFC_change_pct": -21.0}, "engine", 1, "fcs.section_index", ["a", "cruise"])
    # burned fuel is linear in time: 16 kg and 12 kg at t = 80 s, the last time both reached
    assert res["common_time_s"] == 80.0
    assert res["engines"]["baseline"]["fuel_at_common_time_kg"] == pytest.approx(16.0)
    assert res["fuel_change_at_common_time_pct"] == pytest.approx(-25.0)
    assert res["mission_fuel_change_pct"] is None and "not completed by both" in res["note"]
    assert res["section"]["name"] == "cruise" and res["section"]["notes"] == []
    for name in ("fuel_burned.png", "section.png", "report.md", "report.json"):
        assert (tmp_path / "report" / name).stat().st_size > 0
    assert json.loads((tmp_path / "report" / "report.json").read_text())["design_point_SFC_change_pct"] == -21.0

    assert res["engines"]["baseline"]["life"] is None and res["life_change_pct"] == {}   # the failed one: no life

    life_b = {"lcf_limiting_disc": "HP disc", "lcf_equivalent_cycles": 1.2, "lcf_damage": 4e-5, "creep_damage": 5e-7,
              "missions_to_life": 25000.0}
    life_r = {**life_b, "lcf_equivalent_cycles": 0.9, "creep_damage": 2e-6, "missions_to_life": 20000.0}
    results = {"b": CaseResult("b", "completed", summary={"mission_completed": True, "fuel_burned_kg": 100.0,
                                                          "life": {"mission": life_b}}),
               "r": CaseResult("r", "completed", summary={"mission_completed": True, "fuel_burned_kg": 90.0,
                                                          "life": {"mission": life_r}})}
    res = compare_engines(tmp_path, {"baseline": "b", "redesigned": "r"}, results, {}, "engine", 7,
                          "fcs.section_index")
    assert res["mission_fuel_change_pct"] == pytest.approx(-10.0)
    assert res["engines"]["redesigned"]["life"] == life_r
    assert res["life_change_pct"]["lcf_equivalent_cycles"] == pytest.approx(-25.0)
    assert res["life_change_pct"]["creep_damage"] == pytest.approx(300.0)
    assert res["life_change_pct"]["missions_to_life"] == pytest.approx(-20.0)
    md = (tmp_path / "report" / "report.md").read_text()
    assert "| HP disc | 0.9 | 2e-06 | 2e+04 |" in md and "creep damage change: +300.00 %" in md
    assert math.isclose(res["fuel_change_at_common_time_pct"], -25.0)
    assert len(res["section"]["notes"]) == 2  # section 7 never reached: the whole runs are shown
