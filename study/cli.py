"""``emss study ...``: run a study file on Dask, list its cases.

``emss study run STUDY.yaml [--scheduler ADDRESS] [--workers N] [--out DIR] [--retry-failed] [--json]``
runs every case not yet done (:mod:`.runner`) into ``DIR/cases/<case>`` and writes
``DIR/study.csv``; a study with a ``redesign`` block first runs the cycle sweep
(:mod:`.redesign`) and afterwards compares the two engines (:mod:`.compare`).

``emss study cases STUDY.yaml [--json]`` lists the cases without running them.

``emss study report STUDY_DIR CASE_A CASE_B`` compares two cases (PNG and report.html).

The ``emss`` command finds :func:`register` by itself; :class:`.spec.StudyError` is bad
input and prints as one line.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from openemss.orchestrator import interrupt
from openemss.orchestrator.cli.argtypes import finite_number, folder_name
from openemss.orchestrator.exit_codes import ExitCode
from openemss.orchestrator.results import os_reason

from .lock import study_lock
from .spec import StudyDef, StudyError, load_study

__all__ = ["register", "run_study", "cmd_run", "cmd_cases"]


def register(subparsers: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``study`` and its sub-commands to `subparsers`; return the user-error types."""
    st = subparsers.add_parser("study", help="parametric studies: many cases of a system on Dask",
                               description="Run every case of a study file (variants, grids of parameter "
                                           "values, missions, scenarios), one after the other in each worker's "
                                           "case process (its FMUs reset between cases), on a Dask LocalCluster "
                                           "or a scheduler; resumable.")
    sub = st.add_subparsers(dest="study_command", required=True, parser_class=type(st))
    run = sub.add_parser("run", help="run a study (skips cases already done)",
                         description="Run the cases of STUDY.yaml not yet done into DIR/cases/<case> and write "
                                     "the study table DIR/study.csv; progress on stderr.")
    run.add_argument("study", type=Path, metavar="STUDY.yaml", help="the study file")
    run.add_argument("--scheduler", metavar="ADDRESS",
                     help="a Dask scheduler (tcp://host:8786); default: a LocalCluster on this machine")
    run.add_argument("--workers", type=int, metavar="N",
                     help="worker processes of the LocalCluster (default: the number of cores)")
    run.add_argument("--out", type=folder_name, metavar="DIR", help="study folder (default: results/study-<name>)")
    run.add_argument("--retry-failed", action="store_true", help="run cases again that failed in an earlier run")
    run.add_argument("--stop-time", type=finite_number, metavar="S",
                     help="stop time [s] of every case instead of the study file's (e.g. a short trial)")
    run.add_argument("--json", action="store_true", help="print the outcome as JSON")
    run.set_defaults(handler=cmd_run)
    cases = sub.add_parser("cases", help="list the cases of a study without running them")
    cases.add_argument("study", type=Path, metavar="STUDY.yaml", help="the study file")
    cases.add_argument("--json", action="store_true", help="print as JSON")
    cases.set_defaults(handler=cmd_cases)
    rep = sub.add_parser("report", help="compare two cases of a study run: PNG plots and report.html",
                         description="The plots and the interactive report of two cases of a study that ran, "
                                     "on the same figures (solid: CASE_A, dashed: CASE_B), into "
                                     "STUDY_DIR/compare_<CASE_A>_<CASE_B>/ (or --out).")
    rep.add_argument("study_dir", type=Path, metavar="STUDY_DIR", help="the study folder (holding study.csv)")
    rep.add_argument("cases", nargs=2, metavar="CASE", help="two case names (see study.csv)")
    rep.add_argument("--out", type=folder_name, metavar="DIR", help="folder for the files")
    rep.set_defaults(handler=cmd_report)
    return (StudyError,)


def cmd_report(args: argparse.Namespace) -> int:
    from openemss.report.html import REPORT, write_html_report
    from openemss.report.plots import PlotRun, plot_runs
    from openemss.report.rundata import load_mission, load_run

    from .case import case_dir

    study_dir: Path = args.study_dir
    if not (study_dir / "cases").is_dir():
        raise StudyError(f"{study_dir}: not a study folder (no cases/; give the folder of emss study run)")
    known = sorted(p.name for p in (study_dir / "cases").iterdir() if p.is_dir())
    runs = []
    for name in args.cases:
        folder = case_dir(study_dir, name)
        if not folder.is_dir():
            import difflib

            close = difflib.get_close_matches(name, known, n=3)
            raise StudyError(f"{study_dir}: no case '{name}'" + (f"; did you mean {', '.join(close)}?" if close else
                                                                  f" (cases: {', '.join(known[:6])})"))
        data = load_run(folder)
        runs.append(PlotRun(data, load_mission(data)[0], name))
    out = Path(args.out or study_dir / f"compare_{args.cases[0]}_{args.cases[1]}")
    files = plot_runs(runs, out)
    page = write_html_report(runs, out / REPORT) if files else None
    files += [page] if page is not None else []
    if not files:  # no mission: every recorded column, as emss plot does for any system
        from openemss.report.html import write_variables_html
        from openemss.report.plots import plot_variables
        from openemss.report.plugin import MAX_ALL_COLUMNS

        names = [n for n in runs[0].data.columns if n != "time_s"][:MAX_ALL_COLUMNS]
        files = [plot_variables(runs, names, out / "variables.png"), write_variables_html(runs, names, out / REPORT)]
    print(f"{len(files)} file(s) comparing {args.cases[0]} and {args.cases[1]} in {out}: "
          f"{', '.join(f.name for f in files)}")
    return 0


def _with_redesign(study: StudyDef, out: Path) -> tuple[StudyDef, dict[str, Any] | None]:
    if not study.redesign:
        return study, None
    from dataclasses import replace

    from .redesign import cycle_redesign, parse_redesign

    cfg = parse_redesign(study)
    variants, info = cycle_redesign(study, cfg, out)
    return replace(study, variants=tuple(variants)), {"config": cfg, "info": info}


def run_study(path: Path, out: Path | None = None, scheduler: str | None = None, workers: int | None = None,
              retry_failed: bool = False, stop_time_s: float | None = None) -> dict[str, Any]:
    """Run a study file end to end; returns what the command prints (see ``--json``)."""
    from dataclasses import replace

    study = load_study(path)
    if stop_time_s is not None:
        if not (0.0 < stop_time_s < 1e9):
            raise StudyError(f"--stop-time {stop_time_s}: must be a positive number of seconds")
        study = replace(study, stop_time_s=float(stop_time_s))
    if workers is not None and workers < 1:
        raise StudyError(f"--workers {workers}: must be an integer >= 1")
    folder = (out or Path("results") / f"study-{study.name}").resolve()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise StudyError(f"--out {folder}: cannot create the study folder: {os_reason(exc)}") from None
    with study_lock(folder):  # one study run per folder
        interrupt.phase("study", "during the study", f"the cases done so far are kept in {folder}; run the study "
                                                     "again to go on")
        return _run_locked(study, folder, scheduler, workers, retry_failed)


def _run_locked(study: StudyDef, folder: Path, scheduler: str | None, workers: int | None,
                retry_failed: bool) -> dict[str, Any]:
    from .plan import expand_cases
    from .runner import check_fmus, run_cases

    check_fmus([str(study.system)])  # before the cases' digests, which read the system's FMUs
    study, redesign = _with_redesign(study, folder)
    cases = expand_cases(study)
    outcome = run_cases(cases, folder, scheduler=scheduler, workers=workers, retry_failed=retry_failed)
    result: dict[str, Any] = {
        "study": study.name, "out": str(folder), "table": str(outcome.table), "cases": len(cases),
        "ran": len(outcome.ran), "skipped": len(outcome.skipped), "failed": outcome.failed,
        "wall_time_s": outcome.wall_time_s, "workers": outcome.workers,
        "stepping_fraction": outcome.stepping_fraction,
    }
    if redesign is not None:
        result["redesign"] = _report(study, cases, outcome, redesign, folder)
    return result


def _report(study: StudyDef, cases: list[Any], outcome: Any, redesign: dict[str, Any], folder: Path) -> dict[str, Any]:
    from .compare import compare_engines
    from .redesign import BASELINE, REDESIGNED

    cfg = redesign["config"]
    reports: dict[str, Any] = {"cycle": redesign["info"]}
    missions = [m for m, _ in study.missions] or [""]
    for mission in missions:
        pick = {v: next(c.name for c in cases if dict(c.labels).get("variant") == v
                        and dict(c.labels).get("mission", "") == mission) for v in (BASELINE, REDESIGNED)}
        names = None
        mpath = dict(study.missions).get(mission)
        if mpath is not None:
            try:
                from openemss.models.mission.mission import load_mission

                names = [s.name for s in load_mission(mpath).sections]
            except Exception:  # the names only label the plot
                names = None
        sub = folder / (f"mission-{mission}" if len(missions) > 1 else "")
        reports[mission or "mission"] = compare_engines(
            folder if len(missions) == 1 else sub, pick, outcome.results, redesign["info"], cfg.component,
            cfg.section, cfg.section_variable, names)
        if cfg.carpet:
            from .carpet import carpet_report

            reports[mission or "mission"]["carpet"] = carpet_report(
                folder / "carpet" / (f"mission-{mission}" if len(missions) > 1 else ""), cases, outcome.results,
                redesign["info"], mission)
    return reports


def cmd_run(args: argparse.Namespace) -> int:
    res = run_study(args.study, args.out, args.scheduler, args.workers, args.retry_failed, args.stop_time)
    if args.json:
        print(json.dumps(res, indent=2, default=str))
    else:
        print(f"study {res['study']}: {res['cases']} case(s), {res['ran']} run now, {res['skipped']} skipped, "
              f"{len(res['failed'])} failed; table {res['table']}")
        if res["stepping_fraction"] is not None:
            print(f"  {res['wall_time_s']:.1f} s wall on {res['workers']} worker(s): "
                  f"{100 * res['stepping_fraction']:.1f} % of the workers' time stepping (study.csv: each case's "
                  "setup_s, stepping_s, writing_s)")
        for name, rep in (res.get("redesign") or {}).items():
            if name == "cycle":
                r, b = rep["redesigned"], rep["baseline"]
                print(f"cycle sweep: lowest SFC at BPR {r['BPR']:.2f}, OPR {r['OPR']:.2f} "
                      f"({r['SFC_kg_N_s'] * 1e6:.2f} vs baseline {b['SFC_kg_N_s'] * 1e6:.2f} mg/(N s): "
                      f"{rep['design_point_SFC_change_pct']:+.1f} % at the design point)")
                continue
            mf = rep.get("mission_fuel_change_pct")
            ct = rep.get("fuel_change_at_common_time_pct")
            print(f"{name}: mission fuel change {'n/a' if mf is None else f'{mf:+.1f} %'}; fuel change at "
                  f"t = {rep.get('common_time_s', float('nan')):.0f} s {'n/a' if ct is None else f'{ct:+.1f} %'}"
                  + (f" ({rep['note']})" if rep.get("note") else ""))
            if rep.get("life_change_pct"):
                print("  life change: " + ", ".join(f"{k.replace('_', ' ')} {'n/a' if v is None else f'{v:+.1f} %'}"
                                                   for k, v in rep["life_change_pct"].items()))
            if rep.get("files"):
                print(f"  plots: {', '.join(rep['files'].values())}")
            if rep.get("carpet"):
                cp = rep["carpet"]
                span = "n/a" if cp["ratio_min"] is None else f"{cp['ratio_min']:.2f} to {cp['ratio_max']:.2f}"
                print(f"  carpet: {cp['designs']} designs ({', '.join(f'{n} {k}' for k, n in cp['outcomes'].items())});"
                      f" mission fuel change / SFC change {span}; {cp['files']['table']}, {cp['files']['plot']}")
    return ExitCode.FAILED if res["failed"] else ExitCode.OK


def cmd_cases(args: argparse.Namespace) -> int:
    from .plan import expand_cases

    study = load_study(args.study)
    if study.redesign:
        from dataclasses import replace

        from .redesign import planned_variants

        variants = planned_variants(study)
        if len(variants) == 2:  # without the carpet the sweep is not run here
            print("emss study cases: the redesigned engine's design_* values come from the cycle sweep, run by "
                  "emss study run", file=sys.stderr)
        study = replace(study, variants=tuple(variants), redesign={})
    cases = expand_cases(study)
    if args.json:
        print(json.dumps([{"name": c.name, "labels": dict(c.labels), "values": dict(c.values),
                           "digest": c.digest} for c in cases], indent=2, default=str))
        return 0
    for c in cases:
        print(f"{c.name}  ({', '.join(f'{k}={v}' for k, v in c.values) or 'no parameter values'})")
    print(f"{len(cases)} case(s)", file=sys.stderr)
    return 0
