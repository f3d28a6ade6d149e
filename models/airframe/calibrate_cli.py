"""``emss airframe calibrate DATA.csv``: fit the correction factors, regenerate the aircraft file,
print and plot the residuals per point before and after.

Writes into ``--out`` (default ``results/airframe-calibration/``) only: ``calibration.json`` (the
factors, their bounds, the data's source and the per-point residuals), ``UPERA.xml`` (the JSBSim
aircraft file with the factors, ready to replace the shipped one), ``residuals.csv`` and
``residuals.png``. ``--apply`` also installs the factors as the shipped calibration
(``models/airframe/data/upera_calibration.json``) and rewrites the shipped ``UPERA.xml``; the FMUs
are rebuilt by the next ``build-fmus`` or ``emss run``.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from ..infra.files import atomic_write, csv_text, figure_bytes
from .aero import aero_model
from .calibrate import DRAG_FACTORS, LIFT_FACTORS, Calibration, fit, load_points
from .corrections import CALIBRATION_FILE, FACTOR_BOUNDS, AeroCorrections, save_corrections
from .errors import CalibrationError

__all__ = ["add_parser", "cmd_calibrate", "DEFAULT_FACTORS"]

#: Factors fitted unless ``--factors`` says otherwise. The drag-due-to-lift factor needs a polar over
#: a range of lift coefficients to be told apart from CD0; level-flight points (CL 0.14 to 0.20 in
#: the shipped CFD) cannot, so it is fitted only on request.
DEFAULT_FACTORS = (*LIFT_FACTORS, "cd0_factor")


def add_parser(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add ``calibrate`` to the ``emss airframe`` sub-commands."""
    c = sub.add_parser(
        "calibrate", help="fit the aerodynamic correction factors to CFD or wind-tunnel points",
        description="Fit bounded correction factors of UPERA's geometric aerodynamics ("
                    + ", ".join(f"{k} {lo:g} to {hi:g}" for k, (lo, hi) in FACTOR_BOUNDS.items())
                    + ") to points of altitude, Mach, alpha, lift and drag; write calibration.json, the "
                      "regenerated UPERA.xml, residuals.csv and residuals.png into --out; print the residuals "
                      "per point before and after.")
    c.add_argument("data", type=Path, metavar="DATA.csv",
                   help="points: columns alt_m, mach, alpha_deg and a lift and a drag column (CL/CD, lift_N/drag_N "
                        "or lift_kN/drag_kN); optional p_Pa or p_kPa, point; '#' lines are the data's source")
    c.add_argument("--factors", default=",".join(DEFAULT_FACTORS), metavar="F1,F2",
                   help=f"factors to fit (default {','.join(DEFAULT_FACTORS)}; also {','.join(DRAG_FACTORS)})")
    c.add_argument("--lift-column", metavar="COL", help="the lift column when there are several")
    c.add_argument("--drag-column", metavar="COL", help="the drag column when there are several")
    c.add_argument("--reference-columns", metavar="LIFT,DRAG",
                   help="another code's lift and drag columns in the same file, shown beside (not fitted), e.g. "
                        "lift_flightsim_kN,drag_flightsim_kN")
    c.add_argument("--out", type=Path, default=Path("results/airframe-calibration"), metavar="DIR",
                   help="output folder (default: results/airframe-calibration)")
    c.add_argument("--apply", action="store_true",
                   help="also install the factors as the shipped calibration and rewrite the shipped UPERA.xml")
    c.add_argument("--json", action="store_true", help="print the factors and residuals as JSON")
    c.set_defaults(handler=cmd_calibrate)


def _table(cal: Calibration) -> list[dict[str, float | str]]:
    rows: list[dict[str, float | str]] = []
    for r in cal.results:
        p = r.point
        rows.append({"point": p.label, "alt_m": p.alt_m, "mach": p.mach, "alpha_deg": math.degrees(p.alpha_rad),
                     "CL_data": p.cl, "CL_before": r.cl_before, "CL_after": r.cl_after,
                     "CD_data": p.cd, "CD_before": r.cd_before, "CD_after": r.cd_after,
                     **{f"err_{k}": v for k, v in r.errors().items()}})
        if p.cl_reference is not None and p.cd_reference is not None:
            rows[-1].update({"CL_reference": p.cl_reference, "CD_reference": p.cd_reference,
                             "err_cl_reference": p.cl_reference / p.cl - 1, "err_cd_reference": p.cd_reference / p.cd - 1})
    return rows


def _plot(cal: Calibration, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = _table(cal)
    labels = [str(r["point"]) for r in rows]
    x = np.arange(len(rows))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, q in zip(axes, ("cl", "cd"), strict=True):
        sets = [("before", "geometric model"), ("after", "calibrated")]
        if f"err_{q}_reference" in rows[0]:
            sets.append(("reference", "reference"))
        width = 0.8 / len(sets)
        for i, (key, name) in enumerate(sets):
            ax.bar(x + (i - (len(sets) - 1) / 2) * width, [100 * float(r[f"err_{q}_{key}"]) for r in rows], width,
                   label=name)
        lim = 10.0 if q == "cl" else 5.0
        for s in (-lim, lim):
            ax.axhline(s, color="k", ls=":", lw=1)
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xticks(x, [f"{lab}\n{r['alt_m']:.0f} m, M {r['mach']:.2f}" for lab, r in zip(labels, rows,
                                                                                             strict=True)])
        ax.set_ylabel(f"{q.upper()} model / data - 1 [%]")
        ax.set_title(f"{'Lift' if q == 'cl' else 'Drag'} (dotted: goal +-{lim:g} %)")
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize=8)
    f = cal.corrections.factors()
    fig.suptitle("UPERA calibration: " + ", ".join(f"{k} {v:.3f}" for k, v in f.items()), fontsize=9)
    fig.tight_layout()
    atomic_write(path, figure_bytes(fig, dpi=120))
    plt.close(fig)


def _write_outputs(cal: Calibration, out: Path, data: Path) -> None:
    from .xmlgen import aircraft_xml

    rows = _table(cal)
    out.mkdir(parents=True, exist_ok=True)
    save_corrections(cal.corrections, out / "calibration.json",
                     {"data_file": str(data), "residuals": rows, "worst": cal.worst()})
    atomic_write(out / "residuals.csv", csv_text(list(rows[0]), ([v if isinstance(v, str) else f"{v:.6g}"
                                                                    for v in r.values()] for r in rows)))
    atomic_write(out / "UPERA.xml", aircraft_xml(aero_model(None, cal.corrections)))
    _plot(cal, out / "residuals.png")


def _print(cal: Calibration) -> None:
    c: AeroCorrections = cal.corrections
    print("fitted: " + ", ".join(f"{k} = {getattr(c, k):.4f}" for k in c.fitted))
    rows = _table(cal)
    has_ref = "err_cl_reference" in rows[0]
    ref_h = f" {'ref.':>7}" if has_ref else ""
    print(f"  {'point':>5} {'alt_m':>6} {'mach':>5} {'alpha':>6} | {'CL data':>8} {'before':>7} {'after':>7}{ref_h} | "
          f"{'CD data':>8} {'before':>7} {'after':>7}{ref_h}")

    def pct(r: dict[str, float | str], k: str) -> str:
        return f" {100 * float(r[k]):+6.1f}%"

    for r in rows:
        rl = pct(r, "err_cl_reference") if has_ref else ""
        rd = pct(r, "err_cd_reference") if has_ref else ""
        print(f"  {r['point']:>5} {r['alt_m']:6.0f} {r['mach']:5.2f} {r['alpha_deg']:6.2f} | {r['CL_data']:8.4f}"
              f"{pct(r, 'err_cl_before')}{pct(r, 'err_cl_after')}{rl} | {r['CD_data']:8.5f}"
              f"{pct(r, 'err_cd_before')}{pct(r, 'err_cd_after')}{rd}")
    w = cal.worst()
    print(f"  worst |error|: lift {100 * w['cl_before']:.1f} % -> {100 * w['cl_after']:.1f} %, "
          f"drag {100 * w['cd_before']:.1f} % -> {100 * w['cd_after']:.1f} %")


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Handler of ``emss airframe calibrate``; returns the exit code."""
    factors = tuple(f.strip() for f in str(args.factors).split(",") if f.strip())
    bad = [f for f in factors if f not in FACTOR_BOUNDS]
    if bad or not factors:
        raise CalibrationError(f"--factors: unknown {', '.join(bad) or '(none given)'}; allowed: "
                               f"{', '.join(FACTOR_BOUNDS)}")
    refs = None
    if args.reference_columns:
        refs = tuple(c.strip() for c in str(args.reference_columns).split(","))
        if len(refs) != 2:
            raise CalibrationError(f"--reference-columns: give two columns, lift and drag, not {args.reference_columns!r}")
    points, source = load_points(args.data, aero_model(None, AeroCorrections()), args.lift_column, args.drag_column,
                                 refs)  # type: ignore[arg-type]
    cal = fit(points, factors, source=source)
    _write_outputs(cal, args.out, args.data)
    if args.apply:
        from .xmlgen import write

        save_corrections(cal.corrections, CALIBRATION_FILE,
                         {"data_file": args.data.name, "residuals": _table(cal), "worst": cal.worst()})
        aero_model.cache_clear()
        write()
    if args.json:
        json.dump({"factors": cal.corrections.factors(), "fitted": list(cal.corrections.fitted),
                   "source": cal.corrections.source, "residuals": _table(cal), "worst": cal.worst()},
                  sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    _print(cal)
    print(f"wrote {args.out}/calibration.json, UPERA.xml, residuals.csv, residuals.png")
    if args.apply:
        print(f"installed {CALIBRATION_FILE} and the shipped UPERA.xml (the FMUs rebuild on the next run)")
    return 0
