"""``emss engine design``: output keys with SI units, presets, one-line errors and exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from openemss.orchestrator.cli import main


def test_design_json_has_si_keys_and_every_station(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["engine", "design", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("Fn_N", "Fg_N", "ram_drag_N", "W2_kg_s", "Wf_kg_s", "SFC_kg_N_s", "Tt4_K", "OPR", "BPR",
                "A8_m2", "A18_m2"):
        assert key in out
    assert out["Fn_N"] == pytest.approx(13.0e3, rel=0.01)
    for st in ("2", "13", "21", "25", "3", "4", "41", "45", "5", "7", "17"):
        assert set(out["stations"][st]) == {"W_kg_s", "Tt_K", "Pt_Pa", "FAR"}


def test_design_text_and_presets(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["engine", "design", "--preset", "pycycle_simple_turbojet"]) == 0
    text = capsys.readouterr().out
    assert "SFC" in text and "burner exit" in text


def test_bad_input_is_one_line_nonzero(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "p.json"
    f.write_text(json.dumps({"engine": "turbofan", "W2_kg_s": 20.0, "BPR": -1.0}))
    assert main(["engine", "design", "--params", str(f)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "BPR=-1.0" in err and "p.json" in err
    assert main(["engine", "design", "--params", str(tmp_path / "missing.json")]) == 1
    assert "does not exist" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["engine", "design", "--preset", "nope"])
    assert exc.value.code == 2
