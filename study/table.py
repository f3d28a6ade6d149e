"""The study table: one CSV row per case (parameters, outcome, fuel, times, limits)."""
from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from openemss.orchestrator.results import atomic_write

from .case import CaseDef, CaseResult

__all__ = ["OUTCOME_COLUMNS", "rows", "write_table"]

#: Columns after the case's parameters. setup_s, stepping_s, writing_s: the case's wall time [s] before its
#: first step, in its steps and after its last step (:class:`.case.CaseResult`). ``summary.json`` (written by
#: ``emss run`` where the
#: project's report hook is installed) gives mission_completed ... limits_hit (final_soc: the battery's
#: state of charge at the end, in a system with an electrical system; life_*: its ``life.mission``, the engine's
#: life usage); a case without one leaves them empty.
OUTCOME_COLUMNS: tuple[str, ...] = ("status", "error", "attempts", "ran", "mission_completed", "landed",
                                    "fuel_burned_kg", "sim_time_s", "wall_time_s", "realtime_factor",
                                    "setup_s", "stepping_s", "writing_s",
                                    "max_Tt4_K", "final_soc", "life_lcf_equivalent_cycles", "life_lcf_damage",
                                    "life_creep_damage", "life_missions_to_life", "limits_hit", "folder")


def _cell(v: Any) -> Any:
    if v is None:
        return ""
    if isinstance(v, list | tuple):
        return ";".join(str(x) for x in v)
    if isinstance(v, dict):  # e.g. limits_hit: {name: {count: n, ...}}: the names that were hit
        return ";".join(str(k) for k, x in v.items() if (x.get("count") if isinstance(x, dict) else x))
    return v


def rows(cases: Sequence[CaseDef], results: dict[str, CaseResult], ran: set[str],
         out: Path) -> tuple[list[str], list[dict[str, Any]]]:
    """The table's columns and rows, in case order (a case without a result has status ``pending``)."""
    dims: list[str] = []
    for c in cases:
        for dim, _ in [*c.labels, *c.values]:  # the study's dimensions, then every parameter value that varies
            if dim not in dims:
                dims.append(dim)
    dims = [d for d in dims if any(d == k for c in cases for k, _ in c.labels)
            or len({repr(dict(c.values).get(d)) for c in cases}) > 1]
    table: list[dict[str, Any]] = []
    for c in cases:
        values = dict(c.values)
        row: dict[str, Any] = {"case": c.name}
        for dim in dims:
            row[dim] = values.get(dim, dict(c.labels).get(dim, ""))
        r = results.get(c.name)
        s = r.summary if r is not None else {}
        sim = r.sim_time_s if r is not None else None
        wall = r.wall_time_s if r is not None else None
        row.update({
            "status": r.status if r is not None else "pending",
            "error": r.error if r is not None else "",
            "attempts": r.attempts if r is not None else 0,
            "ran": ("this run" if c.name in ran else "earlier") if r is not None else "",
            "mission_completed": s.get("mission_completed"), "landed": s.get("landed"),
            "fuel_burned_kg": s.get("fuel_burned_kg"), "sim_time_s": sim, "wall_time_s": wall,
            "realtime_factor": s.get("realtime_factor", sim / wall if sim is not None and wall else None),
            **{k: getattr(r, k) if r is not None else None for k in ("setup_s", "stepping_s", "writing_s")},
            "max_Tt4_K": s.get("max_Tt4_K"),
            "final_soc": ((s.get("electric") or {}).get("soc") or {}).get("end"),  # systems with a battery
            **{f"life_{k}": (s.get("life") or {}).get("mission", {}).get(k)   # summary.json's life (report/life.py)
               for k in ("lcf_equivalent_cycles", "lcf_damage", "creep_damage", "missions_to_life")},
            "limits_hit": s.get("limits_hit"),
            "folder": str(Path("cases") / c.name),
        })
        table.append({k: _cell(v) for k, v in row.items()})
    return ["case", *dims, *OUTCOME_COLUMNS], table


def write_table(path: Path, cases: Sequence[CaseDef], results: dict[str, CaseResult], ran: set[str]) -> Path:
    """Write (atomically) the study table ``path`` (CSV, header line first)."""
    columns, table = rows(cases, results, ran, path.parent)
    text = io.StringIO(newline="")
    w = csv.DictWriter(text, fieldnames=columns)
    w.writeheader()
    w.writerows(table)
    return atomic_write(path, text.getvalue())
