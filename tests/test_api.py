"""The Python API (issue 17): ``openemss.run`` returns the time series (NumPy, pandas), the summary and the run
record; ``emss run`` and a study's case run through it; the notebook example runs.

Checked against what does not come from the API: the files on disk read with pyarrow itself, the start value
the parameter set gives, the time grid t = k h, the units of the FMUs' model descriptions.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import openemss
from openemss.orchestrator.cli import api
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError

ROOT = Path(__file__).resolve().parents[1]


def test_run_returns_tables_summary_and_record(oscillator: Path, tmp_path: Path) -> None:
    import pyarrow.dataset as ds

    r = openemss.run(oscillator, stop_time=2.0, set={"mass1.x1_start_m": 0.3}, out=tmp_path / "r", rate=20.0)
    assert r.status == "completed" and r.exit_code == 0 and r.rows == 41 and r.error is None
    assert r.info["status"] == "completed" and r.info["parameters"]["mass1.x1_start_m"] == 0.3
    np.testing.assert_allclose(r["time_s"], np.arange(41) * 0.05, rtol=0, atol=1e-12)
    assert r["mass1.x1_m"][0] == 0.3  # the value set, at the start
    on_disk = ds.dataset(tmp_path / "r" / "timeseries.parquet").to_table().to_pandas()
    df = r.df
    assert list(df.index) == list(on_disk["time_s"])
    assert (df["mass2.f_c_N"].to_numpy() == on_disk["mass2.f_c_N"].to_numpy()).all()
    assert df.attrs["units"]["mass1.x1_m"] == "m" and r.units["mass2.f_c_N"] == "N"
    assert r.summary is None  # no mission: no summary.json
    with pytest.raises(KeyError, match="did you mean"):
        r["mass1.x1_n"]


def test_bad_input_is_one_clear_error_before_the_run(oscillator: Path, tmp_path: Path) -> None:
    with pytest.raises(ConfigurationError, match="did you mean mass1.x1_start_m"):
        openemss.run(oscillator, stop_time=1.0, set={"mass1.x1_strat_m": 0.3}, out=tmp_path / "a")
    with pytest.raises(ConfigurationError, match="--format"):
        openemss.run(oscillator, stop_time=1.0, format="xlsx", out=tmp_path / "b")


def test_emss_run_and_the_study_child_go_through_the_api(oscillator: Path, tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[dict[str, object]] = []
    real = api.run

    def spy(*args: object, **kwargs: object) -> api.RunResult:
        calls.append(kwargs)
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(api, "run", spy)
    assert main(["run", str(oscillator), "--stop-time", "0.5", "--out", str(tmp_path / "cli")]) == 0
    from openemss.study import child

    monkeypatch.setattr(sys, "argv", ["child", "run", str(oscillator), "--stop-time", "0.5", "--format", "csv",
                                      "--out", str(tmp_path / "child")])
    assert child.main() == 0
    assert [c["format"] for c in calls] == ["parquet", "csv"]
    assert len(openemss.read_timeseries(tmp_path / "child")) == len(openemss.read_timeseries(tmp_path / "cli")) == 11


def test_the_notebook_example_runs(tmp_path: Path) -> None:
    """examples/notebook_api.py as a script: two runs of the Munich mission's first 240 s, a table, a figure."""
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "notebook_api.py"), str(tmp_path / "nb")],
                          capture_output=True, text=True, cwd=tmp_path, timeout=900, check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "larzac04: completed" in proc.stdout and "reference_study: completed" in proc.stdout
    assert (tmp_path / "nb" / "thrust_compare.png").is_file()
    summary = json.loads((tmp_path / "nb" / "larzac04" / "summary.json").read_text())
    assert summary["sim_time_s"] == pytest.approx(240.0)
    assert not (tmp_path / "results").exists()  # nothing written outside the folder it was given
