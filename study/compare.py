"""Two engines through the same mission, side by side: fuel and life used, fuel flow and Tt4 on the same axes.

Reads each case's time series (and ``summary.json`` where there is one),
and writes into ``out/report/``: ``report.json``, ``report.md``,
``fuel_burned.png`` (burned fuel over time) and ``section.png`` (fuel flow and
Tt4 over one mission section, against the time since the section began).

Missions that were not flown to the end by both engines are compared at the
last time both reached (stated in the report), never as whole-mission fuel or life.
The life used (``summary.json``'s ``life.mission``, report/life.py: the limiting disc's
low-cycle fatigue in equivalent 0-100-0 % cycles, the HP turbine blade's creep damage, the
missions to the first life) is compared for engines that completed the mission.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from openemss.models.infra.files import figure_bytes
from openemss.orchestrator.results import atomic_write

from .case import CaseResult, case_dir

__all__ = ["read_series", "compare_engines", "LIFE_KEYS"]

#: The life figures of a mission compared between the engines (keys of ``summary.json``'s ``life.mission``).
LIFE_KEYS: tuple[str, ...] = ("lcf_limiting_disc", "lcf_equivalent_cycles", "lcf_damage", "creep_damage",
                              "missions_to_life")


def read_series(path: Path, columns: list[str]) -> dict[str, np.ndarray]:
    """The named columns (and ``time_s``) of a case's time series (a results folder or a file, any format
    emss run writes) as float arrays (missing: absent; unreadable: empty)."""
    from openemss.orchestrator.recording.timeseries import TimeSeriesError, read_timeseries

    try:
        data = read_timeseries(path).floats()
    except TimeSeriesError:
        return {}
    return {name: data[name] for name in ["time_s", *columns] if name in data}


def _section_window(s: dict[str, np.ndarray], var: str, section: int) -> tuple[np.ndarray, str]:
    """Mask of the rows in `section` (the whole run when it was not reached) and a note."""
    if var in s and np.any(s[var] == section):
        return s[var] == section, ""
    return np.ones_like(s["time_s"], dtype=bool), f"section {section} not reached: whole run shown"


def compare_engines(out: Path, cases: dict[str, str], results: dict[str, CaseResult], info: dict[str, Any],
                    component: str, section: int, section_variable: str,
                    section_names: list[str] | None = None) -> dict[str, Any]:
    """Compare the engines of `cases` (label -> case name) flying one mission; write the report files.

    Returns
    -------
    dict
        ``design_point_SFC_change_pct``, per engine the burned fuel at the common time and in the
        mission and its life used (where both completed), the changes in fuel and life [%], and the
        report's file paths.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    report = out / "report"
    report.mkdir(parents=True, exist_ok=True)
    cols = [f"{component}.fuel_burned_kg", f"{component}.Wf_kg_s", f"{component}.Tt4_K", section_variable]
    series: dict[str, dict[str, np.ndarray]] = {}
    for label, name in cases.items():
        path = case_dir(out, name)
        if path.is_dir():
            s = read_series(path, cols)
            if s.get("time_s") is not None and s["time_s"].size and cols[0] in s:
                series[label] = s
    res: dict[str, Any] = {"design_point_SFC_change_pct": info.get("design_point_SFC_change_pct"),
                           "engines": {}, "files": {}}
    if len(series) < 2:
        res["note"] = "fewer than two engines have recorded results: nothing to compare"
        atomic_write(report / "report.json", json.dumps(res, indent=2) + "\n")
        return res
    t_common = min(float(s["time_s"][-1]) for s in series.values())
    for label, s in series.items():
        r = results.get(cases[label])
        summ = r.summary if r is not None else {}
        res["engines"][label] = {
            "case": cases[label], "status": r.status if r is not None else "missing",
            "sim_time_s": float(s["time_s"][-1]),
            "fuel_at_common_time_kg": float(np.interp(t_common, s["time_s"], s[cols[0]])),
            "mission_completed": summ.get("mission_completed"),
            "mission_fuel_kg": summ.get("fuel_burned_kg") if summ.get("mission_completed") else None,
            "life": _life(summ) if summ.get("mission_completed") else None,
        }
    labels = list(series)
    a, b = (res["engines"][k] for k in labels[:2])
    res["common_time_s"] = t_common
    res["fuel_change_at_common_time_pct"] = 100.0 * (b["fuel_at_common_time_kg"] / a["fuel_at_common_time_kg"] - 1.0) \
        if a["fuel_at_common_time_kg"] > 0 else None
    res["life_change_pct"] = {k: _change_pct(a["life"][k], b["life"][k])
                              for k in LIFE_KEYS[1:] if a["life"] and b["life"]}
    if a["mission_fuel_kg"] and b["mission_fuel_kg"]:
        res["mission_fuel_change_pct"] = 100.0 * (b["mission_fuel_kg"] / a["mission_fuel_kg"] - 1.0)
    else:
        res["mission_fuel_change_pct"] = None
        res["note"] = (f"the mission was not completed by both engines: fuel compared at t = {t_common:.1f} s, "
                       "the last time both reached")

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, s in series.items():
        ax.plot(s["time_s"], s[cols[0]], label=label)
    ax.axvline(t_common, color="0.6", lw=0.8, ls=":")
    ax.set(xlabel="time [s]", ylabel="burned fuel [kg]", title="Burned fuel over the mission")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    atomic_write(report / "fuel_burned.png", figure_bytes(fig, dpi=120))
    plt.close(fig)

    name = section_names[section] if section_names and 0 <= section < len(section_names) else f"section {section}"
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    notes = []
    for label, s in series.items():
        mask, note = _section_window(s, section_variable, section)
        t = s["time_s"][mask]
        t = t - t[0]
        if cols[1] in s:
            ax1.plot(t, s[cols[1]][mask], label=label)
        if cols[2] in s:
            ax2.plot(t, s[cols[2]][mask], label=label)
        if note:
            notes.append(f"{label}: {note}")
    missed = [n.split(":")[0] for n in notes]
    ax1.set(ylabel="fuel flow [kg/s]", title=f"Mission section {section}: {name}" + (
        f"\n(not reached by {', '.join(missed)}: the whole run is shown)" if missed else ""))
    ax2.set(xlabel="time since the section began [s]" if not missed else "time [s]", ylabel="Tt4 [K]")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.legend()
    fig.tight_layout()
    atomic_write(report / "section.png", figure_bytes(fig, dpi=120))
    plt.close(fig)
    res["section"] = {"index": section, "name": name, "notes": notes}
    res["files"] = {"fuel_burned": str(report / "fuel_burned.png"), "section": str(report / "section.png")}
    atomic_write(report / "report.json", json.dumps(res, indent=2, default=float) + "\n")
    atomic_write(report / "report.md", markdown(res))
    return res


def _life(summary: dict[str, Any]) -> dict[str, Any] | None:
    """The mission's life figures of a case's summary (None without them)."""
    mission = (summary.get("life") or {}).get("mission")
    return {k: mission.get(k) for k in LIFE_KEYS} if mission else None


def _change_pct(a: Any, b: Any) -> float | None:
    """The change from `a` to `b` [%], None where either is missing or `a` is not positive."""
    return 100.0 * (b / a - 1.0) if isinstance(a, int | float) and isinstance(b, int | float) and a > 0 else None


def _g(v: Any) -> str:
    return "" if v is None else f"{v:.4g}" if isinstance(v, float) else str(v)


def _pct(v: Any) -> str:
    return "n/a" if v is None else f"{v:+.2f} %"


def markdown(res: dict[str, Any]) -> str:
    """The comparison as a short Markdown report."""
    lines = ["# Engine redesign: design-point SFC against mission fuel", "",
             f"- design-point SFC change (redesigned vs baseline): {_pct(res.get('design_point_SFC_change_pct'))}",
             f"- mission fuel change: {_pct(res.get('mission_fuel_change_pct'))}",
             f"- fuel change at t = {res.get('common_time_s', float('nan')):.1f} s (both engines flying): "
             f"{_pct(res.get('fuel_change_at_common_time_pct'))}", ""]
    if res.get("note"):
        lines += [f"Note: {res['note']}.", ""]
    for key, v in (res.get("life_change_pct") or {}).items():
        lines.insert(-1, f"- {key.replace('_', ' ')} change: {_pct(v)}")
    lines += ["| engine | case | status | simulated [s] | fuel at common time [kg] | mission fuel [kg] | "
              "LCF-limiting disc | its equivalent 0-100-0 % cycles | blade creep damage | missions to first life |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for label, e in res.get("engines", {}).items():
        mf, life = e.get("mission_fuel_kg"), e.get("life") or {}
        lines.append(f"| {label} | {e['case']} | {e['status']} | {e['sim_time_s']:.1f} | "
                     f"{e['fuel_at_common_time_kg']:.2f} | {'' if mf is None else f'{mf:.2f}'} | "
                     + " | ".join(_g(life.get(k)) for k in ("lcf_limiting_disc", "lcf_equivalent_cycles",
                                                             "creep_damage", "missions_to_life")) + " |")
    lines += ["", "![burned fuel](fuel_burned.png)", "", "![fuel flow and Tt4](section.png)", ""]
    return "\n".join(lines)
