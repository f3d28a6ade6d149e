"""Studies on Dask: a small study on a LocalCluster and on a separately started scheduler + worker.

The system is the two-mass oscillator with a third component, the test FMU
FailingClock, which raises once the simulated time reaches its parameter
``fail_time_s``: a case that sets it inside the run fails for a reason of its own
(a Python exception in an FMU), independent of the study machinery.
"""
from __future__ import annotations

import csv
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.recording.timeseries import read_timeseries
from openemss.study.case import CaseDef, CaseResult, run_case
from openemss.study.dataset import read_study
from openemss.study.plan import expand_cases
from openemss.study.runner import run_cases
from openemss.study.spec import load_study
from systems import Comp, write_system

STOP_S = 1.0
MASS1 = [("f_c_N", "input", "Real"), ("x1_m", "output", "Real"), ("v1_m_s", "output", "Real")]
MASS2 = [("x1_m", "input", "Real"), ("v1_m_s", "input", "Real"), ("x2_m", "output", "Real"),
         ("f_c_N", "output", "Real")]
LINKS = [("mass1.x1_m", "mass2.x1_m"), ("mass1.v1_m_s", "mass2.v1_m_s"), ("mass2.f_c_N", "mass1.f_c_N")]


@pytest.fixture(scope="module")
def system(tmp_path_factory: pytest.TempPathFactory, fmu_dir: Path) -> Path:
    folder = tmp_path_factory.mktemp("study_system") / "osc_clock"
    write_system(folder, fmu_dir, [Comp("mass1", "ForceDrivenMass.fmu", MASS1),
                                   Comp("mass2", "DisplacementDrivenMass.fmu", MASS2),
                                   Comp("clock", "FailingClock.fmu", [("clock_s", "output", "Real")])],
                 LINKS, name="OscillatorWithClock", stop_time=10.0)
    return folder


def write_study(folder: Path, system: Path, variants: str) -> Path:
    path = folder / "small.yaml"
    path.write_text(f"study: small\nsystem: {system}\nstop_time_s: {STOP_S}\n"
                    f"values: {{clock.fail_time_s: 100.0}}\nvariants:\n{variants}", encoding="utf-8")
    return path


TWO_AND_BROKEN = ("  - {name: light, values: {mass1.m1_kg: 1.0}}\n"
                  "  - {name: heavy, values: {mass1.m1_kg: 4.0}}\n"
                  "  - {name: broken, values: {clock.fail_time_s: 0.5}}\n")


def table(path: Path) -> dict[str, dict[str, str]]:
    with open(path, newline="", encoding="utf-8") as f:
        return {row["case"]: row for row in csv.DictReader(f)}


def last_time(folder: Path) -> float:
    return float(read_timeseries(folder).data["time_s"][-1])


def test_local_cluster_runs_cases_records_a_failure_and_resumes(tmp_path: Path, system: Path) -> None:
    study = load_study(write_study(tmp_path, system, TWO_AND_BROKEN))
    cases = expand_cases(study)
    assert [c.name for c in cases] == ["light", "heavy", "broken"]
    out = tmp_path / "out"
    first = run_cases(cases, out, workers=2)
    assert sorted(first.ran) == ["broken", "heavy", "light"] and first.skipped == []
    rows = table(out / "study.csv")
    assert [rows[n]["status"] for n in ("light", "heavy", "broken")] == ["completed", "completed", "failed"]
    assert "deliberate failure of the test FMU" in rows["broken"]["error"]
    assert rows["light"]["mass1.m1_kg"] == "1.0" and rows["heavy"]["mass1.m1_kg"] == "4.0"
    for name, m1 in (("light", 1.0), ("heavy", 4.0)):
        folder = out / "cases" / name
        # each case ran with its own parameter values (as the run itself reports them), to the stop time
        assert json.loads((folder / "run.json").read_text())["parameters"]["mass1.m1_kg"] == m1
        assert last_time(folder) == pytest.approx(STOP_S)
        assert float(rows[name]["sim_time_s"]) == pytest.approx(STOP_S)
    # the failing case kept what it recorded: every sample up to t = 0.5 s, where the FMU raised in its step
    assert last_time(out / "cases" / "broken") == pytest.approx(0.5)

    # one dataset of every case beside study.csv: each case's rows, as its own folder holds them
    df = read_study(out, columns=["time_s", "mass1.x1_m"])
    assert set(df["case"].astype(str)) == {"light", "heavy", "broken"}
    for name in ("light", "heavy", "broken"):
        own = read_timeseries(out / "cases" / name).data
        mine = df[df["case"] == name].sort_values("time_s")
        assert list(mine["time_s"]) == list(own["time_s"]) and list(mine["mass1.x1_m"]) == list(own["mass1.x1_m"])
    # the heavier mass oscillates more slowly: its x1 differs from the light one's after the start
    light, heavy = (df[df["case"] == n].sort_values("time_s")["mass1.x1_m"].to_numpy() for n in ("light", "heavy"))
    assert light[0] == heavy[0] and abs(light[-1] - heavy[-1]) > 1e-3
    # two cases compared (no mission here: every recorded column), and a case that does not exist refused
    assert main(["study", "report", str(out), "light", "heavy"]) == 0
    assert {f.name for f in (out / "compare_light_heavy").iterdir()} == {"variables.png", "report.html"}
    assert main(["study", "report", str(out), "light", "hevy"]) == 2

    stream = open(os.devnull, "w")  # noqa: SIM115 - closed below
    again = run_cases(expand_cases(load_study(tmp_path / "small.yaml")), out, workers=2, stream=stream)
    stream.close()
    assert again.ran == [] and sorted(again.skipped) == ["broken", "heavy", "light"]
    assert {r["ran"] for r in table(out / "study.csv").values()} == {"earlier"}


def test_changed_definition_runs_again(tmp_path: Path, system: Path) -> None:
    path = write_study(tmp_path, system, "  - {name: light, values: {mass1.m1_kg: 1.0}}\n")
    out = tmp_path / "out"
    run_cases(expand_cases(load_study(path)), out, workers=1)
    path.write_text(path.read_text().replace(f"stop_time_s: {STOP_S}", "stop_time_s: 0.5"), encoding="utf-8")
    again = run_cases(expand_cases(load_study(path)), out, workers=1)
    assert again.ran == ["light"]
    assert last_time(out / "cases" / "light") == pytest.approx(0.5)


def crashing_task(case: CaseDef, out: str, attempt: int) -> CaseResult:
    """Kills its worker process: always for case 'dead', on the first attempt for case 'flaky'."""
    if case.name == "dead" or (case.name == "flaky" and attempt == 1):
        os.kill(os.getpid(), signal.SIGKILL)
    return run_case(case, out, attempt)


def test_killed_worker_case_is_retried_once_then_failed(tmp_path: Path, system: Path) -> None:
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers cannot import this test module
    try:
        path = write_study(tmp_path, system, "  - {name: flaky, values: {mass1.m1_kg: 1.0}}\n"
                                             "  - {name: dead, values: {mass1.m1_kg: 2.0}}\n")
        out = tmp_path / "out"
        res = run_cases(expand_cases(load_study(path)), out, workers=1, task=crashing_task)
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    flaky, dead = res.results["flaky"], res.results["dead"]
    assert (flaky.status, flaky.attempts) == ("completed", 2)
    assert (dead.status, dead.attempts) == ("failed", 2) and "worker died" in dead.error
    assert not (out / "cases" / "dead" / "done.json").exists()  # a rerun tries it again
    assert table(out / "study.csv")["dead"]["status"] == "failed"


def test_a_case_only_queued_on_a_killed_worker_is_not_charged_a_retry(tmp_path: Path, system: Path) -> None:
    """One worker; 'flaky' kills it on its first attempt while three cases wait. The waiting cases were
    never running on it: each completes at its first attempt (issue 15); only 'flaky' is retried."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    try:
        path = write_study(tmp_path, system, "  - {name: flaky, values: {mass1.m1_kg: 1.0}}\n"
                                             "  - {name: q1, values: {mass1.m1_kg: 2.0}}\n"
                                             "  - {name: q2, values: {mass1.m1_kg: 3.0}}\n"
                                             "  - {name: q3, values: {mass1.m1_kg: 4.0}}\n")
        res = run_cases(expand_cases(load_study(path)), tmp_path / "out", workers=1, task=crashing_task)
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    assert {n: (r.status, r.attempts) for n, r in res.results.items()} == {
        "flaky": ("completed", 2), "q1": ("completed", 1), "q2": ("completed", 1), "q3": ("completed", 1)}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_separately_started_scheduler_and_worker(tmp_path: Path, system: Path) -> None:
    from distributed import Client

    dask_cli = Path(sys.executable).parent / "dask"
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = open(tmp_path / "dask.log", "wb")  # noqa: SIM115 - closed below
    procs = [subprocess.Popen([str(dask_cli), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], stdout=logs, stderr=logs, start_new_session=True)]
    try:
        procs.append(subprocess.Popen([str(dask_cli), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                       "--no-dashboard", "--host", "127.0.0.1"], stdout=logs, stderr=logs,
                                      start_new_session=True))
        deadline = time.monotonic() + 40.0
        with Client(address, timeout="30s") as client:
            while not client.nthreads() and time.monotonic() < deadline:
                time.sleep(0.2)
            assert client.nthreads(), "the worker did not join the scheduler"
        path = write_study(tmp_path, system, "  - {name: light, values: {mass1.m1_kg: 1.0}}\n"
                                             "  - {name: heavy, values: {mass1.m1_kg: 4.0}}\n")
        out = tmp_path / "out"
        res = run_cases(expand_cases(load_study(path)), out, scheduler=address)
        assert {n: r.status for n, r in res.results.items()} == {"light": "completed", "heavy": "completed"}
        assert res.workers == 1
        rows = table(out / "study.csv")
        assert [rows[n]["status"] for n in ("light", "heavy")] == ["completed", "completed"]
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
        for p in reversed(procs):
            try:
                p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=5)
        logs.close()
