"""``emss engine design``: output keys with SI units, presets, one-line errors and exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main


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
    assert main(["engine", "design", "--params", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'BPR': -1.0" in err and "p.json:1:" in err
    assert main(["engine", "design", "--params", str(tmp_path / "missing.json")]) == 2
    assert "does not exist" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["engine", "design", "--preset", "nope"])
    assert exc.value.code == 2


def test_point_json_outputs_of_spec(capsys: pytest.CaptureFixture[str]) -> None:
    """emss engine point: the outputs SPEC.md asks for, SI keys; a design-point round trip."""
    assert main(["engine", "point", "--alt-m", "0", "--mach", "0", "--n1-pct", "100", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("Fn_N", "Fg_N", "ram_drag_N", "Wf_kg_s", "N1_rpm", "N2_rpm", "N1_pct", "N2_pct", "N1c_rpm",
                "Tt4_K", "T41_K", "Tt21_K", "Tt17_K", "Tt7_K", "Pt3_Pa", "OPR", "BPR", "SM_fan", "SM_hpc",
                "SFC_kg_N_s"):
        assert key in out, key
    assert out["Fn_N"] == pytest.approx(13.0e3, rel=0.01) and out["Tt4_K"] == pytest.approx(1403.0, rel=1e-6)


def test_point_turbojet_and_errors(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["engine", "point", "--preset", "pycycle_simple_turbojet", "--fn-n", "45000", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["Fn_N"] == pytest.approx(45000.0, rel=1e-8)
    assert main(["engine", "point", "--fn-n", "1e6"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no convergence" in err and "power_setting=" in err
    with pytest.raises(SystemExit) as exc:
        main(["engine", "point", "--alt-m", "0"])
    assert exc.value.code == 2


def test_point_with_distortion(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["engine", "point", "--n1-pct", "95", "--json"]) == 0
    clean = json.loads(capsys.readouterr().out)
    assert main(["engine", "point", "--n1-pct", "95", "--distortion-fan", "0.25", "0.1", "0", "--json"]) == 0
    dist = json.loads(capsys.readouterr().out)
    assert dist["SM_fan"] < clean["SM_fan"] - 0.05 and dist["distortion_fan"]["dPt_frac"] == 0.1
