"""Time series of a run on disk: Parquet (the default), CSV with a units row, MATLAB .mat; and reading them back.

Recorders (observers of :class:`~.execution.Execution`) sample the exchange vectors into typed
blocks (float64 for Real, int32 for Integer, bool for Boolean) and write them in one of the formats
of :data:`FORMATS`, the one registry that ``emss run --format``, its help, the results folder's checks and
the readers take them from (a new format is one :func:`register_format`):

* ``parquet``: ``timeseries.parquet/``, a Parquet dataset folder (as Spark, Dask and pyarrow write
  one: read it with ``pandas.read_parquet``, ``pyarrow.dataset``, DuckDB, Polars). Every flush (at
  least every 2 s of wall time, or every :data:`PART_ROWS` rows) writes one complete part file
  (``part-00000.parquet``, ...; written to a hidden name, then renamed), so a run that is killed
  keeps every row up to its last flush, readable by any Parquet reader. Why parts and not one file:
  a Parquet file is readable only once its footer is written at the very end, so a single file
  streamed during the run would be lost whole by a ``kill -9``. Compression zstd on byte-stream-split
  floats (smooth signals compress 3 to 10 times).
* ``csv``: ``timeseries.csv``, a header of names, then a row of units, then the rows (see
  :class:`~.observers.CsvRecorder`: whole rows, cut back on a failed write).
* ``mat``: ``timeseries.mat`` (MATLAB v5, scipy.io) for users coming from Simulink: ``data`` (rows x
  columns, double), ``names``, ``units``, ``descriptions`` (cell arrays). A .mat file cannot be
  appended to, so the run streams Parquet parts into a hidden folder and converts them at its end
  (also at a failed or interrupted end); a killed run leaves the parts, which :func:`read_timeseries`
  reads.

Units and descriptions come from the FMUs' model descriptions: the variable's ``unit`` attribute
(its declared type's), else the SSD connector's unit, else the ``[unit]`` that ends the description
(FMUs built with pythonfmu have no unit attribute; the house rule puts it in the description).
"""
from __future__ import annotations

import contextlib
import os
import re
import shutil
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConfigurationError, EmssError
from ..results import ResultsError, os_reason, record_written
from .observers import CsvRecorder, EveryNth
from .timeseries_files import (
    PART_GLOB,
    TIME_COLUMN,
    Column,
    TimeSeries,
    TimeSeriesError,
    csv_columns,
    mat_columns,
    parquet_columns,
    read_csv,
    read_mat,
    read_parquet,
    write_mat,
)

if TYPE_CHECKING:

    from ..master.execution import Execution
    from ..ssp.system import BoundSystem

DEFAULT_FORMAT = "parquet"
MAT_STAGING = ".timeseries.mat.parts"
PART_ROWS = 16384  #: rows of one Parquet part at most (one row group each)
ZSTD_LEVEL = 3
_UNIT_IN_TEXT = re.compile(r"\[([^\[\]]+)\]\s*$")
_NUMPY = {"Real": np.float64, "Integer": np.int32, "Boolean": np.bool_}


def unit_from_description(text: str | None) -> str:
    """The unit written in brackets at the end of a description (``"Net thrust [N]"`` -> ``N``), else ''."""
    m = _UNIT_IN_TEXT.search(text or "")
    return m.group(1).strip() if m else ""


def columns_of(execution: Execution) -> list[Column]:
    """The columns a recorder of ``execution`` writes: time, then every signal, with unit and description."""
    out = [TIME_COLUMN]
    comps = {c.name: c for c in execution.system.components}
    for s in execution.signals:
        v = s.variable
        comp = comps.get(s.component)
        unit = v.unit or (comp.connector_unit(v.name) if comp is not None else None) or \
            unit_from_description(v.description)
        out.append(Column(s.path, v.type_name, unit or "", v.description or "", v.causality))
    return out


#: What :func:`default_record` records, as ``emss run --help`` says it (written once, beside the code).
DEFAULT_RECORD_TEXT = (f"every connector of the SSD of type {', '.join(_NUMPY)} (Strings are not recorded), less "
                       "the inputs that only copy a connected output (--record-inputs keeps them); the inputs a "
                       "scenario sets are added")


def default_record(bound: BoundSystem, inputs: bool = False) -> list[str]:
    """What a run records by default: every connector of the SSD, less the inputs that only copy an output
    (connected, with no transformation, unit conversion or mapping) unless ``inputs`` (:data:`DEFAULT_RECORD_TEXT`).

    An input that is not connected (it keeps its start value, or a scenario sets it) is recorded, and so is
    one whose connection converts its value (its unit or a transformation).
    """
    copies: set[tuple[int, str]] = set()
    for ln in bound.links:
        if ln.mapping is None and ln.affine.scale == 1.0 and ln.affine.offset == 0.0:
            copies.add((ln.target, ln.target_var.name))
    out = []
    for i, c in enumerate(bound.components):
        for k in c.definition.connectors:
            v = c.variables.get(k.name)
            if v is None or v.type_name not in _NUMPY:
                continue
            if not inputs and (i, k.name) in copies:
                continue
            out.append(f"{c.name}.{k.name}")
    return out


# -- sampling -----------------------------------------------------------------------------------
@dataclass
class _TypedSampler:
    """Fills rows into one preallocated block per type.

    A row is a copy of each whole exchange vector that holds a recorded signal (a slice assignment, the
    cheapest copy NumPy has: no index array per row); the recorded columns are picked out of the block
    once per flush, vectorized over its rows.
    """

    block_rows: int
    columns: list[Column] = field(default_factory=list)
    rows: int = 0
    time: np.ndarray = field(default_factory=lambda: np.empty(0))
    blocks: dict[str, np.ndarray] = field(default_factory=dict)
    copies: list[tuple[np.ndarray, int, int, np.ndarray]] = field(default_factory=list)  # block, a, b, vector
    order: list[tuple[str, int]] = field(default_factory=list)  # per signal column: (type, column in block)

    def attach(self, execution: Execution) -> None:
        self.columns = columns_of(execution)
        offset: dict[tuple[str, str], int] = {}
        width: dict[str, int] = {}
        for s in execution.signals:
            key = (s.variable.type_name, s.vector)
            if key not in offset:
                offset[key] = width.get(key[0], 0)
                width[key[0]] = offset[key] + len(getattr(execution.vectors[key[0]], key[1]))
        self.blocks = {t: np.ones((self.block_rows, n), dtype=execution.vectors[t].outputs.dtype)
                       for t, n in width.items()}  # ones, not empty: memory touched now, not in the first rows
        self.copies = [(self.blocks[t], a, a + len(getattr(execution.vectors[t], which)),
                        getattr(execution.vectors[t], which)) for (t, which), a in offset.items()]
        self.order = [(s.variable.type_name, offset[(s.variable.type_name, s.vector)] + s.index)
                      for s in execution.signals]
        self.time = np.empty(self.block_rows)
        self.rows = 0

    def fill(self, time_s: float) -> None:
        r = self.rows
        self.time[r] = time_s
        for block, a, b, vector in self.copies:
            block[r, a:b] = vector
        self.rows = r + 1

    def arrays(self) -> list[np.ndarray]:
        """The buffered rows as one contiguous array per column (file order), typed; empties the buffer."""
        n = self.rows
        out = [self.time[:n].copy()]
        for (t, j), c in zip(self.order, self.columns[1:], strict=True):
            out.append(np.ascontiguousarray(self.blocks[t][:n, j], dtype=_NUMPY[c.type_name]))
        self.rows = 0
        return out


def arrow_schema(columns: Sequence[Column]) -> Any:
    """The Arrow schema of a time series: typed fields with ``unit``, ``description``, ``causality`` metadata."""
    import pyarrow as pa

    types = {"Real": pa.float64(), "Integer": pa.int32(), "Boolean": pa.bool_()}
    return pa.schema([pa.field(c.name, types[c.type_name], nullable=False,
                               metadata={"unit": c.unit, "description": c.description, "causality": c.causality,
                                         "fmi_type": c.type_name}) for c in columns])


class ParquetRecorder(EveryNth):
    """Streams samples into a Parquet dataset folder, one complete part file per flush.

    Parameters
    ----------
    path : Path
        The folder (``timeseries.parquet``); created anew (refused if something is in its place).
    every : int
        Record every n-th macro step.
    flush_interval_s : float
        Wall time [s] after which buffered rows are written at the latest.
    part_rows : int
        Rows of a part at most.
    """

    def __init__(self, path: Path, every: int = 1, flush_interval_s: float = 2.0, part_rows: int = PART_ROWS) -> None:
        self.path = Path(path)
        self.every = every
        self.flush_interval_s = flush_interval_s
        self._sampler = _TypedSampler(part_rows)
        self._schema: Any = None
        self._parts = 0
        self._last_flush = 0.0
        self._last_time_s: float | None = None
        self._open = False
        self.rows_written = 0
        self._writer: ThreadPoolExecutor | None = None
        self._pending: Future[None] | None = None

    @property
    def columns(self) -> list[Column]:
        return self._sampler.columns

    def start(self, execution: Execution) -> None:
        import pyarrow as pa
        import pyarrow.parquet  # noqa: F401  (imported here, not in the first flush during the run)

        self._sampler.attach(execution)
        self._schema = arrow_schema(self._sampler.columns)
        pa.Table.from_arrays([pa.array([], type=f.type) for f in self._schema], schema=self._schema)  # lazy init
        claim_timeseries(self.path)
        try:
            self.path.mkdir(parents=True)
        except OSError as exc:
            raise ResultsError(f"cannot write {self.path}: {os_reason(exc)}") from None
        record_written(self.path)
        self._parts = 0
        self._open = True
        self._last_flush = time.perf_counter()

    def sample(self, k: int, time_s: float) -> None:
        if not self._due(k, time_s):
            return
        s = self._sampler
        s.fill(time_s)
        if s.rows == s.block_rows or (s.rows & 63 == 0 and time.perf_counter() - self._last_flush >
                                      self.flush_interval_s):
            self.flush()

    def flush(self) -> None:
        """Hand the buffered rows to the writer thread as one more part file (whole: written to a hidden
        name, then renamed).

        The write (pyarrow's compression and file output, C++ that releases the GIL) overlaps the next
        macro steps on another core: it is about two thirds of what recording costs. At most one part is
        in flight: a flush first waits for the one before and raises its error, so a failed write stops
        the run at the next flush (within ``flush_interval_s``) or at its end, never silently.
        """
        self._wait()
        s = self._sampler
        if not self._open:
            return
        self._last_flush = time.perf_counter()
        if not s.rows:
            return
        rows = s.rows
        arrays = s.arrays()  # copies: the sampler fills its buffer again meanwhile
        final = self.path / f"part-{self._parts:05d}.parquet"
        self._parts += 1
        if self._writer is None:
            self._writer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="emss-parquet")
        self._pending = self._writer.submit(self._write, arrays, rows, final)

    def _wait(self) -> None:
        """Wait for the part in flight; its ResultsError is raised here, in the run's thread."""
        if self._pending is not None:
            pending, self._pending = self._pending, None
            pending.result()

    def _write(self, arrays: list[np.ndarray], rows: int, final: Path) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        last = float(arrays[0][-1])
        s = self._sampler
        tmp = self.path / f".{final.name}.tmp"
        try:
            table = pa.Table.from_arrays([pa.array(a) for a in arrays], schema=self._schema)
            with open(tmp, "wb") as f:  # our own handle: closed here even when the disk is full
                pq.write_table(table, f, compression="zstd", compression_level=ZSTD_LEVEL,
                               use_byte_stream_split=[c.name for c in s.columns if c.type_name == "Real"],
                               use_dictionary=[c.name for c in s.columns if c.type_name != "Real"],
                               row_group_size=rows)
            os.replace(tmp, final)
            record_written(final)
        except (OSError, pa.ArrowException) as exc:
            with contextlib.suppress(OSError):
                tmp.unlink()
            self._open = False
            if not isinstance(exc, OSError):  # pyarrow's IOError text carries the cause
                exc = OSError(getattr(exc, "errno", None), str(exc))
            kept = f"; rows up to t = {self._last_time_s:.6g} s kept" if self._last_time_s is not None else ""
            raise ResultsError(f"cannot write {final} at t = {last:.6g} s: {os_reason(exc)}{kept}") from None
        self.rows_written += rows
        self._last_time_s = last

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        try:
            self._record_last_step(error)
            self.flush()
            self._wait()
        finally:
            self._open = False
            if self._writer is not None:
                self._writer.shutdown(wait=True)
                self._writer = None


class MatRecorder(ParquetRecorder):
    """Streams Parquet parts into a hidden folder beside ``path`` during the run and writes ``path``
    (MATLAB v5, :func:`scipy.io.savemat`) from them at the end; the parts are then removed."""

    def __init__(self, path: Path, every: int = 1, flush_interval_s: float = 2.0) -> None:
        self.mat_path = Path(path)
        super().__init__(self.mat_path.parent / MAT_STAGING, every, flush_interval_s)

    def start(self, execution: Execution) -> None:
        claim_timeseries(self.mat_path)
        super().start(execution)

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        super().finish(execution, error)
        write_mat(read_parquet(self.path), self.mat_path)
        shutil.rmtree(self.path, ignore_errors=True)


class UnitsCsvRecorder(CsvRecorder):
    """:class:`~.observers.CsvRecorder` with a second line of units (``s`` for ``time_s``, '' where none)."""

    def start(self, execution: Execution) -> None:
        super().start(execution)
        self.columns = columns_of(execution)
        self._write((",".join(_csv_text(c.unit) for c in self.columns) + "\n").encode("utf-8"), execution.time_s)


def _csv_text(text: str) -> str:
    return f'"{text}"' if ("," in text or '"' in text) else text


# -- the formats ----------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class ResultFormat:
    """A time series format of ``emss run --format``.

    Attributes
    ----------
    name : str
        The ``--format`` value.
    file_name : str
        What a run writes into its results folder (a file, or a folder of parts); its suffix tells a path of the
        format when it is read back.
    summary : str
        One line for ``--help``.
    recorder : callable
        ``(path, every) -> EveryNth``: the recorder writing ``path`` (``file_name`` in the results folder) every
        ``every``-th step; it has ``rows_written``.
    read : callable
        ``(path) -> TimeSeries``: what the recorder wrote, read back (:class:`TimeSeriesError` naming the file).
    columns : callable
        ``(path) -> list of str``: the column names, without reading the rows.
    leftovers : tuple of str
        Names beside ``file_name`` that a killed run of the format may leave: Parquet part folders, read back
        as such.
    """

    name: str
    file_name: str
    summary: str
    recorder: Callable[[Path, int], EveryNth]
    read: Callable[[Path], TimeSeries]
    columns: Callable[[Path], list[str]]
    leftovers: tuple[str, ...] = ()

    @property
    def suffix(self) -> str:
        return Path(self.file_name).suffix


#: The time series formats by their ``--format`` name, in the order a results folder is searched for one.
FORMATS: dict[str, ResultFormat] = {}


def register_format(fmt: ResultFormat) -> ResultFormat:
    """Register a time series format under its name (once; its file name and suffix its own).

    Raises
    ------
    ValueError
        When the name, the file name or its suffix is empty or taken.
    """
    taken = [f.name for f in FORMATS.values() if fmt.name == f.name or fmt.file_name == f.file_name
             or fmt.suffix == f.suffix]
    if not fmt.name or not fmt.suffix or taken:
        raise ValueError(f"time series format {fmt.name!r} ({fmt.file_name}): name, file name or suffix empty or "
                         f"taken{' by ' + ', '.join(taken) if taken else ''}")
    FORMATS[fmt.name] = fmt
    return fmt


def format_help() -> str:
    """The formats for ``--help``: each with its summary, the default named."""
    return "time series format: " + "; ".join(f"{f.name} ({f.summary})" for f in FORMATS.values()) + \
        f" (default: {DEFAULT_FORMAT})"


def timeseries_names() -> list[str]:
    """Every name a time series of any format (or what a killed run of it left) has in a results folder."""
    return [n for f in FORMATS.values() for n in (f.file_name, *f.leftovers)]


def get_format(name: str) -> ResultFormat:
    """The format of ``name``.

    Raises
    ------
    ConfigurationError
        Naming the formats allowed.
    """
    fmt = FORMATS.get(name)
    if fmt is None:
        raise ConfigurationError(f"--format {name!r}: not a time series format (allowed: {', '.join(FORMATS)})")
    return fmt


def recorder(fmt: str, out: Path, every: int = 1) -> EveryNth:
    """The recorder of format ``fmt`` (:data:`FORMATS`) writing into the results folder ``out``."""
    kind = get_format(fmt)
    for name in timeseries_names():  # one time series per folder, and nothing replaced
        claim_timeseries(Path(out) / name)
    return kind.recorder(Path(out) / kind.file_name, every)


def claim_timeseries(path: Path) -> None:
    """Refuse a time series at ``path`` when something is in its place: the results folder
    (:class:`~openemss.orchestrator.results.ResultsFolder`) has removed what an earlier run of ours wrote,
    so whatever is left there is not ours to remove."""
    path = Path(path)
    if os.path.lexists(path):
        raise ResultsError(f"cannot write {path}: something of that name is in the way (not written by a run "
                           "of openEMSS, or changed since; it is left as it is); move it away or give another "
                           "folder")


# -- reading ------------------------------------------------------------------------------------
def find_timeseries(folder: Path) -> Path | None:
    """The time series in a results folder (in the order of :data:`FORMATS`: Parquet, then CSV, then .mat; then
    what a killed run left)."""
    folder = Path(folder)
    for name in (*(f.file_name for f in FORMATS.values()), *(n for f in FORMATS.values() for n in f.leftovers)):
        if (folder / name).exists():
            return folder / name
    return None


def _format_of(path: Path) -> ResultFormat:
    """The format that reads ``path``: by its suffix; a folder of Parquet parts (a killed .mat run's too) is
    Parquet."""
    for f in FORMATS.values():
        if path.suffix == f.suffix:
            return f
    if path.is_dir() or path.name in (n for f in FORMATS.values() for n in f.leftovers):
        return FORMATS["parquet"]
    raise TimeSeriesError(f"{path}: not a time series file (the formats: "
                          f"{', '.join(f'{f.file_name} ({f.name})' for f in FORMATS.values())})")


def read_columns(path: Path) -> list[str]:
    """Column names of a time series without reading its rows ([] when unreadable)."""
    path = Path(path)
    try:
        return _format_of(path).columns(path)
    except (OSError, ValueError, EmssError):
        return []


def read_timeseries(path: Path) -> TimeSeries:
    """Read a time series written by a recorder of this module (a file or a parts folder, or a results
    folder holding one).

    Raises
    ------
    TimeSeriesError
        Naming the file and what is wrong.
    """
    path = Path(path)
    if path.is_dir() and path.name not in timeseries_names() and not any(path.glob(PART_GLOB)):
        found = find_timeseries(path)
        if found is None:
            raise TimeSeriesError(f"{path}: no time series ({', '.join(f.file_name for f in FORMATS.values())}); "
                                  "give a folder written by emss run")
        path = found
    if not path.exists():
        raise TimeSeriesError(f"{path}: no such file")
    return _format_of(path).read(path)


register_format(ResultFormat(
    "parquet", "timeseries.parquet", "timeseries.parquet/, typed, compressed, units in the column metadata",
    lambda path, every: ParquetRecorder(path, every=every), read_parquet, parquet_columns))
register_format(ResultFormat(
    "csv", "timeseries.csv", "timeseries.csv with a units row",
    lambda path, every: UnitsCsvRecorder(path, every=every), read_csv, csv_columns))
register_format(ResultFormat(
    "mat", "timeseries.mat", "timeseries.mat, MATLAB v5", lambda path, every: MatRecorder(path, every=every),
    read_mat, mat_columns, leftovers=(MAT_STAGING,)))
