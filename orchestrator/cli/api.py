"""Run a system from Python: ``openemss.run(...)`` returns the time series, the summary and the run record.

The ``emss run`` command is this function with its arguments parsed from the command line
(:func:`openemss.orchestrator.cli.main.cmd_run`), and a study's case is ``emss run`` in a child process
(:mod:`openemss.study.child`): one code path for all three.

Example
-------
>>> import openemss
>>> r = openemss.run("examples/oscillator", stop_time=2.0, out="results/osc")   # doctest: +SKIP
>>> r.status, len(r.df), r.units["mass1.x1_m"]                                  # doctest: +SKIP
('completed', 41, 'm')
"""
from __future__ import annotations

import contextlib
import difflib
import math
import numbers
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import interrupt
from ..errors import ConfigurationError, EmssError, Problem, SettingError, SystemStructureError
from ..exit_codes import ExitCode
from ..fmu.build import PACKAGE_ROOT, ensure_built
from ..master.execution import Execution
from ..recording.observers import Progress, RealTimePacer, RunRecord
from ..recording.timeseries import (
    DEFAULT_FORMAT,
    FORMATS,
    TimeSeries,
    default_record,
    read_timeseries,
    recorder,
    timeseries_names,
)
from ..results import ResultsError, ResultsFolder, RunInterrupted, atomic_write, check_name, stop_on_signals
from ..scenarios.manipulators import ScenarioManipulator, load_scenario
from ..ssp.model import ParameterValue, SystemDef
from ..ssp.read import load_system
from ..ssp.system import BoundSystem, VariableInfo, bind_system
from ..ssp.values import ValueT, is_file_parameter, parse_value, short

if TYPE_CHECKING:
    import pandas

__all__ = ["run", "RunResult", "load", "DEFAULT_SYSTEM"]

#: The system run without a SYSTEM argument: the project's coupled system in ssp/ (the Munich mission).
DEFAULT_SYSTEM = PACKAGE_ROOT / "ssp"
MIN_REALTIME, MAX_REALTIME = 1e-3, 1e6  #: pacing factors allowed (a factor of 1e-300 would sleep for ever)
SETTINGS_FILE = "cli_parameters.ssv"  #: the ``--set`` values as a parameter set, kept with a run's results


@dataclass
class RunResult:
    """What a run left in its results folder, read back.

    Attributes
    ----------
    out : Path
        The results folder.
    status : str
        ``completed``, ``failed`` or ``interrupted``.
    error : str or None
        The run's one-line error.
    info : dict
        ``run.json``.
    summary : dict or None
        The run's summary where a plugin wrote one (the report plugin's ``summary.json`` of a mission run;
        :func:`.hooks.run_summary`).
    files : list of Path
        Files the post-run hooks wrote (summary, plots, report.html).
    post_run_failures : list of str
        One line per post-run hook that failed.
    pre_run : list of str
        The pre-run hooks' warnings (e.g. sections of a mission the aircraft cannot fly).
    rows : int
        Rows recorded.
    stopped_by : str or None
        The stop condition that ended the run early.
    exit_code : int
        What ``emss run`` exits with (:class:`..exit_codes.ExitCode`): 0, 128 + signal when interrupted, 2 when
        bad input stopped it (an error before it could step: a scenario naming no variable, a mission file an
        FMU refuses at initialization), 3 when it failed while stepping.
    """

    out: Path
    status: str
    error: str | None
    info: dict[str, Any]
    summary: dict[str, Any] | None = None
    files: list[Path] = field(default_factory=list)
    post_run_failures: list[str] = field(default_factory=list)
    pre_run: list[str] = field(default_factory=list)
    rows: int = 0
    stopped_by: str | None = None
    exit_code: int = 0
    step_size_s: float = 0.0
    _ts: TimeSeries | None = None

    @property
    def timeseries(self) -> TimeSeries:
        """The recorded time series (typed NumPy arrays, units, descriptions), read once."""
        if self._ts is None:
            self._ts = read_timeseries(self.out)
        return self._ts

    @property
    def df(self) -> pandas.DataFrame:
        """The time series as a pandas DataFrame indexed by ``time_s`` (units in ``df.attrs["units"]``)."""
        return self.timeseries.to_pandas()

    @property
    def units(self) -> dict[str, str]:
        return self.timeseries.units

    def __getitem__(self, name: str) -> np.ndarray:
        """One recorded column (``time_s`` or ``component.variable``) as a NumPy array."""
        data = self.timeseries.data
        if name not in data:
            close = difflib.get_close_matches(name, list(data), n=3)
            raise KeyError(f"{name!r} was not recorded" + (f"; did you mean {', '.join(close)}?" if close else ""))
        return data[name]


def load(system: Path | str | SystemDef, params: Sequence[Path | str] = (),
         settings: Mapping[str, Any] | Sequence[str] = (), folder: Path | None = None) -> BoundSystem:
    """Bind ``system`` (read once, here or by the caller) with its parameter sets and ``settings``
    (``{"comp.var": value}`` or ``["comp.var=value"]``), typed by the variables they set and applied
    last, as one more parameter set whose messages name each item (``--set 'a.k=nan': ...``). With
    ``folder`` (the results), the settings are also written there as ``cli_parameters.ssv``, so that
    a run records what it was given; nothing is written elsewhere.

    Raises
    ------
    SettingError
        With every item that is malformed, given twice, names no variable (with the closest names of
        the system) or whose value is not one of the variable's type.
    SystemStructureError
        With every problem of the system and its parameter sets.
    """
    problems: list[Problem] = []
    items = setting_items(settings, problems)
    sysdef = system if isinstance(system, SystemDef) else load_system(Path(system))
    params = [Path(p) for p in params]
    model_descriptions: dict[Path, Any] = {}
    bound = bind_system(sysdef, params, model_descriptions)
    if not items and not problems:
        return bound
    values: list[ParameterValue] = []
    every: list[str] | None = None
    for path, text, where in items:
        try:
            _, var = bound.variable(path)
        except EmssError:
            every = every or [f"{c.name}.{v}" for c in bound.components for v in c.variables]
            close = difflib.get_close_matches(path, every, n=3, cutoff=0.6)
            hint = f"; did you mean {', '.join(close)}?" if close else " (write component.variable with a " \
                                                                       "component of this system)"
            problems.append(Problem(where, f"no variable '{path}'{hint}"))
            continue
        try:
            values.append(ParameterValue(path, var.type_name, typed(text, var), None, where))
        except ValueError as exc:
            problems.append(Problem(where, f"not a valid {var.type_name} value: {short(text)} is {exc}"))
    if problems:
        raise SettingError(problems)
    if folder is not None:
        from lxml import etree

        from ..ssp.write import ParameterSet

        folder.mkdir(parents=True, exist_ok=True)
        atomic_write(folder / SETTINGS_FILE, etree.tostring(
            ParameterSet("cli_parameters", {v.name: v.value for v in values}).element(), xml_declaration=True,
            encoding="UTF-8", pretty_print=True))
    return bind_system(sysdef, params, model_descriptions, settings=values)


def setting_items(settings: Mapping[str, Any] | Sequence[str],
                  problems: list[Problem] | None = None) -> list[tuple[str, str, str]]:
    """(variable, value as text, where: ``--set 'item'``) of every well-formed setting; a Python value is
    written as on the command line (``True`` as ``true``). Items without ``=`` and a variable given twice
    (the last would silently win) are added to ``problems``, or raised without it.

    Raises
    ------
    SettingError
        Without ``problems``, for the items that are not well formed.
    """
    own: list[Problem] = []
    if isinstance(settings, str):
        settings = [settings]
    pairs: list[tuple[str, Any, str]] = []
    if isinstance(settings, Mapping):
        pairs = [(str(k).strip(), v, f"{k}={v}") for k, v in settings.items()]
    else:
        for item in settings:
            path, eq, text = str(item).partition("=")
            pairs.append((path.strip() if eq else "", text.strip(), str(item)))
    first: dict[str, str] = {}
    out = []
    for path, value, item in pairs:
        where = f"--set {short(item, 80)}"
        if not path:
            own.append(Problem(where, "write component.variable=value"))
            continue
        if path in first:
            own.append(Problem(where, f"'{path}' is given twice (first: {first[path]}); give each parameter once"))
            continue
        first[path] = where
        text = value if isinstance(value, str) else str(value).lower() if isinstance(value, bool) else str(value)
        out.append((path, text, where))
    if problems is None and own:
        raise SettingError(own)
    if problems is not None:
        problems.extend(own)
    return out


def typed(text: str, var: VariableInfo) -> ValueT:
    """``text`` as a value of the variable ``var`` (:func:`..ssp.values.parse_value`; an enumeration by item
    name or value). A String stays the text given, except for a file parameter (its name ends in ``_file``):
    a relative path naming a file in the working directory becomes that file's absolute path, so that the FMU
    (which takes relative paths from its own resources folder) opens the user's file.

    Raises
    ------
    ValueError
        Saying what is allowed.
    """
    if var.enum_items is not None:
        if text.strip() in var.enum_items:
            return var.enum_items[text.strip()]
        value = parse_value("Integer", text)
        if value not in var.enum_items.values():
            raise ValueError("not an item of the enumeration (allowed: "
                             + ", ".join(f"{k} ({v})" for k, v in var.enum_items.items()) + ")")
        return value
    value = parse_value(var.type_name, text)
    if is_file_parameter(var.name, var.type_name) and text and Path(text).is_file():
        return str(Path(text).resolve())
    return value


def default_system() -> Path:
    if not (DEFAULT_SYSTEM / "SystemStructure.ssd").is_file():
        raise ConfigurationError("no SYSTEM given and the project's system is not available "
                                 f"({DEFAULT_SYSTEM}); give a system folder, .ssd or .ssp")
    return DEFAULT_SYSTEM


#: The project's own systems whose FMUs are built on demand: (system folder, its slaves' sources, whether its
#: sub-folders are systems of the same FMUs too, e.g. ssp/hybrid/).
PROJECT_SYSTEMS = ((Path("ssp"), Path("fmus"), True),
                   (Path("examples") / "oscillator", Path("examples") / "oscillator" / "fmus", False))


def ensure_project_fmus(system: Path, report: Callable[[str], None] | None = None) -> None:
    """The project's own systems (:data:`PROJECT_SYSTEMS`: ssp/ and its sub-folders, e.g. ssp/hybrid/, and
    the oscillator example) get their FMUs built from their sources when they are missing or stale; ``report``
    (default: stderr) hears of each FMU built, nothing of those up to date. Other systems are left alone."""
    if not system.is_dir():
        return
    where = system.resolve()
    for folder, sources, nested in PROJECT_SYSTEMS:
        project = PACKAGE_ROOT / folder
        if project.is_dir() and project.resolve() in ((where, where.parent) if nested else (where,)):
            before = interrupt.current()
            interrupt.phase("build", "during the FMU build")
            ensure_built(PACKAGE_ROOT / sources, system / "resources", report_up_to_date=False,
                         report=report or (lambda m: print(m, file=sys.stderr)))
            interrupt.phase(before.key, before.during, before.outcome)


def _record_not_run(out: Path, system: Path, exc: BaseException) -> None:
    """run.json of a run interrupted before its first step (a run that started has its own record)."""
    import json
    import signal

    if (out / "run.json").exists():
        return
    name = signal.Signals(interrupt.signal_of(exc)).name
    atomic_write(out / "run.json", json.dumps({"system": str(system), "status": "interrupted", "steps": 0,
                                               "error": f"interrupted by {name} before the first step; "
                                                        f"{interrupt.NOTHING_RUN}"}, indent=2) + "\n")


def multiples(items: Mapping[str, int] | Sequence[str]) -> dict[str, int]:
    from ..master.execution import MAX_STEP_MULTIPLE

    pairs = [f"{k}={v}" for k, v in items.items()] if isinstance(items, Mapping) else list(items)
    out: dict[str, int] = {}
    for item in pairs:
        name, sep, value = item.partition("=")
        try:
            n = parse_value("Integer", value) if sep else 0
        except ValueError:
            n = 0
        if not 1 <= n <= MAX_STEP_MULTIPLE:
            raise ConfigurationError(f"--step-multiple {short(item)}: expected COMPONENT=N with an integer N from 1 "
                                     f"to {MAX_STEP_MULTIPLE}")
        if name.strip() in out:
            raise ConfigurationError(f"--step-multiple {short(item)}: component '{name.strip()}' is given twice "
                                     f"(first: {out[name.strip()]}); give each component once")
        out[name.strip()] = int(n)
    return out


def record_paths(bound: BoundSystem, patterns: Sequence[str] | None, inputs: bool = False) -> list[str]:
    """The variables to record: ``patterns`` (``component.variable``, wildcards, commas) or, without them,
    :func:`.timeseries.default_record`."""
    import fnmatch

    if not patterns:
        return default_record(bound, inputs)
    every = [f"{c.name}.{v}" for c in bound.components for v in c.variables]
    chosen: list[str] = []
    for pattern in (p.strip() for item in patterns for p in item.split(",") if p.strip()):
        hits = [p for p in every if fnmatch.fnmatchcase(p, pattern)]
        if not hits:
            close = difflib.get_close_matches(pattern, every, n=3)
            raise ConfigurationError(f"--record '{pattern}' matches no variable (write component.variable; "
                                     "wildcards * and ? are allowed)" + (f"; did you mean {', '.join(close)}?"
                                                                         if close else ""))
        chosen.extend(h for h in hits if h not in chosen)
    return chosen


def _is_variable(bound: BoundSystem, path: str) -> bool:
    try:
        _, v = bound.variable(path)
    except EmssError:
        return False  # the scenario names it wrongly: its manipulator says so
    return v.causality == "input" and v.type_name in ("Real", "Integer", "Boolean")


def run(system: Path | str | None = None, *, stop_time: float | None = None, params: Sequence[Path | str] = (),
        set: Mapping[str, Any] | Sequence[str] = (), scenario: Path | str | None = None,  # noqa: A002
        out: Path | str | None = None, rate: float | None = None, algorithm: str = "jacobi",
        step_multiple: Mapping[str, int] | Sequence[str] = (), record: Sequence[str] | None = None,
        record_inputs: bool = False, record_every: int = 1, format: str = DEFAULT_FORMAT,  # noqa: A002
        until: str | None = None, realtime: float = 0.0, status: str | None = None, pre_run: bool = True,
        post_run: bool = True, figures: bool = True, build: bool = True, progress: bool = False,
        warn: Callable[[str], None] | None = None) -> RunResult:
    """Run a system and return its results (the same run as ``emss run``, same folder, same files).

    Parameters
    ----------
    system : path, optional
        A folder with ``SystemStructure.ssd``, an ``.ssd`` or an ``.ssp`` (default: ``ssp/``, the Munich mission).
    stop_time : float, optional
        Stop time [s] (default: the SSD's).
    params : paths
        Parameter sets (``.ssv``) applied after the SSD's.
    set : dict or list of str
        Parameter values applied last: ``{"engine.preset": "reference_study"}`` or ``["fcs.x=1"]``.
    scenario : path, optional
        A scenario file (timed or triggered overrides).
    out : path, optional
        Results folder (default ``results/<system>-<time>``).
    rate, algorithm, step_multiple, realtime, until, status
        As ``emss run --rate --algorithm --step-multiple --realtime --until --status``.
    record, record_inputs, record_every, format
        What to record (default: outputs, and inputs not merely copied from a connected output), every
        n-th step, in ``parquet`` (default), ``csv`` or ``mat``.
    pre_run, post_run : bool
        Run the plugins' checks before and reports after (summary.json, plots, report.html).
    figures : bool
        Let the post-run reports draw their figures (plots, report.html); without, a report writes its
        tables only (summary.json), and ``emss plot RUN_DIR`` draws the figures later.
    build : bool
        Build the project's own FMUs first when they are missing or stale (:func:`ensure_project_fmus`);
        False when the caller made sure of them (a study's cases: the study checked them once).
    progress : bool
        Show the progress bar on stderr (when it is a terminal).
    warn : callable, optional
        Receives each warning line (default: printed to stderr).

    Returns
    -------
    RunResult
        Also for a failed or interrupted run (``status``, ``error``; what was recorded is kept). Its
        ``info["timing"]`` (also in run.json) splits the call's wall time [s] into ``setup_s`` (to the first
        step: reading, building, instantiating, initializing), ``stepping_s`` (the steps) and ``writing_s``
        (after the last step: the recorder's last rows, the post-run reports), and the same for the process's CPU
        time (``setup_cpu_s`` ...: what a loaded machine does not change); ``info["instances"]`` says of
        each component whether its FMU instance was ``instantiated`` or taken warm from the pool and ``reset``
        (:mod:`..master.pool`).

    Raises
    ------
    ConfigurationError
        For bad input (one line: what, where, what is allowed), before anything runs.
    """
    say = warn or (lambda line: print(f"emss run: warning: {line}", file=sys.stderr))
    setting_items(set)  # malformed or repeated items are refused before anything is built or read
    multiples(step_multiple)
    if stop_time is not None and (isinstance(stop_time, bool) or not isinstance(stop_time, numbers.Real)
                                  or not math.isfinite(stop_time)):
        raise ConfigurationError(f"--stop-time {short(str(stop_time))}: not a finite number of seconds")
    stop_time = float(stop_time) if stop_time is not None else None  # a NumPy number as a Python float
    started = time.perf_counter(), time.process_time()
    system = Path(system) if system is not None else default_system()
    interrupt.phase("start", "before the run", interrupt.NOTHING_RUN)
    if build:
        ensure_project_fmus(system, warn or (lambda line: print(f"emss run: {line}", file=sys.stderr)))  # news
    interrupt.phase("load", "while loading the system", interrupt.NOTHING_RUN)
    sysdef = load_system(system)  # the one reading of the SSD in this run
    if out is None:  # the default folder is named after the system: that name must be one path component
        name = check_name(str(sysdef.name), "the system's name (the SSD's System name; or give --out)")
        out = Path("results") / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    out = Path(out)
    if not str(out).strip():
        raise ConfigurationError("--out '': an empty folder name; give the results folder, e.g. results/run1")
    from . import hooks

    # locked for this run, cleared of what earlier runs wrote, nothing else replaced (the time series' names of
    # every format, the plugins' output files)
    plugin_files = hooks.output_files() if post_run else ()
    with interrupt.entered_whole(ResultsFolder(out, names=[*timeseries_names(), *plugin_files])):
        try:
            interrupt.phase("pre-run", "before the first step", f"nothing was run (run.json in {out} says so)")
            return _run(system, sysdef, out, stop_time, params, set, scenario, rate, algorithm, step_multiple,
                        record, record_inputs, record_every, format, until, realtime, status, pre_run, post_run,
                        figures, progress, say, started)
        except BaseException as exc:  # a signal, also one that surfaced as an FMU's error (its code cut)
            if isinstance(exc, KeyboardInterrupt) or interrupt.received():
                _record_not_run(out, system, exc)
            raise


def _run(system: Path, sysdef: SystemDef, out: Path, stop_time: float | None, params: Sequence[Path | str],
         settings: Mapping[str, Any] | Sequence[str], scenario: Path | str | None, rate: float | None,
         algorithm: str, step_multiple: Mapping[str, int] | Sequence[str], record: Sequence[str] | None,
         record_inputs: bool, record_every: int, fmt: str, until: str | None, realtime: float,
         status: str | None, pre_run: bool, post_run: bool, figures: bool, progress: bool,
         say: Callable[[str], None], started: tuple[float, float]) -> RunResult:
    from . import hooks

    bound = load(sysdef, params, settings, out)
    stop = stop_time if stop_time is not None else bound.definition.stop_time_s
    if stop is None:
        raise ConfigurationError("no stop time: give --stop-time or a DefaultExperiment stopTime in the SSD")
    if not isinstance(record_every, int) or record_every < 1:
        raise ConfigurationError(f"--record-every {record_every}: must be an integer >= 1")
    events = load_scenario(Path(scenario)) if scenario is not None else []
    recorded = record_paths(bound, record, record_inputs)
    if not record:  # an input a scenario overrides no longer copies its connected output: recorded
        recorded += [p for p in dict.fromkeys(e.path for e in events) if p not in recorded and _is_variable(bound, p)]
    ex = Execution(bound, rate_hz=rate, algorithm=algorithm, multiples=multiples(step_multiple), record=recorded)
    if scenario is not None:
        ex.add_manipulator(ScenarioManipulator(events))
    condition = hooks.stop_condition(bound, until)
    if condition:
        ex.stop_when(condition)
    if not (realtime == 0 or MIN_REALTIME <= realtime <= MAX_REALTIME):
        raise ConfigurationError(f"--realtime {realtime}: must be >= 0 (0 = as fast as possible; else "
                                 f"{MIN_REALTIME:g} to {MAX_REALTIME:g} simulated seconds per wall second)")
    pacer = RealTimePacer(realtime) if realtime > 0 else None
    rec = recorder(fmt, out, every=record_every)
    record_ = RunRecord(out / "run.json", str(system), [str(p) for p in params],
                        {"system_name": bound.definition.name, "stop_time_s": stop,
                         "scenario": str(scenario) if scenario else None, "format": fmt},
                        reporters=[pacer] if pacer else [])
    record_.add_files([FORMATS[fmt].file_name] + ([SETTINGS_FILE] if settings else []))
    bar = Progress(stop, status=hooks.status_variable(bound, status)) if progress else None
    for o in (pacer, rec, record_, bar):
        if o is not None:
            ex.add_observer(o)
    from .plugins import load_problems

    for line in load_problems:
        say(line)
    pre = hooks.pre_run(bound) if pre_run else []
    for line in pre:
        say(line)
    error: BaseException | None = None
    try:
        with stop_on_signals(lambda signum: (interrupt.stopping_run(signum), ex.request_stop(signum))):
            ex.run(stop)
    except (EmssError, KeyboardInterrupt) as exc:
        error = RunInterrupted(interrupt.signal_of(exc), ex.time_s) if isinstance(exc, KeyboardInterrupt) else exc
    written: list[Path] = []
    failures: list[str] = []
    if post_run and not isinstance(error, ResultsError):  # what was recorded is on disk
        interrupt.phase("report", "during the report", f"the run's results are in {out} (run.json: "
                                                       f"{record_.info.get('status')}), the report is incomplete")
        written, failures = hooks.post_run(out, error, figures)
        if written:
            record_.add_files([f.name for f in written])
    first = ex.stepping_started if ex.stepping_started is not None else time.perf_counter()
    last = ex.stepping_ended if ex.stepping_ended is not None else first
    cpu_first, cpu_last = ex.stepping_cpu if ex.stepping_started is not None else (time.process_time(),) * 2
    record_.info["timing"] = {"setup_s": first - started[0], "stepping_s": last - first,
                              "writing_s": time.perf_counter() - last, "setup_cpu_s": cpu_first - started[1],
                              "stepping_cpu_s": cpu_last - cpu_first, "writing_cpu_s": time.process_time() - cpu_last}
    record_.info["instances"] = {s.name: "reset" if s.reused else "instantiated" for s in ex.slaves}
    with contextlib.suppress(OSError, ResultsError):  # run.json cannot be written again: the outcome still returns
        record_.rewrite()
    result = RunResult(out, str(record_.info.get("status")), None if error is None else str(error), record_.info,
                       files=written, post_run_failures=failures, pre_run=pre, rows=rec.rows_written,
                       stopped_by=ex.stopped_by, step_size_s=ex.step_size_s)
    if written:
        result.summary, failed = hooks.run_summary(written)
        result.post_run_failures.extend(failed)
    if isinstance(error, RunInterrupted):
        result.exit_code = error.exit_code
    elif isinstance(error, (ConfigurationError, SystemStructureError)) or (error is not None and not ex.initialized):
        result.exit_code = ExitCode.USAGE  # bad input found as the run started (a scenario, a mission file)
    elif error is not None:
        result.exit_code = ExitCode.FAILED
    result.info["stats"] = ex.stats()
    return result
