"""``emss engine ...`` sub-commands, contributed to the ``emss`` command.

``emss engine design [--params FILE | --preset NAME] [--json]`` prints the design
point: performance (Fn_N, Fg_N, ram_drag_N, W2_kg_s, Wf_kg_s, SFC_kg_N_s, OPR, BPR,
Tt4_K, nozzle areas) and every station's W_kg_s, Tt_K, Pt_Pa, FAR. The JSON keys
carry SI units in their names (:meth:`.cycle_design.DesignPoint.to_dict`).

The ``emss`` command finds :func:`register` by itself; errors of the engine model
(:class:`.errors.ModelError`) are bad input and print as one line.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .cycle_design import DesignPoint, design
from .design_params import PRESETS_DIR, load_params, preset_path
from .errors import ModelError
from .stations import STATIONS

__all__ = ["register", "cmd_design", "format_design"]

DEFAULT_PRESET = "larzac04_sls"


def register(subparsers: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``engine`` and its sub-commands to `subparsers`; return the user-error types."""
    eng = subparsers.add_parser("engine", help="engine performance: design point (more to come)",
                                description="Engine performance synthesis of the two-spool turbofan "
                                            "and the turbojet (0-D, real gas, SI units).")
    sub = eng.add_subparsers(dest="engine_command", required=True, parser_class=type(eng))
    presets = sorted(p.stem for p in PRESETS_DIR.glob("*.json"))
    d = sub.add_parser("design", help="compute and print a design point",
                       description="Compute the design point of a parameter file: every station, "
                                   "thrust, fuel flow, SFC, nozzle areas and the design values for map "
                                   f"scaling. Default: the preset {DEFAULT_PRESET!r}.")
    src = d.add_mutually_exclusive_group()
    src.add_argument("--params", type=Path, metavar="FILE",
                     help="parameter file (JSON; see models/engine/presets/README.md)")
    src.add_argument("--preset", choices=presets, metavar="NAME",
                     help=f"a shipped preset: {', '.join(presets)}")
    d.add_argument("--json", action="store_true", help="print JSON (keys carry SI units: Fn_N, Tt_K ...)")
    d.set_defaults(handler=cmd_design)
    return (ModelError,)


def cmd_design(args: argparse.Namespace) -> int:
    """Handler of ``emss engine design``; returns the exit code."""
    path = args.params if args.params is not None else preset_path(args.preset or DEFAULT_PRESET)
    dp = design(load_params(path))
    if args.json:
        json.dump(dp.to_dict(), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(format_design(dp, str(path)))
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
