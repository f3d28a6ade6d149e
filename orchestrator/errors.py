"""The orchestrator's error hierarchy.

Every message says what went wrong, where (file:line, component.variable,
simulation time) and, where it helps, what is allowed. The CLI prints the message
as one line and exits non-zero; it never shows a traceback for these.
"""
from __future__ import annotations

import ast
import re
from dataclasses import dataclass


class EmssError(Exception):
    """Base of every error the orchestrator reports to a user."""


class ConfigurationError(EmssError):
    """A run option is outside what is allowed (rate, algorithm, stop time, ...)."""


@dataclass(frozen=True)
class Problem:
    """One problem found in a system description or its FMUs.

    Attributes
    ----------
    where : str
        File and line, or component and variable, the problem belongs to.
    what : str
        What is wrong and, where useful, what is allowed.
    """

    where: str
    what: str

    def __str__(self) -> str:
        return f"{self.where}: {self.what}"


class SystemStructureError(EmssError):
    """A system description (SSD, SSV, SSP archive) or the FMUs it names is invalid.

    Carries every problem found, not only the first, so that one run of
    ``emss validate`` lists them all.
    """

    def __init__(self, problems: list[Problem]) -> None:
        self.problems = list(problems)
        first = str(self.problems[0]) if self.problems else "invalid system"
        more = f" (and {len(self.problems) - 1} more problem(s))" if len(self.problems) > 1 else ""
        super().__init__(first + more)


class SettingError(SystemStructureError, ConfigurationError):
    """``--set`` values (or the Python API's ``set=``) that cannot be applied: malformed, given twice, naming
    no variable, or not of the variable's type; every problem named by its item (``--set 'a.k=nan'``)."""


class RunFailed(EmssError):
    """A run that started and did not complete (an FMU's or a model's error, a full disk), or whose post-run
    report failed; what it recorded is kept. The command exits with ``ExitCode.FAILED``, not as bad input."""


class SlaveError(EmssError):
    """An FMU returned error/fatal/discard, or a Python slave raised.

    Attributes
    ----------
    component : str
        Instance name of the component in the system.
    call : str
        The FMI call or the variable concerned.
    time_s : float | None
        Simulation time [s] at which it happened, if the run had started.
    """

    def __init__(self, component: str, call: str, time_s: float | None, detail: str = "") -> None:
        self.component = component
        self.call = call
        self.time_s = time_s
        detail = python_error(detail) or detail
        self.detail = detail
        at = f" at t = {time_s:.6g} s" if time_s is not None else ""
        if _LOCATED.match(detail):  # the model's own error names its file and line: it leads
            super().__init__(f"{detail} (component '{component}', in {call}{at})")
            return
        tail = f": {detail}" if detail else ""
        super().__init__(f"component '{component}' failed in {call}{at}{tail}")


#: A message that starts with its location, ``file:line: ...``.
_LOCATED = re.compile(r"^[^\s:]+(?:\.[A-Za-z0-9]+)?(?: \(converted\))?:\d+: ")
#: How a Python slave (pythonfmu) reports an exception it raised: its repr, ``NameError('message')``.
_PY_REPR = re.compile(r"^\s*([A-Za-z_][\w.]*(?:Error|Exception))\((['\"].*['\"])\)\s*$", re.DOTALL)


def python_error(detail: str) -> str | None:
    """The message of a Python exception reported as its repr by a Python FMU (``MissionError('x.yaml:3:
    ...')`` gives ``x.yaml:3: ...``); None when ``detail`` is not one."""
    m = _PY_REPR.match(detail or "")
    if m is None:
        return None
    try:
        message = ast.literal_eval(m.group(2))
    except (ValueError, SyntaxError):
        return None
    if not isinstance(message, str):
        return None
    return message if _LOCATED.match(message) else f"{m.group(1)}: {message}"


class InitializationError(EmssError):
    """The initial exchange of outputs to inputs did not reach a fixed point."""


class BuildError(EmssError):
    """An FMU could not be built from its slave source."""


class ScenarioError(ConfigurationError):
    """A scenario file, or a condition on a variable, that cannot be applied."""


class CouplingError(EmssError):
    """An iterative master algorithm did not converge within a macro step."""
