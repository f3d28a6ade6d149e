"""``emss airframe ...`` sub-commands, contributed to the ``emss`` command.

``emss airframe trim --alt-m A --mach M [--mass-kg W] [--json]`` trims UPERA in
level flight and prints alpha_deg, elevator, Fn_N, lift_N, drag_N, CL, CD.
``emss airframe polar [--out DIR] [--mass-kg W]`` trims over the envelope and
writes the drag polar and the thrust required (``polar.csv``, ``polar.png``).
``emss airframe compare [--points CSV] [--out DIR] [--json]`` puts the handbook
aerodynamics side by side with AeroSandbox's AeroBuildup and vortex lattice and
with the CFD points (``compare.csv``, ``lift_slopes.csv``, ``compare.png``).

The ``emss`` command finds :func:`register` by itself; airframe errors
(:class:`.errors.AirframeError`) are bad input or an impossible condition and
print as one line.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..infra.files import atomic_write, csv_text, figure_bytes
from . import calibrate_cli
from .aero import aero_model
from .aircraft import DEFAULT_AIRCRAFT
from .errors import AirframeError, TrimError
from .trim import ALT_RANGE_M, MACH_RANGE, TrimResult, trim_level

__all__ = ["register", "cmd_trim", "cmd_polar", "cmd_compare", "POLAR_ALTS_M", "POLAR_MACHS"]

POLAR_ALTS_M = (0.0, 2500.0, 5000.0, 7500.0)
POLAR_MACHS = tuple(np.round(np.arange(0.2, 0.801, 0.05), 3))
_TRIM_KEYS = ("alpha_deg", "elevator", "Fn_N", "lift_N", "drag_N", "CL", "CD")


def register(subparsers: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``airframe`` and its sub-commands to ``subparsers``; return the user-error types."""
    af = subparsers.add_parser("airframe", help="UPERA airframe: level-flight trim, drag polar",
                               description="The UPERA airframe in JSBSim (SI units): trim in level flight with "
                                           "the engine's thrust as an external force, drag polar over the envelope.")
    sub = af.add_subparsers(dest="airframe_command", required=True, parser_class=type(af))
    t = sub.add_parser("trim", help="trim in level flight and print alpha, elevator, thrust, lift, drag",
                       description="Solve steady level flight for angle of attack, elevator and thrust "
                                   f"(altitude {ALT_RANGE_M[0]:g} to {ALT_RANGE_M[1]:g} m, Mach "
                                   f"{MACH_RANGE[0]:g} to {MACH_RANGE[1]:g}, mass 1500 to 2100 kg).")
    t.add_argument("--alt-m", type=float, required=True, metavar="A", help="altitude above mean sea level [m]")
    t.add_argument("--mach", type=float, required=True, metavar="M", help="Mach number [-]")
    t.add_argument("--mass-kg", type=float, metavar="W", help="aircraft mass [kg] (default 2100, MTOM)")
    t.add_argument("--flight-path-deg", type=float, default=0.0, metavar="G",
                   help="flight-path angle of a steady climb (> 0) or descent [deg] (default 0: level)")
    t.add_argument("--aircraft", default=DEFAULT_AIRCRAFT, metavar="NAME_OR_DIR",
                   help="the JSBSim aircraft (models/airframe/README.md, Any JSBSim aircraft): a name of the jsbsim "
                        "package's (737, T38...) or a folder; default UPERA, whose envelope and mass range are "
                        "above (another aircraft: -400 to 20000 m, Mach 0.05 to 0.95, empty to full)")
    t.add_argument("--json", action="store_true", help="print JSON (keys carry SI units)")
    t.set_defaults(handler=cmd_trim)
    p = sub.add_parser("polar", help="drag polar and thrust required over the envelope (PNG + CSV)",
                       description="Trim at altitudes " + ", ".join(f"{a:g}" for a in POLAR_ALTS_M)
                                   + f" m and Mach {POLAR_MACHS[0]:g} to {POLAR_MACHS[-1]:g}; write polar.csv "
                                   "and polar.png (CL over CD, thrust required over Mach). Conditions "
                                   "beyond the stall are skipped.")
    p.add_argument("--out", type=Path, default=Path("results/airframe-polar"), metavar="DIR",
                   help="output folder (default: results/airframe-polar)")
    p.add_argument("--mass-kg", type=float, metavar="W", help="aircraft mass [kg] (default 2100, MTOM)")
    p.add_argument("--json", action="store_true", help="print the rows as JSON")
    p.set_defaults(handler=cmd_polar)
    c = sub.add_parser("compare", help="handbook aerodynamics vs AeroSandbox (AeroBuildup, vortex lattice) vs CFD",
                       description="Evaluate UPERA's lift and drag by the handbook model (aero.py), by "
                                   "AeroSandbox's AeroBuildup and by its vortex lattice (inviscid, Göthert rule) "
                                   "at the points of a CSV file, and over alpha at the file's (altitude, Mach) "
                                   "conditions (at most 3). Print them side by side with the CFD where the file "
                                   "gives it, and the lift-curve slopes. Write compare.csv, lift_slopes.csv and "
                                   "compare.png. The file needs the columns alt_m, mach, alpha_deg (altitude 0 to "
                                   "8000 m, Mach above 0 up to 0.85, alpha -10 to 20 deg), and may give point, p_kPa, "
                                   "lift_cfd_kN and drag_cfd_kN. Lines starting with # are comments.")
    c.add_argument("--points", type=Path, default=None, metavar="CSV",
                   help="points file (default: the CFD points, models/airframe/data/upera_cfd.csv)")
    c.add_argument("--out", type=Path, default=Path("results/airframe-compare"), metavar="DIR",
                   help="output folder (default: results/airframe-compare)")
    c.add_argument("--sweep-alpha-deg", type=float, nargs=3, default=None, metavar=("START", "STOP", "STEP"),
                   help="alpha sweep at each condition [deg] (default: -2 10 1)")
    c.add_argument("--json", action="store_true", help="print the rows as JSON")
    c.set_defaults(handler=cmd_compare)
    calibrate_cli.add_parser(sub)
    return (AirframeError,)


def cmd_trim(args: argparse.Namespace) -> int:
    """Handler of ``emss airframe trim``; returns the exit code."""
    from .adapter import Airframe

    af = Airframe(aircraft=args.aircraft)
    r = trim_level(args.alt_m, args.mach, args.mass_kg, airframe=af, flight_path_rad=math.radians(args.flight_path_deg))
    d = r.as_dict()
    if args.json:
        json.dump(d, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    kind = "level flight" if args.flight_path_deg == 0 else f"flight path {args.flight_path_deg:g} deg"
    print(f"{af.aircraft.name} {kind} at {r.alt_m:g} m, Mach {r.mach:g}, {r.mass_kg:.1f} kg "
          f"(TAS {r.tas_m_s:.2f} m/s, q {r.qbar_Pa:.0f} Pa)")
    for k in _TRIM_KEYS:
        print(f"  {k:10s} {d[k]:12.5g}")
    print(f"  {'L/D':10s} {r.lift_N / r.drag_N:12.5g}")
    return 0


def _rows(mass_kg: float | None) -> list[TrimResult]:
    from .adapter import Airframe

    af = Airframe()
    rows: list[TrimResult] = []
    for alt in POLAR_ALTS_M:
        for mach in POLAR_MACHS:
            try:
                rows.append(trim_level(alt, float(mach), mass_kg, airframe=af))
            except TrimError:
                continue
    return rows


def cmd_polar(args: argparse.Namespace) -> int:
    """Handler of ``emss airframe polar``; returns the exit code."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = _rows(args.mass_kg)
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    keys = ("alt_m", "mach", "tas_m_s", "mass_kg", "alpha_deg", "elevator", "CL", "CD", "lift_N", "drag_N",
            "Fn_N", "qbar_Pa", "re_mac")
    atomic_write(out / "polar.csv", csv_text(keys, ([f"{r.as_dict()[k]:.6g}" for k in keys] for r in rows)))
    a = aero_model()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 5))
    for alt in POLAR_ALTS_M:
        sel = [r for r in rows if r.alt_m == alt]
        ax1.plot([r.CD for r in sel], [r.CL for r in sel], "o-", ms=3, label=f"trim, {alt:g} m")
        ax2.plot([r.mach for r in sel], [r.Fn_N / 1e3 for r in sel], "o-", ms=3, label=f"{alt:g} m")
    cl = np.linspace(0.0, 0.9, 50)
    ax1.plot(float(a.cd0(0.5, 1.5e7)) + a.k_induced() * cl ** 2, cl, "k--", lw=1,
             label="CD0 + k CL^2 (M 0.5, Re 1.5e7)")
    ax1.set_xlabel("CD [-]")
    ax1.set_ylabel("CL [-]")
    ax1.set_title("UPERA drag polar in trimmed level flight")
    ax1.grid(True, alpha=0.3)
    ax1.legend(fontsize=8)
    ax2.set_xlabel("Mach [-]")
    ax2.set_ylabel("thrust required [kN]")
    ax2.set_title(f"Thrust required, {rows[0].mass_kg:.0f} kg" if rows else "Thrust required")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    atomic_write(out / "polar.png", figure_bytes(fig, dpi=120))
    plt.close(fig)
    if args.json:
        json.dump([r.as_dict() for r in rows], sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(f"{len(rows)} trimmed conditions; wrote {out / 'polar.csv'} and {out / 'polar.png'}")
        print(f"  {'alt_m':>7} {'mach':>5} {'CL':>7} {'CD':>8} {'L/D':>6} {'Fn_N':>9}")
        for r in rows:
            print(f"  {r.alt_m:7.0f} {r.mach:5.2f} {r.CL:7.4f} {r.CD:8.5f} {r.lift_N / r.drag_N:6.2f} "
                  f"{r.Fn_N:9.0f}")
    return 0


def cmd_compare(args: argparse.Namespace) -> int:
    """Handler of ``emss airframe compare``; returns the exit code."""
    from . import compare

    alphas = compare.SWEEP_ALPHAS_DEG if args.sweep_alpha_deg is None else \
        compare.sweep_alphas(*args.sweep_alpha_deg)
    points = compare.read_points(args.points or compare.DEFAULT_POINTS)
    conditions = compare.sweep_conditions(points)
    total = len(points) + len(conditions) * (len(alphas) + 1)
    done = [0]
    tty = sys.stderr.isatty()

    def tick() -> None:
        done[0] += 1
        if tty:
            print(f"\rairframe compare: {done[0]}/{total} conditions", end="", file=sys.stderr, flush=True)

    rows = []
    for pt in points:
        rows.append(compare.compare_point(pt))
        tick()
    sweeps = compare.sweep(conditions, alphas, tick=tick)
    slopes = []
    for alt, mach in conditions:
        slopes.append(compare.lift_slopes(alt, mach))
        tick()
    if tty:
        print(file=sys.stderr)
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    compare.write_csv(out / "compare.csv", rows + sweeps)
    compare.write_csv(out / "lift_slopes.csv", slopes)
    compare.plot(out / "compare.png", rows, sweeps)
    if args.json:
        json.dump({"points": [asdict(r) for r in rows], "sweep": [asdict(r) for r in sweeps],
                   "lift_slopes": [asdict(s) for s in slopes]}, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    print("UPERA lift and drag coefficients (S = 11.2 m^2, zero elevator, clean); d% against the CFD")
    print(compare.points_table(rows))
    print("\nDrag decomposed, tail lift and pitching moment about the design CG")
    print(compare.drag_table(rows))
    print("\nLift-curve slopes [1/rad] (central differences about alpha 2 deg; wing alone without incidence)")
    print(compare.slopes_table(slopes))
    print(f"\nwrote {out / 'compare.csv'}, {out / 'lift_slopes.csv'} and {out / 'compare.png'}")
    return 0
