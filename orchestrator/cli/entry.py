"""The console scripts ``emss`` and ``build-fmus``: signals handled before anything heavy is imported.

A Ctrl-C while Python imports fmpy, numpy and the models (a second or more) would otherwise end in a
traceback. This module imports nothing of the project at its top but :mod:`..interrupt` (light, and the
package ``openemss`` imports its API lazily); each entry point installs the signal handling, then imports
and runs the command, and turns an interruption anywhere into one line and 128 + the signal.
"""
from __future__ import annotations

import sys
from collections.abc import Sequence

from .. import interrupt


def emss(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``emss`` command (:func:`.main.main`)."""
    interrupt.install()
    try:
        interrupt.phase("start-up", "during start-up", interrupt.NOTHING_RUN)
        from .main import main

        return main(argv)
    except KeyboardInterrupt as exc:  # before the command knew its name (imports, argument parsing)
        return interrupt.report("emss", exc)


def build_fmus(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``build-fmus`` command (:func:`openemss.orchestrator.fmu.build.main`)."""
    interrupt.install()
    try:
        interrupt.phase("start-up", "during start-up", "no FMU was written")
        from ..fmu.build import main

        return main(list(argv) if argv is not None else None)
    except KeyboardInterrupt as exc:
        return interrupt.report("build-fmus", exc)


if __name__ == "__main__":
    sys.exit(emss())
