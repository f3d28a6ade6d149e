"""The mission-fuel carpet: every design of the cycle sweep flown through the mission, beside its SFC carpet.

A study whose ``redesign`` block says ``carpet: true`` (``studies/engine_carpet.yaml``) flies every feasible
design of the sweep (:func:`.redesign.cycle_redesign` makes one variant per design; the lowest-SFC one is the
``redesigned`` engine) and the baseline engine (the reference preset). :func:`carpet_report` then writes
``carpet/`` (``carpet/mission-<name>/`` per mission of a study of several):

* ``mission_carpet.csv``: one row per design of the sweep (BPR, OPR), also those not flown: the design-point
  SFC and its change against the baseline engine, the case, its status, whether the mission was completed,
  the mission fuel and its change against the baseline's, and the ratio ``mission fuel change / SFC change``
  (how much of the design-point promise the mission keeps); ``outcome`` says plainly what happened
  (``flown``, ``infeasible design: ...`` from the cycle sweep, ``failed: ...``, ``mission not completed``,
  ``not run``). Nothing is left out: a design that could not fly is a row that says so.
* ``mission_carpet.png``: the design-point SFC carpet, the mission-fuel carpet and the ratio, over OPR with a
  line per BPR, the baseline and the lowest-SFC design marked on the first two.

The changes are against the baseline engine flying the same mission (its fuel; its design-point SFC), both
in percent; the ratio is left empty where the SFC change is below :data:`MIN_SFC_CHANGE_PCT` (a ratio of two
small numbers says nothing).
"""
from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Any

from openemss.models.infra.files import figure_bytes
from openemss.orchestrator.results import atomic_write

from .case import CaseDef, CaseResult

__all__ = ["carpet_rows", "carpet_report", "COLUMNS", "MIN_SFC_CHANGE_PCT"]

#: SFC change [%] below which the ratio mission fuel change / SFC change is not given
MIN_SFC_CHANGE_PCT = 0.1
COLUMNS = ("BPR", "OPR", "SFC_kg_N_s", "SFC_change_pct", "case", "status", "mission_completed", "fuel_burned_kg",
           "fuel_change_pct", "fuel_change_per_SFC_change", "outcome")


def _mission_fuel(r: CaseResult | None) -> float | None:
    """The fuel [kg] of a completed mission (None when the case did not complete it)."""
    if r is None or r.status != "completed" or not r.summary.get("mission_completed"):
        return None
    fuel = r.summary.get("fuel_burned_kg")
    return float(fuel) if isinstance(fuel, int | float) and math.isfinite(fuel) else None


def _outcome(point: dict[str, Any], r: CaseResult | None) -> str:
    if point.get("variant") is None:
        return f"infeasible design: {point.get('note') or 'the cycle sweep found no design'}"
    if r is None:
        return "not run"
    if r.status != "completed":
        return f"{r.status}: {r.error}" if r.error else r.status
    if not r.summary.get("mission_completed"):
        return "mission not completed"
    return "flown"


def carpet_rows(points: list[dict[str, Any]], case_of: dict[str, str], results: dict[str, CaseResult],
                baseline_case: str, baseline_SFC_kg_N_s: float) -> list[dict[str, Any]]:
    """One row per design of the sweep (:data:`COLUMNS`).

    Parameters
    ----------
    points : list of dict
        The sweep's designs (``redesign.json``'s ``carpet``: BPR, OPR, SFC_kg_N_s, variant, note).
    case_of : dict
        Variant name -> case name (one mission).
    results : dict
        Case name -> result.
    baseline_case : str
        The case of the baseline engine on that mission.
    baseline_SFC_kg_N_s : float
        The baseline engine's design-point SFC [kg/(N s)].
    """
    base_fuel = _mission_fuel(results.get(baseline_case))
    rows = []
    for p in points:
        case = case_of.get(p["variant"]) if p.get("variant") else None
        r = results.get(case) if case else None
        sfc = p.get("SFC_kg_N_s")
        dsfc = 100.0 * (sfc / baseline_SFC_kg_N_s - 1.0) if sfc is not None else None
        fuel = _mission_fuel(r)
        dfuel = 100.0 * (fuel / base_fuel - 1.0) if fuel is not None and base_fuel else None
        ratio = dfuel / dsfc if dfuel is not None and dsfc is not None and abs(dsfc) >= MIN_SFC_CHANGE_PCT else None
        rows.append({"BPR": p["BPR"], "OPR": p["OPR"], "SFC_kg_N_s": sfc, "SFC_change_pct": dsfc, "case": case or "",
                     "status": r.status if r is not None else "", "mission_completed":
                     r.summary.get("mission_completed") if r is not None else None, "fuel_burned_kg": fuel,
                     "fuel_change_pct": dfuel, "fuel_change_per_SFC_change": ratio, "outcome": _outcome(p, r)})
    return rows


def _csv(rows: list[dict[str, Any]]) -> str:
    text = io.StringIO(newline="")
    w = csv.DictWriter(text, fieldnames=COLUMNS)
    w.writeheader()
    w.writerows({k: "" if v is None else v for k, v in row.items()} for row in rows)
    return text.getvalue()


def _plot(rows: list[dict[str, Any]], marks: dict[str, tuple[float, float, float | None]], path: Path,
          title: str) -> Path:
    """Three panels over OPR, a line per BPR: design-point SFC, mission fuel, and their changes' ratio."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(16, 5))
    panels = (("SFC_kg_N_s", 1e6, "design-point SFC [mg/(N s)]"), ("fuel_burned_kg", 1.0, "mission fuel [kg]"),
              ("fuel_change_per_SFC_change", 1.0, "mission fuel change / SFC change [-]"))
    for ax, (key, scale, label) in zip(axes, panels, strict=True):
        for bpr in sorted({r["BPR"] for r in rows}):
            line = [(r["OPR"], r[key] * scale) for r in rows if r["BPR"] == bpr and r[key] is not None]
            if line:
                ax.plot(*zip(*line, strict=True), marker="o", ms=3, label=f"BPR {bpr:g}")
        ax.set(xlabel="overall pressure ratio OPR [-]", ylabel=label)
        ax.grid(True, alpha=0.3)
    for name, (opr, sfc, fuel), style in ((k, v, s) for (k, v), s in zip(marks.items(), ("k*", "rD"), strict=False)):
        axes[0].plot(opr, sfc * 1e6, style, ms=11, label=name)
        if fuel is not None:
            axes[1].plot(opr, fuel, style, ms=11, label=name)
    axes[2].axhline(1.0, color="0.5", lw=0.8, ls=":")
    for ax in axes[:2]:
        ax.legend(fontsize=7)
    axes[0].set_title("design point (same thrust, Tt4, jet velocity ratio)")
    axes[1].set_title("the mission flown")
    axes[2].set_title("share of the SFC change kept in the mission")
    fig.suptitle(title)
    fig.tight_layout()
    atomic_write(path, figure_bytes(fig, dpi=110))
    plt.close(fig)
    return path


def carpet_report(out: Path, cases: list[CaseDef], results: dict[str, CaseResult], info: dict[str, Any],
                  mission: str = "") -> dict[str, Any]:
    """Write ``mission_carpet.csv``, ``.png`` and ``.json`` into ``out`` for one mission; what they say.

    Parameters
    ----------
    out : Path
        The folder of the files (the study's ``carpet/``, per mission when it has several).
    cases, results : the study's cases and their results
    info : dict
        The redesign's ``redesign.json`` (baseline, redesigned, carpet).
    mission : str
        The mission's name in the study ("" when it has none).
    """
    from .redesign import BASELINE, REDESIGNED

    case_of = {dict(c.labels).get("variant", ""): c.name for c in cases if dict(c.labels).get("mission", "") == mission}
    points = info.get("carpet") or []
    base_sfc = float(info["baseline"]["SFC_kg_N_s"])
    rows = carpet_rows(points, case_of, results, case_of.get(BASELINE, ""), base_sfc)
    folder = out
    folder.mkdir(parents=True, exist_ok=True)
    csv_path = atomic_write(folder / "mission_carpet.csv", _csv(rows))
    base_fuel = _mission_fuel(results.get(case_of.get(BASELINE, "")))
    red = next((r for r in rows if r["case"] == case_of.get(REDESIGNED)), None)
    marks = {f"baseline (BPR {info['baseline']['BPR']:.2f}, OPR {info['baseline']['OPR']:.2f})":
             (float(info["baseline"]["OPR"]), base_sfc, base_fuel)}
    if red is not None:
        marks[f"lowest SFC (BPR {red['BPR']:g}, OPR {red['OPR']:g})"] = (red["OPR"], red["SFC_kg_N_s"],
                                                                         red["fuel_burned_kg"])
    png = _plot(rows, marks, folder / "mission_carpet.png", f"Cycle sweep flown through the mission "
                f"{mission or ''}: {sum(r['outcome'] == 'flown' for r in rows)} of {len(rows)} designs flown")
    counts: dict[str, int] = {}
    for r in rows:
        key = r["outcome"].split(":")[0]
        counts[key] = counts.get(key, 0) + 1
    ratios = [r["fuel_change_per_SFC_change"] for r in rows if r["fuel_change_per_SFC_change"] is not None]
    res = {"designs": len(rows), "outcomes": counts, "baseline_fuel_kg": base_fuel,
           "ratio_min": min(ratios) if ratios else None, "ratio_max": max(ratios) if ratios else None,
           "lowest_SFC": red, "files": {"table": str(csv_path), "plot": str(png)}}
    atomic_write(folder / "mission_carpet.json", json.dumps(res, indent=2) + "\n")
    return res
