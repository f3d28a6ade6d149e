"""``emss engine design | point | sweep`` on an engine file (:mod:`.engine_file`), solved by :class:`.engine_graph.
EngineGraph`; :mod:`.cli` registers the commands and sends an engine file here (a JSON parameter file stays there).

Every point is printed (or written as JSON, SI units in the keys) with its performance, every station of the file's
``flow:`` and each turbomachine's operating point on its map: the map's own corrected speed (relative to the map's
design speed) and R-line or pressure ratio, the scaled corrected flow, pressure ratio and efficiency, and a
compressor's surge margin (at constant corrected flow, :meth:`.map_scaled.ScaledCompressorMap.surge_margin`).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

from ..infra.files import atomic_write, csv_text, figure_bytes
from .engine_file import ENGINES_DIR, EngineDef, EngineFileError, read_engine_file
from .engine_graph import EngineGraph, GraphPoint
from .engine_study import SWEEP_COLUMNS, check_grid, design_sweep
from .errors import ModelError

__all__ = ["is_engine_file", "cmd_graph_design", "cmd_graph_point", "cmd_graph_sweep", "map_points", "format_point",
           "demand_of"]


def is_engine_file(arg: str | Path) -> bool:
    """An engine file (``.yaml``, ``.yml``) or a shipped engine's name (:data:`.engine_file.ENGINES_DIR`)."""
    p = Path(arg)
    return p.suffix in (".yaml", ".yml") or (p.suffix == "" and len(p.parts) == 1
                                             and (ENGINES_DIR / f"{p.name}.yaml").is_file())


def map_points(g: EngineGraph, p: GraphPoint) -> dict[str, dict[str, float]]:
    """Each turbomachine's operating point on its map (the map's own coordinates and the scaled values)."""
    out: dict[str, dict[str, float]] = {}
    for name, m in g.maps.items():
        o = p.elements[name]
        if g.eng.elements[name].kind == "turbine":
            out[name] = dict(Nc_map_rel=o["Nc_rpm"] / m.s_Nc,
                             PR_map=m.map_pr(o["PR"]), Wc_kg_s=o["Wc_kg_s"], PR=o["PR"], eta=o["eta"])
            continue
        beta = o["beta"] if not math.isnan(o["beta"]) else m.beta_map
        out[name] = dict(Nc_map_rel=o["Nc_rpm"] / m.s_Nc, Rline=m.map.rline_of_beta(beta), beta=beta,
                         Wc_kg_s=o["Wc_kg_s"], PR=o["PR"], eta=o["eta"], surge_margin=m.surge_margin(o["Nc_rpm"], beta))
    return out


def _report(g: EngineGraph, p: GraphPoint) -> dict[str, Any]:
    return {"name": g.eng.name, "file": g.eng.file, **p.to_dict(), "maps": map_points(g, p)}


def format_point(r: dict[str, Any], title: str) -> str:
    """Human-readable report of a point (:func:`_report`'s dictionary)."""
    lines = [f"{r['name']}  ({r['file']}): {title}",
             f"  flight: alt {r['alt_m']:.0f} m, Mach {r['Mach']:.4g}, dT_isa {r['dT_isa_K']:+.1f} K",
             f"  Fn {r['Fn_N'] / 1e3:10.4f} kN   Fg {r['Fg_N'] / 1e3:10.4f} kN   ram drag {r['ram_drag_N'] / 1e3:.4f} kN",
             f"  W {r['W_kg_s']:10.4f} kg/s   Wf {r['Wf_kg_s']:10.5f} kg/s   OPR {r['OPR']:.4f}",
             f"  SFC {r['SFC_kg_N_s']:.5e} kg/(N s) = {r['SFC_kg_N_s'] * 3.6e6:.3f} kg/(kN h)", "",
             f"  {'station':>7} {'W kg/s':>10} {'Tt K':>9} {'Pt kPa':>10} {'FAR':>9}"]
    for k, s in r["stations"].items():
        lines.append(f"  {k:>7} {s['W_kg_s']:10.4f} {s['Tt_K']:9.2f} {s['Pt_Pa'] / 1e3:10.3f} {s['FAR']:9.6f}")
    lines += ["", f"  {'shaft':>7} {'N rpm':>10} {'turbine kW':>11} {'compr. kW':>10} {'net kW':>10}"]
    for k, s in r["shafts"].items():
        lines.append(f"  {k:>7} {s['N_rpm']:10.1f} {s['turbine_W'] / 1e3:11.2f} {s['compressor_W'] / 1e3:10.2f} "
                     f"{s['net_W'] / 1e3:10.2f}")
    lines += ["", f"  {'map':>9} {'Nc/map':>7} {'R-line/PRmap':>12} {'Wc kg/s':>9} {'PR':>8} {'eta':>7} {'SM':>7}"]
    for k, m in r["maps"].items():
        y = m.get("Rline", m.get("PR_map"))
        sm = f"{m['surge_margin']:7.3f}" if "surge_margin" in m else f"{'':>7}"
        lines.append(f"  {k:>9} {m['Nc_map_rel']:7.4f} {y:12.4f} {m['Wc_kg_s']:9.4f} {m['PR']:8.4f} {m['eta']:7.4f} {sm}")
    burners = [k for k, e in r["elements"].items() if "Wf_kg_s" in e]
    for k in burners:
        e = r["elements"][k]
        lines.append(f"  burner {k}: Wf {e['Wf_kg_s']:.5f} kg/s, FAR {e['FAR']:.6f}, exit Tt {e['Tt_exit_K']:.2f} K")
    for k, e in r["elements"].items():
        if "Fg_N" in e:
            lines.append(f"  nozzle {k}: Fg {e['Fg_N'] / 1e3:.4f} kN, A {e['A_geom_m2']:.6f} m^2, PR {e['PR']:.4f}, "
                         f"{'choked' if e['choked'] else 'unchoked'}")
    return "\n".join(lines) + "\n"


def _emit(r: dict[str, Any], as_json: bool, title: str) -> None:
    if as_json:
        json.dump(r, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(format_point(r, title))


def cmd_graph_design(source: str, as_json: bool) -> int:
    """``emss engine design FILE``: the design point of an engine file."""
    g = EngineGraph(read_engine_file(source))
    _emit(_report(g, g.design()), as_json, "design point")
    return 0


def demand_of(g: EngineGraph, args: argparse.Namespace) -> tuple[str, float, str | None]:
    """The power setting of ``emss engine point`` as :meth:`.engine_graph.EngineGraph.solve` takes it."""
    shaft = g._demand_shaft(args.shaft)
    if args.n1c_pct is not None and args.shaft is not None and not any(
            g.eng.elements[c].attrs["shaft"] == shaft for c in g.compressors):
        raise ModelError(f"--shaft {shaft}: it drives no compressor, so it has no corrected speed for --n1c-pct")
    if args.wf_kg_s is not None:
        return "Wf_kg_s", args.wf_kg_s, shaft
    if args.tt4_k is not None:
        return "Tt_K", args.tt4_k, shaft
    if args.fn_n is not None:
        return "Fn_N", args.fn_n, shaft
    if args.power_w is not None:
        return "power_W", args.power_w, shaft
    g.design()
    if args.n1_pct is not None:
        return "N_rpm", args.n1_pct / 100.0 * g.eng.shafts[shaft].attrs["N_rpm"], shaft
    comp = next(c for c in g.compressors if g.eng.elements[c].attrs["shaft"] == shaft)
    return "Nc_rpm", args.n1c_pct / 100.0 * g.ref[("Nc", comp)], shaft


def _settings(g: EngineGraph, args: argparse.Namespace) -> dict[str, Any]:
    burners: dict[str, dict[str, float]] = {}
    for item in args.far or []:
        name, eq, v = item.partition("=")
        ok = [e for e, el in g.eng.elements.items() if el.kind == "burner" and e != g.main_burner]
        if not eq or name not in ok:
            raise ModelError(f"--far {item}: give BURNER=FAR for a burner other than the main one "
                             f"({', '.join(ok) or 'this engine has none'})")
        try:
            far = float(v)
        except ValueError:
            raise ModelError(f"--far {item}: {v!r} is not a number") from None
        if not 0.0 <= far <= 0.07:
            raise ModelError(f"--far {item}: a fuel-air ratio from 0 to 0.07")
        burners[name] = {"FAR": far}
    return {"burners": burners} if burners else {}


def cmd_graph_point(source: str, args: argparse.Namespace) -> int:
    """``emss engine point FILE``: an off-design point of an engine file."""
    if args.distortion_fan is not None or args.distortion_hpc is not None:
        raise ModelError("--distortion-fan/--distortion-hpc: inlet distortion is available for parameter files "
                         "(--params, --preset), not yet for engine files")
    g = EngineGraph(read_engine_file(source))
    demand = demand_of(g, args)
    p = g.solve(args.alt_m, args.mach, args.dtisa_k, demand=demand, settings=_settings(g, args))
    _emit(_report(g, p), args.json, f"{demand[0]} = {demand[1]:.6g}" + (
        f" (shaft {demand[2]})" if demand[0] in ("N_rpm", "Nc_rpm", "power_W") else ""))
    return 0


def _check_out(out: Path, *names: str) -> Path:
    if not str(out).strip():
        raise ModelError("--out '': an empty folder name; give the output folder, e.g. --out results/sweep")
    if out.exists() and not out.is_dir():
        raise ModelError(f"--out {out}: is a file, not a folder")
    for name in names:
        if (out / name).exists():
            raise ModelError(f"--out {out}: already holds {name}; give another folder (nothing is overwritten)")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"--out {out}: cannot create the folder: {exc.strerror}") from None
    return out / names[0]


def cmd_graph_sweep(source: str, args: argparse.Namespace) -> int:
    """``emss engine sweep FILE --vary NAME V ...``: the design at every combination (CSV, and a PNG of SFC)."""
    eng: EngineDef = read_engine_file(source)
    grid = []
    for item in args.vary or []:
        name, vs = item[0], item[1:]
        if not vs:
            raise EngineFileError(f"--vary {name}: give its values, e.g. --vary {name} 10 12 14")
        try:
            grid.append((name, [float(v) for v in vs]))
        except ValueError:
            raise EngineFileError(f"--vary {name}: values must be numbers, got {' '.join(vs)}") from None
    if len(grid) > 2:
        raise EngineFileError("--vary: at most two values are varied (a carpet); give --vary twice at most")
    check_grid(eng, grid)
    target = _check_out(args.out, "sweep.csv", "sweep.png")
    rows = design_sweep(eng, grid)
    names = [n for n, _ in grid]
    header = [*names, *SWEEP_COLUMNS, "note"]
    table = [[r.values[n] for n in names] + [r.performance[c] for c in SWEEP_COLUMNS] + [r.note] for r in rows]
    csv_path = atomic_write(target, csv_text(header, table))
    png_path = _plot(rows, names, args.out / "sweep.png", eng.name)
    if args.json:
        json.dump({"csv": str(csv_path), "png": str(png_path),
                   "rows": [dict(zip(header, t, strict=True)) for t in table]}, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write("  " + " ".join(f"{h:>12}" for h in [*names, "Fn kN", "W kg/s", "SFC g/(kN s)"]) + "  note\n")
        for r in rows:
            p = r.performance
            sys.stdout.write("  " + " ".join(f"{r.values[n]:12.5g}" for n in names)
                             + f" {p['Fn_N'] / 1e3:12.4f} {p['W_kg_s']:12.4f} {p['SFC_kg_N_s'] * 1e6:12.4f}  {r.note}\n")
        sys.stdout.write(f"wrote {csv_path} and {png_path}\n")
    return 0


def _plot(rows: list[Any], names: list[str], path: Path, title: str) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    groups: dict[float | None, list[Any]] = {}
    for r in rows:
        groups.setdefault(r.values[names[1]] if len(names) > 1 else None, []).append(r)
    for key, rs in groups.items():
        ax.plot([r.values[names[0]] for r in rs], [r.performance["SFC_kg_N_s"] * 1e6 for r in rs], "o-",
                label=None if key is None else f"{names[1]} = {key:g}")
    ax.set_xlabel(names[0])
    ax.set_ylabel("SFC [g/(kN s)]")
    ax.set_title(f"design sweep of {title}")
    if len(names) > 1:
        ax.legend()
    ax.grid(True, alpha=0.3)
    out = atomic_write(path, figure_bytes(fig, dpi=120))
    plt.close(fig)
    return out
