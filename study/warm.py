"""Warm cases: each Dask worker keeps one case process whose FMUs stay instantiated from case to case.

A case used to be a new ``emss run`` process: the interpreter, the imports, the FMUs'
instantiation (each pythonfmu FMU imports its model and loads its compiled kernels) came before
every case's first step. Now the worker starts one **case process** (``python -m
openemss.study.child serve``, tied to the worker as before: it gets SIGTERM when the worker dies)
and sends it case after case; the case process runs each one as ``emss ARGS`` in its own
interpreter, with the FMU instance pool enabled (:mod:`openemss.orchestrator.master.pool`): an FMU
whose case ended cleanly is reset (``fmi2Reset``) for the next case instead of being instantiated
again. pythonfmu FMUs of one model share the interpreter they run in, so a case process runs one
case at a time; a worker with several threads gets one case process per case it runs at once.

What a case sees is what ``emss run`` in a new process sees: its folder as working directory,
its own ``stdout.log`` and ``stderr.log`` (file descriptors 1 and 2 redirected, so that what the
FMUs' native code prints goes there too), the exit code of ``emss``. A case ended by a signal ends
its case process as well (the next case starts a new one); a case process that dies (a crash in
an FMU) gives the exit code of its death, and the case is retried once as before
(:mod:`.runner`).

The protocol is one JSON line each way on the case process's stdin and on a copy of its stdout
taken before the redirection: ``{"argv": [...], "cwd": "..."}`` and ``{"rc": N}``.
"""
from __future__ import annotations

import contextlib
import json
import os
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

__all__ = ["CaseHost", "run_warm", "serve", "SERVE"]

SERVE = "serve"  #: ``python -m openemss.study.child serve``: the case process


class CaseHost:
    """One case process, started at the first case and kept for the next ones (worker side)."""

    def __init__(self, env: dict[str, str]) -> None:
        self.env = env
        self.proc: subprocess.Popen[bytes] | None = None

    def _start(self) -> subprocess.Popen[bytes]:
        if self.proc is None or self.proc.poll() is not None:
            self.proc = subprocess.Popen([sys.executable, "-m", "openemss.study.child", SERVE], stdin=subprocess.PIPE,
                                         stdout=subprocess.PIPE, env=self.env)
        return self.proc

    def run(self, argv: Sequence[str], cwd: Path) -> int:
        """Run ``emss ARGV`` in the case process with ``cwd`` as working directory; its exit code, or the case
        process's own (negative: the signal that killed it) when it ended during the case."""
        proc = self._start()
        assert proc.stdin is not None and proc.stdout is not None
        try:
            proc.stdin.write((json.dumps({"argv": list(argv), "cwd": str(cwd)}) + "\n").encode())
            proc.stdin.flush()
            line = proc.stdout.readline()
        except OSError:  # the case process died before it read the case
            line = b""
        if not line:  # it ended during the case: how it ended is the case's outcome
            rc = proc.wait()
            self.proc = None
            return rc
        rc = int(json.loads(line)["rc"])
        if rc >= 128:  # ended by a signal, as emss run ends: the case process ends with it
            with contextlib.suppress(subprocess.TimeoutExpired):
                proc.wait(timeout=30)
            self.proc = None
        return rc

    def close(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            with contextlib.suppress(OSError):
                assert self.proc.stdin is not None
                self.proc.stdin.close()  # end of input: it ends
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.proc.wait(timeout=30)
        self.proc = None


_idle: list[CaseHost] = []
_lock = threading.Lock()


def run_warm(argv: Sequence[str], cwd: Path, env: dict[str, str]) -> int:
    """Run one case in an idle case process of this worker (a new one when none is idle); its exit code."""
    with _lock:
        host = _idle.pop() if _idle else CaseHost(env)
    try:
        return host.run(argv, cwd)
    finally:
        with _lock:
            _idle.append(host)


# -- the case process ----------------------------------------------------------------------------
def _redirect(folder: Path) -> None:
    """Point file descriptors 1 and 2 at ``folder``'s stdout.log and stderr.log."""
    for stream in (sys.stdout, sys.stderr):
        stream.flush()
    for fd, name in ((1, "stdout.log"), (2, "stderr.log")):
        target = os.open(folder / name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(target, fd)
        os.close(target)


def _restore(fds: dict[int, int]) -> None:
    """Point file descriptors 1 and 2 back where they were between cases (``fds``: their saved copies)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    for fd, saved in fds.items():
        os.dup2(saved, fd)


def _one(argv: list[str], cwd: Path, idle: dict[int, int]) -> int:
    from openemss.orchestrator.cli.entry import emss

    here = os.getcwd()
    try:
        try:
            os.chdir(cwd)
            _redirect(cwd)
        except OSError as exc:
            print(f"emss study: case folder {cwd}: {exc.strerror or exc}", file=sys.stderr)
            return 1
        return int(emss(argv) or 0)
    except SystemExit as exc:  # argparse and the like
        return exc.code if isinstance(exc.code, int) else 1
    finally:
        _restore(idle)
        with contextlib.suppress(OSError):
            os.chdir(here)


def serve(requests: IO[bytes] | None = None) -> int:
    """The case process: read one case per line, run it, answer its exit code; ends at the end of its input or
    after a case that a signal ended (with that case's code)."""
    from openemss.orchestrator import interrupt
    from openemss.orchestrator.master import pool

    interrupt.install()
    pool.enable()
    replies = os.fdopen(os.dup(1), "wb", buffering=0)
    idle = {1: os.open(os.devnull, os.O_WRONLY), 2: os.dup(2)}  # between cases: stdout nowhere, stderr the worker's
    os.dup2(idle[1], 1)
    source = requests if requests is not None else sys.stdin.buffer
    try:
        while True:
            interrupt.phase("study-idle", "waiting for the next case", "no case was running")
            line = source.readline()
            if not line:
                return 0
            try:
                req: dict[str, Any] = json.loads(line)
                argv, cwd = [str(a) for a in req["argv"]], Path(str(req["cwd"]))
            except (ValueError, KeyError, TypeError) as exc:
                print(f"emss study: case process: unreadable request ({exc})", file=sys.stderr)
                return 2
            rc = _one(argv, cwd, idle)
            try:
                replies.write((json.dumps({"rc": rc}) + "\n").encode())
            except OSError:  # the worker is gone (it died during the case): nobody to answer
                return rc
            if interrupt.received():
                return rc
    except KeyboardInterrupt as exc:  # a signal between cases (the worker ended): nothing to report
        return 128 + interrupt.signal_of(exc)
    finally:
        pool.enable(False)
