"""Time series of a run on disk: Parquet (the default), CSV with a units row, MATLAB .mat; and reading them back.

Recorders (observers of :class:`~.execution.Execution`) sample the exchange vectors into typed
blocks (float64 for Real, int32 for Integer, bool for Boolean) and write them:

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
from collections.abc import Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConfigurationError, EmssError
from ..results import ResultsError, atomic_write, os_reason, record_written
from .observers import CsvRecorder, EveryNth

if TYPE_CHECKING:
    import pandas

    from ..master.execution import Execution
    from ..ssp.system import BoundSystem

FORMATS = ("parquet", "csv", "mat")
DEFAULT_FORMAT = "parquet"
FILE_NAMES = {"parquet": "timeseries.parquet", "csv": "timeseries.csv", "mat": "timeseries.mat"}
MAT_STAGING = ".timeseries.mat.parts"
PART_ROWS = 16384  #: rows of one Parquet part at most (one row group each)
PART_GLOB = "part-*.parquet"
ZSTD_LEVEL = 3
_UNIT_IN_TEXT = re.compile(r"\[([^\[\]]+)\]\s*$")
_NUMPY = {"Real": np.float64, "Integer": np.int32, "Boolean": np.bool_}


class TimeSeriesError(EmssError):
    """A time series file that cannot be read (missing, damaged, not written by emss run)."""


@dataclass(frozen=True)
class Column:
    """What one recorded column holds.

    Attributes
    ----------
    name : str
        ``time_s`` or ``component.variable``.
    type_name : str
        ``Real``, ``Integer`` or ``Boolean`` (``time_s``: ``Real``).
    unit : str
        Its unit as the FMU gives it ('' when none is known).
    description : str
        The FMU variable's description ('' when none).
    causality : str
        ``output``, ``input``, ``parameter``, ... (``time_s``: ``independent``).
    """

    name: str
    type_name: str = "Real"
    unit: str = ""
    description: str = ""
    causality: str = ""


TIME_COLUMN = Column("time_s", "Real", "s", "simulation time", "independent")


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


def default_record(bound: BoundSystem, inputs: bool = False) -> list[str]:
    """What a run records by default: every connector of the SSD, less the inputs that only copy an output
    (connected, with no transformation, unit conversion or mapping) unless ``inputs``.

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
        write_mat(read_timeseries(self.path), self.mat_path)
        shutil.rmtree(self.path, ignore_errors=True)


class UnitsCsvRecorder(CsvRecorder):
    """:class:`~.observers.CsvRecorder` with a second line of units (``s`` for ``time_s``, '' where none)."""

    def start(self, execution: Execution) -> None:
        super().start(execution)
        self.columns = columns_of(execution)
        self._write((",".join(_csv_text(c.unit) for c in self.columns) + "\n").encode("utf-8"), execution.time_s)


def _csv_text(text: str) -> str:
    return f'"{text}"' if ("," in text or '"' in text) else text


def recorder(fmt: str, out: Path, every: int = 1) -> ParquetRecorder | UnitsCsvRecorder:
    """The recorder of format ``fmt`` (:data:`FORMATS`) writing into the results folder ``out``."""
    if fmt not in FORMATS:
        raise ConfigurationError(f"--format {fmt!r}: not a time series format (allowed: {', '.join(FORMATS)})")
    for name in (*FILE_NAMES.values(), MAT_STAGING):  # one time series per folder, and nothing replaced
        claim_timeseries(Path(out) / name)
    path = Path(out) / FILE_NAMES[fmt]
    if fmt == "csv":
        return UnitsCsvRecorder(path, every=every)
    return MatRecorder(path, every=every) if fmt == "mat" else ParquetRecorder(path, every=every)


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
@dataclass
class TimeSeries:
    """A run's time series as read back.

    Attributes
    ----------
    columns : list of Column
        Names, types, units and descriptions, ``time_s`` first.
    data : dict[str, numpy.ndarray]
        One typed array per column name.
    source : Path
        The file or folder read.
    note : str
        What reading left out (a torn last CSV row), '' when the file was whole.
    """

    columns: list[Column]
    data: dict[str, np.ndarray]
    source: Path
    note: str = ""

    @property
    def names(self) -> list[str]:
        return [c.name for c in self.columns]

    @property
    def units(self) -> dict[str, str]:
        return {c.name: c.unit for c in self.columns}

    def __len__(self) -> int:
        return len(self.data["time_s"]) if "time_s" in self.data else 0

    def floats(self) -> dict[str, np.ndarray]:
        """Every column as float64 (Booleans as 0/1)."""
        return {n: a.astype(np.float64) if a.dtype != np.float64 else a for n, a in self.data.items()}

    def to_pandas(self) -> pandas.DataFrame:
        """A DataFrame indexed by ``time_s``; units and descriptions in ``df.attrs``."""
        import pandas as pd

        df = pd.DataFrame({n: a for n, a in self.data.items() if n != "time_s"},
                          index=pd.Index(self.data["time_s"], name="time_s"))
        df.attrs["units"] = self.units
        df.attrs["descriptions"] = {c.name: c.description for c in self.columns}
        return df


def find_timeseries(folder: Path) -> Path | None:
    """The time series in a results folder (Parquet, then CSV, then .mat, then a killed .mat run's parts)."""
    folder = Path(folder)
    for name in (*FILE_NAMES.values(), MAT_STAGING):
        if (folder / name).exists():
            return folder / name
    return None


def read_columns(path: Path) -> list[str]:
    """Column names of a time series without reading its rows ([] when unreadable)."""
    path = Path(path)
    try:
        if path.suffix == ".csv":
            with open(path, encoding="utf-8") as f:
                return f.readline().rstrip("\r\n").split(",")
        if path.suffix == ".mat":
            return [c.name for c in read_timeseries(path).columns]
        import pyarrow.parquet as pq

        parts = _parts(path)
        return list(pq.read_schema(parts[0]).names) if parts else []
    except (OSError, ValueError, EmssError):
        return []


def _parts(path: Path) -> list[Path]:
    return sorted(path.glob(PART_GLOB)) if path.is_dir() else [path]


def read_timeseries(path: Path) -> TimeSeries:
    """Read a time series written by a recorder of this module (a file or a parts folder, or a results
    folder holding one).

    Raises
    ------
    TimeSeriesError
        Naming the file and what is wrong.
    """
    path = Path(path)
    if path.is_dir() and path.name not in (FILE_NAMES["parquet"], MAT_STAGING) and not any(path.glob(PART_GLOB)):
        found = find_timeseries(path)
        if found is None:
            raise TimeSeriesError(f"{path}: no time series ({', '.join(FILE_NAMES.values())}); give a folder "
                                  "written by emss run")
        path = found
    if not path.exists():
        raise TimeSeriesError(f"{path}: no such file")
    if path.suffix == ".csv":
        return _read_csv(path)
    if path.suffix == ".mat":
        return _read_mat(path)
    return _read_parquet(path)


def _read_parquet(path: Path) -> TimeSeries:
    import pyarrow as pa
    import pyarrow.parquet as pq

    parts = _parts(path)
    try:
        tables = [pq.read_table(p) for p in parts]
    except (OSError, pa.ArrowException) as exc:
        raise TimeSeriesError(f"{path}: unreadable Parquet ({exc})") from None
    if not tables:
        raise TimeSeriesError(f"{path}: no rows recorded (no part file)")
    table = pa.concat_tables(tables) if len(tables) > 1 else tables[0]
    if not table.column_names or table.column_names[0] != "time_s":
        raise TimeSeriesError(f"{path}: not a timeseries of emss run (the first column must be time_s)")
    cols = []
    for f in table.schema:
        md = {k.decode(): v.decode() for k, v in (f.metadata or {}).items()}
        t = md.get("fmi_type") or ("Boolean" if pa.types.is_boolean(f.type) else
                                   "Integer" if pa.types.is_integer(f.type) else "Real")
        cols.append(Column(f.name, t, md.get("unit", ""), md.get("description", ""), md.get("causality", "")))
    data = {c.name: table.column(i).to_numpy() for i, c in enumerate(cols)}
    return TimeSeries(cols, data, path)


def _read_csv(path: Path) -> TimeSeries:
    """A CSV of :class:`UnitsCsvRecorder` (or of the former recorder, without the units row). A torn last
    row (a killed run) is left out and said in ``note``; a damaged row before it is an error naming its line."""
    try:
        lines = path.read_bytes().decode("utf-8", "replace").replace("\r\n", "\n").split("\n")
    except OSError as exc:
        raise TimeSeriesError(f"{path}: cannot read: {exc.strerror}") from None
    if not lines or not lines[0].startswith("time_s"):
        raise TimeSeriesError(f"{path}: not a timeseries of emss run (the first column must be time_s)")
    names = lines[0].split(",")
    units = [""] * len(names)
    first = 1
    if len(lines) > 2 and lines[1].split(",", 1)[0] == "s":
        units = [u.strip('"') for u in _split_units(lines[1])]
        first = 2
    complete = lines[-1] == ""
    body = lines[first:-1] if complete else lines[first:]
    note = ""
    if not complete and body:
        note = (f"{path}: the last row (line {len(lines)}) is torn, {len(body[-1].split(','))} of {len(names)} "
                "values (the run stopped while writing it); it is left out")
        body = body[:-1]
    for i, line in enumerate(body, start=first + 1):
        if line.count(",") != len(names) - 1:
            raise TimeSeriesError(f"{path}:{i}: {line.count(',') + 1} values for {len(names)} columns; the file "
                                  "is damaged")
    try:
        rows = np.loadtxt(body, delimiter=",", ndmin=2) if body else np.empty((0, len(names)))
    except ValueError as exc:
        raise TimeSeriesError(f"{path}: unreadable row ({exc})") from None
    cols = [Column(n, "Real", u) for n, u in zip(names, units, strict=False)]
    return TimeSeries(cols, {n: rows[:, j] for j, n in enumerate(names)}, path, note)


def _split_units(line: str) -> list[str]:
    import csv

    return next(csv.reader([line]))


def write_mat(ts: TimeSeries, path: Path) -> Path:
    """Write a time series as a MATLAB v5 file: ``data`` (rows x columns, double), ``names``, ``units``,
    ``descriptions`` (cell arrays of text, one per column)."""
    import io

    from scipy.io import savemat

    data = np.column_stack([ts.data[c.name].astype(np.float64) for c in ts.columns]) if len(ts) else \
        np.empty((0, len(ts.columns)))

    def cells(values: list[str]) -> np.ndarray:
        out = np.empty((len(values), 1), dtype=object)
        for i, v in enumerate(values):
            out[i, 0] = v
        return out

    buf = io.BytesIO()
    savemat(buf, {"data": data, "names": cells(ts.names), "units": cells([c.unit for c in ts.columns]),
                  "descriptions": cells([c.description for c in ts.columns])}, do_compression=True)
    return atomic_write(path, buf.getvalue())


def _read_mat(path: Path) -> TimeSeries:
    from scipy.io import loadmat

    try:
        m = loadmat(path)
    except (OSError, ValueError) as exc:
        raise TimeSeriesError(f"{path}: unreadable MATLAB file ({exc})") from None

    def texts(key: str) -> list[str]:
        return [str(c[0][0]) if len(c[0]) else "" for c in m[key]]

    names, units, descriptions = texts("names"), texts("units"), texts("descriptions")
    data = m["data"]
    cols = [Column(n, "Real", u, d) for n, u, d in zip(names, units, descriptions, strict=True)]
    return TimeSeries(cols, {n: data[:, j] for j, n in enumerate(names)}, path)
