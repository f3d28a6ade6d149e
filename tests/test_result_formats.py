"""Time series formats are one registry (orchestrator/recording/timeseries.py: FORMATS, register_format) that
``emss run --format``, its help, the results folder's checks and the readers all take them from (issue 37.3).

A format registered by a test (tab-separated text under the name ``tsv``, written by a recorder of its own) is
offered by ``emss run --format`` and its help, written by a run, found and read back by ``read_timeseries``
with the values the Parquet run of the same system recorded (the same steps of the same FMUs: equal to the
17 significant digits the text keeps), refused when a file of the user's stands at its name, and cleared by
the next run into the folder like any format of ours.
"""
from __future__ import annotations

import io
import shutil
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.cli.main import build_parser, main
from openemss.orchestrator.recording.timeseries import (
    FORMATS,
    Column,
    ParquetRecorder,
    ResultFormat,
    TimeSeries,
    find_timeseries,
    read_timeseries,
    register_format,
)
from openemss.orchestrator.results import atomic_write


class TsvRecorder(ParquetRecorder):
    """Records as Parquet parts beside the file, writes the tab-separated text at the end."""

    def __init__(self, path: Path, every: int = 1) -> None:
        self.tsv_path = Path(path)
        super().__init__(self.tsv_path.parent / ".tsv-parts", every)

    def finish(self, execution: object, error: BaseException | None) -> None:
        super().finish(execution, error)  # type: ignore[arg-type]
        ts = read_timeseries(self.path)
        buf = io.StringIO()
        np.savetxt(buf, np.column_stack([ts.data[n].astype(float) for n in ts.names]), delimiter="\t", fmt="%.17g",
                   header="\t".join(ts.names), comments="")
        atomic_write(self.tsv_path, buf.getvalue())  # through the results folder, as every recorder writes
        shutil.rmtree(self.path)


def _read_tsv(path: Path) -> TimeSeries:
    lines = path.read_text().splitlines()
    names = lines[0].split("\t")
    rows = np.loadtxt(lines[1:], delimiter="\t", ndmin=2)
    return TimeSeries([Column(n, "Real") for n in names], {n: rows[:, j] for j, n in enumerate(names)}, path)


TSV = ResultFormat("tsv", "timeseries.tsv", "timeseries.tsv, tab-separated text", TsvRecorder, _read_tsv,
                   lambda path: path.read_text().splitlines()[0].split("\t"))


@pytest.fixture()
def tsv() -> Iterator[ResultFormat]:
    register_format(TSV)
    try:
        yield TSV
    finally:
        del FORMATS["tsv"]


def test_registering_twice_is_refused(tsv: ResultFormat) -> None:
    with pytest.raises(ValueError, match="taken by tsv"):
        register_format(ResultFormat("tsv", "other.dat", "", TsvRecorder, _read_tsv, _read_tsv))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="taken by csv"):
        register_format(ResultFormat("csv2", "series.csv", "", TsvRecorder, _read_tsv, _read_tsv))  # type: ignore[arg-type]
    assert list(FORMATS) == ["parquet", "csv", "mat", "tsv"]


def test_a_registered_format_is_offered_written_read_and_cleared(tsv: ResultFormat, oscillator: Path,
                                                                 tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    run = next(a for a in build_parser()._subparsers._group_actions[0].choices["run"]._actions  # type: ignore[union-attr]
               if "--format" in a.option_strings)
    assert "tsv" in run.choices and "timeseries.tsv, tab-separated text" in (run.help or "")

    ref, out = tmp_path / "parquet", tmp_path / "tsv"
    assert main(["run", str(oscillator), "--stop-time", "2", "--out", str(ref)]) == 0
    assert main(["run", str(oscillator), "--stop-time", "2", "--out", str(out), "--format", "tsv"]) == 0
    assert find_timeseries(out) == out / "timeseries.tsv" and not (out / ".tsv-parts").exists()
    a, b = read_timeseries(ref), read_timeseries(out)
    assert b.names == a.names and len(b) == len(a) == 41
    for n in a.names:
        np.testing.assert_array_equal(b.data[n], a.data[n].astype(float), err_msg=n)

    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(out)]) == 0  # ours: cleared
    assert not (out / "timeseries.tsv").exists() and find_timeseries(out) == out / "timeseries.parquet"

    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "timeseries.tsv").write_text("the user's\n")
    capsys.readouterr()
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(mine)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "timeseries.tsv" in err[0] and "not written by a run of openEMSS" in err[0], err
    assert (mine / "timeseries.tsv").read_text() == "the user's\n"
