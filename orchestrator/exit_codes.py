"""The exit codes of ``emss`` and ``build-fmus``: one table, read by the commands, their ``--help`` and the README.

The scheme follows grep and diff (0: nothing found, 1: something found, 2: trouble) and keeps every count out
of the exit code: ``emss validate`` and ``emss mission check`` exit 1 when they find problems and print how many
(last line on stderr, and in ``--json``), so that no count can be read as a crash (a count of 3 was the
internal error's code before). A signal ends a command with 128 + its number, as a shell reports it.
"""
from __future__ import annotations

from enum import IntEnum


class ExitCode(IntEnum):
    """What an ``emss`` command exits with (see :data:`MEANINGS`)."""

    OK = 0
    FINDINGS = 1
    USAGE = 2
    FAILED = 3
    INTERNAL = 4


#: Exit code of a command ended by a signal: 128 + the signal's number (SIGINT 130, SIGTERM 143).
SIGNAL_BASE = 128

#: What each code means, as the README's table of exit codes and ``emss --help`` show it.
MEANINGS: dict[ExitCode, str] = {
    ExitCode.OK: "success: the command did what it was asked (a run completed, or stopped by its `--until` "
                 "condition)",
    ExitCode.FINDINGS: "findings: `emss validate` found problems, `emss mission check` infeasible sections; "
                       "their number is printed (`--json`: in the output)",
    ExitCode.USAGE: "bad input: the command line, or a file, value or option it names, or a file it cannot "
                    "read or write, or that an FMU refuses at initialization (one line: what, where, what is "
                    "allowed)",
    ExitCode.FAILED: "failed: a run (or a study's case, or the report after a run) was initialized and did not "
                     "complete; one line says where and when, what was recorded is kept",
    ExitCode.INTERNAL: "internal error: a defect of openEMSS (one line; `EMSS_DEBUG=1` shows the traceback)",
}
INTERRUPTED = "interrupted by SIGINT (130) or SIGTERM (143): 128 + the signal's number; what was recorded is kept"


def markdown_table() -> str:
    """The exit codes as the README's Markdown table."""
    rows = [f"| {int(code)} | {text} |" for code, text in MEANINGS.items()]
    return "\n".join(["| exit code | meaning |", "|---|---|", *rows, f"| 130, 143 | {INTERRUPTED} |"])


def help_text() -> str:
    """The exit codes as the epilog of ``emss --help`` (plain text)."""
    lines = [f"  {int(code)}  {text.replace('`', '')}" for code, text in MEANINGS.items()]
    return "exit codes:\n" + "\n".join(lines) + f"\n  130, 143  {INTERRUPTED}"
