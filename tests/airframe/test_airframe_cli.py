"""``emss airframe trim`` and ``emss airframe polar``: keys with SI units, files, one-line errors."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main


def test_trim_json_keys_and_balance(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["airframe", "trim", "--alt-m", "5000", "--mach", "0.6", "--mass-kg", "1800", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("alpha_deg", "elevator", "Fn_N", "lift_N", "drag_N", "CL", "CD"):
        assert key in out
    # level flight: L + T sin(alpha) = W (0.5 %: Earth-rotation terms), D = T cos(alpha)
    a = math.radians(out["alpha_deg"])
    assert out["lift_N"] + out["Fn_N"] * math.sin(a) == pytest.approx(1800 * 9.80665, rel=5e-3)
    assert out["drag_N"] == pytest.approx(out["Fn_N"] * math.cos(a), rel=1e-4)
    assert out["mass_kg"] == 1800


def test_trim_text(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["airframe", "trim", "--alt-m", "0", "--mach", "0.3"]) == 0
    text = capsys.readouterr().out
    for key in ("alpha_deg", "elevator", "Fn_N", "lift_N", "drag_N", "CL", "CD"):
        assert key in text


@pytest.mark.parametrize("argv,expect", [
    (["--alt-m", "3000", "--mach", "1.5"], "Mach = 1.5 is outside the valid range 0.1 to 0.85"),
    (["--alt-m", "20000", "--mach", "0.5"], "altitude = 20000 m is outside the valid range 0 to 8000 m"),
    (["--alt-m", "3000", "--mach", "0.5", "--mass-kg", "900"], "mass = 900 kg is outside the valid range"),
    (["--alt-m", "8000", "--mach", "0.2"], "stall"),
])
def test_bad_input_one_line_nonzero(argv: list[str], expect: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["airframe", "trim", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expect in err and "Traceback" not in err


def test_polar_writes_csv_and_png(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["airframe", "polar", "--out", str(tmp_path)]) == 0
    rows = list(csv.DictReader((tmp_path / "polar.csv").open()))
    assert len(rows) > 30
    assert {"alt_m", "mach", "CL", "CD", "Fn_N"} <= set(rows[0])
    png = (tmp_path / "polar.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    # thrust required at 7500 m has its minimum (the L/D max speed) inside the Mach range, above the stall
    hi = [r for r in rows if float(r["alt_m"]) == 7500.0]
    t = [float(r["Fn_N"]) for r in hi]
    assert 0 < t.index(min(t)) < len(t) - 1
    assert "trimmed conditions" in capsys.readouterr().out
