"""Observers: the CSV recorder flushes while the run goes on; the progress bar only on a terminal."""
from __future__ import annotations

import io
from pathlib import Path

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import CsvRecorder, MemoryRecorder, Progress
from openemss.orchestrator.recording.timeseries import ParquetRecorder, read_timeseries
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system


class FileWatcher:
    """Reads the CSV file while the run is still going."""

    def __init__(self, path: Path, at_step: int) -> None:
        self.path, self.at_step, self.lines_seen = path, at_step, -1

    def start(self, execution: Execution) -> None:
        return

    def sample(self, k: int, time_s: float) -> None:
        if k == self.at_step:
            self.lines_seen = len(self.path.read_text().splitlines())

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        return


def test_csv_rows_reach_the_disk_during_the_run(oscillator: Path, tmp_path: Path) -> None:
    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    csv_path = tmp_path / "timeseries.csv"
    ex.add_observer(CsvRecorder(csv_path, flush_interval_s=0.0))  # flush at every sample
    watcher = FileWatcher(csv_path, at_step=50)
    ex.add_observer(watcher)
    ex.run(5.0)
    assert watcher.lines_seen == 1 + 51  # header and rows 0..50 were on disk at step 50
    assert len(csv_path.read_text().splitlines()) == 1 + 101


def test_csv_and_memory_recorders_agree(oscillator: Path, tmp_path: Path) -> None:
    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    mem = MemoryRecorder(every=2)
    csv = CsvRecorder(tmp_path / "t.csv", every=2)
    ex.add_observer(mem)
    ex.add_observer(csv)
    ex.run(2.0)
    import numpy as np

    data = np.genfromtxt(tmp_path / "t.csv", delimiter=",", names=True)
    ref = mem.result()
    assert len(data) == 21
    assert np.allclose(data["mass2f_c_N"], ref["mass2.f_c_N"], rtol=1e-14, atol=1e-14)


def test_the_last_step_is_recorded_when_the_run_stops_between_two_samples(oscillator: Path, tmp_path: Path) -> None:
    """Every 3rd of 41 samples (0..40) and the last one: the final state is never lost (a summary reads it)."""
    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    mem, csv = MemoryRecorder(every=3), CsvRecorder(tmp_path / "t.csv", every=3)
    parquet = ParquetRecorder(tmp_path / "t.parquet", every=3)
    for recorder in (mem, csv, parquet):
        ex.add_observer(recorder)
    ex.run(2.0)
    import numpy as np

    data = np.genfromtxt(tmp_path / "t.csv", delimiter=",", names=True)
    times = [0.05 * k for k in range(0, 41, 3)] + [2.0]
    assert np.allclose(data["time_s"], times, rtol=0, atol=1e-12)
    assert np.allclose(mem.result()["time_s"], times, rtol=0, atol=1e-12)
    assert np.allclose(read_timeseries(tmp_path / "t.parquet").data["time_s"], times, rtol=0, atol=1e-12)


class Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_draws_on_a_terminal_and_stays_quiet_otherwise(oscillator: Path) -> None:
    for stream, expect in ((Tty(), True), (io.StringIO(), False)):
        ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
        ex.add_observer(Progress(10.0, stream=stream, delay_s=0.0, interval_s=0.0))
        ex.run(10.0)
        text = stream.getvalue()
        assert ("real time" in text and "100.0%" in text) is expect, text


def test_progress_ends_at_100_percent_whatever_ended_the_run(oscillator: Path) -> None:
    """The bar counts against the stop time, but a run ended by its stop condition at a third of it (as a
    mission run ends when the mission is completed) ends at 100 %, saying so; a failed run too."""
    stream = Tty()
    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    ex.add_observer(Progress(30.0, stream=stream, delay_s=0.0, interval_s=0.0))
    ex.stop_when("mass1.x1_m > -1e300")  # holds after the first step
    ex.run(30.0)
    *drawn, last = stream.getvalue().split("\r")
    assert ex.time_s < 1.0 and not any("100.0%" in d for d in drawn)
    assert "[" + "#" * 30 + "] 100.0%" in last and "completed (mass1.x1_m > " in last, last
    stream = Tty()
    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    bar = Progress(30.0, stream=stream, delay_s=0.0, interval_s=0.0)
    ex.add_observer(bar)
    bar._shown = True  # as after a first draw
    bar.finish(ex, RuntimeError("an FMU failed"))
    assert "100.0%" in stream.getvalue() and stream.getvalue().rstrip().endswith("failed")
