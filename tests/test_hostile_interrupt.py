"""The hostile corpus, interruption and full disks (issue 33 point 5, and point 1's FMUs): SIGINT and SIGTERM
in every phase of ``build-fmus``, ``emss run`` and ``emss study run``, a full disk under ``build-fmus``, two
study runs into one folder.

A signal is sent in a known phase, never after a guessed sleep: the program, started with
``OPENEMSS_HOLD_AT=PHASE=FILE``, writes FILE when it enters PHASE and waits there, so the signal arrives
exactly there (``orchestrator/interrupt.py``). What is asserted is independent of the code under test: the
exit code (128 + the signal), the one stderr line, the files the test planted compared byte for byte, the
folders listed (no lock, no staging folder, no temporary file), run.json read back as JSON.
"""
from __future__ import annotations

import contextlib
import json
import os
import resource
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main
from openemss.study.lock import STUDY_LOCK, study_lock
from systems import Comp, wait_for, write_gain_pair, write_system

ROOT = Path(__file__).resolve().parent.parent
FSIZE_LIMIT = 100_000  # bytes per file: above every staged source file of Gain, below the FMU (0.2 MB)
HOLD_TIMEOUT_S = 300.0  # generous: start-up on a loaded 2-core machine; only a bound, never a measurement


@pytest.fixture()
def system(tmp_path: Path, fmu_dir: Path) -> Path:
    """Two Gain FMUs wired both ways, 1 s (as tests/test_hostile_runs.py's)."""
    return write_gain_pair(tmp_path / "sys", fmu_dir)

def _env(tmp_path: Path, hold: str | None = None, marker: Path | None = None) -> dict[str, str]:
    """The child's environment: its own TMPDIR (to see what it leaves there) and the phase to hold in."""
    temp = tmp_path / "tmp"
    temp.mkdir(exist_ok=True)
    env = dict(os.environ, TMPDIR=str(temp))
    env.pop("OPENEMSS_HOLD_AT", None)
    if hold is not None:
        env["OPENEMSS_HOLD_AT"] = f"{hold}={marker}"
    return env


def held(argv: list[str], phase: str, tmp_path: Path, **popen: object) -> subprocess.Popen[bytes]:
    """``argv`` started and waiting in ``phase`` (its marker file written)."""
    marker = tmp_path / f"held-{phase}"
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=_env(tmp_path, phase, marker), **popen)  # type: ignore[call-overload]
    # the marker holds the pid once written whole (it exists, empty, for a moment before)
    wait_for(lambda: marker.exists() and marker.read_text().strip() != "", proc, f"phase {phase}", HOLD_TIMEOUT_S)
    assert int(marker.read_text()) == proc.pid
    return proc


def interrupt_it(proc: subprocess.Popen[bytes], signum: int, send: bool = True) -> list[str]:
    """Send ``signum`` (unless sent already); the exit code must be 128 + it and stderr one line without a
    traceback."""
    if send:
        proc.send_signal(signum)
    _, err = proc.communicate(timeout=HOLD_TIMEOUT_S)
    lines = [ln for ln in err.decode().splitlines() if ln.strip()]
    assert proc.returncode == 128 + signum, lines
    assert len(lines) == 1, lines
    assert "Traceback" not in lines[0] and "internal error" not in lines[0]
    assert f"interrupted by {signal.Signals(signum).name}" in lines[0], lines
    return lines


def leftovers(tmp_path: Path) -> list[str]:
    """What the child left in its TMPDIR (staging folders, extracted FMUs, temporary files)."""
    return sorted(p.name for p in (tmp_path / "tmp").iterdir())


EMSS = [sys.executable, "-m", "openemss.orchestrator.cli"]
BUILD = [sys.executable, "-c", "import sys; from openemss.orchestrator.cli.entry import build_fmus; "
                               "sys.exit(build_fmus())"]


# -- build-fmus -----------------------------------------------------------------------------------
@pytest.fixture()
def built(tmp_path: Path, fmu_dir: Path) -> tuple[Path, bytes]:
    """A folder holding a valid Gain.fmu (the one a rebuild must not spoil) and its bytes."""
    out = tmp_path / "fmus"
    out.mkdir()
    data = (fmu_dir / "Gain.fmu").read_bytes()
    (out / "Gain.fmu").write_bytes(data)
    return out, data


def _build_argv(out: Path) -> list[str]:
    return [*BUILD, "--src", str(ROOT / "tests" / "fmus"), "--out", str(out), "gain", "--force"]


def test_build_fmus_interrupted_at_start_up(tmp_path: Path, built: tuple[Path, bytes]) -> None:
    out, data = built
    proc = held(_build_argv(out), "start-up", tmp_path)
    line = interrupt_it(proc, signal.SIGINT)[0]
    assert line.startswith("build-fmus: ") and "during start-up" in line
    assert (out / "Gain.fmu").read_bytes() == data and sorted(os.listdir(out)) == ["Gain.fmu"]


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_build_fmus_interrupted_while_building(tmp_path: Path, built: tuple[Path, bytes], signum: int) -> None:
    """Held with the staging folder full (the slave and its vendored code laid out): the signal leaves the
    old FMU byte for byte, nothing beside it, and no staging folder."""
    out, data = built
    proc = held(_build_argv(out), "build-stage", tmp_path)
    staging = [p for p in (tmp_path / "tmp").glob("emss_build_*/stage/*")]
    assert staging  # the case is real: there was something to remove
    line = interrupt_it(proc, signum)[0]
    assert "while building Gain.fmu" in line and str(out) in line
    assert (out / "Gain.fmu").read_bytes() == data and sorted(os.listdir(out)) == ["Gain.fmu"]
    assert leftovers(tmp_path) == []


def _limit_file_size() -> None:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write beyond the limit fails with EFBIG instead
    resource.setrlimit(resource.RLIMIT_FSIZE, (FSIZE_LIMIT, FSIZE_LIMIT))


def test_build_fmus_on_a_full_disk_keeps_the_old_fmu(tmp_path: Path, built: tuple[Path, bytes]) -> None:
    out, data = built
    assert len(data) > FSIZE_LIMIT
    proc = subprocess.run(_build_argv(out), capture_output=True, preexec_fn=_limit_file_size, env=_env(tmp_path),
                          timeout=HOLD_TIMEOUT_S)
    lines = [ln for ln in proc.stderr.decode().splitlines() if ln.strip()]
    assert proc.returncode == 2 and len(lines) == 1, lines
    assert "Traceback" not in lines[0] and "File too large" in lines[0]
    assert f"{out / 'Gain.fmu'} is unchanged" in lines[0]
    assert (out / "Gain.fmu").read_bytes() == data and sorted(os.listdir(out)) == ["Gain.fmu"]
    assert leftovers(tmp_path) == []


def test_the_fmu_copy_on_a_full_disk_leaves_the_target(tmp_path: Path) -> None:
    """The last step of a build (the FMU copied beside its target, then renamed), alone: a copy larger than the
    file-size limit fails with EFBIG naming the target; the target and its folder are as they were."""
    big = tmp_path / "new.fmu"
    big.write_bytes(os.urandom(3 * FSIZE_LIMIT))
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "Gain.fmu").write_bytes(b"the old FMU")
    code = textwrap.dedent(f"""
        import errno, sys
        from openemss.models.infra.files import atomic_copy
        try:
            atomic_copy({str(big)!r}, {str(folder / 'Gain.fmu')!r})
        except OSError as exc:
            print(errno.errorcode[exc.errno], exc.filename)
            sys.exit(0)
        sys.exit(1)
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, preexec_fn=_limit_file_size,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["EFBIG", str(folder / "Gain.fmu")]
    assert (folder / "Gain.fmu").read_bytes() == b"the old FMU" and os.listdir(folder) == ["Gain.fmu"]


# -- emss run ---------------------------------------------------------------------------------------
def _run_argv(system: Path, out: Path) -> list[str]:
    return [*EMSS, "run", str(system), "--out", str(out), "--format", "csv"]


@pytest.mark.parametrize("phase, signum, words", [
    ("start-up", signal.SIGINT, "emss: interrupted by SIGINT during start-up; nothing was run"),
    ("load", signal.SIGTERM, "emss run: interrupted by SIGTERM while loading the system; nothing was run"),
])
def test_run_interrupted_before_its_folder(system: Path, tmp_path: Path, phase: str, signum: int,
                                           words: str) -> None:
    out = tmp_path / "out"
    proc = held(_run_argv(system, out), phase, tmp_path, cwd=tmp_path)
    assert interrupt_it(proc, signum) == [words]
    assert not out.exists() and leftovers(tmp_path) == []


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_run_interrupted_before_the_first_step(system: Path, tmp_path: Path, signum: int) -> None:
    """The folder is taken and the FMUs instantiated: the signal leaves no lock, no extracted FMU, and a
    run.json that says the run was interrupted before its first step."""
    out = tmp_path / "out"
    proc = held(_run_argv(system, out), "pre-run", tmp_path)
    line = interrupt_it(proc, signum)[0]
    assert f"emss run: interrupted by {signal.Signals(signum).name} before the first step; nothing was run" in line
    assert not (out / ".emss.lock").exists() and not (out / "timeseries.csv").exists()
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "interrupted" and info["steps"] == 0 and "before the first step" in info["error"]
    assert leftovers(tmp_path) == []
    rc = main(["run", str(system), "--out", str(out), "--format", "csv", "--no-post-run"])  # the folder is free
    assert rc == 0 and json.loads((out / "run.json").read_text())["status"] == "completed"


def test_run_interrupted_during_its_report(system: Path, tmp_path: Path) -> None:
    """The run completed: its rows and run.json stay as they were written, the line says where they are."""
    out = tmp_path / "out"
    proc = held(_run_argv(system, out), "report", tmp_path)
    line = interrupt_it(proc, signal.SIGINT)[0]
    assert "during the report" in line and str(out) in line and "completed" in line
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "completed" and info["steps"] == 20
    rows = (out / "timeseries.csv").read_text().splitlines()
    assert len(rows) == 2 + 21 and float(rows[-1].split(",")[0]) == pytest.approx(1.0)
    assert not (out / ".emss.lock").exists() and leftovers(tmp_path) == []


def test_run_interrupted_during_the_project_fmu_build(tmp_path: Path) -> None:
    """The project's own system (ssp/): held where its FMUs are checked and built (the build itself is
    build-fmus's code, interrupted above); nothing runs, no results folder is made."""
    out = tmp_path / "out"
    proc = held([*EMSS, "run", "--out", str(out), "--stop-time", "1"], "build", tmp_path)
    assert interrupt_it(proc, signal.SIGTERM) == ["emss run: interrupted by SIGTERM during the FMU build; "
                                                  "nothing was run"]
    assert not out.exists() and leftovers(tmp_path) == []


def test_a_second_signal_does_not_cut_the_clean_up(system: Path, tmp_path: Path) -> None:
    """SIGTERM then SIGINT at once (an impatient user): one of them decides the exit and the line (two signals
    pending together are handled in signal-number order), the other does not cut the clean-up: the lock is
    still removed and run.json still written."""
    out = tmp_path / "out"
    proc = held(_run_argv(system, out), "pre-run", tmp_path)
    proc.send_signal(signal.SIGTERM)
    with contextlib.suppress(ProcessLookupError):
        proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=HOLD_TIMEOUT_S)
    lines = [ln for ln in err.decode().splitlines() if ln.strip()]
    assert len(lines) == 1 and proc.returncode in (130, 143), lines
    assert f"interrupted by {signal.Signals(proc.returncode - 128).name} before the first step" in lines[0]
    assert not (out / ".emss.lock").exists()
    assert json.loads((out / "run.json").read_text())["status"] == "interrupted"


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # as a shell starts a background job


def test_an_ignored_sigint_stays_ignored(system: Path, tmp_path: Path) -> None:
    """A command started with SIGINT ignored (``cmd &`` in a script) is not stopped by SIGINT; SIGTERM
    still ends it cleanly."""
    out = tmp_path / "out"
    proc = held(_run_argv(system, out), "pre-run", tmp_path, preexec_fn=_ignore_sigint)
    proc.send_signal(signal.SIGINT)
    with pytest.raises(subprocess.TimeoutExpired):
        proc.wait(timeout=2)  # still held: the bound of a negative, not a measurement
    interrupt_it(proc, signal.SIGTERM)
    assert not (out / ".emss.lock").exists()


def test_a_signal_in_a_deferred_section_is_raised_at_its_end(tmp_path: Path) -> None:
    """interrupt.deferred(): a lock taken and its release registered are never separated by a signal."""
    code = textwrap.dedent("""
        import os, signal, sys
        from openemss.orchestrator import interrupt
        interrupt.install()
        steps = []
        try:
            with interrupt.deferred():
                os.kill(os.getpid(), signal.SIGTERM)
                steps.append("after the signal, inside")
        except KeyboardInterrupt as exc:
            steps.append(f"raised at the end: {exc.signum}")
        print(steps)
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(["after the signal, inside", f"raised at the end: {int(signal.SIGTERM)}"])


# -- studies ----------------------------------------------------------------------------------------
def _study(tmp_path: Path, system: Path, stop_s: float) -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(f"study: s\nsystem: {system}\nstop_time_s: {stop_s}\nvariants:\n"
                    "  - {name: a, values: {a.k: 1.0}}\n  - {name: b, values: {a.k: 2.0}}\n", encoding="utf-8")
    return path


def test_a_study_folder_in_use_is_refused(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "study"
    out.mkdir()
    (out / "study.csv").write_text("case\nmine\n")
    with study_lock(out):  # the lock another study run holds
        rc = main(["study", "run", str(_study(tmp_path, system, 1.0)), "--out", str(out)])
        err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
        assert rc == 2 and len(err) == 1, err
        assert str(out) in err[0] and "in use by another study run" in err[0] and f"pid {os.getpid()}" in err[0]
        assert (out / "study.csv").read_text() == "case\nmine\n" and not (out / "cases").exists()
    assert not (out / STUDY_LOCK).exists()


def test_a_study_interrupted_stops_its_cases_cleanly(system: Path, tmp_path: Path) -> None:
    """SIGINT to ``emss study run`` while both cases run: each case stops as emss run does (run.json
    'interrupted', rows kept, its lock released), the study lock is removed, one line says so."""
    out = tmp_path / "study"
    proc = subprocess.Popen([*EMSS, "study", "run", str(_study(tmp_path, system, 1e6)), "--out", str(out),
                             "--workers", "2"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=_env(tmp_path))
    wait_for(lambda: all((out / "cases" / n / "timeseries.parquet").exists() for n in "ab"), proc,
             "both cases run", HOLD_TIMEOUT_S)
    assert (out / STUDY_LOCK).exists()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=HOLD_TIMEOUT_S)
    lines = [ln for ln in err.decode().splitlines() if ln.strip() and not ln.startswith("study: ")]  # progress
    assert proc.returncode == 130 and len(lines) == 1, lines
    assert "emss study: interrupted by SIGINT during the study" in lines[0] and "Traceback" not in err.decode()
    assert not (out / STUDY_LOCK).exists()
    for name in "ab":
        case = out / "cases" / name
        assert not (case / ".emss.lock").exists() and not (case / "done.json").exists()
        assert json.loads((case / "run.json").read_text())["status"] == "interrupted"



SLOW_START = '''
import os
import time

from pythonfmu import Fmi2Causality, Fmi2Slave, Real


class SlowStart(Fmi2Slave):
    """When SLOW_START_MARKER names a file, writes it in its constructor (fmi2Instantiate) and waits there
    until the file SLOW_START_RELEASE exists: the run is inside the FMU's own code when the signal comes."""

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.y = 0.0
        self.register_variable(Real("y", causality=Fmi2Causality.output, description="Zero [-]"))
        marker = os.environ.get("SLOW_START_MARKER")
        if marker:
            with open(marker, "w") as f:
                f.write(str(os.getpid()))
            while not os.path.exists(os.environ["SLOW_START_RELEASE"]):
                time.sleep(0.05)

    def do_step(self, current_time: float, step_size: float) -> bool:
        return True
'''


def test_a_signal_inside_an_fmu_call_stops_the_run_after_it(tmp_path: Path) -> None:
    """SIGTERM while the FMU's Python code runs inside fmi2Instantiate: the call is not cut (an FMU left in
    the middle of its own code is not freed safely); when it returns, the run stops before its first step,
    with one line, 143, no lock and run.json 'interrupted'."""
    from openemss.orchestrator.fmu.build import ensure_built

    src = tmp_path / "src"
    src.mkdir()
    (src / "slow_start.py").write_text(SLOW_START, encoding="utf-8")
    ensure_built(src, tmp_path / "fmus")
    system = tmp_path / "sys"
    write_system(system, tmp_path / "fmus", [Comp("s", "SlowStart.fmu", [("y", "output", "Real")])], [],
                 stop_time=1.0)
    out, marker, release = tmp_path / "out", tmp_path / "in-the-fmu", tmp_path / "release"
    proc = subprocess.Popen(_run_argv(system, out), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=dict(_env(tmp_path), SLOW_START_MARKER=str(marker), SLOW_START_RELEASE=str(release)))
    wait_for(marker.exists, proc, "the FMU's constructor runs", HOLD_TIMEOUT_S)
    proc.send_signal(signal.SIGTERM)
    with pytest.raises(subprocess.TimeoutExpired):
        proc.wait(timeout=1)  # still in the FMU's call (the bound of a negative, not a measurement)
    release.touch()
    line = interrupt_it(proc, signal.SIGTERM, send=False)[0]
    assert line.startswith("emss run: interrupted by SIGTERM at t = 0 s"), line
    assert not (out / ".emss.lock").exists()
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "interrupted" and info["steps"] == 0
