"""``emss engine ...`` sub-commands, contributed to the ``emss`` command.

Each command takes an engine file (``FILE``: ``.yaml``, or a shipped engine's name such as ``pycycle_hbtf``; solved
by :class:`.engine_graph.EngineGraph`, handlers in :mod:`.cli_graph`) or, as before, a JSON parameter file of the
two-spool turbofan or the turbojet (``FILE`` ending in ``.json``, ``--params FILE`` or ``--preset NAME``).
``emss engine design FILE [--json]``; ``emss engine point FILE --alt-m A --mach M (--N1-pct | --N1c-pct | --Fn-N |
--Wf-kg-s | --Tt4-K | --power-W) X [--shaft NAME] [--far BURNER=FAR] [--json]`` (stations, performance, each map's
operating point); ``emss engine sweep FILE --vary NAME V [V ...] [--vary NAME V ...] [--out DIR]`` (the design at
every combination of one or two engine-file values, :mod:`.engine_study`). What follows describes the parameter
files.

``emss engine point --alt-m A --mach M [--dtisa-k T] (--wf-kg-s | --n1-pct | --n1c-pct |
--tt4-k | --fn-n) X [--params FILE | --preset NAME] [--json]`` sizes the engine at its
design point, scales the shipped maps to it and prints the matched off-design state
(:mod:`.offdesign`).

``emss engine sweep [--params FILE | --preset NAME] [--out DIR] [--bpr ...] [--opr ...]``
runs the parametric cycle study of SPEC.md (:mod:`.cycle_study`) and writes
``carpet.csv`` and ``carpet.png``.

``emss engine design [--params FILE | --preset NAME] [--json]`` prints the design
point: performance (Fn_N, Fg_N, ram_drag_N, W2_kg_s, Wf_kg_s, SFC_kg_N_s, OPR, BPR,
Tt4_K, nozzle areas) and every station's W_kg_s, Tt_K, Pt_Pa, FAR. The JSON keys
carry SI units in their names (:meth:`.cycle_design.DesignPoint.to_dict`).

The ``emss`` command finds :func:`register` through the entry point ``engine`` of the group
``openemss.plugins`` (pyproject.toml); errors of the engine model
(:class:`.errors.ModelError`) are bad input and print as one line.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from .cycle_design import DesignPoint, design
from .cycle_study import COLUMNS, cycle_study, plot_carpet, write_csv
from .design_params import PRESETS_DIR, TurbofanParams, load_params, preset_path
from .engine_file import ENGINES_DIR
from .distortion import Distortion
from .errors import ModelError
from .offdesign import TurbofanOffDesign, scaled_maps
from .offdesign_turbojet import TurbojetOffDesign, scaled_turbojet_maps
from .stations import STATIONS

__all__ = ["register", "cmd_design", "cmd_point", "cmd_sweep", "cmd_convert", "format_design"]

_FILE_HELP = ("an engine file (.yaml) or a shipped engine's name (" + ", ".join(sorted(
    p.stem for p in ENGINES_DIR.glob("*.yaml"))) + "), or a JSON parameter file (as --params)")

DEFAULT_PRESET = "larzac04_sls"


def register(subparsers: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``engine`` and its sub-commands to `subparsers`; return the user-error types."""
    eng = subparsers.add_parser("engine", help="engine performance: design point, off-design point, cycle study",
                                description="Engine performance synthesis of the two-spool turbofan "
                                            "and the turbojet (0-D, real gas, SI units).")
    sub = eng.add_subparsers(dest="engine_command", required=True, parser_class=type(eng))
    presets = sorted(p.stem for p in PRESETS_DIR.glob("*.json"))
    d = sub.add_parser("design", help="compute and print a design point",
                       description="Compute the design point of a parameter file: every station, "
                                   "thrust, fuel flow, SFC, nozzle areas and the design values for map "
                                   f"scaling; of an engine file, also each map's design point. Default: the preset "
                                   f"{DEFAULT_PRESET!r}.")
    d.add_argument("file", nargs="?", metavar="FILE", help=_FILE_HELP)
    src = d.add_mutually_exclusive_group()
    src.add_argument("--params", type=Path, metavar="FILE",
                     help="parameter file (JSON; see models/engine/presets/README.md)")
    src.add_argument("--preset", choices=presets, metavar="NAME",
                     help=f"a shipped preset: {', '.join(presets)}")
    d.add_argument("--json", action="store_true", help="print JSON (keys carry SI units: Fn_N, Tt_K ...)")
    d.set_defaults(handler=cmd_design)

    pt = sub.add_parser("point", help="compute an off-design steady state on the scaled component maps",
                        description="Size the engine at its design point (the parameter file), scale the "
                                    "shipped component maps to it, and match the engine at the given flight "
                                    "condition and power setting (exactly one of --wf-kg-s, --n1-pct, "
                                    "--n1c-pct, --tt4-k, --fn-n; an engine file also --power-w). For an engine "
                                    "file it prints the stations, the performance and each map's operating point.")
    pt.add_argument("file", nargs="?", metavar="FILE", help=_FILE_HELP)
    src = pt.add_mutually_exclusive_group()
    src.add_argument("--params", type=Path, metavar="FILE", help="parameter file (JSON)")
    src.add_argument("--preset", choices=presets, metavar="NAME", help=f"a shipped preset: {', '.join(presets)}")
    pt.add_argument("--alt-m", type=float, default=0.0, metavar="M", help="geopotential altitude [m] (default 0)")
    pt.add_argument("--mach", type=float, default=0.0, metavar="M", help="flight Mach number (default 0)")
    pt.add_argument("--dtisa-k", type=float, default=0.0, metavar="K", help="ISA temperature deviation [K]")
    ps = pt.add_mutually_exclusive_group(required=True)
    ps.add_argument("--wf-kg-s", "--Wf-kg-s", type=float, metavar="X", help="fuel flow [kg/s] (the main burner's)")
    ps.add_argument("--n1-pct", "--N1-pct", type=float, metavar="X",
                    help="LP spool speed [%% of design] (turbojet: N; engine file: the --shaft's, default the first "
                         "compressor's)")
    ps.add_argument("--n1c-pct", "--N1c-pct", type=float, metavar="X", help="corrected LP spool speed [%% of design]")
    ps.add_argument("--tt4-k", "--Tt4-K", type=float, metavar="X", help="burner exit temperature [K]")
    ps.add_argument("--fn-n", "--Fn-N", type=float, metavar="X", help="net thrust [N]")
    ps.add_argument("--power-w", "--power-W", type=float, metavar="X",
                    help="engine file: net power of the --shaft [W] (a free power turbine's load)")
    pt.add_argument("--shaft", metavar="NAME", help="engine file: the shaft of --N1-pct, --N1c-pct and --power-W")
    pt.add_argument("--far", action="append", metavar="BURNER=FAR",
                    help="engine file: fuel-air ratio of a burner other than the main one (an afterburner lit); "
                         "repeatable")
    for comp in ("fan", "hpc"):
        pt.add_argument(f"--distortion-{comp}", type=float, nargs=3, metavar=("SECTOR", "DPT", "DTT_K"),
                        help=f"sector distortion at the {comp.upper()} face (parallel compressor): distorted share "
                             "of the annulus (0-1), its relative Pt deficit, its Tt excess [K] (turbofan only)")
    pt.add_argument("--json", action="store_true", help="print JSON (keys carry SI units)")
    pt.set_defaults(handler=cmd_point)

    sw = sub.add_parser("sweep", help="parametric cycle study: SFC over OPR for several BPR (CSV and PNG)",
                        description="From a reference design with a thrust target (default: the preset "
                                    "'reference_study'), vary BPR and OPR at constant Tt4, thrust and core/bypass "
                                    "jet velocity ratio (fan pressure ratios adjusted); write carpet.csv and "
                                    "carpet.png (SFC in kg/(N s) over OPR, one line per BPR). With an engine file: "
                                    "the design at every combination of the --vary values (the file's own sizing "
                                    "held: its Fn_N or W_kg_s), written to sweep.csv and sweep.png.")
    sw.add_argument("file", nargs="?", metavar="FILE", help=_FILE_HELP)
    src = sw.add_mutually_exclusive_group()
    src.add_argument("--params", type=Path, metavar="FILE", help="reference parameter file (JSON, turbofan)")
    src.add_argument("--preset", choices=presets, metavar="NAME", help="reference preset")
    sw.add_argument("--vary", nargs="+", action="append", metavar="NAME V",
                    help="engine file: a value to vary and its values, NAME as element.attribute (comp.PR, "
                         "burner.Tt_K), shaft.attribute or design.attribute; at most twice")
    sw.add_argument("--out", type=Path, default=Path("results") / "engine-sweep", metavar="DIR",
                    help="output folder, created if missing (default: results/engine-sweep)")
    sw.add_argument("--bpr", type=float, nargs="+", default=[0.5, 1.0, 1.5, 2.0], metavar="X",
                    help="bypass ratios (default 0.5 1 1.5 2)")
    sw.add_argument("--opr", type=float, nargs="+", default=[float(v) for v in range(9, 21)], metavar="X",
                    help="overall pressure ratios (default 9 to 20 in steps of 1)")
    sw.add_argument("--json", action="store_true", help="print the carpet as JSON")
    sw.set_defaults(handler=cmd_sweep)

    cv = sub.add_parser("convert", help="convert another code's engine model to an engine file",
                        description="Convert an engine model of another code to an engine file (YAML).")
    cvs = cv.add_subparsers(dest="convert_from", required=True, parser_class=type(eng))
    np_ = cvs.add_parser("npss", help="an NPSS model (.mdl): elements, map includes, linkPorts",
                         description="Convert an NPSS model made of the element kinds we have (attribute "
                                     "assignments, map includes, linkPorts; input files of assignments applied "
                                     "after it). What cannot be carried (a function body, an unknown element or "
                                     "attribute) is refused with one line naming it; --drop leaves a named item out, "
                                     "listed in the engine file's notes.")
    np_.add_argument("model", type=Path, metavar="MODEL.mdl", help="the NPSS model file")
    np_.add_argument("--out", type=Path, required=True, metavar="ENGINE_FILE",
                     help="the engine file to write (.yaml; never overwritten)")
    np_.add_argument("--input", type=Path, action="append", default=[], metavar="FILE",
                     help="a file of assignments (Element.attribute = value;) applied after the model; repeatable")
    np_.add_argument("--drop", action="append", default=[], metavar="NAME",
                     help="leave out a function body (Element.function), an element, or assignments to a name "
                          "(a solver variable); repeatable")
    np_.set_defaults(handler=cmd_convert)
    return (ModelError,)


def cmd_convert(args: argparse.Namespace) -> int:
    """Handler of ``emss engine convert npss``; returns the exit code."""
    from .npss_convert import convert_npss
    path = convert_npss(args.model, args.out, tuple(args.input), tuple(args.drop))
    sys.stdout.write(f"wrote {path}\n")
    return 0


def _source(args: argparse.Namespace, default: str) -> Path | str:
    """The engine file (a str) or the JSON parameter file (a Path) the command reads."""
    if args.file is not None:
        if args.params is not None or args.preset is not None:
            raise ModelError(f"{args.file}: give FILE or --params/--preset, not both")
        from .cli_graph import is_engine_file
        if is_engine_file(args.file):
            return str(args.file)
        if Path(args.file).suffix != ".json":
            raise ModelError(f"{args.file}: not an engine file (.yaml), a shipped engine ("
                             f"{', '.join(sorted(p.stem for p in ENGINES_DIR.glob('*.yaml')))}) or a JSON parameter "
                             "file (.json)")
        return Path(args.file)
    return args.params if args.params is not None else preset_path(args.preset or default)


def _engine_only(args: argparse.Namespace, *names: str) -> None:
    for n in names:
        if getattr(args, n, None) is not None:
            raise ModelError(f"--{n.replace('_', '-')}: only for an engine file (FILE.yaml or a shipped engine)")


def cmd_design(args: argparse.Namespace) -> int:
    """Handler of ``emss engine design``; returns the exit code."""
    path = _source(args, DEFAULT_PRESET)
    if isinstance(path, str):
        from .cli_graph import cmd_graph_design
        return cmd_graph_design(path, args.json)
    dp = design(load_params(path))
    if args.json:
        json.dump(dp.to_dict(), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(format_design(dp, str(path)))
    return 0


def cmd_point(args: argparse.Namespace) -> int:
    """Handler of ``emss engine point``; returns the exit code."""
    path = _source(args, DEFAULT_PRESET)
    if isinstance(path, str):
        from .cli_graph import cmd_graph_point
        return cmd_graph_point(path, args)
    _engine_only(args, "power_w", "shaft", "far")
    dp = design(load_params(path))
    cond = (args.alt_m, args.mach, args.dtisa_k)
    if isinstance(dp.params, TurbofanParams):
        kw: dict[str, Any] = {k: v for k, v in (("Wf_kg_s", args.wf_kg_s), ("N1_pct", args.n1_pct),
                                                  ("N1c_pct", args.n1c_pct), ("Tt4_K", args.tt4_k),
                                                  ("Fn_N", args.fn_n)) if v is not None}
        for comp in ("fan", "hpc"):
            v = getattr(args, f"distortion_{comp}")
            if v is not None:
                kw[f"distortion_{comp}"] = Distortion(*v)
        od = TurbofanOffDesign(dp, scaled_maps(dp)).solve(*cond, **kw)
        out = od.to_dict()
    else:
        if args.n1c_pct is not None:
            raise ModelError("emss engine point: --n1c-pct is not available for a turbojet")
        cm, tm, beta = scaled_turbojet_maps(dp)
        kw = {k: v for k, v in (("Wf_kg_s", args.wf_kg_s), ("Tt4_K", args.tt4_k), ("Fn_N", args.fn_n),
                                ("N_rpm", None if args.n1_pct is None else args.n1_pct / 100 * dp.params.N_rpm))
              if v is not None}
        tj = TurbojetOffDesign(dp, cm, tm, beta).solve(*cond, **kw)
        out = {k: getattr(tj, k) for k in ("Fn_N", "Fg_N", "ram_drag_N", "Wf_kg_s", "SFC_kg_N_s", "N_rpm", "N_pct",
                                           "Nc_rpm", "Tt4_K", "OPR", "beta", "PR_t", "iterations", "residual_max")}
        out["stations"] = {k: {"W_kg_s": s.W_kg_s, "Tt_K": s.Tt_K, "Pt_Pa": s.Pt_Pa, "FAR": s.FAR}
                           for k, s in tj.stations.items()}
    out = {"name": dp.params.name, "alt_m": args.alt_m, "Mach": args.mach, "dT_isa_K": args.dtisa_k, **out}
    if args.json:
        json.dump(out, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        for k, v in out.items():
            if k != "stations" and not isinstance(v, dict):
                sys.stdout.write(f"  {k:<20} {v:.6g}\n" if isinstance(v, float) else f"  {k:<20} {v}\n")
        sys.stdout.write(f"\n  {'station':>7} {'W kg/s':>10} {'Tt K':>9} {'Pt kPa':>10} {'FAR':>9}\n")
        for k, st in out["stations"].items():
            sys.stdout.write(f"  {k:>7} {st['W_kg_s']:10.4f} {st['Tt_K']:9.2f} {st['Pt_Pa'] / 1e3:10.3f} "
                             f"{st['FAR']:9.6f}\n")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    """Handler of ``emss engine sweep``; returns the exit code."""
    path = _source(args, "reference_study")
    if isinstance(path, str):
        from .cli_graph import cmd_graph_sweep
        return cmd_graph_sweep(path, args)
    _engine_only(args, "vary")
    ref = load_params(path)
    if not isinstance(ref, TurbofanParams):
        raise ModelError(f"{path}: the cycle study needs a turbofan parameter file")
    if not str(args.out).strip():
        raise ModelError("--out '': an empty folder name; give the output folder, e.g. --out results/sweep")
    if args.out.exists() and not args.out.is_dir():
        raise ModelError(f"--out {args.out}: is a file, not a folder")
    try:
        args.out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"--out {args.out}: cannot create the folder: {exc.strerror}") from None
    pts = cycle_study(ref, args.bpr, args.opr)
    csv_path = write_csv(pts, args.out / "carpet.csv")
    png_path = plot_carpet(pts, args.out / "carpet.png", f"SFC carpet from {ref.name}")
    if args.json:
        json.dump({"csv": str(csv_path), "png": str(png_path),
                   "points": [{c: getattr(p, c) for c in COLUMNS} for p in pts]}, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(f"  {'BPR':>5} {'OPR':>6} {'PR_fan':>7} {'W2 kg/s':>8} {'SFC kg/(N s)':>13}  note\n")
        for p in pts:
            sys.stdout.write(f"  {p.BPR:5.2f} {p.OPR:6.2f} {p.PR_fan_outer:7.3f} {p.W2_kg_s:8.2f} "
                             f"{p.SFC_kg_N_s:13.5e}  {p.note}\n")
        sys.stdout.write(f"wrote {csv_path} and {png_path}\n")
    return 0


def format_design(dp: DesignPoint, source: str = "") -> str:
    """Human-readable report of a design point."""
    p = dp.params
    lines = [f"{p.name}" + (f"  ({source})" if source else ""),
             f"  flight: alt {p.alt_m:.0f} m, Mach {p.Mach:.3f}, dT_isa {p.dT_isa_K:+.1f} K",
             f"  Fn {dp.Fn_N / 1e3:10.4f} kN   Fg {dp.Fg_N / 1e3:10.4f} kN   ram drag {dp.ram_drag_N / 1e3:.4f} kN",
             f"  W2 {dp.W2_kg_s:10.4f} kg/s  Wf {dp.Wf_kg_s:10.5f} kg/s",
             f"  SFC {dp.SFC_kg_N_s:.5e} kg/(N s) = {dp.SFC_kg_N_s * 3.6e6:.3f} kg/(kN h)",
             f"  OPR {dp.OPR:.4f}   BPR {dp.BPR:.4f}   Tt4 {dp.Tt4_K:.2f} K   FAR4 {dp.stations['4'].FAR:.6f}"]
    for name, n in dp.nozzles.items():
        lines.append(f"  {name} nozzle: A {n.A_geom_m2:.6f} m^2 (effective {n.A_eff_m2:.6f}), "
                     f"{'choked' if n.choked else 'unchoked'}, PR {n.PR:.4f}, Fg {n.Fg_N / 1e3:.4f} kN")
    lines.append("")
    lines.append(f"  {'station':>7} {'W kg/s':>10} {'Tt K':>9} {'Pt kPa':>10} {'FAR':>9}  meaning")
    for k, s in dp.stations.items():
        lines.append(f"  {k:>7} {s.W_kg_s:10.4f} {s.Tt_K:9.2f} {s.Pt_Pa / 1e3:10.3f} {s.FAR:9.6f}  {STATIONS[k]}")
    lines.append("")
    lines.append(f"  {'component':>10} {'Wc kg/s':>9} {'PR':>8} {'eta_is':>7} {'Nc rpm':>9} {'power kW':>10}")
    for k, c in dp.components.items():
        lines.append(f"  {k:>10} {c.Wc_kg_s:9.4f} {c.PR:8.4f} {c.eta_is:7.4f} {c.Nc_rpm:9.1f} {c.power_W / 1e3:10.2f}")
    return "\n".join(lines) + "\n"
