"""The ``emss`` command: run, inspect and validate SSP systems of FMUs.

Bad input gives one line on stderr (what, where, what is allowed) and a non-zero
exit code, never a traceback; a run that fails keeps what it recorded. The exit codes: :mod:`..exit_codes`.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from .. import interrupt
from ..errors import EmssError, Problem, RunFailed, SystemStructureError
from ..exit_codes import ExitCode, help_text
from ..master import algorithm_registry
from ..master.algorithm import step_order
from ..master.execution import DEFAULT_RATE_HZ, MAX_RATE_HZ, MIN_RATE_HZ
from ..recording.timeseries import DEFAULT_FORMAT, DEFAULT_RECORD_TEXT, FORMATS, format_help
from ..results import RunInterrupted, os_reason
from ..ssp.system import BoundSystem
from . import api
from .argtypes import finite_number, folder_name
from .hooks import USER_ERRORS
from .plugins import plugins

#: The system ``emss run`` and ``emss info`` use without a SYSTEM argument (ssp/, the Munich mission).
DEFAULT_SYSTEM = api.DEFAULT_SYSTEM


class _Parser(argparse.ArgumentParser):
    """argparse, but usage errors are one line."""

    def error(self, message: str) -> NoReturn:
        self.exit(ExitCode.USAGE, f"{self.prog}: error: {message} (see --help)\n")


def _add_system_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("system", nargs="?", type=Path,
                   help="folder holding SystemStructure.ssd, an .ssd file or an .ssp archive (default: ssp/, the "
                        "Munich mission)")
    p.add_argument("--params", type=Path, nargs="+", action="extend", default=[], metavar="FILE.ssv",
                   help="system-level parameter sets (names component.variable), applied after the SSD's")
    p.add_argument("--set", nargs="+", action="extend", default=[], metavar="COMPONENT.VARIABLE=VALUE",
                   help="parameter values, applied last (e.g. fcs.mission_file=missions/my.yaml, "
                        "engine.preset=reference_study)")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = _Parser(prog="emss", description="openEMSS: run SSP systems of FMI 2.0 co-simulation FMUs.",
                     epilog=help_text(), formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"emss (openEMSS) {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    run = sub.add_parser("run", help="run a system and record its time histories",
                         description="Run a system with a fixed-step master; writes the time series ("
                                     + ", ".join(f"{f.file_name}{' by default' if f.name == DEFAULT_FORMAT else ''}"
                                                 for f in FORMATS.values())
                                     + ": --format) and run.json into the results folder (--out); plugins add "
                                       "theirs (the report plugin: summary.json, plots, report.html).")
    _add_system_args(run)
    run.add_argument("--stop-time", type=finite_number, metavar="S", help="stop time [s] (default: the SSD's)")
    run.add_argument("--rate", type=float, metavar="HZ",
                     help=f"communication rate [Hz], {MIN_RATE_HZ} to {MAX_RATE_HZ} "
                          f"(default: the SSD's OSP FixedStepAlgorithm annotation, else {DEFAULT_RATE_HZ})")
    run.add_argument("--algorithm", choices=algorithm_registry.names(), default=algorithm_registry.DEFAULT,
                     help="master algorithm: " + "; ".join(f"{e.name}: {e.summary}" for e in
                                                           algorithm_registry.REGISTRY.values())
                          + f" (default: {algorithm_registry.DEFAULT})")
    run.add_argument("--step-multiple", nargs="+", action="extend", default=[], metavar="COMPONENT=N",
                     help="let a component step every N-th macro step")
    run.add_argument("--out", type=folder_name, help="output folder (default: results/<system>-<time>); one run at a "
                                                 "time: a folder another run is writing is refused; what earlier "
                                                 "runs wrote there is removed first, nothing else")
    run.add_argument("--record", nargs="+", action="extend", metavar="VARS",
                     help="variables to record, component.variable, wildcards and commas allowed "
                          f"(default: {DEFAULT_RECORD_TEXT})")
    run.add_argument("--record-inputs", action="store_true",
                     help="also record the inputs that only copy a connected output")
    run.add_argument("--record-every", type=int, default=1, metavar="N", help="record every N-th step")
    run.add_argument("--format", choices=list(FORMATS), default=DEFAULT_FORMAT, help=format_help())
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
    run.add_argument("--no-figures", action="store_true",
                     help="post-run reports write their tables only (summary.json), no plots or report.html; "
                          "emss plot RUN_DIR draws them later")
    run.add_argument("--no-build", action="store_true",
                     help="do not check the project's own FMUs against their sources before the run (a study's "
                          "cases: the study checked them once)")
    run.add_argument("--json", action="store_true", help="print the run summary as JSON")

    info = sub.add_parser("info", help="describe a system: components, connections, parameters, step order")
    _add_system_args(info)
    info.add_argument("--parameters", action="store_true",
                      help="list every settable parameter (for --set) with type, unit, default, range and "
                           "description")
    info.add_argument("--json", action="store_true", help="print as JSON")

    exp = sub.add_parser("export", help="export a system as one FMU (fmpy's container FMU)",
                         description="Write the whole system as one FMI 2.0 co-simulation FMU that other tools "
                                     "run (fmpy's container runtime: no transformations, unit conversions, "
                                     "mappings or step multiples; initialization in one pass).")
    _add_system_args(exp)
    exp.add_argument("--container", type=Path, required=True, metavar="FILE.fmu", help="the FMU to write")
    exp.add_argument("--rate", type=float, metavar="HZ",
                     help=f"the container's fixed step as a rate [Hz] (default: the SSD's, else {DEFAULT_RATE_HZ:g})")
    exp.add_argument("--expose", nargs="+", action="extend", default=[], metavar="VARS",
                     help="further component.variable paths to expose (comma-separated allowed)")

    _register_plugin_commands(sub)

    val = sub.add_parser("validate", help=f"check a system and its FMUs; exit code {ExitCode.FINDINGS:d} "
                                          "when it finds problems (their number printed)",
                         description="List every problem of a system: schema, FMUs, connectors, connections, "
                                     f"parameters, and their number. Exit code {ExitCode.OK:d}: none, "
                                     f"{ExitCode.FINDINGS:d}: problems found.")
    _add_system_args(val)
    return parser


def _register_plugin_commands(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the sub-commands of the ``openemss.plugins`` entry points (see :mod:`.plugins`): the only way a
    command comes in (``emss engine``, ``emss airframe``, ``emss study``, the report's); the orchestrator knows
    none by name."""
    USER_ERRORS.clear()
    for module in plugins():
        register = getattr(module, "register", None)
        if register is not None:
            USER_ERRORS.extend(register(sub))


def cmd_run(args: argparse.Namespace) -> int:
    """``emss run``: :func:`.api.run` with the command line's arguments, and its outcome printed."""
    res = api.run(args.system, stop_time=args.stop_time, params=args.params, set=args.set, scenario=args.scenario,
                  out=args.out, rate=args.rate, algorithm=args.algorithm, step_multiple=args.step_multiple,
                  record=args.record, record_inputs=args.record_inputs, record_every=args.record_every,
                  format=args.format, until=args.until, realtime=args.realtime, status=args.status,
                  pre_run=not args.no_pre_run, post_run=not args.no_post_run, figures=not args.no_figures,
                  build=not args.no_build, progress=True)
    out = res.out
    if res.status == "interrupted":
        for line in res.post_run_failures:
            print(f"emss run: {line}", file=sys.stderr)
        print(f"emss run: {res.error} (results so far in {out})", file=sys.stderr)
        return res.exit_code
    if res.status != "completed":
        for line in res.post_run_failures:
            print(f"emss run: {line}", file=sys.stderr)
        error = RunFailed if res.exit_code == ExitCode.FAILED else EmssError
        raise error(f"{res.error}" + (f" (results so far in {out})" if res.rows else ""))
    info = res.info
    summary = {k: info.get(k) for k in ("status", "algorithm", "rate_hz", "stop_time_s", "steps",
                                         "wall_time_s", "realtime_factor", "realtime")}
    summary.update(system=load_system_name(info), out=str(out), rows=res.rows, pre_run=res.pre_run,
                   post_run=[str(f) for f in res.files])
    if args.stats:
        summary["step_statistics"] = info["stats"]
    for line in res.post_run_failures:
        print(f"emss run: error: {line}", file=sys.stderr)
    code = ExitCode.FAILED if res.post_run_failures else ExitCode.OK
    if args.json:
        print(json.dumps(summary, indent=2))
        return code
    print(f"{summary['system']}: {summary['steps']} steps of {res.step_size_s:g} s ({args.algorithm}) to "
          f"t = {info['stop_time_s']:g} s in {summary['wall_time_s']:.3f} s wall, {summary['realtime_factor']:.1f}x "
          f"real time; results in {out}" + (f" (stopped early: {res.stopped_by})" if res.stopped_by else ""))
    if info.get("realtime"):
        rt = info["realtime"]
        print(f"paced at {rt['target_factor']:g}x real time: achieved {rt['achieved_factor']:.3f}x, "
              f"{rt['overruns']} overrun(s), largest lag {rt['max_lag_s'] * 1e3:.1f} ms")
    if res.files:
        print(f"written after the run: {', '.join(f.name for f in res.files)}")
    if args.stats:
        print(_stats_table(info["stats"]))
    return code


def load_system_name(info: dict[str, Any]) -> str:
    """The system's name as run.json records it (the SSD's System name)."""
    return str(info.get("system_name") or Path(str(info.get("system", "system"))).name)


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
    ex_order = step_order(bound)
    names = [c.name for c in bound.components]
    return {
        "name": sysdef.name,
        "ssd": sysdef.origin.shown(sysdef.ssd_path),
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


def _load(args: argparse.Namespace) -> BoundSystem:
    """The command's system (default ssp/) bound with ``--params`` and ``--set``."""
    system = args.system if args.system is not None else api.default_system()
    api.ensure_project_fmus(system)
    return api.load(system, args.params, args.set)


def fix_swallowed_system(args: argparse.Namespace) -> None:
    """``--params A.ssv B.ssv SYSTEM``: argparse gives SYSTEM to ``--params`` (nargs='+'); a folder, ``.ssd``
    or ``.ssp`` among them is the SYSTEM argument when none was given."""
    params = getattr(args, "params", None)
    if not params or not hasattr(args, "system"):
        return
    systems = [p for p in params if p.is_dir() or p.suffix.lower() in (".ssd", ".ssp")]
    if len(systems) == 1 and args.system is None:
        args.system = systems[0]
        args.params = [p for p in params if p is not systems[0]]


def cmd_export(args: argparse.Namespace) -> int:
    from ..fmu.export import export_container
    from ..master.execution import check_rate

    bound = _load(args)
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
    bound = _load(args)
    if args.parameters:
        from .describe import parameter_lines, parameters

        rows = parameters(bound)
        if args.json:
            print(json.dumps(rows, indent=2, default=str))
        else:
            print("\n".join(parameter_lines(rows)))
            print(f"{len(rows)} parameter(s); set one with --set component.variable=value", file=sys.stderr)
        return 0
    d = _describe(bound)
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
            problems.append(Problem(bound.definition.origin.shown(path), f"fmpy validate: {message.strip()}"))
    return problems


def cmd_validate(args: argparse.Namespace) -> int:
    try:
        bound = _load(args)
        problems = _fmu_problems(bound)
    except SystemStructureError as exc:
        problems = exc.problems
        bound = None
    for p in problems:
        print(p)
    warnings = binding_warnings(bound) if bound is not None else []
    for w in warnings:
        print(w)
    print(f"{len(problems)} problem(s) found in {args.system or api.DEFAULT_SYSTEM}"
          + (f"; {len(warnings)} warning(s)" if warnings else ""), file=sys.stderr)
    return ExitCode.FINDINGS if problems else ExitCode.OK


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
    fix_swallowed_system(args)
    builtin: dict[str, Callable[[argparse.Namespace], int]] = {"run": cmd_run, "info": cmd_info,
                                                               "validate": cmd_validate, "export": cmd_export}
    handler = builtin.get(args.command) or args.handler
    interrupt.phase(args.command, "", "")  # the command names its phases (emss run: build, load, run, report)
    try:
        try:
            return handler(args)
        except Exception as exc:  # a signal that surfaced as another error (an FMU's code cut): an interruption
            if interrupt.received() and not isinstance(exc, RunInterrupted):
                raise interrupt.Interrupted(interrupt.received()) from None
            raise
    except RunInterrupted as exc:
        print(f"emss {args.command}: {exc}", file=sys.stderr)
        return exc.exit_code
    except RunFailed as exc:
        print(f"emss {args.command}: error: {exc}", file=sys.stderr)
        return ExitCode.FAILED
    except (EmssError, *USER_ERRORS) as exc:
        print(f"emss {args.command}: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE
    except KeyboardInterrupt as exc:  # SIGINT or SIGTERM before or after the run's own steps
        return interrupt.report(f"emss {args.command}", exc)
    except OSError as exc:  # a file the command reads or writes: one line naming it and the cause
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"emss {args.command}: error: {where}{os_reason(exc)}", file=sys.stderr)
        return ExitCode.USAGE
    except Exception as exc:  # an internal error: one line, traceback only on request
        if os.environ.get("EMSS_DEBUG"):
            raise
        print(f"emss {args.command}: internal error: {type(exc).__name__}: {exc} "
              "(set EMSS_DEBUG=1 for the traceback)", file=sys.stderr)
        return ExitCode.INTERNAL


if __name__ == "__main__":
    sys.exit(main())
