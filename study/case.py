"""One case of a study: its definition, its folder, and running it as ``emss run`` in its worker's case process.

pythonfmu FMUs of the same model share one interpreter, so a case never runs beside
another in one process: :func:`run_case` (the Dask task) hands ``emss run ...`` to its
worker's case process (:mod:`.warm`: one case at a time, its FMUs reset between cases, tied
to its worker) with the case's parameters written to ``case.ssv`` in the case folder; the case
writes into that folder (``timeseries.parquet/``, ``run.json``, ``stdout.log``, ``stderr.log``,
``command.txt``: the same case in a process of its own) and the outcome is read back
(``run.json`` and, where the run writes one, ``summary.json``).

A case that ran to its end (completed, or failed with an error of the run
itself) leaves ``done.json`` holding the digest of its definition (the case's
parameters and the contents of every file it reads); a rerun of the study skips
it while the digest is unchanged.
"""
from __future__ import annotations

import hashlib
import json
import os
import signal
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from lxml import etree

from openemss.orchestrator.master import algorithm_registry
from openemss.orchestrator.results import atomic_write, check_name
from openemss.report.files import SUMMARY

from .child import PARENT_ENV
from .lock import LOCK_NAME, wait_released
from .warm import run_warm

__all__ = ["CaseDef", "CaseResult", "command", "run_case", "read_done", "DONE_FILE", "CASE_SSV"]

DONE_FILE = "done.json"
#: Exit codes of a case ended by SIGINT or SIGTERM (emss run stops cleanly with 128 + the signal).
INTERRUPTED_CODES = (128 + signal.SIGINT, 128 + signal.SIGTERM)
CASE_SSV = "case.ssv"
#: How long a case waits for an earlier attempt of it to release its folder [s]; then its run says it is busy.
RELEASE_TIMEOUT_S = 60.0
ValueT = float | int | bool | str


@dataclass(frozen=True)
class CaseDef:
    """What one case runs; every path is absolute so that any worker can run it."""

    name: str
    labels: tuple[tuple[str, str], ...]  # study dimension -> value label (variant, mission, scenario, grid)
    system: str
    params: tuple[str, ...] = ()
    values: tuple[tuple[str, ValueT], ...] = ()  # written to case.ssv, typed as the FMU variables
    scenario: str | None = None
    stop_time_s: float | None = None
    rate_hz: float | None = None
    algorithm: str = algorithm_registry.DEFAULT
    record: tuple[str, ...] = ()
    record_every: int = 1
    pre_run: bool = False  # emss run's pre-run checks (--no-pre-run without)
    figures: bool = False  # the report's figures after the run (--no-figures without)
    digest: str = ""  # of the definition and the contents of the files it reads


@dataclass
class CaseResult:
    """The outcome of one case, one row of the study table."""

    name: str
    status: str  # completed, failed (the run's own error), killed (process or worker died), skipped
    error: str = ""
    returncode: int | None = None
    attempts: int = 1
    sim_time_s: float | None = None
    wall_time_s: float | None = None
    process_time_s: float | None = None  # wall time of the case in its (warm) case process
    #: The case's wall time [s] in its task, split: before the first step (folder, reading, FMU reset or
    #: instantiation, initialization), the steps, after the last step (recorder, summary, dataset, done marker)
    setup_s: float | None = None
    stepping_s: float | None = None
    writing_s: float | None = None
    summary: dict[str, Any] = field(default_factory=dict)
    digest: str = ""

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> CaseResult:
        known = {k: d[k] for k in cls.__dataclass_fields__ if k in d}
        return cls(**known)


def case_dir(out: Path | str, name: str) -> Path:
    """The folder of case `name` in the study folder `out` (`name` must be one path component)."""
    return Path(out) / "cases" / check_name(name, "case name")


def write_case_ssv(path: Path, values: tuple[tuple[str, ValueT], ...]) -> Path:
    """The case's parameter values as an SSP parameter set (system-level names component.variable)."""
    from openemss.orchestrator.ssp.write import ParameterSet

    root = ParameterSet("case", dict(values)).element()
    path.parent.mkdir(parents=True, exist_ok=True)
    etree.ElementTree(root).write(str(path), xml_declaration=True, encoding="UTF-8", pretty_print=True)
    return path


def emss_args(case: CaseDef, folder: Path) -> list[str]:
    """The ``emss`` arguments of a case (``run ...``), writing into `folder`. The study checks its FMUs against
    their sources once before the cases (``--no-build``); a case writes its summary, and its figures only
    when the study asks (else ``--no-figures``: ``emss plot`` draws them from the case's folder)."""
    cmd = ["run", case.system, "--out", str(folder), "--algorithm", case.algorithm, "--record-every",
           str(case.record_every), "--json", "--no-build", *([] if case.figures else ["--no-figures"])]
    params = [*case.params, *([str(folder / CASE_SSV)] if case.values else [])]
    if params:
        cmd += ["--params", *params]
    if case.stop_time_s is not None:
        cmd += ["--stop-time", repr(case.stop_time_s)]
    if case.rate_hz is not None:
        cmd += ["--rate", repr(case.rate_hz)]
    if case.scenario:
        cmd += ["--scenario", case.scenario]
    if case.record:
        cmd += ["--record", *case.record]
    if not case.pre_run:
        cmd += ["--no-pre-run"]
    return cmd


def command(case: CaseDef, folder: Path, python: str | None = None) -> list[str]:
    """The command line of a case in a process of its own (``command.txt``: the case run again by hand)."""
    return [python or sys.executable, "-m", "openemss.study.child", *emss_args(case, folder)]


def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _last_line(path: Path) -> str:
    try:
        lines = [ln.strip() for ln in path.read_text(encoding="utf-8", errors="replace").splitlines() if ln.strip()]
    except OSError:
        return ""
    return lines[-1] if lines else ""


def read_done(out: Path | str, case: CaseDef) -> CaseResult | None:
    """The recorded result of a case that is done with this very definition (same digest), else None."""
    data = _read_json(case_dir(out, case.name) / DONE_FILE)
    if data.get("digest") != case.digest or data.get("status") not in ("completed", "failed"):
        return None
    return CaseResult.from_dict(data)


def _child_env() -> dict[str, str]:
    env = dict(os.environ)
    # One case per core: numerical libraries in the child stay single-threaded; no display.
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1", MPLBACKEND="Agg")
    env.pop("EMSS_DEBUG", None)
    env[PARENT_ENV] = str(os.getpid())
    return env


def run_case(case: CaseDef, out: str, attempt: int = 1) -> CaseResult:
    """Run one case in a child process (the Dask task); never raises for a failing case.

    Parameters
    ----------
    case : CaseDef
        The case.
    out : str
        The study folder; the case writes into ``out/cases/<name>``.
    attempt : int
        1 for the first try, 2 for the retry after a killed worker or process.

    Returns
    -------
    CaseResult
        ``completed``; ``failed`` with the run's one-line error; or ``killed`` when the
        child process died from a signal (the study retries it once).
    """
    t0 = time.perf_counter()
    folder = case_dir(out, case.name)
    folder.mkdir(parents=True, exist_ok=True)
    wait_released(folder / LOCK_NAME, RELEASE_TIMEOUT_S)  # an earlier attempt still stopping (its worker died)
    (folder / DONE_FILE).unlink(missing_ok=True)
    for stale in ("run.json", SUMMARY):
        (folder / stale).unlink(missing_ok=True)
    if case.values:
        write_case_ssv(folder / CASE_SSV, case.values)
    atomic_write(folder / "command.txt", " ".join(command(case, folder)) + "\n")
    t1 = time.perf_counter()
    rc = run_warm(emss_args(case, folder), folder, _child_env())
    elapsed = time.perf_counter() - t1
    run = _read_json(folder / "run.json")
    summary = _read_json(folder / SUMMARY)
    if rc == 0:
        status, error = "completed", ""
    elif rc < 0 or rc in INTERRUPTED_CODES:  # died from a signal, or ended by one as emss run does (128 + N)
        n = -rc if rc < 0 else rc - 128
        name = signal.Signals(n).name if n in signal.Signals._value2member_map_ else str(n)
        status, error = "killed", f"the case's process was {'killed' if rc < 0 else 'interrupted'} by signal {name}"
    else:
        status = "failed"
        error = _last_line(folder / "stderr.log") or str(run.get("error") or f"emss run exited with code {rc}")
    result = CaseResult(case.name, status, error, rc, attempt,
                        sim_time_s=_float(summary.get("sim_time_s", run.get("stop_time_s"))),
                        wall_time_s=_float(summary.get("wall_time_s", run.get("wall_time_s"))),
                        process_time_s=elapsed, summary=summary, digest=case.digest)
    timing = run.get("timing") if isinstance(run.get("timing"), dict) else {}
    stepping, writing = _float(timing.get("stepping_s")) or 0.0, _float(timing.get("writing_s")) or 0.0
    if status in ("completed", "failed"):
        from .dataset import publish_case

        publish_case(Path(out), case.name, folder)  # before done.json: a case marked done is in the dataset
    now = time.perf_counter()
    result.stepping_s = stepping
    result.writing_s = writing + (now - t1 - elapsed)  # and the dataset
    result.setup_s = max(now - t0 - stepping - result.writing_s, 0.0)
    if status in ("completed", "failed"):
        mark_done(out, result)
    return result


def mark_done(out: Path | str, result: CaseResult) -> None:
    """Write the done marker of a case (atomically)."""
    folder = case_dir(out, result.name)
    folder.mkdir(parents=True, exist_ok=True)
    atomic_write(folder / DONE_FILE, json.dumps(result.to_dict(), indent=2, default=str) + "\n")


def _float(v: Any) -> float | None:
    try:
        return None if v is None else float(v)
    except (TypeError, ValueError):
        return None


def file_digest(path: Path, cache: dict[Path, str]) -> str:
    """sha256 of a file's contents (of every file below a folder, by relative name)."""
    path = Path(path)
    if path not in cache:
        h = hashlib.sha256()
        files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
        for f in files:
            if f.name in (DONE_FILE,) or "__pycache__" in f.parts:
                continue
            h.update(str(f.relative_to(path) if path.is_dir() else f.name).encode())
            h.update(f.read_bytes())
        cache[path] = h.hexdigest()
    return cache[path]


def definition_digest(case: CaseDef, files: list[Path], cache: dict[Path, str]) -> str:
    """Digest of the case definition (without its name and digest) and of the files it reads."""
    d = asdict(case)
    for key in ("digest", "name", "pre_run", "figures"):  # checks before and figures after: the results stay
        d.pop(key)
    h = hashlib.sha256(json.dumps(d, sort_keys=True, default=str).encode())
    for f in files:
        h.update(file_digest(f, cache).encode())
    return h.hexdigest()[:16]
