"""Locks of a study: one ``emss study run`` per study folder, and a case's folder free before its case runs.

* :func:`study_lock`: the study folder's lock (``.emss-study.lock``, flock, holding the pid), taken for
  the whole ``emss study run`` and removed when it ends however it ends; a second study run into the same
  folder is refused with one line while the first runs (two runs would rewrite each other's table and run
  the same cases into the same folders).
* :func:`wait_released`: a case's run (``emss run`` in a child process) holds its folder's run lock
  (:data:`openemss.orchestrator.results.LOCK_NAME`); the retry of a case whose first attempt is still
  stopping (its worker died, the child got SIGTERM) waits for that lock instead of failing on it.
"""
from __future__ import annotations

import contextlib
import fcntl
import os
import time
from collections.abc import Iterator
from pathlib import Path

from openemss.orchestrator import interrupt
from openemss.orchestrator.results import LOCK_NAME, lock_file

__all__ = ["STUDY_LOCK", "study_lock", "held", "wait_released", "LOCK_NAME"]

STUDY_LOCK = ".emss-study.lock"


def held(lock: Path) -> bool:
    """Whether a process holds the flock of the file ``lock`` (False when there is no such file)."""
    try:
        fd = os.open(lock, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:
        return True
    finally:
        os.close(fd)
    return False


def wait_released(lock: Path, timeout_s: float) -> bool:
    """Wait until no process holds ``lock`` (up to ``timeout_s`` [s]); whether it is free."""
    deadline = time.monotonic() + timeout_s
    while held(lock):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.1)
    return True


@contextlib.contextmanager
def study_lock(folder: Path, what: str = "--out") -> Iterator[Path]:
    """The study folder ``folder`` locked for this process until the block ends (the lock file removed).

    Raises
    ------
    ConfigurationError
        When another study run holds it (naming its pid), or the lock file cannot be made.
    """
    lock = Path(folder) / STUDY_LOCK
    fd: int | None = None
    try:
        with interrupt.deferred():  # a signal cannot fall between taking the lock and its release below
            fd = _take(lock, what)
        yield lock
    finally:
        if fd is not None:
            with contextlib.suppress(OSError):
                os.unlink(lock)
            os.close(fd)


def _take(lock: Path, what: str) -> int:
    """The descriptor of ``lock``, exclusively locked (:func:`openemss.orchestrator.results.lock_file`),
    holding this process's pid."""
    fd = lock_file(lock, f"{what} {lock.parent}", "the study folder is in use by another study run")
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    return fd
