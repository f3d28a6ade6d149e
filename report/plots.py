"""Plots of one mission run, or of several on the same figures (PNG, matplotlib's Agg canvas).

Figures are built on :class:`.agg.Figure`, on the Agg canvas (no pyplot, no global
backend, whatever ``MPLBACKEND`` says): ground track, altitude and Mach against the
commands with the sections shaded (the altitude constraints as markers, planned holds
shaded, the airbrake and lever below), burned fuel, fuel flow and Tt4 over a window, spool
speeds, attitude. Runs are told apart by line style and named in the legends; sections and
the mission's places come from the first run that has them. A figure whose signals a run
lacks is left out for that run, and not drawn at all when no run has them.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from enum import StrEnum
from pathlib import Path

import numpy as np

from openemss.models.infra.files import figure_bytes
from openemss.models.mission.geo import R_EARTH_M
from openemss.orchestrator.results import atomic_write

from .agg import Axes, Figure  # matplotlib imported whatever MPLBACKEND says, figures on the Agg canvas
from .drawing import DPI, PlotRun, _label, _save, _sections, _style, shade_sections
from .errors import ReportError
from .life import life_figure
from .panels import SFC_LABEL, runway_lines, signal_colors, waypoints_deg


def section_legend(fig: Figure, r: PlotRun | None) -> None:
    """The numbered sections' names below the figure, in columns."""
    if r is None or r.mission is None:
        return
    from .panels import section_spans

    seen = {i for i, _, _ in section_spans(r.data, r.mission)}
    items = [f"{s.index}  {s.name}" for s in r.mission.sections if s.index in seen]
    if not items:
        return
    ncol = 3
    rows = math.ceil(len(items) / ncol)
    for c in range(ncol):
        text = "\n".join(items[c * rows:(c + 1) * rows])
        fig.text(0.02 + c * 0.33, 0.005, text, fontsize=7, va="bottom", ha="left", color="0.25", family="monospace")


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
        color = "C0" if len(drawn) == 1 else f"C{i}"
        ax.plot(lon, lat, _style(i), color=color, lw=1.2, label=r.label, zorder=3)
        ax.plot(lon[0], lat[0], "o", color=color, ms=7, zorder=4, label="start" if i == 0 else None)
        ax.plot(lon[-1], lat[-1], "s", color=color, ms=7, mfc="none", mew=1.5, zorder=4,
                label="end" if i == 0 else None)
        lat_all.extend([float(np.nanmin(lat)), float(np.nanmax(lat))])
    mission = next((r.mission for r in runs if r.mission is not None), None)
    if mission is not None:
        for label, lon_d, lat_d in waypoints_deg(mission):
            ax.plot(lon_d, lat_d, "^", color="C3", ms=6)
            ax.annotate(label, (lon_d, lat_d), textcoords="offset points", xytext=(4, 4), fontsize=8, color="C3")
            lat_all.append(lat_d)
        for j, rl in enumerate(runway_lines(mission)):
            ax.plot(rl.lon_deg, rl.lat_deg, "-", color="0.3", lw=3, solid_capstyle="butt", zorder=1,
                    label="runways" if j == 0 else None)
            if rl.used:  # the runways the mission flies from or to (the others would crowd the map)
                ax.annotate(f"runway {rl.name.rpartition('_')[2] or rl.name}", (rl.lon_deg[0], rl.lat_deg[0]),
                            textcoords="offset points", xytext=(8, -14), fontsize=8, fontweight="bold",
                            arrowprops={"arrowstyle": "-", "color": "0.3", "lw": 0.8})
        ax.plot([], [], "^", color="C3", label="waypoints")
    mid = 0.5 * (min(lat_all) + max(lat_all))
    ax.set_aspect(1.0 / max(math.cos(math.radians(mid)), 1e-3))
    _distance_scale(ax, mid)
    ax.set_xlabel("longitude [deg]")
    ax.set_ylabel("latitude [deg]")
    ax.set_title("Ground track" + (f": {mission.name}" if mission is not None else ""))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def _distance_scale(ax: Axes, lat_deg: float) -> None:
    """A scale bar of a round number of km (about a fifth of the map's width) in the lower left corner."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    m_per_deg = math.radians(1.0) * R_EARTH_M * math.cos(math.radians(lat_deg))
    target_km = 0.2 * (x1 - x0) * m_per_deg / 1e3
    km = next((k for k in (100, 50, 20, 10, 5, 2, 1, 0.5) if k <= target_km), 0.5)
    dx = km * 1e3 / m_per_deg
    xs, ys = x0 + 0.05 * (x1 - x0), y0 + 0.05 * (y1 - y0)
    ax.plot([xs, xs + dx], [ys, ys], "-", color="k", lw=2.5, solid_capstyle="butt")
    ax.text(xs + dx / 2, ys + 0.012 * (y1 - y0), f"{km:g} km", ha="center", va="bottom", fontsize=8)


def constraint_markers(ax: Axes, runs: Sequence[PlotRun]) -> None:
    """Each section's altitude constraint as a marker at the time the section ended (where the constraint is
    due): a down triangle where the section descended to it, an up triangle where it climbed, a circle
    where it was level; the stretches of a planned hold (vertical mode HOLD) shaded red."""
    from openemss.models.fcs.vertical import VNAV_MODES

    r = _sections(runs)
    if r is None or r.mission is None:
        return
    t, idx = r.data.time_s, np.rint(r.data.get("fcs", "section_index")).astype(int)
    alt = r.data.get("airframe", "alt_m")
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
           decorate: Callable[[Axes, Sequence[PlotRun]], None] | None = None,
           limits: Sequence[Sequence[str]] = ()) -> Path | None:
    """Stacked panels over time. Each panel: (y label, [(role, variable, legend, transform), ...]);
    ``decorate`` draws more on the first panel; ``limits[p]`` names the limits (:data:`.panels.LIMITS`) drawn
    on panel ``p`` as lines, with a mark where the fuel controller engaged them. A legend entry ending in
    "command" is drawn wide, light and under the flown lines, so that both stay visible where they agree."""
    if not any(r.data.get(role, var) is not None for r in runs for _, series in panels for role, var, _, _ in series):
        return None
    colors = signal_colors([(role, var) for _, series in panels for role, var, _, _ in series])  # as the HTML's
    shaded = _sections(runs) if shade else None
    legend_in = 0.0 if shaded is None or shaded.mission is None else \
        0.13 * math.ceil(len(shaded.mission.sections) / 3) + 0.15  # the sections' names below [in]
    fig = Figure(figsize=(10, 2.6 * len(panels) + 0.6 + legend_in))
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for p, (ylabel, series) in enumerate(panels):
        ax = axes[p]
        if shaded is not None:
            shade_sections(ax, shaded, label=p == 0)
        for i, r in enumerate(runs):
            t = r.data.time_s
            keep = slice(None) if window is None else (t >= window[0]) & (t <= window[1])
            for role, var, what, fn in series:
                y = r.data.get(role, var)
                if y is None:
                    continue
                command = "command" in what  # "commanded" too
                ax.plot(t[keep], fn(y)[keep], ls=_style(i), color=colors[(role, var)], lw=3.0 if command else 1.1,
                        alpha=0.45 if command else 1.0, zorder=2.5 if command else 3, label=_label(runs, r, what))
        for name in (limits[p] if p < len(limits) else ()):
            _limit_line(ax, runs, name, window)
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
    if legend_in:
        fig.tight_layout(rect=(0, legend_in / fig.get_figheight(), 1, 1))
        section_legend(fig, shaded)
        return atomic_write(path, figure_bytes(fig, path.suffix.lstrip(".") or "png", dpi=DPI))
    return _save(fig, path)


def _limit_line(ax: Axes, runs: Sequence[PlotRun], name: str, window: tuple[float, float] | None) -> None:
    """A limit as a dashed red line at its value in each run, and an x where the fuel controller engaged it."""
    from .panels import LIMITS, limit_hits, limit_value

    for r in runs:
        v = limit_value(r.data, name)
        if v is None:
            continue
        ax.axhline(v, color="C3", ls=(0, (6, 3)), lw=1.0, zorder=2,
                   label=_label(runs, r, f"{LIMITS[name][1]} {v:g}"))
        hits = limit_hits(r.data, name)
        if window is not None:
            hits = hits[(hits >= window[0]) & (hits <= window[1])]
        if hits.size:
            ax.plot(hits, np.full(hits.shape, v), "x", color="C3", ms=7, mew=1.5, zorder=5,
                    label=_label(runs, r, f"{LIMITS[name][1]} engaged ({hits.size}x)"))


def _ident(y: np.ndarray) -> np.ndarray:
    return y


def _kilo(y: np.ndarray) -> np.ndarray:
    return y / 1e3


def _sfc(y: np.ndarray) -> np.ndarray:
    from .panels import _sfc_shown

    return _sfc_shown(y)


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


class FigureFile(StrEnum):
    """The files of :func:`plot_runs`, by what they show (the report plugin names them before a run)."""

    GROUND_TRACK = "ground_track.png"
    ALTITUDE_MACH = "altitude_mach.png"
    FUEL_BURNED = "fuel_burned.png"
    FUEL_FLOW_TT4 = "fuel_flow_tt4.png"
    THRUST = "thrust.png"
    SPOOL_SPEEDS = "spool_speeds.png"
    SFC_SURGE_MARGIN = "sfc_surge_margin.png"
    ATTITUDE = "attitude.png"
    ELECTRIC = "electric.png"
    LIFE = "life.png"


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
        ground_track(runs, out / FigureFile.GROUND_TRACK),
        _lines(runs, out / FigureFile.ALTITUDE_MACH, "Altitude and Mach, flown and commanded", [
            ("altitude MSL [m]", [("airframe", "alt_m", "flown", _ident), ("fcs", "alt_cmd_m", "commanded",
                                                                                 _ident)]),
            ("Mach [-]", [("airframe", "mach", "flown", _ident), ("fcs", "mach_cmd", "commanded", _ident)]),
            ("airbrake, lever [-]", [("airframe", "airbrake_pos_norm", "airbrake", _ident),
                                     ("fcs", "lever_norm", "thrust lever", _ident)]),
        ], shade=True, decorate=constraint_markers),
        _lines(runs, out / FigureFile.FUEL_BURNED, "Burned fuel", [
            ("burned fuel [kg]", [("engine", "fuel_burned_kg", "burned fuel", _from_start)])], shade=True),
        _lines(runs, out / FigureFile.FUEL_FLOW_TT4, "Fuel flow and Tt4" + (
            f", {window[0]:g} to {window[1]:g} s" if window is not None else ""), [
            ("fuel flow [kg/s]", [("engine", "Wf_kg_s", "fuel flow", _ident),
                                  ("fcs", "Wf_cmd_kg_s", "fuel flow command", _ident)]),
            ("temperature [K]", [("engine", "Tt4_K", "Tt4 burner exit", _ident),
                                 ("engine", "Tt41_K", "Tt41 HPT rotor inlet", _ident)]),
        ], shade=True, window=window, limits=((), ("Tt41_max",))),
        _lines(runs, out / FigureFile.THRUST, "Thrust", [
            ("thrust [kN]", [("engine", "Fn_N", "net thrust", _kilo), ("engine", "Fg_N", "gross thrust",
                                                                          _kilo)])], shade=True),
        _lines(runs, out / FigureFile.SPOOL_SPEEDS, "Spool speeds", [
            ("spool speed [%]", [("engine", "N1_pct", "N1 fan", _ident), ("engine", "N2_pct", "N2 core", _ident),
                                 ("engine", "N1c_pct", "N1c corrected fan speed", _ident)])], shade=True,
            limits=(("N1_max",),)),
        _lines(runs, out / FigureFile.SFC_SURGE_MARGIN, "SFC and surge margins", [
            (SFC_LABEL, [("engine", "SFC_kg_N_s", "SFC", _sfc)]),
            ("surge margin [-]", [("engine", "SM_fan", "fan", _ident), ("engine", "SM_hpc", "HPC", _ident)]),
        ], shade=True),
        _lines(runs, out / FigureFile.ATTITUDE, "Attitude", [
            ("roll phi [deg]", [("airframe", "phi_rad", "phi", _deg)]),
            ("pitch theta [deg]", [("airframe", "theta_rad", "theta", _deg)]),
            ("heading psi [deg]", [("airframe", "psi_rad", "psi", _heading_deg)]),
        ], shade=True),
        _lines(runs, out / FigureFile.ELECTRIC, "Electrical system", [
            ("state of charge [-]", [("electric", "soc", "SOC", _ident)]),
            ("power [kW]", [("electric", "battery_W", "battery to bus", _kilo),
                            ("electric", "offtake_lp_W", "LP shaft offtake (< 0 boost)", _kilo),
                            ("electric", "offtake_hp_W", "HP shaft offtake", _kilo),
                            ("electric", "load_W", "bus load", _kilo)]),
        ], shade=True),
        life_figure(runs, out / FigureFile.LIFE),
    ]
    return [f for f in figures if f is not None]


def plot_variables(runs: Sequence[PlotRun], names: Sequence[str], path: Path,
                   window: tuple[float, float] | None = None) -> Path:
    """Any recorded columns over time, one panel each (any system), labelled with their units."""
    check_window(runs, window)
    fig = Figure(figsize=(10, 1.9 * len(names) + 0.8))
    axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    for ax, name in zip(axes, names, strict=True):
        for i, r in enumerate(runs):
            y = r.data.columns.get(name)
            if y is None:
                continue
            t = r.data.time_s
            keep = slice(None) if window is None else (t >= window[0]) & (t <= window[1])
            ax.plot(t[keep], y[keep], _style(i), lw=1.1, label=_label(runs, r, name))
        unit = runs[0].data.unit(name)
        ax.set_ylabel(f"{name.rpartition('.')[2]} [{unit or '-'}]", fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("time [s]")
    if window is not None:
        axes[-1].set_xlim(*window)
    path.parent.mkdir(parents=True, exist_ok=True)
    return _save(fig, path)
