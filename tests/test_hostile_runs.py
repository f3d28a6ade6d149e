"""The hostile corpus, runs: the command line, the results folder, signals and faults (issue 15).

Each case builds its system (two Gain test FMUs), runs ``emss`` and asserts the behaviour: one
clear line and a non-zero exit for bad input; nothing written outside the results folder; no
stale or torn file; SIGINT, SIGTERM, kill -9 and a full disk leave complete rows and a closed
run.json. The references are independent of the code under test: the CSV is read back with the
standard library's csv module, the files the test planted are compared byte for byte.
"""
from __future__ import annotations

import csv
import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.recording.timeseries import FORMATS, read_timeseries
from openemss.orchestrator.results import ResultsFolder, atomic_write
from systems import write_gain_pair

FSIZE_LIMIT = 1_000_000  # bytes per file: above the test FMU's largest file (0.35 MB), below the run's CSV


@pytest.fixture()
def system(tmp_path: Path, fmu_dir: Path) -> Path:
    return write_gain_pair(tmp_path / "sys", fmu_dir)


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    try:
        rc = main(list(argv))
    except SystemExit as exc:  # argparse's usage errors
        rc = int(exc.code or 0)
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    return rc, err


def assert_one_line(rc: int, err: list[str], *fragments: str) -> str:
    assert rc != 0, err
    assert len(err) == 1, err
    assert "Traceback" not in err[0] and "internal error" not in err[0], err[0]
    for f in fragments:
        assert f in err[0], (f, err[0])
    return err[0]


def complete_rows(path: Path) -> list[list[str]]:
    """The rows of a CSV, asserting every line is complete (header width, newline-terminated)."""
    raw = path.read_bytes()
    assert raw.endswith(b"\n"), raw[-80:]
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    assert rows[0][0] == "time_s" and all(len(r) == len(rows[0]) for r in rows), [len(r) for r in rows]
    assert rows[1][0] == "s"  # the units row
    for r in rows[2:]:
        [float(x) for x in r]
    return rows[2:]


# -- the command line: numbers where they enter, bounded work ------------------------------------
CLI_CASES: dict[str, tuple[list[str], list[str]]] = {
    "stop_time_nan": (["--stop-time", "nan"], ["--stop-time", "not a finite number"]),
    "stop_time_inf": (["--stop-time", "inf"], ["--stop-time", "not a finite number"]),
    "stop_time_text": (["--stop-time", "soon"], ["--stop-time", "invalid number"]),
    "realtime_nan": (["--realtime", "nan"], ["--realtime", "not a finite number"]),
    "rate_inf": (["--rate", "inf"], ["out of range", "0.1 to 100.0 Hz"]),
    "step_multiple_huge": (["--step-multiple", "a=1000000000"], ["--step-multiple", "from 1 to 1000"]),
    "step_multiple_zero": (["--step-multiple", "a=0"], ["--step-multiple", "from 1 to 1000"]),
    "set_nan": (["--set", "a.k=nan"], ["--set 'a.k=nan'", "finite number"]),
    "set_inf": (["--set", "a.k=-inf"], ["--set 'a.k=-inf'", "finite number"]),
    "until_nan": (["--until", "a.y_real > nan"], ["--until", "finite number"]),
    "out_empty": (["--out", ""], ["--out", "empty folder name"]),
    "stop_time_astronomical": (["--stop-time", "1e300"], ["stop time 1e+300 s", "more than 1e+09", "allowed: up to"]),
    "realtime_tiny": (["--realtime", "1e-300"], ["--realtime", "0.001 to 1e+06"]),
    "set_integer_beyond_32_bits": (["--set", "a.u_int=99999999999"],
                                   ["--set 'a.u_int=99999999999'", "outside the range of an FMI Integer"]),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_hostile_command_line(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    extra, fragments = CLI_CASES[case]
    cwd = os.getcwd()
    os.chdir(tmp_path)  # whatever happens, nothing may land in the working directory
    try:
        before = set(tmp_path.iterdir())
        argv = ["run", str(system), *extra] + ([] if "--out" in extra else ["--out", str(tmp_path / "out")])
        rc, err = run_cli(capsys, *argv)
    finally:
        os.chdir(cwd)
    assert_one_line(rc, err, *fragments)
    assert set(tmp_path.iterdir()) <= before | {tmp_path / "out"}
    assert not (tmp_path / "timeseries.csv").exists() and not (tmp_path / "run.json").exists()


def test_out_naming_a_file(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "results.txt"
    f.write_text("mine\n")
    rc, err = run_cli(capsys, "run", str(system), "--out", str(f))
    assert_one_line(rc, err, str(f), "is a file, not a folder")
    assert f.read_text() == "mine\n"


def test_out_below_a_file(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "results.txt"
    f.write_text("mine\n")
    rc, err = run_cli(capsys, "run", str(system), "--out", str(f / "run1"))
    assert_one_line(rc, err, str(f / "run1"), "cannot create the results folder", "Not a directory")


def test_out_in_a_read_only_place(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    ro = tmp_path / "ro"
    ro.mkdir()
    if os.geteuid() == 0:  # root writes through permissions: a read-only file system instead
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(ro)],
                          capture_output=True).returncode:
            pytest.skip("root, and no read-only tmpfs can be mounted here")
    else:
        ro.chmod(0o555)
    try:
        rc, err = run_cli(capsys, "run", str(system), "--out", str(ro / "run1"))
    finally:
        if os.geteuid() == 0:
            subprocess.run(["umount", str(ro)], check=False)
        else:
            ro.chmod(0o755)
    assert_one_line(rc, err, str(ro / "run1"), "cannot create the results folder")


def test_export_into_a_directory(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "exports"
    target.mkdir()
    rc, err = run_cli(capsys, "export", str(system), "--container", str(target))
    assert_one_line(rc, err, "--container", "is a folder", "give the .fmu file")
    assert list(target.iterdir()) == []


def test_export_below_a_file(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "plain"
    f.write_text("x")
    rc, err = run_cli(capsys, "export", str(system), "--container", str(f / "sys.fmu"))
    assert_one_line(rc, err, "--container", "cannot create its folder")


def test_plot_window_nan_and_out_empty(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = run_cli(capsys, "plot", str(tmp_path), "--window", "nan", "10")
    assert_one_line(rc, err, "--window", "'nan' is not a time [s] (a finite number)")
    rc, err = run_cli(capsys, "plot", str(tmp_path), "--out", "")
    assert_one_line(rc, err, "--out", "empty folder name")


def test_study_out_empty_and_stop_time_nan(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    study = tmp_path / "s.yaml"
    study.write_text("study: s\nsystem: .\n")
    rc, err = run_cli(capsys, "study", "run", str(study), "--out", "")
    assert_one_line(rc, err, "--out", "empty folder name")
    rc, err = run_cli(capsys, "study", "run", str(study), "--stop-time", "nan")
    assert_one_line(rc, err, "--stop-time", "not a finite number")


def test_system_name_is_not_a_path(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Without --out the folder is results/<system name>-<time>: a name '../../x' must not climb out."""
    ssd = system / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text().replace('name="TestSystem"', 'name="../../escaped"'))
    work = tmp_path / "work"
    work.mkdir()
    cwd = os.getcwd()
    os.chdir(work)
    try:
        rc, err = run_cli(capsys, "run", str(system))
    finally:
        os.chdir(cwd)
    assert_one_line(rc, err, "the system's name", "'../../escaped'", "one path component", "--out")
    assert not list(tmp_path.glob("escaped*")) and not list(work.iterdir())


@pytest.mark.parametrize("command", ["run", "info", "validate"])
def test_doctype_in_a_parameter_file(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     command: str) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("SECRET-7f3a9c")
    ssv = tmp_path / "xxe.ssv"
    ssv.write_text(f'<?xml version="1.0"?>\n<!DOCTYPE p [<!ENTITY x SYSTEM "file://{secret}">]>\n'
                   '<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" '
                   'version="1.0" name="&x;"><ssv:Parameters/></ssv:ParameterSet>\n')
    try:
        rc = main([command, str(system), "--params", str(ssv)])
    except SystemExit as exc:
        rc = int(exc.code or 0)
    out, err = capsys.readouterr()
    lines = [ln for ln in (out if command == "validate" else err).splitlines() if ln.strip()]
    if command == "validate":  # the problems on stdout, their count on stderr, exit code 1 (findings)
        assert rc == 1 and len(lines) >= 1 and f"{len(lines)} problem(s)" in err
    else:
        assert rc == 2 and len(lines) == 1, lines
    assert str(ssv) in lines[0] and ("DOCTYPE" in lines[0] or "external entity" in lines[0]), lines
    assert "SECRET-7f3a9c" not in out + err  # the entity was never expanded


@pytest.mark.parametrize("what", ["directory", "missing"])
def test_scenario_that_is_not_a_file(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     what: str) -> None:
    scenario = tmp_path / "scenario.yaml"
    if what == "directory":
        scenario.mkdir()
    rc, err = run_cli(capsys, "run", str(system), "--scenario", str(scenario), "--out", str(tmp_path / "out"))
    assert_one_line(rc, err, str(scenario), "cannot read the scenario",
                    "Is a directory" if what == "directory" else "No such file")


def test_summary_of_a_folder_whose_timeseries_is_a_directory(tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "run" / "timeseries.csv").mkdir(parents=True)
    rc, err = run_cli(capsys, "summary", str(tmp_path / "run"))
    assert_one_line(rc, err, "timeseries.csv")


def test_scenario_integer_beyond_32_bits(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = tmp_path / "s.yaml"
    scenario.write_text("events:\n  - at: 0.5\n    set: {a.u_int: 4294967296}\n")  # 2**32 would wrap to 0
    rc, err = run_cli(capsys, "run", str(system), "--scenario", str(scenario), "--out", str(tmp_path / "out"))
    assert_one_line(rc, err, f"{scenario}:3:", "a.u_int", "outside the range of an FMI Integer")


# -- the results folder --------------------------------------------------------------------------
def test_links_in_the_results_folder_are_neither_followed_nor_replaced(system: Path, tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """Links of the user's where a run writes: refused before the run (one line naming them); the links and
    the files they point to are left as they were."""
    out = tmp_path / "out"
    out.mkdir()
    precious = {}
    for name in ("timeseries.csv", "run.json", "cli_parameters.ssv"):
        target = tmp_path / f"precious-{name}"
        target.write_text(f"do not overwrite {name}\n")
        precious[target] = target.read_bytes()
        (out / name).symlink_to(target)
    rc, err = run_cli(capsys, "run", str(system), "--out", str(out), "--set", "a.k=2.0", "--format", "csv")
    assert_one_line(rc, err, str(out), "timeseries.csv", "run.json", "cli_parameters.ssv", "not written by a run")
    for target, content in precious.items():
        assert target.read_bytes() == content, target
        assert (out / target.name.removeprefix("precious-")).is_symlink()


def test_a_second_run_replaces_only_what_the_first_wrote(system: Path, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    rc, err = run_cli(capsys, "run", str(system), "--out", str(out), "--format", "csv")
    assert rc == 0, err
    (out / "notes.txt").write_text("the user's own file\n")
    rc, err = run_cli(capsys, "run", str(system), "--out", str(out), "--format", "parquet")
    assert rc == 0, err
    assert not (out / "timeseries.csv").exists()  # the first run's time series, in another format: removed
    assert (out / "notes.txt").read_text() == "the user's own file\n"
    assert json.loads((out / "run.json").read_text())["files"] == ["timeseries.parquet", "run.json"]


def test_a_folder_in_use_is_refused(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    with ResultsFolder(out):  # the lock another run holds (flock: per open file, so this process counts too)
        atomic_write(out / "timeseries.csv", "time_s\n0\n")  # written by that run (recorded as its own)
        rc, err = run_cli(capsys, "run", str(system), "--out", str(out))
        assert_one_line(rc, err, str(out), "in use by another run", f"pid {os.getpid()}")
        assert (out / "timeseries.csv").read_text() == "time_s\n0\n"  # the other run's file is untouched
    rc, err = run_cli(capsys, "run", str(system), "--out", str(out))  # released: the folder is free again
    assert rc == 0, err


# -- signals and faults --------------------------------------------------------------------------
def start_run(system: Path, out: Path, tmp: Path, stop_s: float = 120.0) -> subprocess.Popen[bytes]:
    """A paced run (real time) in a child process, with its own temporary folder."""
    tmp.mkdir(exist_ok=True)
    env = dict(os.environ, TMPDIR=str(tmp))
    return subprocess.Popen([sys.executable, "-m", "openemss.orchestrator.cli", "run", str(system), "--out", str(out),
                             "--stop-time", str(stop_s), "--realtime", "1", "--rate", "100", "--format", "csv"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)


def wait_for_rows(proc: subprocess.Popen[bytes], csv_path: Path, rows: int = 2, timeout_s: float = 60.0) -> None:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        assert proc.poll() is None, proc.communicate()
        if csv_path.is_file() and csv_path.read_bytes().count(b"\n") > rows:
            return
        time.sleep(0.1)
    proc.kill()
    raise AssertionError("the run wrote no rows in time")


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_ends_the_run_cleanly(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     signum: int, code: int) -> None:
    out = tmp_path / "out"
    proc = start_run(system, out, tmp_path / "tmp")
    wait_for_rows(proc, out / "timeseries.csv")
    if signum == signal.SIGTERM:  # meanwhile a second run into the same folder is refused
        rc, err = run_cli(capsys, "run", str(system), "--out", str(out))
        assert_one_line(rc, err, "in use by another run", f"pid {proc.pid}")
    proc.send_signal(signum)
    _, stderr = proc.communicate(timeout=60)
    lines = [ln for ln in stderr.decode().splitlines() if ln.strip()]
    assert proc.returncode == code, lines
    assert len(lines) == 1 and f"interrupted by {signal.Signals(signum).name}" in lines[0], lines
    assert "fmi2" not in lines[0] and "Traceback" not in lines[0]
    info = json.loads((out / "run.json").read_text())
    rows = complete_rows(out / "timeseries.csv")
    assert info["status"] == "interrupted" and "interrupted by" in info["error"]
    assert float(rows[-1][0]) == pytest.approx(info["stop_time_s"])  # every step up to the stop is kept
    assert len(rows) == info["steps"] + 1
    assert not list((tmp_path / "tmp").glob("emss_fmu_*"))  # the extracted FMUs are removed


def test_kill_9_leaves_complete_rows(system: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = start_run(system, out, tmp_path / "tmp")
    wait_for_rows(proc, out / "timeseries.csv", rows=50)
    proc.kill()
    proc.wait(timeout=30)
    rows = complete_rows(out / "timeseries.csv")
    times = [float(r[0]) for r in rows]
    assert len(rows) >= 50 and times == sorted(times)
    assert json.loads((out / "run.json").read_text())["status"] == "running"  # says it never closed


def _check_full_disk(out: Path, rc: int, err: list[str], cause: str, fmt: str = "csv") -> None:
    assert_one_line(rc, err, "cannot write", FORMATS[fmt].file_name, cause, "rows up to t =")
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "failed" and cause in info["error"]
    if fmt == "csv":
        rows = complete_rows(out / "timeseries.csv")
        assert rows and float(rows[-1][0]) < 1000.0
    else:  # every part on disk whole; the one being written when the disk filled is not left behind
        t = read_timeseries(out).data["time_s"]
        assert len(t) and t[-1] < 1000.0 and np.allclose(np.diff(t), 0.01)
        assert not list((out / FORMATS[fmt].file_name).glob(".*.tmp"))


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_full_disk_is_one_line_and_a_closed_run_json(system: Path, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str], fmt: str) -> None:
    """ENOSPC on a 1 MiB tmpfs: the run fails with one line; run.json says failed; every row is whole."""
    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(disk)], capture_output=True).returncode:
        pytest.skip("cannot mount a 1 MiB tmpfs here (needs root); the file-size limit case covers the path")
    try:
        if fmt == "parquet":  # compressed, the rows of this (constant) run would fit: leave about 300 KiB
            (disk / "ballast").write_bytes(bytes(724 * 1024))
        rc, err = run_cli(capsys, "run", str(system), "--out", str(disk / "out"), "--stop-time", "1000",
                          "--rate", "100", "--format", fmt, "--record-inputs")
        _check_full_disk(disk / "out", rc, err, "No space left on device", fmt)
    finally:
        if subprocess.run(["umount", str(disk)], check=False).returncode:
            subprocess.run(["umount", "-l", str(disk)], check=False)


def _limit_file_size() -> None:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write beyond the limit fails with EFBIG instead
    resource.setrlimit(resource.RLIMIT_FSIZE, (FSIZE_LIMIT, FSIZE_LIMIT))


def test_file_size_limit_is_one_line_and_a_closed_run_json(system: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "run", str(system), "--out", str(out),
                           "--stop-time", "1000", "--rate", "100", "--no-post-run", "--format", "csv"],
                          capture_output=True, preexec_fn=_limit_file_size, timeout=300)
    err = [ln for ln in proc.stderr.decode().splitlines() if ln.strip()]
    _check_full_disk(out, proc.returncode, err, "File too large")
    assert (out / "timeseries.csv").stat().st_size <= FSIZE_LIMIT
