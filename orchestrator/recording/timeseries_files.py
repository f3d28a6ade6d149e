"""Time series files of a run read back, and written whole: Parquet (a file or a folder of parts), CSV with a
units row, MATLAB v5 (:mod:`.timeseries` streams them during a run and registers each format with its reader).

Units and descriptions of the columns are those the recorder wrote (Parquet column metadata, the CSV's units
row, the .mat file's ``units`` and ``descriptions``).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import EmssError
from ..results import atomic_write

if TYPE_CHECKING:
    import pandas

__all__ = ["TimeSeriesError", "Column", "TIME_COLUMN", "TimeSeries", "PART_GLOB", "write_mat", "read_parquet",
           "read_csv", "read_mat", "parquet_columns", "csv_columns", "mat_columns", "part_files"]

PART_GLOB = "part-*.parquet"


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


def csv_columns(path: Path) -> list[str]:
    with open(path, encoding="utf-8") as f:
        return f.readline().rstrip("\r\n").split(",")


def parquet_columns(path: Path) -> list[str]:
    import pyarrow.parquet as pq

    parts = part_files(path)
    return list(pq.read_schema(parts[0]).names) if parts else []


def part_files(path: Path) -> list[Path]:
    return sorted(path.glob(PART_GLOB)) if path.is_dir() else [path]


def read_parquet(path: Path) -> TimeSeries:
    import pyarrow as pa
    import pyarrow.parquet as pq

    parts = part_files(path)
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


def read_csv(path: Path) -> TimeSeries:
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


def read_mat(path: Path) -> TimeSeries:
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


def mat_columns(path: Path) -> list[str]:
    return [c.name for c in read_mat(path).columns]
