"""Calibration of the geometric aerodynamics on CFD or wind-tunnel points.

References: (1) synthetic data made by a model with known factors, which the fit must recover,
exactly without noise and within the noise's statistical spread with it; (2) the CFD of the
shipped data file (RANS of the same aircraft, independent of our code), against which the shipped
aircraft file, read and evaluated by JSBSim itself, is held to the goals of the issue (drag within
5 %, lift within 10 %).
"""
from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from openemss.models.airframe.adapter import Airframe
from openemss.models.airframe.aero import aero_model, geometric_model, isa
from openemss.models.airframe.calibrate import fit, jsbsim_coefficients, load_points, model_coefficients
from openemss.models.airframe.corrections import AeroCorrections, load_corrections
from openemss.models.airframe.errors import CalibrationError

DATA = Path(__file__).resolve().parents[2] / "models" / "airframe" / "data" / "upera_cfd.csv"
ALL = ("cla_factor", "alpha0_shift_deg", "cd0_factor", "k_factor")
TRUE = AeroCorrections(cd0_factor=1.12, k_factor=1.25, cla_factor=0.82, alpha0_shift_deg=0.6)


def _synthetic_csv(path: Path, truth: AeroCorrections, noise: float = 0.0, seed: int = 1) -> Path:
    """A wind-tunnel-like polar (three Mach numbers, alpha -1 to 7 deg) from the model with ``truth``,
    forces in N with multiplicative Gaussian noise of relative size ``noise``."""
    m = aero_model(None, truth)
    s = m.geom.wing.area_m2
    rng = np.random.default_rng(seed)
    rows = ["# synthetic polar with known factors", "alt_m,mach,alpha_deg,lift_N,drag_N"]
    for alt, mach in ((1000.0, 0.3), (4000.0, 0.5), (7000.0, 0.7)):
        _, p, rho, a, mu = isa(alt)
        for al in np.linspace(-1.0, 7.0, 9):
            if math.radians(al) > 0.85 * m.alpha_stall(mach):
                continue
            q = 0.7 * p * mach ** 2
            cl = float(m.cl_basic(math.radians(al), mach))
            cd = m.drag_coefficient(math.radians(al), mach, rho * mach * a * m.geom.wing.mac_m / mu)
            if cl <= 0.02:
                continue
            e1, e2 = (1.0 + noise * rng.standard_normal(2)) if noise else (1.0, 1.0)
            rows.append(f"{alt},{mach},{al:.4f},{cl * q * s * e1:.6f},{cd * q * s * e2:.6f}")
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_fit_recovers_known_factors(tmp_path: Path) -> None:
    pts, src = load_points(_synthetic_csv(tmp_path / "polar.csv", TRUE))
    assert "synthetic polar" in src
    cal = fit(pts, ALL, source=src)
    for k, v in TRUE.factors().items():
        assert cal.corrections.factors()[k] == pytest.approx(v, abs=2e-4), k
    assert max(cal.worst()[k] for k in ("cl_after", "cd_after")) < 1e-5


def test_fit_with_noise_stays_within_its_spread(tmp_path: Path) -> None:
    """1 % noise on 20-odd points: each factor within about three standard errors of the truth
    (by hand: a relative error of 1 %/sqrt(n) on a mean, magnified by the spread of CL and alpha)."""
    pts, _ = load_points(_synthetic_csv(tmp_path / "noisy.csv", TRUE, noise=0.01, seed=7))
    f = fit(pts, ALL).corrections.factors()
    assert f["cla_factor"] == pytest.approx(TRUE.cla_factor, rel=0.02)
    assert f["alpha0_shift_deg"] == pytest.approx(TRUE.alpha0_shift_deg, abs=0.15)
    assert f["cd0_factor"] == pytest.approx(TRUE.cd0_factor, rel=0.04)
    assert f["k_factor"] == pytest.approx(TRUE.k_factor, rel=0.08)


def test_shipped_calibration_is_the_fit_of_the_shipped_data() -> None:
    """The shipped factors are what the fit of the shipped CFD file gives (nobody edited them by hand)."""
    pts, src = load_points(DATA, geometric_model())
    cal = fit(pts, ("cla_factor", "alpha0_shift_deg", "cd0_factor"), source=src)
    shipped = load_corrections()
    for k, v in cal.corrections.factors().items():
        assert shipped.factors()[k] == pytest.approx(v, rel=1e-6, abs=1e-9), k
    assert "Engine Mission Simulation System paper" in shipped.source


def test_shipped_aircraft_against_cfd_in_jsbsim() -> None:
    """The aircraft file as JSBSim flies it, at the CFD's altitude, Mach and alpha with controls neutral:
    drag within 5 % and lift within 10 % of the CFD (the issue's goal; the reference flight simulator
    reached 6.7 % and 23.8 % on its points). JSBSim's coefficients also equal the Python model's to the
    tables' interpolation (0.5 %)."""
    pts, _ = load_points(DATA, geometric_model())
    af = Airframe()
    for p in pts:
        cl, cd = jsbsim_coefficients(p, af)
        cl_m, cd_m = model_coefficients(aero_model(), p)
        print(f"point {p.label}: CL {cl:.4f} (CFD {p.cl:.4f}, {cl / p.cl - 1:+.1%}), "
              f"CD {cd:.5f} (CFD {p.cd:.5f}, {cd / p.cd - 1:+.1%})")
        assert cl == pytest.approx(p.cl, rel=0.10)
        assert cd == pytest.approx(p.cd, rel=0.05)
        assert cl == pytest.approx(cl_m, rel=5e-3)
        assert cd == pytest.approx(cd_m, rel=5e-3)


def test_too_few_points_and_undetermined_factors(tmp_path: Path) -> None:
    pts, _ = load_points(_synthetic_csv(tmp_path / "p.csv", TRUE))
    with pytest.raises(CalibrationError, match="cannot determine 2 factors"):
        fit(pts[:1], ALL)
    # two points at one condition cannot separate CD0 from k
    same = (pts[3], replace(pts[3], label="dup"))
    with pytest.raises(CalibrationError, match="do not determine"):
        fit(same, ("cd0_factor", "k_factor"))
    with pytest.raises(CalibrationError, match="unknown"):
        fit(pts, ("cd0_factor", "magic"))


def test_fit_that_hits_a_bound_is_refused(tmp_path: Path) -> None:
    """Drag given in kN but labelled N (a factor 1000 off): no factor within its bounds explains it."""
    text = _synthetic_csv(tmp_path / "p.csv", TRUE).read_text().splitlines()
    rows = [text[0], text[1]] + [",".join([*r.split(",")[:4], f"{float(r.split(',')[4]) * 3:.6f}"]) for r in text[2:]]
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(rows) + "\n")
    with pytest.raises(CalibrationError, match="ends on a bound: cd0_factor"):
        fit(load_points(bad)[0], ALL)


@pytest.mark.parametrize(("text", "match"), [
    ("alt_m,mach,lift_N,drag_N\n1000,0.5,1,1\n", "missing column\\(s\\) alpha_deg"),
    ("alt_m,mach,alpha_deg,lift_N\n1000,0.5,2,1\n", "needs exactly one drag column"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,nan,1,1\n", "line 2: column alpha_deg: 'nan' is not a finite"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,x,1,1\n", "'x' is not a number"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,1.5,2,1,1\n", "mach = 1.5 is outside the model's envelope"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n90000,0.5,2,1,1\n", "alt_m = 90000 is outside"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.6,14.5,20000,1000\n", "beyond the model's linear lift range"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,16,20000,1000\n", "alpha_deg = 16 is outside"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,2,-5,1\n", "must be positive"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,2,1\n", "4 values for 5 columns"),
    ("alt_m,mach,alt_m,alpha_deg,lift_N,drag_N\n", "duplicate column"),
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n", "no data rows"),
    ("alt_m,mach,alpha_deg,lift_a_kN,lift_b_kN,drag_N\n1000,0.5,2,1,1,1\n", "name it with --lift-column"),
    # every problem of the file in one line, with its count
    ("alt_m,mach,alpha_deg,lift_N,drag_N\n1000,0.5,nan,1,1\n1000,1.5,2,1,1\n", "line 3: column mach = 1.5.*2 problems"),
])
def test_bad_data_one_clear_line(tmp_path: Path, text: str, match: str) -> None:
    f = tmp_path / "d.csv"
    f.write_text(text)
    with pytest.raises(CalibrationError, match=match):
        load_points(f)


def test_cli_writes_results_and_refuses_bad_input(tmp_path: Path) -> None:
    out = tmp_path / "cal"
    r = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "airframe", "calibrate", str(DATA),
                        "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "worst |error|" in r.stdout
    for name in ("calibration.json", "UPERA.xml", "residuals.csv", "residuals.png"):
        assert (out / name).stat().st_size > 0
    assert "cla_factor" in (out / "UPERA.xml").read_text()
    for args, match in ((["/nonexistent.csv"], "cannot read"),
                        ([str(DATA), "--factors", "cd0_factor,bogus"], "--factors: unknown bogus"),
                        ([str(DATA), "--factors", ",".join(ALL)], "ends on a bound: k_factor")):
        r = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "airframe", "calibrate", *args,
                            "--out", str(tmp_path / "x")], capture_output=True, text=True, timeout=120)
        assert r.returncode != 0
        assert match in r.stderr
        assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
