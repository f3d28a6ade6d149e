"""The report as an ``emss`` plugin (entry point ``openemss.plugins``: see :mod:`openemss.orchestrator.cli.plugins`).

* ``post_run``: after every ``emss run`` of a system with a flight control system's
  ``section_index`` and an engine's ``Wf_kg_s`` and ``fuel_burned_kg``, writes
  ``summary.json``, the mission as flown (``mission.yaml``) and the plots into the
  results folder (also after a failed run, from what was recorded); nothing otherwise.
* ``status_variable``: the progress bar shows the FCS's ``section_name``.
* ``stop_condition``: the run ends when the FCS reports the mission completed.
* ``pre_run``: before every ``emss run`` of a system that flies a mission, its feasibility check
  (:mod:`.mission_check`): the marginal and infeasible sections, as warnings.
* ``run_summary``: ``summary.json`` read back for the Python API (``RunResult.summary``).
* ``emss plot RUN_DIR [RUN_DIR_B ...]``, ``emss summary RUN_DIR`` and ``emss mission check MISSION``.
"""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path, PurePosixPath

from openemss.models.life.errors import LifeDataError
from openemss.orchestrator.cli.argtypes import finite_number, folder_name
from openemss.orchestrator.results import ResultsFolder, atomic_write

from . import mission_check
from .errors import ReportError
from .files import PLOTS_RECORD, SUMMARY
from .html import REPORT, write_html_report, write_variables_html
from .mission_check import pre_run
from .plots import FigureFile, PlotRun, plot_runs, plot_variables
from .rundata import MISSION_COPY, find_roles, load_mission, load_run, read_header
from .summary import summarize

__all__ = ["pre_run", "post_run", "output_files", "run_summary", "status_variable", "stop_condition", "register",
           "write_report", "SUMMARY"]

MAX_RUNS = len(("-", "--", ":", "-."))


def status_variable(variables: Sequence[str]) -> str | None:
    """The active mission section's name (``<fcs>.section_name``) when a component has one."""
    names = set(variables)
    for path in variables:
        comp, _, var = path.partition(".")
        if var == "section_name" and f"{comp}.section_index" in names:
            return path
    return None


def stop_condition(variables: Sequence[str]) -> str | None:
    """End the run once the mission is completed (``<fcs>.mission_completed == 1``), when a component
    flies a mission: the stop time of the system is then an upper bound, not the mission's length."""
    names = set(variables)
    for path in variables:
        comp, _, var = path.partition(".")
        if var == "mission_completed" and f"{comp}.section_index" in names:
            return f"{path} == 1"
    return None


def output_files() -> list[str]:
    """The files :func:`post_run` may write into a results folder (checked free before a run)."""
    return [SUMMARY, REPORT, *FigureFile]


def _default_out(folders: Sequence[Path], runs: Sequence[PlotRun], window: tuple[float, float] | None) -> Path:
    """Where ``emss plot`` writes without ``--out``: the run's own folder (its report drawn again), for
    several runs ``RUN_DIR/compare_<others>``, with a window a folder of its own (``..._window_<T0>-<T1>``)
    so that the whole-run figures stay."""
    parts = ["compare_" + "_".join(r.label.replace("/", "-") for r in runs[1:])] if len(runs) > 1 else []
    if window is not None:
        parts.append(f"window_{window[0]:g}-{window[1]:g}")
    return folders[0] / "_".join(parts) if parts else folders[0]


def _check_origin(out: Path, origin: dict[str, object], names: Sequence[str], what: str) -> dict[str, object]:
    """Refuse to replace a figure of ``out`` that another plot made (other runs, window or variables, as
    :data:`PLOTS_RECORD` says; a figure it does not list is the run's own report, of that folder's run
    alone); returns the record with ``names`` made by ``origin``."""
    try:
        record = json.loads((out / PLOTS_RECORD).read_text(encoding="utf-8"))
        record = record if isinstance(record, dict) else {}
    except (OSError, ValueError):
        record = {}
    own = {"runs": [str(out.resolve())], "window": None, "variables": []}
    for name in names:
        if not (out / name).exists():
            continue
        before = record.get(name, own)
        if before != origin:
            runs = " ".join(str(r) for r in before.get("runs", [])) if isinstance(before, dict) else "?"
            win = before.get("window") if isinstance(before, dict) else None
            made = f"emss plot {runs}" + (f" --window {win[0]:g} {win[1]:g}" if win else "")
            raise ReportError(f"{what} {out}: {name} there was made by {made} ({PLOTS_RECORD}); it is not "
                              "replaced by another plot: give another --out, or remove that folder's figures")
    record.update({name: origin for name in names})
    return record


def _has_mission_signals(run_dir: Path) -> bool:
    roles = find_roles(read_header(run_dir))
    return roles.fcs is not None and roles.engine is not None


def write_report(run_dir: Path, plots: bool = True) -> list[Path]:
    """Write ``summary.json``, the mission copy and (with ``plots``) the figures of a mission run.

    Returns
    -------
    list of Path
        The files written; empty when the folder holds no mission run or no recorded row.
    """
    run_dir = Path(run_dir)
    if not _has_mission_signals(run_dir):
        return []
    try:
        run = load_run(run_dir)
    except ReportError as exc:
        if "no rows recorded" in str(exc):
            return []  # failed before the first sample: nothing to summarize
        raise
    mission, text = load_mission(run)
    written: list[Path] = []
    if mission is not None and text is not None and not list(run_dir.glob(MISSION_COPY + ".*")):
        source = mission.source.removesuffix(" (converted)")
        suffix = PurePosixPath(source.rpartition("!")[2]).suffix or ".yaml"
        copy = run_dir / f"{MISSION_COPY}{suffix}"
        atomic_write(copy, text)
        written.append(copy)
    summary = summarize(run, mission)
    path = run_dir / SUMMARY
    atomic_write(path, json.dumps(summary, indent=2) + "\n")
    written.insert(0, path)
    if plots:
        runs = [PlotRun(run, mission, run.name)]
        written.extend(plot_runs(runs, run_dir))
        page = write_html_report(runs, run_dir / REPORT)
        if page is not None:
            written.append(page)
    return written


def post_run(run_dir: Path, error: BaseException | None, figures: bool = True) -> list[Path]:
    """Post-run hook: the report of a mission run (see :func:`write_report`; without ``figures`` the summary
    and the mission copy only, ``emss plot RUN_DIR`` draws the rest later); nothing for other systems.
    A degraded run (a model held its outputs, see :func:`.summary.degraded`) is said on stderr."""
    written = write_report(run_dir, plots=figures)
    if written and written[0].name == SUMMARY:
        for line in json.loads(written[0].read_text(encoding="utf-8")).get("degraded") or []:
            print(f"emss run: warning: degraded run: {line}", file=sys.stderr)
    return written


def run_summary(files: Sequence[Path]) -> dict | None:
    """The summary among the files the post-run hooks wrote (``summary.json``), read back; None without one."""
    path = next((Path(f) for f in files if Path(f).name == SUMMARY), None)
    return None if path is None else json.loads(path.read_text(encoding="utf-8"))


# -- commands ----------------------------------------------------------------------------------
def _labels(folders: Sequence[Path]) -> list[str]:
    names = [f.resolve().name for f in folders]
    if len(set(names)) == len(names):
        return names
    return [f"{f.resolve().parent.name}/{f.resolve().name}" for f in folders]


#: Columns plotted by ``emss plot RUN`` of a run without mission signals (beyond them, name the variables).
MAX_ALL_COLUMNS = 12


def split_plot_args(items: Sequence[str]) -> tuple[list[Path], list[str]]:
    """``emss plot`` arguments: results folders first (existing folders), then variable names."""
    folders: list[Path] = []
    names: list[str] = []
    for item in items:
        if not names and Path(item).is_dir():
            folders.append(Path(item))
        else:
            names.append(item)
    if not folders:
        raise ReportError(f"{items[0]}: no such results folder (give a folder written by emss run, then "
                          "optionally variables component.variable)")
    return folders, names


def _check_names(runs: Sequence[PlotRun], names: Sequence[str]) -> None:
    import difflib

    recorded = [n for n in runs[0].data.columns if n != "time_s"]
    for name in names:
        if not any(name in r.data.columns for r in runs):
            close = difflib.get_close_matches(name, recorded, n=3)
            raise ReportError(f"{name}: not recorded in {runs[0].label}" + (
                f"; did you mean {', '.join(close)}?" if close else f" (recorded: {', '.join(recorded[:8])}"
                                                                    f"{', ...' if len(recorded) > 8 else ''})"))


def cmd_plot(args: argparse.Namespace) -> int:
    folders, names = split_plot_args(args.run_dirs)
    if len(folders) > MAX_RUNS:
        raise ReportError(f"{len(folders)} runs given; at most {MAX_RUNS} share a figure")
    runs = []
    for folder, label in zip(folders, _labels(folders), strict=True):
        data = load_run(folder)
        runs.append(PlotRun(data, load_mission(data)[0], label))
    window = tuple(args.window) if args.window is not None else None
    names = _names_to_plot(runs, folders, names)
    out = Path(args.out) if args.out is not None else _default_out(folders, runs, window)
    what = "--out" if args.out is not None else "RUN_DIR"
    stem = _variables_stem(names)
    figures = [f"{stem}.png", f"{stem}.html"] if names else [REPORT, *FigureFile]
    origin = {"runs": [str(f.resolve()) for f in folders], "window": list(window) if window else None,
              "variables": list(names)}
    with ResultsFolder(out, what, names=[*output_files(), *figures, PLOTS_RECORD], clear=False):
        record = _check_origin(out, origin, figures, what)
        files = _plot(runs, folders, names, out, window)
        atomic_write(out / PLOTS_RECORD, json.dumps(record, indent=1) + "\n")
    if args.json:
        print(json.dumps([str(f) for f in files], indent=2))
    else:
        print(f"{len(files)} file(s) of {', '.join(r.label for r in runs)} in {out}: "
              f"{', '.join(f.name for f in files)}")
    return 0


def _names_to_plot(runs: list[PlotRun], folders: list[Path], names: list[str]) -> list[str]:
    """The variables to plot: those named (checked), else none for a mission run (its figures), else every
    recorded column (at most :data:`MAX_ALL_COLUMNS`)."""
    mission_run = runs[0].data.roles.fcs is not None and runs[0].data.roles.engine is not None
    if not names and not mission_run:
        names = [n for n in runs[0].data.columns if n != "time_s"]
        if len(names) > MAX_ALL_COLUMNS:
            raise ReportError(f"{folders[0]}: no mission signals and {len(names)} recorded columns; name the ones "
                              f"to plot: emss plot {folders[0]} {' '.join(names[:2])} ...")
    if names:
        _check_names(runs, names)
    return names


def _plot(runs: list[PlotRun], folders: list[Path], names: list[str], out: Path,
          window: tuple[float, float] | None) -> list[Path]:
    """The files of ``emss plot`` written into ``out`` (a folder held by the caller)."""
    if names:
        stem = _variables_stem(names)
        files = [plot_variables(runs, names, out / f"{stem}.png", window),  # type: ignore[arg-type]
                 write_variables_html(runs, names, out / f"{stem}.html")]
    else:
        files = plot_runs(runs, out, window)  # type: ignore[arg-type]
        page = write_html_report(runs, out / REPORT) if files else None
        files += [page] if page is not None else []
    if not files:
        raise ReportError(f"nothing to plot in {', '.join(map(str, folders))}: no mission signals recorded "
                          "(position, altitude, engine)")
    return files


def _variables_stem(names: Sequence[str]) -> str:
    """File name (without suffix) of a plot of variables."""
    return "variables" if len(names) > 3 else "plot_" + "_".join(n.replace(".", "-") for n in names)


def cmd_summary(args: argparse.Namespace) -> int:
    run = load_run(args.run_dir)  # a clear line for a missing or unreadable folder
    if run.roles.fcs is None or run.roles.engine is None:
        raise ReportError(f"{args.run_dir}: no mission run (needs an FCS section_index and an engine's "
                          "Wf_kg_s and fuel_burned_kg)")
    with ResultsFolder(args.run_dir, "RUN_DIR", names=[SUMMARY], clear=False):
        write_report(args.run_dir, plots=False)
    summary = json.loads((args.run_dir / SUMMARY).read_text(encoding="utf-8"))
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    rtf = summary["realtime_factor"]
    print(f"{summary['run']}: {summary['status']}, t = {summary['sim_time_s']:.1f} s"
          + (f" ({rtf:.0f}x real time)" if rtf else "")
          + f"; mission completed: {summary['mission_completed']}, landed: {summary['landed']}; "
          f"fuel {summary['fuel_burned_kg']:.2f} kg; max Tt4 {summary['max_Tt4_K'] or float('nan'):.0f} K")
    for s in summary["sections"]:
        span = "" if s["start_time_s"] is None else f"{s['start_time_s']:8.1f} to {s['end_time_s']:8.1f} s"
        c = s.get("conformance")
        plan = ""
        if c:
            a = c["altitude"]
            worst = a["worst_after_capture_m"]
            plan = (f"  {a['target_m']:6.0f} m: {a['achieved_m']:7.1f} at the end, worst after capture "
                    + ("-" if worst is None else f"{worst:+.1f}") + " m")
        print(f"  {s['index']:>2} {str(s['name']):<36} {str(s['type']):<18} {s['status']:<11} {span:<24} "
              f"{s['fuel_burned_kg']:7.2f} kg{plan}")
    for h in summary.get("holds", []):
        print(f"  planned hold in section {h['section']} ({h['name']}): {h['start_time_s']:.1f} to "
              f"{h['end_time_s']:.1f} s, {h['height_lost_m']:.0f} m lost")
    ils = summary.get("ils")
    if ils and ils["gs_capture_altitude_m"] is not None:
        print(f"  ILS {ils['runway']}: glide slope captured at {ils['gs_capture_altitude_m']:.1f} m "
              f"({ils['gs_capture_error_m']:+.1f} m from the approach altitude), localizer overshoot "
              f"{ils['loc_overshoot_m']:.1f} m, glide slope overshoot {ils['gs_overshoot_m']:.1f} m")
    if summary.get("timeseries_note"):
        print(f"  note: {summary['timeseries_note']}")
    hit = [f"{k} x{v['count']} (first at {v['first_time_s']:g} s)" for k, v in summary["limits_hit"].items()
           if v["count"]]
    print(f"  limits hit: {', '.join(hit) or 'none'}")
    return 0


def _window(text: str) -> float:
    try:
        return finite_number(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a time [s] (a finite number)") from None


def register(sub: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``emss plot``, ``emss summary`` and ``emss mission check``."""
    p = sub.add_parser("plot", help="plot a mission run, or compare runs on the same figures",
                       description="Draw the PNG plots and the interactive report.html of finished runs "
                                   "(folders written by emss run): ground track with waypoints and runways, "
                                   "altitude and Mach against the commands with the sections numbered, thrust, "
                                   "fuel flow and its command, Tt4 and T41 with the Tt41 limit, spool speeds with "
                                   "the N1 limit, surge margins, SFC, attitude. Two runs (up to four) share each "
                                   "figure, told apart by line style. With variables (component.variable), those "
                                   "over time for any system (PNG and HTML).")
    p.add_argument("run_dirs", nargs="+", metavar="RUN_DIR|VAR",
                   help="results folder(s) of emss run, then optionally variables (component.variable) to plot "
                        "over time, for any system")
    p.add_argument("--out", type=folder_name, metavar="DIR",
                   help="folder for the figures (default: RUN_DIR; for several runs RUN_DIR/compare_<others>; with "
                        "--window, RUN_DIR/[compare_<others>_]window_<T0>-<T1>); a figure another plot made there "
                        f"(other runs, window or variables: {PLOTS_RECORD}) is not replaced")
    p.add_argument("--window", nargs=2, type=_window, metavar=("T0", "T1"),
                   help="time window [s] of the fuel flow and Tt4 plot (default: the whole run)")
    p.add_argument("--json", action="store_true", help="print the files written as JSON")
    p.set_defaults(handler=cmd_plot)
    s = sub.add_parser("summary", help="(re)write and print summary.json of a mission run",
                       description="Summarize a finished or failed mission run from its results folder: time, "
                                   "fuel, limits hit, landing, and every mission section.")
    s.add_argument("run_dir", type=Path, metavar="RUN_DIR", help="results folder of emss run")
    s.add_argument("--json", action="store_true", help="print summary.json")
    s.set_defaults(handler=cmd_summary)
    return (ReportError, LifeDataError, *mission_check.register(sub))
