"""Plugins of the ``emss`` command: extra commands, post-run hooks, the progress bar's status.

A plugin is a module named by an entry point of the group ``openemss.plugins`` (in
``pyproject.toml``: ``[project.entry-points."openemss.plugins"]``, e.g. ``report =
"openemss.report.plugin"``). It may define any of

``register(subparsers) -> tuple[type[Exception], ...]``
    add sub-commands (each sets ``handler``, a function of the parsed arguments returning
    the exit code); returns the exception types that mean bad input (one line, exit 1);
``status_variable(variables: Sequence[str]) -> str | None``
    given every ``component.variable`` of the system about to run, the variable the
    progress bar shows (e.g. a mission's active section), or None;
``stop_condition(variables: Sequence[str]) -> str | None``
    the condition (``component.variable OP number``) that ends a run of that system before
    its stop time (e.g. a mission completed), or None; ``emss run --until`` overrides it;
``pre_run(components: Mapping[str, Path], parameters: Mapping[str, bool | int | float | str]) -> Sequence[str]``
    called before every ``emss run`` with the FMU of each component and every bound parameter
    value (``component.variable``, after the SSD, the parameter sets and ``--set``); returns
    warning lines to print (e.g. the sections of a mission its aircraft cannot fly), nothing when
    the system is not its business; the run goes ahead whatever it says;
``output_files() -> Sequence[str]``
    the names of the files ``post_run`` may write into a results folder; a run refuses, before it
    starts, a folder where a file of these names stands that no run wrote;
``post_run(run_dir: Path, error: BaseException | None, figures: bool = True) -> Sequence[Path]``
    called after every ``emss run`` (also a failed one, once what was recorded is on
    disk) with the results folder; returns the files it wrote, nothing when the run is
    not its business. ``figures`` False (``emss run --no-figures``, a study's cases) asks for
    the tables only (a hook without that argument is called without it).
``run_summary(files: Sequence[Path]) -> Mapping | None``
    given the files the post-run hooks wrote, the run's summary as the plugin wrote it (e.g. a
    mission run's summary), or None; the Python API's ``RunResult.summary`` (the first answer).
    Only the plugin knows its files' names and formats.

The orchestrator knows no plugin by name. Entry points rather than a scan of the
``openemss`` namespace: an editable install maps each package separately and leaves
the namespace's ``__path__`` empty, so a scan finds nothing there; entry points work in
every kind of install and let other distributions contribute plugins.
"""
from __future__ import annotations

import importlib
from importlib.metadata import entry_points
from types import ModuleType

GROUP = "openemss.plugins"

_loaded: list[ModuleType] | None = None
#: One line per plugin that could not be imported (shown by the CLI, never a traceback).
load_problems: list[str] = []


def plugins() -> list[ModuleType]:
    """The plugin modules of the group, imported once, sorted by entry-point name.

    A plugin that fails to import is left out and named in :data:`load_problems`,
    so a broken plugin never stops a run of a system it has nothing to do with.
    """
    global _loaded
    if _loaded is None:
        _loaded = []
        load_problems.clear()
        for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
            try:
                module = importlib.import_module(ep.value.partition(":")[0])
            except Exception as exc:  # a plugin's bug must not break the orchestrator
                load_problems.append(f"plugin '{ep.name}' ({ep.value}) not loaded: {type(exc).__name__}: {exc}")
                continue
            _loaded.append(module)
    return list(_loaded)


def plugin_name(module: ModuleType) -> str:
    """A short name for messages: the module's package (``openemss.report.plugin`` -> ``report``)."""
    parts = module.__name__.split(".")
    return parts[-2] if len(parts) > 1 and parts[-1] == "plugin" else parts[-1]
