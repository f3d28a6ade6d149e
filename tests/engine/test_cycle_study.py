"""Parametric cycle study (SPEC.md): its constraints hold at every point, and the carpet's trends.

Each design must meet the reference thrust and Tt4 and the reference core/bypass jet
velocity ratio (the constraints of the study); SFC must fall with OPR and with BPR in
this range (Tt4 1403 K, OPR 9-20, BPR 0.5-2: below the optimum OPR and at a jet
velocity ratio held fixed, the classical result, e.g. Walsh & Fletcher fig. 6.9).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from openemss.models.engine.cycle_design import design
from openemss.models.engine.cycle_study import cycle_study, jet_velocity_ratio, plot_carpet, write_csv
from openemss.models.engine.design_params import load_params, preset_path
from openemss.orchestrator.cli.main import main


def test_carpet_meets_its_constraints_and_trends(tmp_path: Path) -> None:
    ref = load_params(preset_path("reference_study"))
    target = jet_velocity_ratio(design(ref))
    BPRs, OPRs = [0.5, 1.0, 2.0], [9.0, 14.0, 20.0]
    pts = cycle_study(ref, BPRs, OPRs)
    assert len(pts) == 9 and all(p.note == "" for p in pts)
    for p in pts:
        assert p.Fn_N == pytest.approx(13.0e3, rel=1e-9)
        assert p.V8_V18 == pytest.approx(target, rel=1e-8)
        assert p.PR_fan_inner * p.PR_hpc * 0.99 == pytest.approx(p.OPR, rel=1e-12)
    sfc = {(p.BPR, p.OPR): p.SFC_kg_N_s for p in pts}
    for b in BPRs:
        assert sfc[(b, 9.0)] > sfc[(b, 14.0)] > sfc[(b, 20.0)]
    for o in OPRs:
        assert sfc[(0.5, o)] > sfc[(1.0, o)] > sfc[(2.0, o)]
    f = write_csv(pts, tmp_path / "c.csv")
    rows = list(csv.DictReader(f.open()))
    assert len(rows) == 9 and float(rows[0]["SFC_kg_N_s"]) == pytest.approx(pts[0].SFC_kg_N_s)
    png = plot_carpet(pts, tmp_path / "c.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_infeasible_points_are_marked_not_fatal() -> None:
    ref = load_params(preset_path("reference_study"))
    (p,) = cycle_study(ref, [30.0], [9.0])            # no fan can give the jet velocity ratio here
    assert math.isnan(p.SFC_kg_N_s) and p.note


def test_sweep_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["engine", "sweep", "--out", str(tmp_path), "--bpr", "1", "--opr", "10", "12", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["points"]) == 2 and (tmp_path / "carpet.csv").is_file() and (tmp_path / "carpet.png").is_file()
    (tmp_path / "a_file").write_text("")
    assert main(["engine", "sweep", "--out", str(tmp_path / "a_file"), "--bpr", "1", "--opr", "10"]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
