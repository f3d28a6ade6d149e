"""Interruption by SIGINT or SIGTERM, whatever a command is doing: one line, 128 + the signal, nothing left.

* :func:`install` (called first by the entry points, :mod:`openemss.orchestrator.cli.entry`): from then on
  SIGINT and SIGTERM raise :class:`Interrupted` (a ``KeyboardInterrupt``) wherever the program is, so that
  every ``with`` and ``finally`` on the way out runs: locks released, staging folders and temporary files
  removed. The first signal is remembered (:func:`received`): an interruption that surfaces as another
  error (an FMU's Python code interrupted inside its own call) is still reported as one. A second signal
  while the program cleans up is noted, not raised, so that the clean-up ends; a third has the default
  effect. A signal that was ignored when the program started (a background job) stays ignored.
* :func:`phase`: what the program is doing and what an interruption then leaves (the one line); also a
  checkpoint (a signal noted but swallowed is raised there) and the test hook :data:`HOLD_ENV`.
* :func:`deferred` and :func:`entered_whole`: a section that a signal must not cut (taking a lock and
  registering its release) runs whole; the signal is raised at its end.
* :func:`report`: the one line and the exit code.

The run itself stops between two steps instead (:func:`openemss.orchestrator.results.stop_on_signals`, told to
:func:`stopping_run`).
"""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
from collections.abc import Iterator
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

__all__ = ["Interrupted", "install", "received", "phase", "deferred", "entered_whole", "report", "HOLD_ENV",
           "NOTHING_RUN", "signal_of", "stopping_run"]

SIGNALS = (signal.SIGINT, signal.SIGTERM)
#: ``KEY=FILE``: on entering the phase ``KEY`` the program writes its pid to ``FILE`` and waits there for a
#: signal (tests send one in a known phase instead of guessing with sleeps).
HOLD_ENV = "OPENEMSS_HOLD_AT"
NOTHING_RUN = "nothing was run"
T = TypeVar("T")


class Interrupted(KeyboardInterrupt):  # noqa: N818 - a stop the user asked for, as KeyboardInterrupt
    """SIGINT or SIGTERM arrived; ``exit_code`` is 128 + the signal number."""

    def __init__(self, signum: int) -> None:
        self.signum = signum
        self.exit_code = 128 + signum
        super().__init__(signal.Signals(signum).name)


@dataclass(frozen=True)
class Phase:
    """What the program does (``during``: "during the FMU build") and what an interruption then leaves
    (``outcome``: "nothing was run")."""

    key: str
    during: str
    outcome: str


_state: dict[str, Any] = {"phase": Phase("start-up", "during start-up", NOTHING_RUN), "signals": [],
                          "deferring": 0, "raised": False, "run_stop": False}


def _handler(signum: int, frame: object) -> None:
    seen: list[int] = _state["signals"]
    seen.append(signum)
    if len(seen) >= 3:  # the user insists: the default effect (the process ends by the signal)
        for s in SIGNALS:
            signal.signal(s, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if len(seen) == 1 and not _state["deferring"]:
        _state["raised"] = True
        raise Interrupted(signum)
    # a second signal while the first unwinds, or one inside a deferred section: noted, not raised


def install() -> None:
    """SIGINT and SIGTERM raise :class:`Interrupted` from now on (main thread only; a signal ignored by the
    program's parent stays ignored)."""
    with contextlib.suppress(ValueError):  # not the main thread: nothing to install
        for s in SIGNALS:
            if signal.getsignal(s) != signal.SIG_IGN:
                signal.signal(s, _handler)


def stopping_run(signum: int) -> None:
    """Note a signal the run takes as a request to stop after its current step (safe in a signal handler):
    a second signal then does not cut the run's closing (run.json, the lock), a third ends the process, and
    the report of the interrupted run is still made."""
    _state["signals"].append(signum)
    _state["run_stop"] = True


def received() -> int:
    """The first signal received since :func:`install` (0 for none)."""
    seen: list[int] = _state["signals"]
    return seen[0] if seen else 0


def current() -> Phase:
    return _state["phase"]  # type: ignore[no-any-return]


def phase(key: str, during: str, outcome: str | None = None) -> None:
    """Enter a phase: ``during`` says what the program does, ``outcome`` what an interruption now leaves
    (None keeps the current one). A signal received but swallowed meanwhile is raised here."""
    _state["phase"] = Phase(key, during, current().outcome if outcome is None else outcome)
    if received() and not _state["deferring"] and not _state["run_stop"]:
        raise Interrupted(received())
    hold = os.environ.get(HOLD_ENV, "")
    name, _, marker = hold.partition("=")
    if name == key and marker:
        Path(marker).write_text(f"{os.getpid()}\n", encoding="utf-8")
        while True:  # until a signal ends it
            time.sleep(3600)


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """A section a signal must not cut: a signal arriving inside is raised when it ends."""
    _state["deferring"] += 1
    try:
        yield
    finally:
        _state["deferring"] -= 1
    if received() and not _state["deferring"] and not _state["raised"]:
        _state["raised"] = True
        raise Interrupted(received())


@contextlib.contextmanager
def entered_whole(cm: AbstractContextManager[T]) -> Iterator[T]:
    """``with cm`` whose entry a signal cannot cut (entered and its exit registered, or not entered)."""
    with contextlib.ExitStack() as stack:
        with deferred():
            value = stack.enter_context(cm)
        yield value


def signal_of(exc: BaseException | None = None) -> int:
    """The signal behind an interruption: the first received, else ``exc``'s, else SIGINT (a plain
    ``KeyboardInterrupt``)."""
    return int(received() or getattr(exc, "signum", 0) or signal.SIGINT)


def report(prog: str, exc: BaseException | None = None) -> int:
    """Print the one line of an interruption to stderr (``prog: interrupted by SIGINT during ...; outcome``)
    and return the exit code (128 + the signal)."""
    signum = signal_of(exc)
    p = current()
    text = f"{prog}: interrupted by {signal.Signals(signum).name}" + (f" {p.during}" if p.during else "") \
        + (f"; {p.outcome}" if p.outcome else "")
    print(text, file=sys.stderr, flush=True)
    return 128 + int(signum)
