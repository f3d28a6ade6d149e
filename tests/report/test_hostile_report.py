"""The hostile corpus, reports: ``emss summary`` on a torn or damaged timeseries (issue 15).

A run killed while writing may leave a last row cut short: the summary leaves it out and says
so (in its text and in summary.json); a row cut short before the last means the file is damaged,
and that is one line naming the file and the line. The synthetic run's rows are counted here.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from synthetic_runs import N, Runs

from openemss.orchestrator.cli.main import main


def test_summary_of_a_torn_last_row_says_so(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = Runs(tmp_path).make()
    csv = folder / "timeseries.csv"
    text = csv.read_text()
    csv.write_text(text.rstrip("\n").rsplit(",", 5)[0])  # the last row cut in the middle of a value list
    assert main(["summary", str(folder)]) == 0
    out = capsys.readouterr().out
    assert f"note: {csv}: the last row (line {N + 1}) is torn" in out and "it is left out" in out
    summary = json.loads((folder / "summary.json").read_text())
    assert "torn" in summary["timeseries_note"]
    assert summary["sim_time_s"] == pytest.approx((N - 2) * 0.05)  # the last complete row


def test_summary_of_a_whole_file_has_no_note(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = Runs(tmp_path).make()
    assert main(["summary", str(folder), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["timeseries_note"] is None


def test_summary_of_a_damaged_row_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = Runs(tmp_path).make()
    csv = folder / "timeseries.csv"
    lines = csv.read_text().splitlines(keepends=True)
    lines[10] = lines[10].split(",", 1)[0] + "\n"  # line 11: one value only
    csv.write_text("".join(lines))
    assert main(["summary", str(folder)]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and f"{csv}:11: 1 values for" in err[0] and "damaged" in err[0], err
