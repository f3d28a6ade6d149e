"""Figures and a table of a two-dimensional grid study: each outcome as a map over the two grid axes.

    python -m openemss.study.grid STUDY_DIR OUT_DIR [--x DIM] [--y DIM] [--outcome COL ...]

reads ``STUDY_DIR/study.csv`` (written by ``emss study run``) and writes into ``OUT_DIR``: ``grid.png``
(one panel per outcome: the value in every cell, with the grid's values on the axes), ``grid.md`` (the
same as tables) and ``study.csv`` (a copy). By default the axes are the table's first two dimension
columns and the outcomes ``fuel_burned_kg`` and ``final_soc``. Cases that failed are shown empty; a
completed run whose table does not say ``mission_completed`` is marked ``*`` in ``grid.md``.
"""
from __future__ import annotations

import argparse
import csv
import math
import shutil
import sys
from pathlib import Path

import numpy as np

from openemss.models.infra.files import figure_bytes
from openemss.orchestrator.results import atomic_write

from .table import OUTCOME_COLUMNS

__all__ = ["grid_tables", "write_grid"]


def _num(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def grid_tables(rows: list[dict[str, str]], x: str, y: str, outcomes: list[str]
                ) -> tuple[list[str], list[str], dict[str, np.ndarray]]:
    """The x and y axis values (in the order of first appearance) and, per outcome, a ``len(y) x len(x)``
    array (NaN where a case is missing or did not complete)."""
    xs = list(dict.fromkeys(r[x] for r in rows))
    ys = list(dict.fromkeys(r[y] for r in rows))
    maps = {o: np.full((len(ys), len(xs)), np.nan) for o in outcomes}
    for r in rows:
        ok = r.get("status") == "completed"
        for o in outcomes:
            maps[o][ys.index(r[y]), xs.index(r[x])] = _num(r.get(o, "")) if ok else math.nan
    return xs, ys, maps


def _unfinished(rows: list[dict[str, str]], x: str, y: str) -> set[tuple[str, str]]:
    """(x, y) of the completed runs whose table does not say the mission was completed."""
    return {(r[x], r[y]) for r in rows if r.get("status") == "completed"
            and r.get("mission_completed", "") not in ("True", "true", "1")}


def write_grid(study_dir: Path, out: Path, x: str | None = None, y: str | None = None,
               outcomes: list[str] | None = None) -> list[Path]:
    """Write ``grid.png``, ``grid.md`` and a copy of ``study.csv`` of the study in ``study_dir`` into ``out``."""
    from matplotlib.figure import Figure

    table = Path(study_dir) / "study.csv"
    with open(table, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        rows, header = list(reader), list(reader.fieldnames or [])
    dims = [c for c in header if c != "case" and c not in OUTCOME_COLUMNS]
    if len(dims) < 2 and (x is None or y is None):
        raise ValueError(f"{table}: a grid map needs two dimensions; the table has {dims}")
    x, y = x or dims[0], y or dims[1]
    outcomes = outcomes or ["fuel_burned_kg", "final_soc"]
    for c in (x, y, *outcomes):
        if c not in header:
            raise ValueError(f"{table}: no column '{c}' (columns: {', '.join(header)})")
    xs, ys, maps = grid_tables(rows, x, y, outcomes)
    out.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(5.2 * len(outcomes), 4.2))
    axes = fig.subplots(1, len(outcomes), squeeze=False)[0]
    for ax, o in zip(axes, outcomes, strict=True):
        m = maps[o]
        im = ax.imshow(m, origin="lower", cmap="viridis", aspect="auto")
        fig.colorbar(im, ax=ax, label=o)
        for (i, j), v in np.ndenumerate(m):
            ax.text(j, i, "-" if math.isnan(v) else f"{v:.4g}", ha="center", va="center", fontsize=9,
                    color="white" if not math.isnan(v) and v < np.nanmean(m) else "black")
        ax.set_xticks(range(len(xs)), xs)
        ax.set_yticks(range(len(ys)), ys)
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        ax.set_title(o, fontsize=10)
    fig.tight_layout()
    png = atomic_write(out / "grid.png", figure_bytes(fig))
    lines = [f"# {Path(study_dir).name}: {', '.join(outcomes)} over {x} and {y}", ""]
    for o in outcomes:
        lines += [f"## {o}", "", f"| {y} \\ {x} | " + " | ".join(xs) + " |", "|---" * (len(xs) + 1) + "|"]
        odd = _unfinished(rows, x, y)
        lines += [f"| {yv} | " + " | ".join("-" if math.isnan(v) else f"{v:.6g}" + ("*" if (xs[j], yv) in odd else "")
                                            for j, v in enumerate(maps[o][i])) + " |" for i, yv in enumerate(ys)]
        lines.append("")
    odd = _unfinished(rows, x, y)
    if odd:
        lines.append("`*`: the run completed but its table does not say the mission was completed: "
                     + ", ".join(f"{x}={a}, {y}={b}" for a, b in sorted(odd)))
        lines.append("")
    md = atomic_write(out / "grid.md", "\n".join(lines))
    copy = out / "study.csv"
    shutil.copyfile(table, copy)
    return [png, md, copy]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m openemss.study.grid", description=__doc__.split("\n\n")[0])
    ap.add_argument("study_dir", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--x")
    ap.add_argument("--y")
    ap.add_argument("--outcome", nargs="+")
    a = ap.parse_args(argv)
    try:
        for p in write_grid(a.study_dir, a.out, a.x, a.y, a.outcome):
            print(p)
    except (OSError, ValueError) as exc:
        print(f"study grid: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
