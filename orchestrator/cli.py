"""The ``emss`` command: run, inspect and validate SSP systems of FMUs.

Bad input gives one line on stderr (what, where, what is allowed) and a non-zero
exit code, never a traceback; a run that fails keeps what it recorded.
"""
from __future__ import annotations

import argparse
import fnmatch
import importlib
import json
import math
import os
import pkgutil
import signal
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from .build import PACKAGE_ROOT, ensure_built
from .errors import ConfigurationError, EmssError, Problem, SystemStructureError
from .execution import DEFAULT_RATE_HZ, MAX_RATE_HZ, MAX_STEP_MULTIPLE, MIN_RATE_HZ, Execution
from .manipulators import INT32_RANGE, ScenarioManipulator, load_scenario
from .observers import CsvRecorder, Progress, RealTimePacer, RunRecord
from .plugins import load_problems, plugin_name, plugins
from .results import (
    ResultsError,
    ResultsFolder,
    RunInterrupted,
    atomic_write,
    check_name,
    os_reason,
    stop_on_signals,
)
from .ssp import load_system
from .system import BoundSystem, bind_system

#: The job ``emss run`` runs without a SYSTEM argument: the project's coupled system in ssp/, which
#: flies the Munich demonstration mission.
DEFAULT_SYSTEM = PACKAGE_ROOT / "ssp"
MIN_REALTIME, MAX_REALTIME = 1e-3, 1e6  #: pacing factors allowed (a factor of 1e-300 would sleep for ever)


class _Parser(argparse.ArgumentParser):
    """argparse, but usage errors are one line."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def finite_number(text: str) -> float:
    """A finite number (argparse type): NaN and infinities are refused where they enter."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def folder_name(text: str) -> Path:
    """A results folder (argparse type): not empty (an empty name would write into the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty folder name; give the results folder, e.g. --out results/run1")
    return Path(text)


def _add_system_args(p: argparse.ArgumentParser, optional: bool = False) -> None:
    p.add_argument("system", nargs="?" if optional else None, type=Path,
                   help="folder holding SystemStructure.ssd, an .ssd file or an .ssp archive"
                        + (" (default: ssp/, the Munich mission)" if optional else ""))
    p.add_argument("--params", type=Path, nargs="+", action="extend", default=[], metavar="FILE.ssv",
                   help="system-level parameter sets (names component.variable), applied after the SSD's")
    p.add_argument("--set", nargs="+", action="extend", default=[], metavar="COMPONENT.VARIABLE=VALUE",
                   help="parameter values, applied last (e.g. fcs.mission_file=missions/my.yaml, "
                        "engine.preset=reference_study)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="emss", description="openEMSS: run SSP systems of FMI 2.0 co-simulation FMUs.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    run = sub.add_parser("run", help="run a system and record its time histories",
                         description="Run a system with a fixed-step master; writes timeseries.csv and run.json.")
    _add_system_args(run, optional=True)
    run.add_argument("--stop-time", type=finite_number, metavar="S", help="stop time [s] (default: the SSD's)")
    run.add_argument("--rate", type=float, metavar="HZ",
                     help=f"communication rate [Hz], {MIN_RATE_HZ} to {MAX_RATE_HZ} "
                          f"(default: the SSD's OSP FixedStepAlgorithm annotation, else {DEFAULT_RATE_HZ})")
    run.add_argument("--algorithm", choices=("jacobi", "gauss-seidel"), default="jacobi",
                     help="master algorithm (default: jacobi)")
    run.add_argument("--step-multiple", nargs="+", action="extend", default=[], metavar="COMPONENT=N",
                     help="let a component step every N-th macro step")
    run.add_argument("--out", type=folder_name, help="output folder (default: results/<system>-<time>); one run at a "
                                                 "time: a folder another run is writing is refused, and an earlier "
                                                 "run's files in it are removed first")
    run.add_argument("--record", nargs="+", action="extend", metavar="VARS",
                     help="variables to record, component.variable, wildcards and commas allowed "
                          "(default: every connector)")
    run.add_argument("--record-every", type=int, default=1, metavar="N", help="record every N-th step")
    run.add_argument("--scenario", type=Path, metavar="FILE",
                     help="YAML file of timed events: set, ramp, hold, release inputs and tunable parameters")
    run.add_argument("--until", metavar="CONDITION",
                     help="end the run after the first step where 'component.variable OP number' holds (OP one of "
                          "== != < <= > >=), e.g. 'fcs.mission_completed == 1'; default: the condition a plugin "
                          "proposes for the system (the report plugin: the mission completed), 'never' for none")
    run.add_argument("--realtime", type=finite_number, default=0.0, metavar="FACTOR",
                     help="pace against the wall clock: 1.0 = real time, 2.0 = twice as fast; 0 = as fast as "
                          "possible (default)")
    run.add_argument("--stats", action="store_true",
                     help="print the time each component spent in doStep, get and set")
    run.add_argument("--status", metavar="VAR",
                     help="component.variable shown in the progress bar, any type (default: what a plugin "
                          "proposes, e.g. the active mission section)")
    run.add_argument("--no-pre-run", action="store_true",
                     help="skip the plugins' pre-run checks (e.g. the feasibility of a mission before flying it)")
    run.add_argument("--no-post-run", action="store_true",
                     help="skip the plugins' post-run hooks (e.g. summary.json and plots of a mission run)")
    run.add_argument("--json", action="store_true", help="print the run summary as JSON")

    info = sub.add_parser("info", help="describe a system: components, connections, parameters, step order")
    _add_system_args(info)
    info.add_argument("--json", action="store_true", help="print as JSON")

    exp = sub.add_parser("export", help="export a system as one FMU (fmpy's container FMU)",
                         description="Write the whole system as one FMI 2.0 co-simulation FMU that other tools "
                                     "run (fmpy's container runtime: no transformations, unit conversions, "
                                     "mappings or step multiples; initialization in one pass).")
    _add_system_args(exp)
    exp.add_argument("--container", type=Path, required=True, metavar="FILE.fmu", help="the FMU to write")
    exp.add_argument("--rate", type=float, metavar="HZ",
                     help="the container's fixed step as a rate [Hz] (default: the SSD's, else 20)")
    exp.add_argument("--expose", nargs="+", action="extend", default=[], metavar="VARS",
                     help="further component.variable paths to expose (comma-separated allowed)")

    _register_model_commands(sub)
    _register_plugin_commands(sub)

    val = sub.add_parser("validate", help="check a system and its FMUs; exit code = number of problems",
                         description="List every problem of a system: schema, FMUs, connectors, "
                                     "connections, parameters. The exit code is the number of problems.")
    _add_system_args(val)
    return parser


#: Exception types that model commands raise for bad input (reported as one line, no traceback).
USER_ERRORS: list[type[Exception]] = []


def _register_model_commands(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the sub-commands of model packages (``emss engine ...``, ``emss airframe ...``).

    Every package ``openemss.models.<name>`` that has a ``cli`` module with a
    ``register(subparsers) -> tuple[type[Exception], ...]`` function contributes
    its commands; each sets ``handler`` (a function of the parsed arguments
    returning the exit code) with ``set_defaults``, and returns the exception
    types that mean bad input. The orchestrator itself knows no model.
    """
    import openemss.models as models

    USER_ERRORS.clear()
    for info in sorted(pkgutil.iter_modules(models.__path__), key=lambda i: i.name):
        if not info.ispkg:
            continue
        try:
            module = importlib.import_module(f"openemss.models.{info.name}.cli")
        except ModuleNotFoundError as exc:
            if exc.name == f"openemss.models.{info.name}.cli":
                continue
            raise
        USER_ERRORS.extend(module.register(sub))
    from openemss.study import cli as study_cli  # ``emss study ...``: studies on Dask, same mechanism

    USER_ERRORS.extend(study_cli.register(sub))


def _register_plugin_commands(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the sub-commands of the ``openemss.plugins`` entry points (see :mod:`.plugins`)."""
    for module in plugins():
        register = getattr(module, "register", None)
        if register is not None:
            USER_ERRORS.extend(register(sub))


def _status_variable(bound: BoundSystem, requested: str | None) -> str | None:
    """The progress bar's status variable: ``--status`` (checked), else the first a plugin proposes."""
    if requested is not None:
        try:
            bound.variable(requested)
        except EmssError:
            raise ConfigurationError(f"--status '{requested}': no such variable (write component.variable "
                                     "with a component of this system)") from None
        return requested
    return _proposed(bound, "status_variable")


def _proposed(bound: BoundSystem, hook: str) -> str | None:
    """The first non-empty answer of the plugins' ``hook(variables)`` for this system, or None."""
    every = [f"{c.name}.{v}" for c in bound.components for v in c.variables]
    for module in plugins():
        propose = getattr(module, hook, None)
        answer = propose(every) if propose is not None else None
        if answer:
            return str(answer)
    return None


def _each_hook(hook_name: str, *args: object) -> list[tuple[list[object], str | None]]:
    """Call every plugin's ``hook_name(*args)``: per plugin that has it, (what it returned, as a list; None)
    or ([], one line saying how it failed). A failing hook never stops the run."""
    label = hook_name.replace("_", "-")
    out: list[tuple[list[object], str | None]] = []
    for module in plugins():
        hook = getattr(module, hook_name, None)
        if hook is None:
            continue
        try:
            out.append((list(hook(*args)), None))
        except (EmssError, *USER_ERRORS) as exc:
            out.append(([], f"{label} hook '{plugin_name(module)}' failed: {exc}"))
        except Exception as exc:
            if os.environ.get("EMSS_DEBUG"):
                raise
            out.append(([], f"{label} hook '{plugin_name(module)}' failed: internal error: "
                            f"{type(exc).__name__}: {exc} (set EMSS_DEBUG=1 for the traceback)"))
    return out


def _pre_run(bound: BoundSystem) -> list[str]:
    """Every plugin's pre-run hook on the bound system: the warning lines they return, and one line per
    hook that failed (a failed check never stops the run)."""
    components = {c.name: c.fmu_path for c in bound.components}
    parameters = {f"{bound.components[p.component].name}.{p.variable.name}": p.value for p in bound.parameters}
    lines: list[str] = []
    for result, failure in _each_hook("pre_run", components, parameters):
        lines.extend(str(line) for line in result)
        if failure is not None:
            lines.append(failure)
    return lines


def _post_run(out: Path, error: BaseException | None) -> tuple[list[Path], list[str]]:
    """Run every plugin's post-run hook on the results folder: (files written, one line per failure)."""
    written: list[Path] = []
    failures: list[str] = []
    for result, failure in _each_hook("post_run", out, error):
        written.extend(Path(str(f)) for f in result)
        if failure is not None:
            failures.append(failure)
    return written, failures


def _load(system: Path, params: Sequence[Path], settings: Sequence[str] = (),
          folder: Path | None = None) -> BoundSystem:
    """Bind the system with its parameter sets; ``settings`` (``component.variable=value``) are typed by
    the variables they set, written as one more parameter set into ``folder`` (the results, so a run
    records what it was given) and applied last."""
    bound = bind_system(load_system(system), list(params))
    if not settings:
        return bound
    from lxml import etree

    from .ssp_write import ParameterSet

    values: dict[str, bool | int | float | str] = {}
    for item in settings:
        path, eq, text = item.partition("=")
        if not eq:
            raise ConfigurationError(f"--set {item!r}: write component.variable=value")
        try:
            _, var = bound.variable(path.strip())
        except EmssError:
            raise ConfigurationError(f"--set {item!r}: no variable '{path.strip()}' (write component.variable "
                                     "with a component of this system)") from None
        values[path.strip()] = _typed(text.strip(), var.type_name, item)
    target = (folder or Path(tempfile.mkdtemp(prefix="emss-set-"))) / "cli_parameters.ssv"
    target.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(target, etree.tostring(ParameterSet("cli_parameters", values).element(), xml_declaration=True,
                                        encoding="UTF-8", pretty_print=True))
    return bind_system(load_system(system), [*params, target])


def _typed(text: str, type_name: str, item: str) -> bool | int | float | str:
    """``text`` as a value of an FMI type; a String that names an existing file becomes its absolute path."""
    try:
        if type_name == "Real":
            value = float(text)
            if not math.isfinite(value):
                raise ValueError
            return value
        if type_name in ("Integer", "Enumeration"):
            value = int(text)
            if not INT32_RANGE[0] <= value <= INT32_RANGE[1]:
                raise ConfigurationError(f"--set {item!r}: outside the range of an FMI Integer "
                                         f"({INT32_RANGE[0]} to {INT32_RANGE[1]})")
            return value
        if type_name == "Boolean":
            if text.lower() not in ("true", "false", "1", "0"):
                raise ValueError
            return text.lower() in ("true", "1")
    except ValueError:
        raise ConfigurationError(f"--set {item!r}: not a valid {type_name} value"
                                 + (" (a finite number)" if type_name == "Real" else "")) from None
    return str(Path(text).resolve()) if Path(text).is_file() else text


def _multiples(items: Sequence[str]) -> dict[str, int]:
    out: dict[str, int] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not value.strip().isdigit() or not 1 <= int(value) <= MAX_STEP_MULTIPLE:
            raise ConfigurationError(f"--step-multiple '{item}': expected COMPONENT=N with an integer N from 1 "
                                     f"to {MAX_STEP_MULTIPLE}")
        out[name.strip()] = int(value)
    return out


def _record_paths(bound: BoundSystem, patterns: Sequence[str] | None) -> list[str] | None:
    if not patterns:
        return None
    every = [f"{c.name}.{v}" for c in bound.components for v in c.variables]
    chosen: list[str] = []
    for pattern in (p.strip() for item in patterns for p in item.split(",") if p.strip()):
        hits = [p for p in every if fnmatch.fnmatchcase(p, pattern)]
        if not hits:
            raise ConfigurationError(f"--record '{pattern}' matches no variable (write component.variable; "
                                     "wildcards * and ? are allowed)")
        chosen.extend(h for h in hits if h not in chosen)
    return chosen


def _default_system() -> Path:
    if not (DEFAULT_SYSTEM / "SystemStructure.ssd").is_file():
        raise ConfigurationError("no SYSTEM given and the project's system is not available "
                                 f"({DEFAULT_SYSTEM}); give a system folder, .ssd or .ssp")
    return DEFAULT_SYSTEM


def _ensure_project_fmus(system: Path) -> None:
    """The project's own system (ssp/) gets its FMUs built from fmus/ when they are missing or stale."""
    project = PACKAGE_ROOT / "ssp"
    if system.is_dir() and project.is_dir() and system.resolve() == project.resolve():
        ensure_built(PACKAGE_ROOT / "fmus", project / "resources", report=lambda m: print(m, file=sys.stderr))


def cmd_run(args: argparse.Namespace) -> int:
    system = args.system if args.system is not None else _default_system()
    _ensure_project_fmus(system)
    if args.out is None:  # the default folder is named after the system: that name must be one path component
        name = check_name(str(load_system(system).name), "the system's name (the SSD's System name; or give --out)")
        out = Path("results") / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    else:
        out = args.out
    with ResultsFolder(out) as _:  # locked for this run, cleared of an earlier run's files
        return _run(args, system, out)


def _run(args: argparse.Namespace, system: Path, out: Path) -> int:
    bound = _load(system, args.params, args.set, out)
    sysdef = bound.definition
    stop = args.stop_time if args.stop_time is not None else sysdef.stop_time_s
    if stop is None:
        raise ConfigurationError("no stop time: give --stop-time or a DefaultExperiment stopTime in the SSD")
    if args.record_every < 1:
        raise ConfigurationError(f"--record-every {args.record_every}: must be an integer >= 1")
    ex = Execution(bound, rate_hz=args.rate, algorithm=args.algorithm, multiples=_multiples(args.step_multiple),
                   record=_record_paths(bound, args.record))
    if args.scenario is not None:
        ex.add_manipulator(ScenarioManipulator(load_scenario(args.scenario)))
    until = _stop_condition(bound, args.until)
    if until:
        ex.stop_when(until)
    if not (args.realtime == 0 or MIN_REALTIME <= args.realtime <= MAX_REALTIME):
        raise ConfigurationError(f"--realtime {args.realtime}: must be >= 0 (0 = as fast as possible; else "
                                 f"{MIN_REALTIME:g} to {MAX_REALTIME:g} simulated seconds per wall second)")
    pacer = RealTimePacer(args.realtime) if args.realtime > 0 else None
    csv = CsvRecorder(out / "timeseries.csv", every=args.record_every)
    record = RunRecord(out / "run.json", str(system), [str(p) for p in args.params],
                       {"stop_time_s": stop, "scenario": str(args.scenario) if args.scenario else None},
                       reporters=[pacer] if pacer else [])
    record.add_files([csv.path.name] + (["cli_parameters.ssv"] if args.set else []))
    for o in (pacer, csv, record, Progress(stop, status=_status_variable(bound, args.status))):
        if o is not None:
            ex.add_observer(o)
    for line in load_problems:
        print(f"emss run: warning: {line}", file=sys.stderr)
    pre = [] if args.no_pre_run else _pre_run(bound)
    for line in pre:
        print(f"emss run: warning: {line}", file=sys.stderr)
    try:
        with stop_on_signals(ex.request_stop):
            ex.run(stop)
    except (EmssError, KeyboardInterrupt) as exc:
        if not args.no_post_run and not isinstance(exc, ResultsError):  # what was recorded is on disk
            written, failures = _post_run(out, exc)
            _list_files(record, written)
            for line in failures:
                print(f"emss run: {line}", file=sys.stderr)
        if isinstance(exc, KeyboardInterrupt):  # a second Ctrl-C, or one before the handlers were in place
            exc = RunInterrupted(signal.SIGINT, ex.time_s)
        if isinstance(exc, RunInterrupted):
            print(f"emss run: {exc} (results so far in {out})", file=sys.stderr)
            return exc.exit_code
        raise EmssError(f"{exc}" + (f" (results so far in {out})" if csv.rows_written else "")) from None
    written, failures = ([], []) if args.no_post_run else _post_run(out, None)
    _list_files(record, written)
    summary = {k: record.info.get(k) for k in ("status", "algorithm", "rate_hz", "stop_time_s", "steps",
                                                "wall_time_s", "realtime_factor", "realtime")}
    summary.update(system=sysdef.name, out=str(out), rows=csv.rows_written, pre_run=pre,
                   post_run=[str(f) for f in written])
    if args.stats:
        summary["step_statistics"] = ex.stats()
    for line in failures:
        print(f"emss run: error: {line}", file=sys.stderr)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 1 if failures else 0
    print(f"{sysdef.name}: {summary['steps']} steps of {ex.step_size_s:g} s ({args.algorithm}) to "
          f"t = {ex.time_s:g} s in {summary['wall_time_s']:.3f} s wall, {summary['realtime_factor']:.1f}x "
          f"real time; results in {out}" + (f" (stopped early: {ex.stopped_by})" if ex.stopped_by else ""))
    if pacer is not None:
        rt = summary["realtime"]
        print(f"paced at {rt['target_factor']:g}x real time: achieved {rt['achieved_factor']:.3f}x, "
              f"{rt['overruns']} overrun(s), largest lag {rt['max_lag_s'] * 1e3:.1f} ms")
    if written:
        print(f"written after the run: {', '.join(f.name for f in written)}")
    if args.stats:
        print(_stats_table(ex.stats()))
    return 1 if failures else 0


def _list_files(record: RunRecord, written: list[Path]) -> None:
    """Add the post-run hooks' files to run.json's list of the run's files (the next run removes them)."""
    if written:
        record.add_files([f.name for f in written])
        record.rewrite()


def _stop_condition(bound: BoundSystem, requested: str | None) -> str | None:
    """``--until``, else the first stop condition a plugin proposes for this system; None for none."""
    if requested is not None:
        return None if requested.strip().lower() == "never" else requested
    return _proposed(bound, "stop_condition")


def _stats_table(stats: dict[str, dict[str, float]]) -> str:
    """Per component: steps, and total [s] and mean [us] per step in doStep, get and set."""
    head = f"{'component':<24} {'steps':>8} {'doStep s':>10} {'us/step':>9} {'get s':>9} {'us/step':>9} " \
           f"{'set s':>9} {'us/step':>9}"
    lines = [head, "-" * len(head)]
    for name, st in stats.items():
        n = max(int(st["steps"]), 1)
        lines.append(f"{name:<24} {int(st['steps']):>8} {st['do_step_s']:>10.4f} {st['do_step_s'] / n * 1e6:>9.2f} "
                     f"{st['get_s']:>9.4f} {st['get_s'] / n * 1e6:>9.2f} {st['set_s']:>9.4f} "
                     f"{st['set_s'] / n * 1e6:>9.2f}")
    return "\n".join(lines)


def _describe(bound: BoundSystem) -> dict[str, Any]:
    sysdef = bound.definition
    ex_order = Execution(bound, rate_hz=None).order
    names = [c.name for c in bound.components]
    return {
        "name": sysdef.name,
        "ssd": str(sysdef.ssd_path),
        "default_experiment": {"start_time_s": sysdef.start_time_s, "stop_time_s": sysdef.stop_time_s},
        "rate_hz": 1.0 / sysdef.step_size_s if sysdef.step_size_s else DEFAULT_RATE_HZ,
        "components": [{
            "name": c.name, "fmu": c.definition.source, "model": c.model_description.modelName,
            "variables": len(c.variables),
            "connectors": [{"name": k.name, "kind": k.kind, "type": c.variables[k.name].type_name,
                            "unit": k.unit or c.variables[k.name].unit} for k in c.definition.connectors],
        } for c in bound.components],
        "connections": [f"{names[ln.source]}.{ln.source_var.name} -> {names[ln.target]}.{ln.target_var.name}"
                        for ln in bound.links],
        "parameters": {f"{names[p.component]}.{p.variable.name}": p.value for p in bound.parameters},
        "gauss_seidel_order": [names[i] for i in ex_order.order],
        "gauss_seidel_lagging": [f"{names[s]} -> {names[t]}" for s, t in ex_order.lagging],
    }


def cmd_export(args: argparse.Namespace) -> int:
    from .execution import check_rate
    from .export import export_container

    bound = _load(args.system, args.params, args.set)
    sysdef = bound.definition
    rate = args.rate if args.rate is not None else (1.0 / sysdef.step_size_s if sysdef.step_size_s
                                                   else DEFAULT_RATE_HZ)
    step = check_rate(rate)
    expose = [p.strip() for item in args.expose for p in item.split(",") if p.strip()]
    path = export_container(bound, args.container, step, expose=expose)
    print(f"{sysdef.name}: {len(bound.components)} FMUs and {len(bound.links)} connections written as "
          f"{path} (fixed step {step:g} s)")
    return 0


def cmd_info(args: argparse.Namespace) -> int:
    d = _describe(_load(args.system, args.params, args.set))
    if args.json:
        print(json.dumps(d, indent=2, default=str))
        return 0
    print(f"system {d['name']}  ({d['ssd']})")
    de = d["default_experiment"]
    print(f"  default experiment: start {de['start_time_s']} s, stop {de['stop_time_s']} s; rate {d['rate_hz']:g} Hz")
    for c in d["components"]:
        print(f"  component {c['name']}: {c['fmu']} (model {c['model']}, {c['variables']} variables)")
        for k in c["connectors"]:
            unit = f" [{k['unit']}]" if k["unit"] else ""
            print(f"    {k['kind']:<8} {k['name']} : {k['type']}{unit}")
    print(f"  connections ({len(d['connections'])}):")
    for line in d["connections"]:
        print(f"    {line}")
    print(f"  parameters ({len(d['parameters'])}):")
    for name, value in d["parameters"].items():
        print(f"    {name} = {value}")
    print(f"  Gauss-Seidel order: {' -> '.join(d['gauss_seidel_order'])}")
    lag = ", ".join(d["gauss_seidel_lagging"]) or "none"
    print(f"  connections using the previous step's value (cycle breaks): {lag}")
    return 0


def _fmu_problems(bound: BoundSystem) -> list[Problem]:
    from fmpy.validation import validate_fmu

    problems: list[Problem] = []
    for path in sorted({c.fmu_path for c in bound.components}):
        for message in validate_fmu(str(path)):
            problems.append(Problem(str(path), f"fmpy validate: {message.strip()}"))
    return problems


def cmd_validate(args: argparse.Namespace) -> int:
    try:
        bound = _load(args.system, args.params, args.set)
        problems = _fmu_problems(bound)
    except SystemStructureError as exc:
        problems = exc.problems
        bound = None
    for p in problems:
        print(p)
    warnings = binding_warnings(bound) if bound is not None else []
    for w in warnings:
        print(w)
    print(f"{len(problems)} problem(s) found in {args.system}"
          + (f"; {len(warnings)} warning(s)" if warnings else ""), file=sys.stderr)
    return min(len(problems), 125)


def binding_warnings(bound: BoundSystem) -> list[str]:
    """One warning per parameter binding whose value differs from the FMU's default (its start value):
    a tool that applies no bindings (FMPy's SSP runner, a container without them) runs the default."""
    out = []
    for a in bound.parameters:
        v, start = a.variable, a.variable.start
        if start is None:
            continue
        same = (math.isclose(float(a.value), float(start), rel_tol=1e-12, abs_tol=0.0)
                if v.type_name == "Real" else str(a.value).lower() == str(start).lower())
        if not same:
            out.append(f"{a.where}: warning: {bound.components[a.component].name}.{v.name} = {a.value!r} differs "
                       f"from the FMU's default {start!r}: a tool that applies no bindings runs the default")
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``emss`` command."""
    args = build_parser().parse_args(argv)
    builtin: dict[str, Callable[[argparse.Namespace], int]] = {"run": cmd_run, "info": cmd_info,
                                                               "validate": cmd_validate, "export": cmd_export}
    handler = builtin.get(args.command) or args.handler
    try:
        return handler(args)
    except RunInterrupted as exc:
        print(f"emss {args.command}: {exc}", file=sys.stderr)
        return exc.exit_code
    except (EmssError, *USER_ERRORS) as exc:
        print(f"emss {args.command}: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"emss {args.command}: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:  # a file the command reads or writes: one line naming it and the cause
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"emss {args.command}: error: {where}{os_reason(exc)}", file=sys.stderr)
        return 1
    except Exception as exc:  # an internal error: one line, traceback only on request
        if os.environ.get("EMSS_DEBUG"):
            raise
        print(f"emss {args.command}: internal error: {type(exc).__name__}: {exc} "
              "(set EMSS_DEBUG=1 for the traceback)", file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
