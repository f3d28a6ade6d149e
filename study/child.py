"""``python -m openemss.study.child ARGS``: ``emss ARGS`` in a process tied to its worker (``serve``: a worker's
case process, :mod:`.warm`).

On Linux the process asks for SIGTERM when the worker process that started it
dies (``PR_SET_PDEATHSIG``): it then stops as ``emss run`` does on SIGTERM (its rows
kept, run.json closed, its folder's lock released), and the retry of the case waits
for that lock (:func:`.case.run_case`), so that it never shares the case folder
with an orphan of the first attempt. Signals are handled as by the ``emss`` command
(:func:`openemss.orchestrator.cli.entry.emss`).
"""
from __future__ import annotations

import os
import signal
import sys

PARENT_ENV = "OPENEMSS_STUDY_PARENT_PID"


def _tie_to_parent() -> None:
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    expected = os.environ.get(PARENT_ENV)
    if expected and expected.isdigit() and os.getppid() != int(expected):  # the parent died before prctl
        os._exit(137)


def main() -> int:
    """Run the ``emss`` command with this process's arguments; with the one argument ``serve``, be a worker's
    case process (:mod:`.warm`: case after case, FMUs kept warm)."""
    from .warm import SERVE, serve

    _tie_to_parent()
    if sys.argv[1:] == [SERVE]:
        return serve()
    from openemss.orchestrator.cli.entry import emss

    return emss(sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())
