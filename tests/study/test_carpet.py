"""The mission-fuel carpet (issue 35 point 1): every design of the sweep a case, and its table.

The sweep part checks the variants against the engine's own design calculation (each design, as the engine FMU
sizes it from its ``design_*`` parameters, has the sweep's SFC) and that no design is dropped: an infeasible one is
a row that says so. The table part checks the ratio against changes computed by hand from given fuels.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path, replace
from openemss.study.carpet import MIN_SFC_CHANGE_PCT, carpet_report, carpet_rows
from openemss.study.case import CaseDef, CaseResult
from openemss.study.redesign import BASELINE, REDESIGNED, cycle_redesign, parse_redesign, planned_variants
from openemss.study.spec import load_study


def test_every_design_of_the_sweep_is_a_case_and_none_is_dropped(tmp_path: Path, engine_system: Path) -> None:
    p = tmp_path / "c.yaml"
    # BPR 9 at OPR 3 cannot meet the jet velocity ratio (the cycle study says why): an infeasible design
    p.write_text(f"study: c\nsystem: {engine_system}\nredesign:\n  preset: reference_study\n"
                 "  bpr: [0.5, 2.0, 9.0]\n  opr: [3.0, 9.0, 20.0]\n  carpet: true\n", encoding="utf-8")
    study = load_study(p)
    cfg = parse_redesign(study)
    assert cfg.carpet
    variants, info = cycle_redesign(study, cfg, tmp_path / "out")
    points = info["carpet"]
    assert [(q["BPR"], q["OPR"]) for q in points] == [(b, o) for b in (0.5, 2.0, 9.0) for o in (3.0, 9.0, 20.0)]
    feasible = [q for q in points if q["variant"] is not None]
    infeasible = [q for q in points if q["variant"] is None]
    assert infeasible and all(q["note"] and q["SFC_kg_N_s"] is None for q in infeasible)
    # one variant per feasible design, the lowest-SFC one named 'redesigned', plus the baseline
    names = [v.name for v in variants]
    assert names[:2] == [BASELINE, REDESIGNED] and len(names) == len(feasible) + 1
    assert sorted(q["variant"] for q in feasible) == sorted(names[1:])
    best = min(feasible, key=lambda q: q["SFC_kg_N_s"])
    assert best["variant"] == REDESIGNED
    # each design, as the engine FMU sizes it from its design_* values, has the sweep's SFC and thrust
    ref = load_params(preset_path("reference_study"))
    for v in variants[1:]:
        values = dict(v.values)
        fields = {k.split(".design_")[1]: x for k, x in values.items() if ".design_" in k and "override" not in k}
        dp = design(replace(ref, Fn_target_N=None, **fields))
        q = next(q for q in feasible if q["variant"] == v.name)
        assert dp.SFC_kg_N_s == pytest.approx(q["SFC_kg_N_s"], rel=1e-9)
        assert dp.Fn_N == pytest.approx(ref.Fn_target_N, rel=1e-6)
    # emss study cases lists the same engines without writing anything
    assert [v.name for v in planned_variants(study)] == names


def test_the_carpet_table_says_what_each_design_did_and_the_ratio(tmp_path: Path) -> None:
    base_sfc = 20e-6
    points = [{"BPR": 1.0, "OPR": 9.0, "SFC_kg_N_s": 18e-6, "variant": "a", "note": ""},        # -10 % SFC
              {"BPR": 1.0, "OPR": 20.0, "SFC_kg_N_s": 16e-6, "variant": REDESIGNED, "note": ""},  # -20 % SFC
              {"BPR": 2.0, "OPR": 9.0, "SFC_kg_N_s": base_sfc * (1 + MIN_SFC_CHANGE_PCT / 200), "variant": "c",
               "note": ""},                                                                     # too small a change
              {"BPR": 2.0, "OPR": 20.0, "SFC_kg_N_s": 17e-6, "variant": "d", "note": ""},
              {"BPR": 9.0, "OPR": 9.0, "SFC_kg_N_s": None, "variant": None, "note": "no feasible fan PR"}]

    def done(name: str, fuel: float, completed: bool = True) -> CaseResult:
        return CaseResult(name, "completed", summary={"mission_completed": completed, "fuel_burned_kg": fuel})

    results = {"b-m": done("b-m", 200.0), "a-m": done("a-m", 196.0), "r-m": done("r-m", 190.0),
               "c-m": done("c-m", 201.0), "d-m": done("d-m", 150.0, completed=False)}
    cases = [CaseDef(f"{v}-m", (("variant", v), ("mission", "m")), "sys")
             for v in (BASELINE, "a", REDESIGNED, "c", "d")]
    cases[0] = CaseDef("b-m", (("variant", BASELINE), ("mission", "m")), "sys")
    cases[2] = CaseDef("r-m", (("variant", REDESIGNED), ("mission", "m")), "sys")
    rows = carpet_rows(points, {dict(c.labels)["variant"]: c.name for c in cases}, results, "b-m", base_sfc)
    by = {(r["BPR"], r["OPR"]): r for r in rows}
    assert len(rows) == 5
    # -2 % fuel for -10 % SFC: 0.2 of the promise kept; -5 % for -20 %: 0.25
    assert by[(1.0, 9.0)]["fuel_change_pct"] == pytest.approx(-2.0)
    assert by[(1.0, 9.0)]["fuel_change_per_SFC_change"] == pytest.approx(0.2)
    assert by[(1.0, 20.0)]["fuel_change_per_SFC_change"] == pytest.approx(0.25)
    assert by[(2.0, 9.0)]["fuel_change_per_SFC_change"] is None and by[(2.0, 9.0)]["outcome"] == "flown"
    assert by[(2.0, 20.0)]["fuel_burned_kg"] is None and by[(2.0, 20.0)]["outcome"] == "mission not completed"
    assert by[(9.0, 9.0)]["outcome"] == "infeasible design: no feasible fan PR" and by[(9.0, 9.0)]["case"] == ""

    info = {"baseline": {"BPR": 1.16, "OPR": 11.22, "SFC_kg_N_s": base_sfc}, "carpet": points}
    results["a-m"] = CaseResult("a-m", "failed", "SlaveError: engine went wrong")
    res = carpet_report(tmp_path / "carpet", cases, results, info, "m")
    with open(tmp_path / "carpet" / "mission_carpet.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert len(table) == 5 and table[0]["outcome"] == "failed: SlaveError: engine went wrong"
    assert res["outcomes"] == {"failed": 1, "flown": 2, "mission not completed": 1, "infeasible design": 1}
    assert res["ratio_min"] == pytest.approx(0.25) and math.isclose(res["ratio_max"], 0.25)
    assert (tmp_path / "carpet" / "mission_carpet.png").stat().st_size > 0
