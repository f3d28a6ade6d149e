"""``python -m openemss.study.child ARGS``: ``emss ARGS`` in a case's own process, tied to its worker.

On Linux the process asks to be killed when the worker process that started it
dies (``PR_SET_PDEATHSIG``), so that the retry of a case whose worker was killed
never shares the case folder with an orphan of the first attempt.
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
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    expected = os.environ.get(PARENT_ENV)
    if expected and expected.isdigit() and os.getppid() != int(expected):  # the parent died before prctl
        os._exit(137)


def main() -> int:
    """Run the ``emss`` command with this process's arguments."""
    _tie_to_parent()
    from openemss.orchestrator.cli.main import main as emss_main

    return emss_main(sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())
