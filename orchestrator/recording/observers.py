"""Observers: recorders (in memory, streamed CSV), the run record (run.json), progress.

Recorders sample the execution's exchange vectors directly (one fancy-indexed
copy per type per sample), so recording costs no extra FMI calls beyond the
batched gets the slaves already make.
"""
from __future__ import annotations

import contextlib
import json
import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from ..results import ResultsError, RunInterrupted, atomic_write, open_stream, os_reason

if TYPE_CHECKING:
    from ..master.execution import Execution

RESERVE_NAME = ".emss-reserve"
RESERVE_BYTES = 256 * 1024  #: disk held back for the last write of run.json [bytes]
CSV_FLOAT_FORMAT = "%.15g"  # 15 significant digits: every double prints back within 1 ulp of 1e-15


@dataclass(frozen=True)
class _Gather:
    """Columns of one exchange vector to copy into a row."""

    columns: np.ndarray
    vector: np.ndarray
    indices: np.ndarray


def _gatherers(execution: Execution) -> list[_Gather]:
    by_vector: dict[tuple[str, str], tuple[list[int], list[int]]] = {}
    for col, sig in enumerate(execution.signals, start=1):
        cols, idx = by_vector.setdefault((sig.variable.type_name, sig.vector), ([], []))
        cols.append(col)
        idx.append(sig.index)
    out = []
    for (t, which), (cols, idx) in by_vector.items():
        vec = getattr(execution.vectors[t], which)
        out.append(_Gather(np.array(cols, dtype=np.intp), vec, np.array(idx, dtype=np.intp)))
    return out


class _RowSampler:
    """Fills rows ``[time, signal...]`` into a preallocated block."""

    def __init__(self, block_rows: int) -> None:
        self.block_rows = block_rows
        self.block = np.empty((0, 0))
        self.rows = 0
        self.gather: list[_Gather] = []
        self.columns: list[str] = []
        self.every = 1

    def attach(self, execution: Execution) -> None:
        self.gather = _gatherers(execution)
        self.columns = ["time_s"] + [s.path for s in execution.signals]
        self.block = np.empty((self.block_rows, len(self.columns)))
        self.rows = 0

    def fill(self, time_s: float) -> None:
        row = self.block[self.rows]
        row[0] = time_s
        for g in self.gather:
            row[g.columns] = g.vector[g.indices]
        self.rows += 1


class EveryNth:
    """The sampling rule of the recorders: every ``every``-th macro step, and the last step of a run
    that stopped between two of them (its final state, which a summary reads)."""

    every: int
    _skipped: float | None = None  # time of the last step when it was not recorded

    def _due(self, k: int, time_s: float) -> bool:
        self._skipped = time_s if k % self.every else None
        return not k % self.every

    def _record_last_step(self, error: BaseException | None) -> None:
        if error is None and self._skipped is not None:
            self.sample(0, self._skipped)  # type: ignore[attr-defined]


class MemoryRecorder(EveryNth):
    """Keeps every sample in memory; ``result()`` gives a dict of numpy arrays by column name.

    Parameters
    ----------
    every : int
        Record every n-th macro step (1 = every step).
    """

    def __init__(self, every: int = 1) -> None:
        self.every = every
        self._sampler = _RowSampler(1024)
        self._blocks: list[np.ndarray] = []

    def start(self, execution: Execution) -> None:
        self._sampler.attach(execution)

    def sample(self, k: int, time_s: float) -> None:
        if not self._due(k, time_s):
            return
        s = self._sampler
        if s.rows == s.block_rows:
            self._blocks.append(s.block.copy())
            s.rows = 0
        s.fill(time_s)

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        s = self._sampler
        self._record_last_step(error)
        if s.rows:
            self._blocks.append(s.block[: s.rows].copy())
            s.rows = 0

    def result(self) -> dict[str, np.ndarray]:
        data = np.vstack(self._blocks) if self._blocks else np.empty((0, len(self._sampler.columns)))
        return {name: data[:, j] for j, name in enumerate(self._sampler.columns)}


class CsvRecorder(EveryNth):
    """Streams samples to a CSV file, flushing at least every ``flush_interval_s`` of wall time.

    Rows are written whole: each flush is one write of complete rows, and a write that fails
    (a full disk) is cut back to the last complete row, so the file always ends with one, and the
    error (:class:`~.results.ResultsError`) names the file, the time and the cause. A run that dies
    leaves a valid file up to its last flush (the execution also flushes on any error it sees).
    The file is created anew (an existing file or link in its place is removed, never followed).
    Columns: ``time_s`` then ``component.variable``; values in the FMUs' units.
    """

    def __init__(self, path: Path, every: int = 1, flush_interval_s: float = 2.0, block_rows: int = 4096) -> None:
        self.path = Path(path)
        self.every = every
        self.flush_interval_s = flush_interval_s
        self._sampler = _RowSampler(block_rows)
        self._file: IO[bytes] | None = None
        self._last_flush = 0.0
        self._fmt = ""
        self._good_bytes = 0  # length of the file up to its last complete row
        self._last_time_s: float | None = None
        self.rows_written = 0

    def start(self, execution: Execution) -> None:
        self._sampler.attach(execution)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = open_stream(self.path)
        self._good_bytes = 0
        self._write((",".join(self._sampler.columns) + "\n").encode("utf-8"), execution.time_s)
        self._fmt = ",".join([CSV_FLOAT_FORMAT] * len(self._sampler.columns)) + "\n"
        self._last_flush = time.perf_counter()

    def _write(self, data: bytes, time_s: float | None) -> None:
        f = self._file
        assert f is not None
        view = memoryview(data)
        try:
            while view:
                n = f.write(view)
                view = view[n:]
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.ftruncate(f.fileno(), self._good_bytes)
            f.close()
            self._file = None
            at = f" at t = {time_s:.6g} s" if time_s is not None else ""
            kept = (f"; rows up to t = {self._last_time_s:.6g} s kept" if self._last_time_s is not None else "")
            raise ResultsError(f"cannot write {self.path}{at}: {os_reason(exc)}{kept}") from None
        self._good_bytes += len(data)

    def sample(self, k: int, time_s: float) -> None:
        if not self._due(k, time_s):
            return
        s = self._sampler
        s.fill(time_s)
        if s.rows == s.block_rows or time.perf_counter() - self._last_flush > self.flush_interval_s:
            self.flush()

    def flush(self) -> None:
        """Write the buffered rows (whole) to the operating system."""
        s = self._sampler
        if self._file is None:
            return
        if s.rows:
            values = s.block[: s.rows]
            last = float(values[-1, 0])
            rows = s.rows
            s.rows = 0
            self._write(((self._fmt * rows) % tuple(values.ravel().tolist())).encode("ascii"), last)
            self.rows_written += rows
            self._last_time_s = last
        self._last_flush = time.perf_counter()

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        if self._file is not None:
            try:
                self._record_last_step(error)
                self.flush()
            finally:
                if self._file is not None:
                    self._file.close()
                    self._file = None


def versions() -> dict[str, str]:
    """Versions of the software a run depends on."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version(), "platform": platform.platform()}
    for pkg in ("openemss", "fmpy", "pythonfmu", "numpy", "lxml"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "not installed"
    return out


class RunRecord:
    """Writes ``run.json``: system, parameters, algorithm, rate, versions, wall time, outcome, step statistics.

    Written once at the start (status ``running``) and again at the end
    (``completed`` or ``failed`` with the error), so a run that dies still says so.
    """

    def __init__(self, path: Path, system_location: str, parameter_files: list[str],
                 extra: dict[str, Any] | None = None, reporters: list[Any] | None = None) -> None:
        self.path = Path(path)
        self.info: dict[str, Any] = {"system": system_location, "parameter_files": parameter_files,
                                     **(extra or {})}
        self.reporters = list(reporters or [])  # objects with report() -> dict, merged in at the end
        self._wall0 = time.perf_counter()

    def _write(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(self.path, json.dumps(self.info, indent=2, default=str) + "\n")

    def _reserve(self, on: bool) -> None:
        """Hold :data:`RESERVE_BYTES` of disk beside run.json while the run goes, freed just before the
        last write, so that a run that fills the disk can still close its run.json as failed."""
        reserve = self.path.parent / RESERVE_NAME
        with contextlib.suppress(OSError, ResultsError):  # no reserve on a nearly full disk: run on without
            if reserve.is_symlink() or reserve.exists():
                reserve.unlink()
            if on:
                with open_stream(reserve) as f:
                    f.write(bytes(RESERVE_BYTES))

    def add_files(self, names: list[str]) -> None:
        """Names (in the results folder) of files this run wrote, listed in run.json so that the next run
        into the folder removes them."""
        files = self.info.setdefault("files", [])
        files.extend(n for n in names if n not in files)

    def rewrite(self) -> None:
        """Write run.json again (after post-run files were added)."""
        self._write()

    def start(self, execution: Execution) -> None:
        ex = execution
        self.info.update({
            "status": "running",
            "algorithm": ex.algorithm.name,
            "rate_hz": ex.rate_hz,
            "step_size_s": ex.step_size_s,
            "start_time_s": ex.start_time_s,
            "step_multiples": {s.name: s.multiple for s in ex.slaves},
            "gauss_seidel_order": [ex.slaves[i].name for i in ex.order.order],
            "components": {c.name: str(c.fmu_path) for c in ex.system.components},
            "parameters": {f"{ex.system.components[p.component].name}.{p.variable.name}": p.value
                           for p in ex.system.parameters},
            "versions": versions(),
        })
        self.add_files([self.path.name])
        self._wall0 = time.perf_counter()
        self._write()
        self._reserve(True)

    def sample(self, k: int, time_s: float) -> None:
        return

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        wall = time.perf_counter() - self._wall0
        sim = execution.time_s - execution.start_time_s
        self._reserve(False)
        self.info.update({
            "status": run_status(error),
            "error": None if error is None else str(error) or type(error).__name__,
            "stopped_by": execution.stopped_by if error is None and execution.stopped_by else None,
            "stop_time_s": execution.time_s,
            "steps": execution.k,
            "wall_time_s": wall,
            "realtime_factor": sim / wall if wall > 0 else None,
            "step_statistics": execution.stats(),
        })
        for r in self.reporters:
            self.info.update(r.report())
        self._write()


class RealTimePacer:
    """Paces a run against the wall clock: ``factor`` simulated seconds per wall second.

    After every macro step it sleeps until the wall clock reaches the step's
    simulated time divided by ``factor``; a step that ends more than
    ``tolerance_s`` late is an overrun. ``report()`` gives the achieved factor,
    the overruns and the largest lag, for run.json.

    Parameters
    ----------
    factor : float
        1.0 is real time, 2.0 twice as fast; must be > 0 (0 means "do not pace": use no pacer).
    tolerance_s : float
        Lateness of a step [s] beyond which it counts as an overrun.
    clock, sleep : callable
        The wall clock [s] and the sleep (default: ``time.perf_counter`` and ``time.sleep``).
    """

    def __init__(self, factor: float, tolerance_s: float = 0.005,
                 clock: Callable[[], float] = time.perf_counter, sleep: Callable[[float], None] = time.sleep) -> None:
        if not factor > 0:
            raise ValueError(f"real-time factor {factor} must be > 0")
        self.factor = factor
        self.tolerance_s = tolerance_s
        self.overruns = 0
        self.max_lag_s = 0.0
        self._wall0 = 0.0
        self._sim0 = 0.0
        self._last_t = 0.0
        self._wall_end = 0.0
        self._clock = clock  # the wall clock [s] and the sleep: a test gives its own, to check without timing
        self._sleep = sleep

    def start(self, execution: Execution) -> None:
        self._sim0 = self._last_t = execution.time_s
        self._wall0 = self._clock()

    def sample(self, k: int, time_s: float) -> None:
        target = self._wall0 + (time_s - self._sim0) / self.factor
        now = self._clock()
        if now < target:
            self._sleep(target - now)
        else:
            lag = now - target
            if lag > self.tolerance_s:
                self.overruns += 1
                self.max_lag_s = max(self.max_lag_s, lag)
        self._last_t = time_s

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        self._wall_end = self._clock()

    def report(self) -> dict[str, Any]:
        wall = (self._wall_end or self._clock()) - self._wall0
        sim = self._last_t - self._sim0
        return {"realtime": {"target_factor": self.factor, "achieved_factor": sim / wall if wall > 0 else None,
                             "overruns": self.overruns, "max_lag_s": self.max_lag_s}}


class Progress:
    """A one-line progress bar on a terminal: simulated time, percent, real-time factor, and a status.

    Quiet when the stream is not a TTY, and for runs shorter than ``delay_s`` of wall time.

    Parameters
    ----------
    stop_time_s : float
        Stop time of the run [s] (100 %).
    status : str | None
        A ``component.variable`` whose current value is shown after the real-time factor
        (any type, String included, e.g. a flight control system's active section name).
        It is read only when the bar is drawn (at most every ``interval_s``), so it costs
        nothing per step; a value that cannot be read shows as ``?``.
    """

    STATUS_WIDTH = 40  # characters of the status shown

    def __init__(self, stop_time_s: float, stream: IO[str] | None = None, delay_s: float = 2.0,
                 interval_s: float = 0.25, status: str | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = bool(getattr(self.stream, "isatty", lambda: False)())
        self.stop_time_s = stop_time_s
        self.delay_s = delay_s
        self.interval_s = interval_s
        self.status = status
        self._read_status: Callable[[], object] | None = None
        self._status_shown = ""
        self._t0_wall = 0.0
        self._next = 0.0
        self._sim0 = 0.0
        self._shown = False

    def start(self, execution: Execution) -> None:
        self._t0_wall = time.perf_counter()
        self._next = self._t0_wall + self.delay_s
        self._sim0 = execution.start_time_s
        self._read_status = (execution.exchange.probe(self.status, "--status") if self.status and self.enabled
                             else None)

    def sample(self, k: int, time_s: float) -> None:
        if not self.enabled or k & 15:
            return
        now = time.perf_counter()
        if now < self._next:
            return
        self._next = now + self.interval_s
        self._draw(time_s, now)

    def _status_text(self) -> str:
        if self._read_status is None:
            return self._status_shown
        try:
            value = self._read_status()
        except Exception:  # a failed or freed FMU: the bar goes on without its status
            value = "?"
        if isinstance(value, bytes):
            value = value.decode("utf-8", "replace")
        text = f"{value:g}" if isinstance(value, float) else str(value)
        w = self.STATUS_WIDTH
        self._status_shown = "  " + (text if len(text) <= w else text[: w - 1] + "~").ljust(w)
        return self._status_shown

    def _draw(self, time_s: float, now: float, ended: str | None = None) -> None:
        span = max(self.stop_time_s - self._sim0, 1e-12)
        frac = 1.0 if ended is not None else min(max((time_s - self._sim0) / span, 0.0), 1.0)
        width = 30
        bar = "#" * int(frac * width) + "-" * (width - int(frac * width))
        rtf = (time_s - self._sim0) / max(now - self._t0_wall, 1e-9)
        self.stream.write(f"\r[{bar}] {frac * 100:5.1f}%  t = {time_s:10.2f} s  {rtf:8.1f}x real time"
                          + (f"  {ended}" if ended is not None else self._status_text()))
        self.stream.flush()
        self._shown = True

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        """The bar drawn whole: the run is over, whatever ended it (its stop time, its stop condition, an
        error or a signal), and how it ended is said instead of the status."""
        if error is not None:  # no FMI call into a failed FMU: the last status read stays
            self._read_status = None
        if self._shown:
            self._draw(execution.time_s, time.perf_counter(), ended=ending(execution, error))
            self.stream.write("\n")
            self.stream.flush()


def run_status(error: BaseException | None) -> str:
    """A run's status as ``run.json`` records it: ``completed``, ``interrupted`` (a signal) or ``failed``."""
    if error is None:
        return "completed"
    return "interrupted" if isinstance(error, (KeyboardInterrupt, RunInterrupted)) else "failed"


def ending(execution: Execution, error: BaseException | None) -> str:
    """How a run ended, as the progress bar's last word: :func:`run_status`, and the stop condition that
    ended it early (``completed (fcs.mission_completed == 1)``)."""
    status = run_status(error)
    return f"{status} ({execution.stopped_by})" if error is None and execution.stopped_by else status

