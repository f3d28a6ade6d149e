"""A study's time series as one Parquet dataset: ``STUDY_DIR/timeseries/case=<name>/part-*.parquet``.

Each case's run writes its own ``cases/<name>/timeseries.parquet/`` (the parts of :mod:`openemss.orchestrator.
timeseries`); when the case ends, its parts are linked (hard links: no copy, same disk; a copy elsewhere)
into the study's dataset, partitioned by case in the Hive layout, beside ``study.csv``. Every reader of
partitioned Parquet queries all cases together, with a ``case`` column::

    import pandas as pd
    df = pd.read_parquet("results/study-x/timeseries", columns=["case", "time_s", "engine.Fn_N"])
    df.groupby("case")["engine.Fn_N"].max()

or ``duckdb.sql("select case, max(\\"engine.fuel_burned_kg\\") from 'results/study-x/timeseries/**/*.parquet'
group by case")``. A case folder holding CSV or .mat instead (a run made with ``--format``) is converted
into the dataset.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import TYPE_CHECKING

from openemss.orchestrator.recording.timeseries import (
    FORMATS,
    PART_GLOB,
    TimeSeriesError,
    arrow_schema,
    find_timeseries,
    read_timeseries,
)
from openemss.orchestrator.results import check_name

if TYPE_CHECKING:
    import pandas

DATASET = "timeseries"


def case_partition(study_dir: Path, case: str) -> Path:
    """The folder of one case in the study's dataset."""
    return Path(study_dir) / DATASET / f"case={check_name(case, 'case name')}"


def publish_case(study_dir: Path, case: str, case_folder: Path) -> Path | None:
    """Put a finished case's time series into the study's dataset (replacing what an earlier run of the case
    put there); None when the case recorded nothing."""
    target = case_partition(study_dir, case)
    if target.exists():
        shutil.rmtree(target)
    source = find_timeseries(case_folder)
    if source is None:
        return None
    target.mkdir(parents=True)
    parts = sorted(source.glob(PART_GLOB)) if source.is_dir() else []
    if source.name == FORMATS["parquet"].file_name and parts:
        for p in parts:
            try:
                os.link(p, target / p.name)
            except OSError:  # another file system, or no hard links there
                shutil.copy2(p, target / p.name)
        return target
    try:
        ts = read_timeseries(source)
    except TimeSeriesError:
        return None
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_arrays([pa.array(ts.data[c.name]) for c in ts.columns], schema=arrow_schema(ts.columns))
    pq.write_table(table, target / "part-00000.parquet", compression="zstd")
    return target


def read_study(study_dir: Path, columns: list[str] | None = None, cases: list[str] | None = None) -> pandas.DataFrame:
    """Every case's time series as one DataFrame with a ``case`` column (``columns``: only these; ``cases``:
    only these cases)."""
    import pandas as pd

    path = Path(study_dir) / DATASET
    if not path.is_dir():
        raise TimeSeriesError(f"{path}: no study dataset (run the study with emss study run first)")
    filters = [("case", "in", list(cases))] if cases else None
    cols = None if columns is None else ["case", *[c for c in columns if c != "case"]]
    return pd.read_parquet(path, columns=cols, filters=filters)
