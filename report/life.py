"""The engine's life usage over a run: ``summary.json``'s ``life``, the figure ``life.png``, the report's table.

Computed after the run from the recorded time series (nothing per macro step) with the life model
:mod:`openemss.models.life.usage`: the discs' low-cycle fatigue from rainflow counting of N1 and N2
(stress from speed squared, strain-life curve with the Smith-Watson-Topper correction, Miner's rule),
the HP turbine blade's creep from its metal temperature (Tt41 and the cooling air Tt3, a cooling
effectiveness) through the alloy's Larson-Miller curve (Robinson's rule), and the time above the
temperature thresholds. The discs' cycles include the start from rest before the record and the stop after
it (a run is one flight from a running engine). A section owns the intervals that start while it is active
(:mod:`.summary`); an LCF cycle belongs to the section where it starts. With ``--record-every N`` the turning
points between recorded samples are missed (rainflow sees the recorded series only): the summary says so.
"""
from __future__ import annotations

import html
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from openemss.models.life.usage import BladeLife, DiscLife, blade_creep, disc_lcf, load_life_spec, time_above

from .agg import Figure
from .drawing import _label, _save, _style, shade_sections
from .rundata import RunData

__all__ = ["life_summary", "life_figure", "life_html", "compute_life"]

_SPOOL_SIGNAL = {"N1": "N1_pct", "N2": "N2_pct"}


def compute_life(run: RunData) -> tuple[list[DiscLife], BladeLife | None, str | None] | None:
    """The discs' LCF and the blade's creep of a run (the blade None without ``Tt3_K``/``Tt41_K``, with the
    reason), or None when the engine's spool speeds are not recorded."""
    spec = load_life_spec()
    if run.roles.engine is None or any(run.get("engine", s) is None for s in _SPOOL_SIGNAL.values()):
        return None
    discs = [disc_lcf(run.get("engine", _SPOOL_SIGNAL[d.spool]), d, from_rest=True)  # type: ignore[arg-type]
             for d in spec.discs]
    Tt41, Tt3, N2 = run.get("engine", "Tt41_K"), run.get("engine", "Tt3_K"), run.get("engine", "N2_pct")
    if Tt41 is None or Tt3 is None:
        return discs, None, (f"{run.roles.engine}.Tt41_K and {run.roles.engine}.Tt3_K are needed for the blade's "
                             "creep (an engine FMU without Tt3_K, or a --record leaving them out)")
    return discs, blade_creep(run.time_s, N2, Tt41, Tt3, spec.blade), None  # type: ignore[arg-type]


def _sampling_note(run: RunData) -> str | None:
    step = run.info.get("step_size_s")
    t = run.time_s
    if step is None or len(t) < 2 or bool(np.allclose(np.diff(t), step, rtol=1e-9, atol=1e-12)):
        return None
    return (f"the time series holds every {float(np.median(np.diff(t))) / float(step):.3g}th step: turning points "
            "between the recorded samples are not counted, the LCF damage is a lower bound")


def life_summary(run: RunData) -> dict[str, Any] | None:
    """The life usage of a run (see the README's Results: ``life``), or None without the engine's N1/N2."""
    got = compute_life(run)
    if got is None:
        return None
    discs, blade, why = got
    spec = load_life_spec()
    t = run.time_s
    idx = run.get("fcs", "section_index")
    owner = np.rint(idx[:-1]).astype(int) if idx is not None and len(t) > 1 else None
    out: dict[str, Any] = {
        "method": "after the run, from the recorded time series (models/life/usage.py); the discs' cycles "
                  "include the spools' start from rest before the record and their stop after it",
        "sampling_note": _sampling_note(run),
        "data": spec.source,
        "data_checked": {m.name: m.checked or "not said" for m in (*(d.spec.material for d in discs),
                                                                   spec.blade.material)},
        "discs": [{"name": d.spec.name, "spool": d.spec.spool, "material": d.spec.material.name,
                   "stress_at_design_speed_Pa": d.spec.stress_at_design_speed_Pa,
                   "cycles_counted": float(d.cycles[:, 2].sum()),
                   "miner_damage": d.total, "reference_cycle_life": d.reference_cycles,
                   "equivalent_cycles": d.equivalent_cycles} for d in discs],
        "blade": None if blade is None else {
            "name": blade.spec.name, "material": blade.spec.material.name,
            "cooling_effectiveness": blade.spec.cooling_effectiveness, "creep_damage": blade.total,
            "max_metal_K": float(np.max(blade.metal_K)), "max_metal_time_s": float(t[int(np.argmax(blade.metal_K))]),
            "min_rupture_time_h": float(np.min(blade.rupture_s)) / 3600.0},
        "blade_note": why,
        "time_above_s": {},
    }
    Tt41 = run.get("engine", "Tt41_K")
    if Tt41 is not None:
        out["time_above_s"]["Tt41_K"] = time_above(t, Tt41, spec.thresholds_K.get("Tt41_K", ()))
    if blade is not None:
        out["time_above_s"]["blade_metal_K"] = time_above(t, blade.metal_K, spec.thresholds_K.get("blade_metal_K", ()))
    lcf = max(discs, key=lambda d: d.total)
    worst = max(lcf.total, blade.total if blade is not None else 0.0)
    out["mission"] = {"lcf_limiting_disc": lcf.spec.name, "lcf_damage": lcf.total,
                      "lcf_equivalent_cycles": lcf.equivalent_cycles,
                      "creep_damage": None if blade is None else blade.total,
                      "missions_to_life": 1.0 / worst if worst > 0.0 else None}
    if owner is not None:
        rows = []
        for s in np.unique(owner):
            row: dict[str, Any] = {"index": int(s), "lcf_damage": {
                d.spec.name: float(d.damage[owner[np.minimum(d.cycles[:, 3].astype(int), len(owner) - 1)] == s].sum())
                for d in discs}}
            row["creep_damage"] = None if blade is None else float(blade.damage[owner == s].sum())
            if Tt41 is not None:
                hot = Tt41[1:] > max(spec.thresholds_K.get("Tt41_K", (np.inf,)))
                row["time_above_top_Tt41_s"] = float(np.diff(t)[(owner == s) & hot].sum())
            rows.append(row)
        out["per_section"] = rows
    return out


def _cumulative(t: np.ndarray, d: DiscLife) -> np.ndarray:
    """A disc's damage over time: each cycle's damage counted when it closes."""
    acc = np.zeros(len(t))
    np.add.at(acc, np.minimum(d.cycles[:, 4].astype(int), len(t) - 1), d.damage)
    return np.cumsum(acc)


def life_figure(runs: Sequence[Any], path: Path) -> Path | None:
    """``life.png``: disc stresses, the blade's temperatures with the thresholds, cumulative damage (log)."""
    got = [(r, compute_life(r.data)) for r in runs]
    got = [(r, g) for r, g in got if g is not None]
    if not got:
        return None
    spec = load_life_spec()
    fig = Figure(figsize=(10, 9))
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    for i, (r, (discs, blade, _)) in enumerate(got):
        t, st = r.data.time_s, _style(i)
        for d in discs:
            sigma = d.spec.stress_at_design_speed_Pa * (r.data.get("engine", _SPOOL_SIGNAL[d.spec.spool]) / 100.0) ** 2
            ax1.plot(t, sigma / 1e6, st, lw=0.9, label=_label(runs, r, d.spec.name))
            ax3.semilogy(t, np.where(_cumulative(t, d) > 0, _cumulative(t, d), np.nan), st, lw=1.0,
                         label=_label(runs, r, f"{d.spec.name} LCF"))
        if blade is not None:
            ax2.plot(t, r.data.get("engine", "Tt41_K"), st, lw=0.8, label=_label(runs, r, "Tt41 gas"))
            ax2.plot(t, r.data.get("engine", "Tt3_K"), st, lw=0.8, label=_label(runs, r, "Tt3 cooling air"))
            ax2.plot(t, blade.metal_K, st, lw=1.2, label=_label(runs, r, "blade metal"))
            cum = np.concatenate(([0.0], np.cumsum(blade.damage)))
            ax3.semilogy(t, np.where(cum > 0, cum, np.nan), st, lw=1.2, label=_label(runs, r, "blade creep"))
        if i == 0 and r.data.get("fcs", "section_index") is not None:
            for ax in (ax1, ax2, ax3):
                shade_sections(ax, r, label=ax is ax1)
    for th in spec.thresholds_K.get("blade_metal_K", ()):
        ax2.axhline(th, color="0.5", lw=0.6, ls=":")
    ax1.set_ylabel("disc peak stress [MPa]")
    ax2.set_ylabel("temperature [K]")
    ax3.set_ylabel("damage used [-]")
    top = max((float(np.nanmax(ln.get_ydata())) for ln in ax3.lines if np.isfinite(ln.get_ydata()).any()),
              default=1.0)
    ax3.set_ylim(top * 1e-6, top * 3.0)            # six decades below the largest: the parts that matter
    ax3.set_xlabel("time [s]")
    ax1.set_title("Life usage: disc LCF (rainflow, Miner) and HPT blade creep (Larson-Miller)", pad=16)
    for ax in (ax1, ax2, ax3):
        ax.grid(True, lw=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="best")
    return _save(fig, path)


def _fmt(v: Any, digits: int = 3) -> str:
    return "" if v is None else f"{v:.{digits}g}" if isinstance(v, float) else html.escape(str(v))


def life_html(runs: Sequence[Any]) -> str:
    """The report's table of life usage, one row per run and life-limited part."""
    rows = []
    for r in runs:
        s = life_summary(r.data)
        if s is None:
            continue
        for d in s["discs"]:
            rows.append((r.label, d["name"], "LCF", d["miner_damage"], f"{d['equivalent_cycles']:.3g} equivalent "
                         f"0-100-0 % cycles of {d['reference_cycle_life']:.3g}; {d['cycles_counted']:.3g} counted"))
        b = s["blade"]
        if b is not None:
            rows.append((r.label, b["name"], "creep", b["creep_damage"],
                         f"max metal {b['max_metal_K']:.0f} K at {b['max_metal_time_s']:.0f} s (phi "
                         f"{b['cooling_effectiveness']:g})"))
        above = "; ".join(f"{k} &gt; {th} K: {v:.0f} s" for k, d in s["time_above_s"].items() for th, v in d.items())
        rows.append((r.label, "time above", "", None, above))
    if not rows:
        return ""
    body = "".join(f"<tr><td>{html.escape(a)}</td><td>{html.escape(b)}</td><td>{c}</td><td>{_fmt(d)}</td>"
                   f"<td>{e if b == 'time above' else html.escape(e)}</td></tr>" for a, b, c, d, e in rows)
    return ("<h2>Life usage (computed after the run; models/life/usage.py)</h2><table><tr><th>run</th><th>part</th>"
            f"<th>mode</th><th>damage [-]</th><th>details</th></tr>{body}</table>")
