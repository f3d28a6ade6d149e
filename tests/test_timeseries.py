"""Time series on disk (issue 17): Parquet by default, CSV with a units row, MATLAB .mat; typed columns with
units and descriptions; outputs only by default; streamed parts that a killed run keeps whole.

The values each format holds are compared with the in-memory recorder of the same run (a separate path:
no file, no encoding), the units with the FMUs' model descriptions (read here with the standard library),
the rows a killed run kept with the integer time grid t = k h.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.recording.timeseries import (
    ParquetRecorder,
    default_record,
    read_timeseries,
    recorder,
    unit_from_description,
)
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system


def _descriptions(fmu: Path) -> dict[str, tuple[str, str]]:
    """(unit attribute or '', description) of each variable, read from modelDescription.xml directly."""
    root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    out = {}
    for sv in root.iter("ScalarVariable"):
        child = next(iter(sv))
        out[sv.attrib["name"]] = (child.attrib.get("unit", ""), sv.attrib.get("description", ""))
    return out


@pytest.mark.parametrize("fmt", ["parquet", "csv", "mat"])
def test_every_format_holds_the_values_of_the_run_with_units(oscillator: Path, tmp_path: Path, fmt: str) -> None:
    bound = bind_system(load_system(oscillator))
    ex = Execution(bound, rate_hz=20.0, record=default_record(bound, inputs=True))
    mem = MemoryRecorder()
    rec = recorder(fmt, tmp_path, every=1)
    ex.add_observer(mem)
    ex.add_observer(rec)
    ex.run(3.0)
    ts = read_timeseries(tmp_path)
    ref = mem.result()
    assert ts.names == list(ref)
    for name, values in ref.items():
        # Parquet and .mat hold the doubles themselves; CSV prints 15 significant digits
        tol = 1e-14 if fmt == "csv" else 0.0
        np.testing.assert_allclose(ts.data[name], values, rtol=tol, atol=tol)
    fmus = {c.name: c.fmu_path for c in bound.components}
    for col in ts.columns[1:]:
        comp, _, var = col.name.partition(".")
        unit, description = _descriptions(fmus[comp])[var]
        assert col.unit == (unit or unit_from_description(description)) != ""
        if fmt != "csv":  # the CSV carries units only
            assert col.description == description
    assert ts.units["time_s"] == "s"


def test_unit_from_the_unit_attribute_first_then_the_description() -> None:
    assert unit_from_description("Net thrust [N]") == "N"
    assert unit_from_description("Fuel flow [kg/s] ") == "kg/s"
    assert unit_from_description("no unit here") == ""
    assert unit_from_description(None) == ""


def test_csv_has_a_units_row_and_parquet_typed_columns(tmp_path: Path, fmu_dir: Path, oscillator: Path) -> None:
    out = tmp_path / "csv"
    assert main(["run", str(oscillator), "--stop-time", "1", "--format", "csv", "--out", str(out)]) == 0
    lines = (out / "timeseries.csv").read_text().splitlines()
    names, units = lines[0].split(","), lines[1].split(",")
    assert units[0] == "s" and units[names.index("mass1.x1_m")] == "m" and units[names.index("mass2.f_c_N")] == "N"
    assert len(lines) == 2 + 21
    import pyarrow.parquet as pq

    out = tmp_path / "pq"
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(out)]) == 0
    schema = pq.read_schema(next((out / "timeseries.parquet").glob("part-*.parquet")))
    field = schema.field("mass1.x1_m")
    assert str(field.type) == "double" and field.metadata[b"unit"] == b"m"
    assert field.metadata[b"causality"] == b"output"


def test_outputs_only_by_default_inputs_that_copy_an_output_on_request(oscillator: Path, tmp_path: Path) -> None:
    bound = bind_system(load_system(oscillator))
    connected = {f"{bound.components[ln.target].name}.{ln.target_var.name}" for ln in bound.links
                 if ln.affine.is_identity and ln.mapping is None}
    every = {f"{c.name}.{k.name}" for c in bound.components for k in c.definition.connectors}
    assert connected and connected <= every
    assert set(default_record(bound)) == every - connected
    assert set(default_record(bound, inputs=True)) == every
    out = tmp_path / "all"
    assert main(["run", str(oscillator), "--stop-time", "0.5", "--record-inputs", "--out", str(out)]) == 0
    assert set(read_timeseries(out).names) == every | {"time_s"}


def test_parts_reach_the_disk_during_the_run(oscillator: Path, tmp_path: Path) -> None:
    class Watcher:
        seen = -1

        def start(self, execution: Execution) -> None: ...

        def sample(self, k: int, time_s: float) -> None:
            if k == 55:
                Watcher.seen = len(read_timeseries(tmp_path / "timeseries.parquet"))

        def finish(self, execution: Execution, error: BaseException | None) -> None: ...

    ex = Execution(bind_system(load_system(oscillator)), rate_hz=20.0)
    ex.add_observer(ParquetRecorder(tmp_path / "timeseries.parquet", part_rows=10))
    ex.add_observer(Watcher())
    ex.run(5.0)
    # parts of 10 rows, at most one in flight in the writer thread: at step 55 the first four (rows 0-39)
    # were surely whole on disk, the fifth (40-49) may still be being written
    assert Watcher.seen in (40, 50)
    assert len(read_timeseries(tmp_path)) == 101


def test_a_killed_run_keeps_whole_rows_readable(oscillator: Path, tmp_path: Path) -> None:
    """kill -9 in the middle of a paced run: the parts on disk read back with pandas and our reader, every row
    complete and on the time grid."""
    import pandas as pd

    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "openemss.orchestrator.cli", "run", str(oscillator),
                             "--stop-time", "600", "--realtime", "20", "--out", str(out)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len(list((out / "timeseries.parquet").glob("part-*.parquet"))) < 2:
            time.sleep(0.2)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(30)
    assert proc.returncode == -signal.SIGKILL
    assert json.loads((out / "run.json").read_text())["status"] == "running"  # it never closed
    ts = read_timeseries(out)
    t = ts.data["time_s"]
    assert len(t) >= 2 and np.allclose(t, np.arange(len(t)) * 0.05, rtol=0, atol=1e-12)
    assert all(np.isfinite(a).all() for a in ts.floats().values())
    df = pd.read_parquet(out / "timeseries.parquet")
    assert len(df) == len(t) and list(df.columns) == ts.names


def test_formats_refused_with_one_line(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["run", str(oscillator), "--format", "hdf9", "--out", str(tmp_path / "x")])
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--format" in err[0] and "parquet" in err[0]
