"""Run the cases of a study on Dask: a LocalCluster by default, or a scheduler by address.

Each case is one Dask task (:func:`.case.run_case`) that runs ``emss run`` in a child
process, so cases never share an interpreter. A case already done with the same
definition is skipped; a case whose worker (or child process) died is submitted once
more and recorded as failed if it dies again; a failing case is recorded with its
error and the others go on. The study table ``study.csv`` is rewritten after every
case, and the progress (done, running, failed, waiting, ETA) goes to stderr.
"""
from __future__ import annotations

import collections
import contextlib
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

from openemss.orchestrator.cli.api import ensure_project_fmus

from .case import CaseDef, CaseResult, case_dir, read_done, run_case
from .lock import LOCK_NAME, wait_released
from .spec import StudyError
from .table import write_table

__all__ = ["StudyOutcome", "Progress", "check_fmus", "run_cases", "TABLE_FILE"]

TABLE_FILE = "study.csv"
#: Attempts of a case whose worker or process died (the first run and one retry).
MAX_ATTEMPTS = 2
#: How long an interrupted study waits for its running cases to stop [s] (a run stops after its current step).
STOP_TIMEOUT_S = 60.0
Task = Callable[[CaseDef, str, int], CaseResult]


@dataclass
class StudyOutcome:
    """What a study run did: results by case name, the cases run now and skipped, the table."""

    out: Path
    table: Path
    results: dict[str, CaseResult]
    ran: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    wall_time_s: float = 0.0
    workers: int = 0
    slots: int = 0  # cases the cluster runs at once (its threads)

    @property
    def failed(self) -> list[str]:
        return [n for n, r in self.results.items() if r.status != "completed"]

    @property
    def stepping_fraction(self) -> float | None:
        """The share of the cluster's time (wall time x slots) that the cases run now spent stepping."""
        if not self.ran or self.wall_time_s <= 0 or self.slots < 1:
            return None
        stepping = sum(self.results[n].stepping_s or 0.0 for n in self.ran)
        return stepping / (self.wall_time_s * self.slots)


class Progress:
    """One line per finished case on `stream`: done, running, failed, waiting and the ETA."""

    def __init__(self, total: int, skipped: int, slots: int, stream: TextIO | None = None) -> None:
        self.total, self.skipped, self.slots = total, skipped, max(slots, 1)
        self.stream = stream if stream is not None else sys.stderr
        self.done = self.failed = 0
        self.t0 = time.perf_counter()

    def line(self, pending: int) -> str:
        elapsed = time.perf_counter() - self.t0
        finished = self.done + self.failed
        running = min(pending, self.slots)
        eta = (f"ETA {_duration(elapsed / finished * pending)}" if finished and pending else
               "ETA --" if pending else f"took {_duration(elapsed)}")
        return (f"{self.skipped + finished}/{self.total} done ({self.failed} failed, {self.skipped} skipped), "
                f"{running} running, {pending - running} waiting; {eta}")

    def case(self, result: CaseResult, pending: int) -> None:
        if result.status == "completed":
            self.done += 1
        else:
            self.failed += 1
        what = result.status + (f": {result.error}" if result.error else "")
        t = f" in {result.process_time_s:.1f} s" if result.process_time_s is not None else ""
        self.stream.write(f"study: case {result.name} {what}{t} | {self.line(pending)}\n")
        self.stream.flush()

    def note(self, text: str) -> None:
        self.stream.write(f"study: {text}\n")
        self.stream.flush()


def _duration(s: float) -> str:
    s = max(s, 0.0)
    if s < 90:
        return f"{s:.0f} s"
    if s < 5400:
        return f"{s / 60:.1f} min"
    return f"{s / 3600:.1f} h"


def _client(scheduler: str | None, workers: int) -> tuple[Any, Any]:
    """A Dask client and the LocalCluster it owns (None for a scheduler address)."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="15s"), None
        except (OSError, TimeoutError) as exc:
            raise StudyError(f"--scheduler {scheduler}: cannot connect ({type(exc).__name__}: {exc})") from None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=40)
    return Client(cluster), cluster


def _stop(client: Any, cluster: Any, out: Path, running: Sequence[CaseDef]) -> None:
    """Close the cluster (its workers end; each running case's process gets SIGTERM from its worker's end,
    :mod:`.child`) and wait for those cases to stop, their folders' locks released and run.json closed."""
    with contextlib.suppress(Exception):  # the study ends: whatever the cluster says while closing
        client.close()
        if cluster is not None:
            cluster.close()
    for c in running:
        wait_released(case_dir(out, c.name) / LOCK_NAME, STOP_TIMEOUT_S)


def check_fmus(systems: Sequence[str], stream: TextIO | None = None) -> None:
    """Build the project's own FMUs of ``systems`` that are missing or stale, once for the study: its cases run
    with ``emss run --no-build`` (each would check them again); each FMU built is said on ``stream``."""
    for system in dict.fromkeys(systems):
        ensure_project_fmus(Path(system), lambda line: Progress(0, 0, 1, stream).note(line))


def run_cases(cases: Sequence[CaseDef], out: Path, scheduler: str | None = None, workers: int | None = None,
              retry_failed: bool = False, task: Task = run_case, stream: TextIO | None = None) -> StudyOutcome:
    """Run every case not yet done into ``out/cases/<name>``; write ``out/study.csv``.

    Parameters
    ----------
    cases : sequence of CaseDef
        The cases (:func:`.plan.expand_cases`).
    out : Path
        The study folder (must be visible to the workers under the same path).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``); default: a LocalCluster.
    workers : int, optional
        Worker processes of the LocalCluster (one thread each); default: the number of cores.
    retry_failed : bool
        Run cases again that failed in an earlier run (by default they are done).
    task : callable
        The Dask task ``task(case, out, attempt) -> CaseResult`` (tests replace it).
    stream : text stream, optional
        Where the progress goes (default: stderr).
    """
    import dask
    from distributed import CancelledError, KilledWorker, wait

    out = Path(out).resolve()
    (out / "cases").mkdir(parents=True, exist_ok=True)
    table = out / TABLE_FILE
    results: dict[str, CaseResult] = {}
    todo: list[CaseDef] = []
    for c in cases:
        r = read_done(out, c)
        if r is not None and (r.status == "completed" or not retry_failed):
            results[c.name] = r
        else:
            todo.append(c)
    skipped = [c.name for c in cases if c.name in results]
    outcome = StudyOutcome(out, table, results, skipped=skipped)
    ran: set[str] = set()
    write_table(table, cases, results, ran)
    t0 = time.perf_counter()
    if not todo:
        progress = Progress(len(cases), len(skipped), 1, stream)
        progress.note(f"all {len(cases)} case(s) already done with the same definition; nothing to run "
                      f"(table: {table})")
        return outcome
    check_fmus([c.system for c in todo], stream)
    n_workers = max(1, min(workers or os.cpu_count() or 1, len(todo)))
    # A LocalCluster fails a task at the first death of its worker, so that the retry is ours (one). Cases
    # are handed to the scheduler only as worker threads are free (never more in flight than threads), so
    # no case waits on a worker: a worker that dies takes only the case it was running, and a case that
    # was still waiting is not charged an attempt for it.
    with dask.config.set({"distributed.scheduler.allowed-failures": 0, "distributed.scheduler.worker-saturation": 1.0}):
        client, cluster = _client(scheduler, n_workers)
        by_key: dict[str, tuple[CaseDef, int]] = {}
        try:
            slots = sum(client.nthreads().values()) or n_workers
            outcome.workers, outcome.slots = len(client.nthreads()), slots
            progress = Progress(len(cases), len(skipped), slots, stream)
            where = f"scheduler {scheduler}" if scheduler else f"a LocalCluster of {n_workers} worker process(es)"
            progress.note(f"{len(todo)} case(s) to run on {where} ({len(skipped)} already done); results in {out}")
            pending: set[Any] = set()
            waiting: collections.deque[tuple[CaseDef, int]] = collections.deque((c, 1) for c in todo)

            def fill() -> None:
                """Submit waiting cases while fewer are in flight than the cluster has threads."""
                free = max(sum(client.nthreads().values()), 1) - len(pending)
                while waiting and free > 0:
                    c, attempt = waiting.popleft()
                    f = client.submit(task, c, str(out), attempt, key=f"case-{c.name}-{c.digest}-{attempt}",
                                      pure=False, retries=0)
                    by_key[f.key] = (c, attempt)
                    pending.add(f)
                    free -= 1

            fill()
            while pending:
                finished, _ = wait(list(pending), timeout=None, return_when="FIRST_COMPLETED")
                for f in finished:
                    pending.discard(f)
                    c, attempt = by_key.pop(f.key)
                    try:
                        r = f.result()
                    except (KilledWorker, CancelledError) as exc:
                        r = CaseResult(c.name, "killed", f"its worker died ({type(exc).__name__})", attempts=attempt,
                                       digest=c.digest)
                    except Exception as exc:  # the task itself raised: record it, go on
                        r = CaseResult(c.name, "failed", f"{type(exc).__name__}: {exc}", attempts=attempt,
                                       digest=c.digest)
                    r.attempts = attempt
                    if r.status == "killed" and attempt < MAX_ATTEMPTS:
                        progress.note(f"case {c.name}: {r.error}; retrying it once")
                        waiting.appendleft((c, attempt + 1))
                        continue
                    if r.status == "killed":
                        r.status, r.error = "failed", f"{r.error} (attempt {attempt} of {MAX_ATTEMPTS})"
                    results[c.name] = r
                    ran.add(c.name)
                    outcome.ran.append(c.name)
                    write_table(table, cases, results, ran)
                    progress.case(r, len(pending) + len(waiting))
                fill()
        except KeyboardInterrupt:  # SIGINT or SIGTERM: the running cases stop as emss run does, then we go
            _stop(client, cluster, out, [c for c, _ in by_key.values()])
            client = cluster = None
            raise
        finally:
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
    outcome.wall_time_s = time.perf_counter() - t0
    write_table(table, cases, results, ran)
    return outcome
