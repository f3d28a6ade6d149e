"""Calling the plugins' hooks for a run (:mod:`.plugins`): status variable, stop condition, pre- and post-run,
the run's summary.

A failing hook never stops the run: it becomes one line saying how it failed.
"""
from __future__ import annotations

import inspect
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import EmssError
from ..ssp.system import BoundSystem
from .plugins import plugin_name, plugins

#: Exception types that model and plugin commands raise for bad input (one line, no traceback); filled by
#: the CLI as it registers their commands.
USER_ERRORS: list[type[Exception]] = []


def variables(bound: BoundSystem) -> list[str]:
    """Every ``component.variable`` of the system."""
    return [f"{c.name}.{v}" for c in bound.components for v in c.variables]


def proposed(bound: BoundSystem, hook: str) -> str | None:
    """The first non-empty answer of the plugins' ``hook(variables)`` for this system, or None."""
    every = variables(bound)
    for module in plugins():
        propose = getattr(module, hook, None)
        answer = propose(every) if propose is not None else None
        if answer:
            return str(answer)
    return None


def status_variable(bound: BoundSystem, requested: str | None) -> str | None:
    """The progress bar's status variable: ``requested`` (checked), else the first a plugin proposes."""
    from ..errors import ConfigurationError

    if requested is not None:
        try:
            bound.variable(requested)
        except EmssError:
            raise ConfigurationError(f"--status '{requested}': no such variable (write component.variable "
                                     "with a component of this system)") from None
        return requested
    return proposed(bound, "status_variable")


def stop_condition(bound: BoundSystem, requested: str | None) -> str | None:
    """``requested`` (``--until``), else the first stop condition a plugin proposes; None for none."""
    if requested is not None:
        return None if requested.strip().lower() == "never" else requested
    return proposed(bound, "stop_condition")


def _accepted(hook: object, options: dict[str, object]) -> dict[str, object]:
    """The keyword ``options`` that ``hook`` takes by name (a plugin written before an option existed is called
    without it)."""
    if not options:
        return {}
    try:
        params = inspect.signature(hook).parameters  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return {}
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values()):
        return options
    return {k: v for k, v in options.items() if k in params}


def each_hook(hook_name: str, *args: object, whole: bool = False, **options: object) -> list[tuple[Any, str | None]]:
    """Call every plugin's ``hook_name(*args, **options)`` (each option only where the hook names it): per plugin
    that has it, (what it returned, as a list, or as it is with ``whole``; None) or ([] or None with ``whole``, one
    line saying how it failed)."""
    label = hook_name.replace("_", "-")
    out: list[tuple[Any, str | None]] = []
    for module in plugins():
        hook = getattr(module, hook_name, None)
        if hook is None:
            continue
        try:
            answer = hook(*args, **_accepted(hook, options))
            out.append((answer if whole else list(answer), None))
        except (EmssError, *USER_ERRORS) as exc:
            out.append((None if whole else [], f"{label} hook '{plugin_name(module)}' failed: {exc}"))
        except Exception as exc:
            if os.environ.get("EMSS_DEBUG"):
                raise
            out.append((None if whole else [], f"{label} hook '{plugin_name(module)}' failed: internal error: "
                                               f"{type(exc).__name__}: {exc} (set EMSS_DEBUG=1 for the traceback)"))
    return out


def pre_run(bound: BoundSystem) -> list[str]:
    """Every plugin's pre-run hook on the bound system: the warning lines, and one line per failed hook."""
    components = {c.name: c.fmu_path for c in bound.components}
    parameters = {f"{bound.components[p.component].name}.{p.variable.name}": p.value for p in bound.parameters}
    lines: list[str] = []
    for result, failure in each_hook("pre_run", components, parameters):
        lines.extend(str(line) for line in result)
        if failure is not None:
            lines.append(failure)
    return lines


def output_files() -> list[str]:
    """The names of the files the plugins' post-run hooks may write into a results folder (a plugin that
    fails to say is left out: its files are still never written over anything of the user's)."""
    names: list[str] = []
    for result, _failure in each_hook("output_files"):
        names.extend(str(n) for n in result)
    return names


def post_run(out: Path, error: BaseException | None, figures: bool = True) -> tuple[list[Path], list[str]]:
    """Every plugin's post-run hook on the results folder: (files written, one line per failure). With
    ``figures`` False, a hook that takes ``figures`` is told to write its tables only."""
    written: list[Path] = []
    failures: list[str] = []
    for result, failure in each_hook("post_run", out, error, figures=figures):
        written.extend(Path(str(f)) for f in result)
        if failure is not None:
            failures.append(failure)
    return written, failures


def run_summary(files: Sequence[Path]) -> tuple[dict[str, Any] | None, list[str]]:
    """The run's summary: the first plugin's ``run_summary(files)`` that gives one (``files``: what the post-run
    hooks wrote), or None; and one line per failed hook."""
    summary: dict[str, Any] | None = None
    failures: list[str] = []
    for answer, failure in each_hook("run_summary", list(files), whole=True):
        if failure is not None:
            failures.append(failure)
        elif answer is not None and summary is None:
            summary = dict(answer)
    return summary, failures
