"""The hybrid system ssp/hybrid/ through the real FMUs, a short run (the first minute: take-off roll,
lift-off, climb with boost). Checked against independent facts:

* the signed shaft power reaches the engine: the LP port power the engine applies in a step is the
  electrical system's output of the step before (Jacobi), negative (an assist) while it boosts;
* the airframe carries the electrical system's mass: its mass at the start is the operating empty mass
  (1500 kg) + the fuel (600 kg) + the electrical system's mass;
* energy: the battery's counter equals the sum of the recorded V I over the steps, the machines' and the
  bus's balances close (summary.json's residuals), and the summary's battery energy is the counter's.
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.recording.timeseries import read_timeseries

ROOT = Path(__file__).resolve().parents[2]


def test_hybrid_first_minute(tmp_path: Path, project_fmus: dict[str, Path]) -> None:
    copy = tmp_path / "hybrid"
    shutil.copytree(ROOT / "ssp" / "hybrid", copy, ignore=shutil.ignore_patterns("resources", "__pycache__"))
    (copy / "resources").mkdir()
    for path in project_fmus.values():
        shutil.copy2(path, copy / "resources" / path.name)
    out = tmp_path / "run"
    assert main(["run", str(copy), "--stop-time", "60", "--no-pre-run", "--out", str(out)]) == 0
    data = read_timeseries(out).data
    col = lambda n: np.asarray(data[n], dtype=float)  # noqa: E731
    lp_out, lp_applied = col("electric.offtake_lp_W"), col("engine.offtake_lp_applied_W")
    mode = col("electric.ems_mode")
    assert np.array_equal(lp_applied[1:], lp_out[:-1])                  # one step later, bit for bit
    boosting = mode[:-1] == 1
    assert boosting.sum() > 100 and np.all(lp_applied[1:][boosting][20:] < 0.0)   # assist on the LP spool
    assert abs(col("airframe.mass_kg")[0] - (1500.0 + 600.0 + col("electric.added_mass_kg")[0])) < 1e-3  # JSBSim slugs
    t, V, I, E = col("time_s"), col("electric.battery_V"), col("electric.battery_A"), col("electric.E_batt_J")
    assert abs(E[-1] - E[0] - np.sum(V[1:] * I[1:] * np.diff(t))) < 1e-6 * np.sum(np.abs(V * I)) * 0.05
    s = json.loads((out / "summary.json").read_text())["electric"]
    assert s is not None and s["mass_kg"] == col("electric.added_mass_kg")[-1]
    assert abs(s["balance_residual_J"]["machines"]) < 1e-3 and abs(s["balance_residual_J"]["bus"]) < 1e-3
    assert s["energy_kWh"]["battery_kWh"] * 3.6e6 == (E[-1] - E[0])
    assert s["soc"]["end"] < s["soc"]["start"]                         # the boost came from the battery
