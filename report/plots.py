"""Plots of one mission run, or of several on the same figures (PNG, matplotlib's Agg canvas).

Figures are built on :class:`matplotlib.figure.Figure` directly (no pyplot, no global
backend): ground track, altitude and Mach against the commands with the sections shaded
(the altitude constraints as markers, planned holds shaded, the airbrake and lever below),
burned fuel, fuel flow and Tt4 over a window, spool speeds, attitude. Runs are told apart
by line style and named in the legends; sections and the mission's places come from the
first run that has them. A figure whose signals a run lacks is left out for that run, and
not drawn at all when no run has them.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from openemss.models.common.files import figure_bytes
from openemss.models.fcs.geo import from_local_ne
from openemss.models.fcs.mission import Mission
from openemss.orchestrator.results import atomic_write

from .errors import ReportError
from .rundata import RunData

STYLES = ("-", "--", ":", "-.")
DPI = 120


@dataclass(frozen=True)
class PlotRun:
    """A run to plot: its data, its mission (or None) and the name in the legends."""

    data: RunData
    mission: Mission | None
    label: str


def _style(i: int) -> str:
    return STYLES[i % len(STYLES)]


def _label(runs: Sequence[PlotRun], r: PlotRun, what: str = "") -> str:
    """Legend text: the quantity, and the run's name when several runs share the figure."""
    if len(runs) == 1:
        return what or r.label
    return f"{what} ({r.label})" if what else r.label


def _save(fig: Figure, path: Path) -> Path:
    fig.tight_layout()
    return atomic_write(path, figure_bytes(fig, path.suffix.lstrip(".") or "png", dpi=DPI))  # whole, no link followed


def _sections(runs: Sequence[PlotRun]) -> PlotRun | None:
    return next((r for r in runs if r.data.get("fcs", "section_index") is not None), None)


def shade_sections(ax: Axes, r: PlotRun, label: bool) -> None:
    """Shade each section's time span in alternating tones; with ``label``, write its index and name."""
    t, idx = r.data.time_s, r.data.get("fcs", "section_index")
    if idx is None:
        return
    idx = np.rint(idx).astype(int)
    change = np.flatnonzero(np.diff(idx)) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [len(t) - 1]))
    names = {s.index: s.name for s in r.mission.sections} if r.mission is not None else {}
    for a, b in zip(starts, ends, strict=True):
        i = int(idx[a])
        ax.axvspan(t[a], t[b], color="0.85" if i % 2 else "0.93", zorder=0, lw=0)
        if label:
            text = f"{i} {names.get(i, '')}".strip()
            ax.text(t[a], 0.98, " " + text, transform=ax.get_xaxis_transform(), rotation=90, va="top", ha="left",
                    fontsize=6, color="0.35", clip_on=True)


def ground_track(runs: Sequence[PlotRun], path: Path) -> Path | None:
    """Latitude over longitude, with the mission's numbered waypoints and its runways."""
    drawn = [r for r in runs if r.data.get("airframe", "lat_deg") is not None]
    if not drawn:
        return None
    fig = Figure(figsize=(8, 7))
    ax = fig.add_subplot()
    lat_all: list[float] = []
    for i, r in enumerate(drawn):
        lat, lon = r.data.get("airframe", "lat_deg"), r.data.get("airframe", "lon_deg")
        ax.plot(lon, lat, _style(i), color="C0" if len(drawn) == 1 else f"C{i}", lw=1.2, label=r.label, zorder=3)
        lat_all.extend([float(np.nanmin(lat)), float(np.nanmax(lat))])
    mission = next((r.mission for r in runs if r.mission is not None), None)
    if mission is not None:
        for k, (name, p) in enumerate(mission.waypoints, start=1):
            lat_d, lon_d = math.degrees(p.lat_rad), math.degrees(p.lon_rad)
            ax.plot(lon_d, lat_d, "^", color="C3", ms=6)
            ax.annotate(f"{k}" if name == f"WP{k}" else f"{k} {name}", (lon_d, lat_d), textcoords="offset points",
                        xytext=(4, 4), fontsize=8, color="C3")
            lat_all.append(lat_d)
        used = {getattr(sec.get("runway"), "name", None) for sec in mission.sections}
        for j, (name, rwy) in enumerate(mission.runways):
            end = from_local_ne(rwy.threshold, rwy.length_m * math.cos(rwy.heading_rad),
                                rwy.length_m * math.sin(rwy.heading_rad), rwy.elevation_m)
            xs = [math.degrees(rwy.threshold.lon_rad), math.degrees(end.lon_rad)]
            ys = [math.degrees(rwy.threshold.lat_rad), math.degrees(end.lat_rad)]
            ax.plot(xs, ys, "-", color="0.3", lw=3, solid_capstyle="butt", zorder=1,
                    label="runways" if j == 0 else None)
            if name in used:  # the runways the mission flies from or to (the others would crowd the label)
                ax.annotate(name, (xs[0], ys[0]), textcoords="offset points", xytext=(3, -9), fontsize=7)
        ax.plot([], [], "^", color="C3", label="waypoints")
    mid = 0.5 * (min(lat_all) + max(lat_all))
    ax.set_aspect(1.0 / max(math.cos(math.radians(mid)), 1e-3))
    ax.set_xlabel("longitude [deg]")
    ax.set_ylabel("latitude [deg]")
    ax.set_title("Ground track" + (f": {mission.name}" if mission is not None else ""))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def constraint_markers(ax: Axes, runs: Sequence[PlotRun]) -> None:
    """Each section's altitude constraint as a marker at the time the section ended (where the constraint is
    due): a down triangle where the section descended to it, an up triangle where it climbed, a circle
    where it was level; the stretches of a planned hold (vertical mode HOLD) shaded red."""
    from openemss.models.fcs.vertical import VNAV_MODES

    r = _sections(runs)
    if r is None or r.mission is None:
        return
    t, idx = r.data.time_s, np.rint(r.data.get("fcs", "section_index")).astype(int)
    alt = r.data.get("airframe", "alt_msl_m")
    first = True
    for sec in r.mission.sections:
        target = sec.get("altitude_m")
        seen = np.flatnonzero(idx == sec.index)
        if target is None or not seen.size:
            continue
        end = min(seen[-1] + 1, len(t) - 1)
        h0 = float(alt[seen[0]]) if alt is not None else target
        marker = "v" if target < h0 - 30.0 else ("^" if target > h0 + 30.0 else "o")
        ax.plot(t[end], target, marker, ms=7, mfc="none", mec="k", mew=1.2, zorder=5,
                label="altitude constraints" if first else None)
        first = False
    mode = r.data.get("fcs", "vnav_mode")
    if mode is not None:
        on = np.rint(mode).astype(int) == VNAV_MODES.index("HOLD")
        edges = np.flatnonzero(np.diff(np.concatenate(([0], on.astype(int), [0]))))
        for j, (a, b) in enumerate(zip(edges[::2], edges[1::2], strict=True)):
            ax.axvspan(t[a], t[b - 1], color="C3", alpha=0.25, lw=0, zorder=1, label="planned hold" if j == 0 else None)


def _lines(runs: Sequence[PlotRun], path: Path, title: str,
           panels: Sequence[tuple[str, Sequence[tuple[str, str, str, Callable[[np.ndarray], np.ndarray]]]]],
           shade: bool = False, window: tuple[float, float] | None = None,
           decorate: Callable[[Axes, Sequence[PlotRun]], None] | None = None) -> Path | None:
    """Stacked panels over time. Each panel: (y label, [(role, variable, legend, transform), ...]);
    ``decorate`` draws more on the first panel."""
    if not any(r.data.get(role, var) is not None for r in runs for _, series in panels for role, var, _, _ in series):
        return None
    fig = Figure(figsize=(10, 2.6 * len(panels) + 0.6))
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    shaded = _sections(runs) if shade else None
    for p, (ylabel, series) in enumerate(panels):
        ax = axes[p]
        if shaded is not None:
            shade_sections(ax, shaded, label=p == 0)
        for i, r in enumerate(runs):
            t = r.data.time_s
            keep = slice(None) if window is None else (t >= window[0]) & (t <= window[1])
            for c, (role, var, what, fn) in enumerate(series):
                y = r.data.get(role, var)
                if y is not None:
                    ax.plot(t[keep], fn(y)[keep], _style(i), color=f"C{c}", lw=1.1, label=_label(runs, r, what))
        if p == 0 and decorate is not None:
            decorate(ax, runs)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("time [s]")
    if window is not None:
        axes[-1].set_xlim(*window)
    fig.suptitle(title + (f" ({shaded.label}'s sections shaded)" if shaded is not None and len(runs) > 1 else ""),
                 fontsize=10)
    return _save(fig, path)


def _ident(y: np.ndarray) -> np.ndarray:
    return y


def _from_start(y: np.ndarray) -> np.ndarray:
    return y - y[0]


def _deg(y: np.ndarray) -> np.ndarray:
    return np.degrees(y)


def _heading_deg(y: np.ndarray) -> np.ndarray:
    """Heading in [0, 360) deg with a gap (NaN) where it wraps, so no vertical line joins 359 and 0."""
    h = np.mod(np.degrees(y), 360.0)
    out = h.copy()
    out[1:][np.abs(np.diff(h)) > 180.0] = np.nan
    return out


def check_window(runs: Sequence[PlotRun], window: tuple[float, float] | None) -> None:
    """Refuse a window that is empty or outside every run."""
    if window is None:
        return
    t0, t1 = window
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < t1):
        raise ReportError(f"--window {t0:g} {t1:g}: need T0 < T1 [s]")
    for r in runs:
        t = r.data.time_s
        if t1 < t[0] or t0 > t[-1]:
            raise ReportError(f"--window {t0:g} {t1:g}: outside run {r.label} ({t[0]:g} to {t[-1]:g} s)")


def plot_runs(runs: Sequence[PlotRun], out: Path, window: tuple[float, float] | None = None) -> list[Path]:
    """Draw every figure the runs' signals allow into ``out``; returns the files written.

    Parameters
    ----------
    runs : sequence of PlotRun
        One run, or several to compare (line styles ``-``, ``--``, ``:``, ``-.`` in turn).
    out : Path
        Folder for the PNG files (created).
    window : (float, float) or None
        Time window [s] of the fuel flow and Tt4 figure; None: the whole run.
    """
    check_window(runs, window)
    out.mkdir(parents=True, exist_ok=True)
    figures = [
        ground_track(runs, out / "ground_track.png"),
        _lines(runs, out / "altitude_mach.png", "Altitude and Mach, flown and commanded", [
            ("altitude MSL [m]", [("airframe", "alt_msl_m", "flown", _ident), ("fcs", "alt_cmd_m", "commanded",
                                                                                 _ident)]),
            ("Mach [-]", [("airframe", "mach", "flown", _ident), ("fcs", "mach_cmd", "commanded", _ident)]),
            ("airbrake, lever [-]", [("airframe", "airbrake_pos_norm", "airbrake", _ident),
                                     ("fcs", "lever_norm", "thrust lever", _ident)]),
        ], shade=True, decorate=constraint_markers),
        _lines(runs, out / "fuel_burned.png", "Burned fuel", [
            ("burned fuel [kg]", [("engine", "fuel_burned_kg", "burned fuel", _from_start)])], shade=True),
        _lines(runs, out / "fuel_flow_tt4.png", "Fuel flow and Tt4" + (
            f", {window[0]:g} to {window[1]:g} s" if window is not None else ""), [
            ("fuel flow [kg/s]", [("engine", "fuel_flow_kg_s", "fuel flow", _ident),
                                  ("fcs", "fuel_flow_cmd_kg_s", "command", _ident)]),
            ("temperature [K]", [("engine", "Tt4_K", "Tt4", _ident), ("engine", "Tt41_K", "Tt41", _ident)]),
        ], window=window),
        _lines(runs, out / "spool_speeds.png", "Spool speeds", [
            ("spool speed [%]", [("engine", "N1_pct", "N1", _ident), ("engine", "N2_pct", "N2", _ident),
                                 ("engine", "N1c_pct", "N1c", _ident)])], shade=True),
        _lines(runs, out / "attitude.png", "Attitude", [
            ("roll phi [deg]", [("airframe", "phi_rad", "phi", _deg)]),
            ("pitch theta [deg]", [("airframe", "theta_rad", "theta", _deg)]),
            ("heading psi [deg]", [("airframe", "psi_rad", "psi", _heading_deg)]),
        ], shade=True),
    ]
    return [f for f in figures if f is not None]
