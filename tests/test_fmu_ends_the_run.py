"""An FMU's own end of the simulation ends the run as completed (issue 34 point 5).

FMI 2.0 (section 4.2.3): an FMU that cannot go on because its simulation is over returns ``fmi2Discard``
from ``fmi2DoStep`` and ``fmi2GetBooleanStatus(fmi2Terminated)`` gives true (the Modelica Reference FMUs'
Stair does so). ``tests/cfmus/stair/stair.c``, compiled here with the FMI headers fmpy ships, counts the
whole seconds and ends the simulation when the count reaches ``stop_count``. The expected end is the closed
form (``stop_count`` seconds); FMPy, another host, is asked the same and ends there too.
"""
from __future__ import annotations

import json
import shutil
import subprocess
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import table
from openemss.orchestrator.cli.main import main
from systems import Comp, write_system

STAIR = Path(__file__).resolve().parent / "cfmus" / "stair"
HEADERS = Path(fmpy.__file__).resolve().parent / "c-code"


@pytest.fixture(scope="module")
def stair_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Stair.fmu compiled from tests/cfmus/stair (skipped where there is no C compiler)."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler")
    out = tmp_path_factory.mktemp("stair")
    lib = out / "binaries" / fmpy.platform / f"Stair{fmpy.sharedLibraryExtension}"
    lib.parent.mkdir(parents=True)
    subprocess.run([cc, "-shared", "-fPIC", "-O2", f"-I{HEADERS}", str(STAIR / "stair.c"), "-o", str(lib), "-lm"],
                   check=True, capture_output=True, text=True)
    fmu = out / "Stair.fmu"
    with zipfile.ZipFile(fmu, "w") as zf:
        zf.write(STAIR / "modelDescription.xml", "modelDescription.xml")
        zf.write(lib, lib.relative_to(out).as_posix())
    return fmu


def _system(folder: Path, fmu: Path, stop_count: int) -> Path:
    return write_system(folder, fmu.parent, [Comp("stair", fmu.name, [("counter", "output", "Integer"),
                                                                       ("y", "output", "Real")],
                                                   {"stop_count": stop_count})], [], stop_time=30.0).parent


@pytest.mark.parametrize("stop_count", [4, 7])
def test_the_fmus_end_completes_the_run_with_its_reason(stair_fmu: Path, tmp_path: Path, stop_count: int,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    system = _system(tmp_path / "sys", stair_fmu, stop_count)
    out = tmp_path / "out"
    assert main(["run", str(system), "--rate", "5", "--record", "stair.counter,stair.y", "--out", str(out)]) == 0
    said = capsys.readouterr()
    reason = f"stair ended the simulation at t = {stop_count} s (fmi2Terminated)"
    assert reason in said.out + said.err
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "completed" and run["error"] is None
    assert run["stopped_by"].startswith(reason) and "stop_count" in run["stopped_by"]  # what the FMU logged
    assert run["stop_time_s"] == pytest.approx(stop_count) and run["steps"] == 5 * stop_count
    t = table(out)
    assert t["time_s"][-1] == pytest.approx(stop_count)
    assert list(t["stair.counter"]) == [int(np.floor(x + 1e-9)) for x in t["time_s"]]


def test_fmpy_ends_the_same_fmu_at_the_same_time(stair_fmu: Path) -> None:
    """The other host's reading of the same FMU: FMPy stops its result at the count as well."""
    r = simulate_fmu(str(stair_fmu), stop_time=30.0, output_interval=0.2, start_values={"stop_count": 7})
    assert r["time"][-1] == pytest.approx(7.0) and r["counter"][-1] == 7


def test_a_run_that_reaches_its_stop_time_first_is_not_stopped_early(stair_fmu: Path, tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    system = _system(tmp_path / "sys", stair_fmu, 50)
    out = tmp_path / "out"
    assert main(["run", str(system), "--rate", "5", "--stop-time", "3", "--out", str(out)]) == 0
    assert "ended the simulation" not in capsys.readouterr().out
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "completed" and run["stopped_by"] is None and run["stop_time_s"] == pytest.approx(3.0)
