"""The interactive report of a mission run, or of runs compared: one self-contained, offline HTML file.

Plotly figures (zoom, pan, hover; the time panels share one time axis) with plotly.js inlined in the
page, so it opens without a network (no CDN, no map tiles: the ground track is drawn on latitude and
longitude axes at the true aspect ratio, with the waypoints, the runways, the runway used, start and end).

Long runs are thinned for the page only: each line keeps at most :data:`MAX_POINTS` points, taken as
the first, minimum, maximum and last sample of equal time buckets, so that peaks (a limit hit, a spike)
survive the thinning; the files on disk keep every sample.
"""
from __future__ import annotations

import html
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from openemss.orchestrator.results import atomic_write

from .panels import LIMITS, TIME_PANELS, limit_hits, limit_value, runway_lines, section_spans, values, waypoints_deg
from .plots import PlotRun

MAX_POINTS = 4000  #: points per line in the page at most
DASHES = ("solid", "dash", "dot", "dashdot")
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b")
REPORT = "report.html"


def thin(t: np.ndarray, y: np.ndarray, max_points: int = MAX_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """At most about ``max_points`` samples of (t, y): per bucket its first, minimum, maximum and last sample,
    in time order (so extremes are kept exactly)."""
    n = len(t)
    if n <= max_points:
        return t, y
    buckets = max(max_points // 4, 1)
    edges = np.linspace(0, n, buckets + 1).astype(int)
    keep: list[int] = []
    finite = np.where(np.isfinite(y), y, 0.0)
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        if b <= a:
            continue
        seg = finite[a:b]
        keep.extend(sorted({a, a + int(np.argmin(seg)), a + int(np.argmax(seg)), b - 1}))
    idx = np.array(keep, dtype=np.intp)
    return t[idx], y[idx]


def _float_list(a: np.ndarray) -> list[float | None]:
    return [None if not math.isfinite(v) else round(float(v), 6) for v in a]


def ground_track_figure(runs: Sequence[PlotRun]) -> object | None:
    """Latitude over longitude of each run, with the mission's waypoints and runways."""
    import plotly.graph_objects as go

    drawn = [r for r in runs if r.data.get("airframe", "lat_deg") is not None]
    if not drawn:
        return None
    fig = go.Figure()
    lats: list[float] = []
    for i, r in enumerate(drawn):
        lat, lon = r.data.get("airframe", "lat_deg"), r.data.get("airframe", "lon_deg")
        t = r.data.time_s
        tt, la = thin(t, lat)
        _, lo = thin(t, lon)
        fig.add_trace(go.Scatter(x=_float_list(lo), y=_float_list(la), mode="lines", name=r.label,
                                 line={"color": COLORS[i % len(COLORS)], "dash": DASHES[i % len(DASHES)]},
                                 customdata=_float_list(tt), hovertemplate="t = %{customdata:.1f} s<br>"
                                 "lat %{y:.5f} deg<br>lon %{x:.5f} deg<extra>" + html.escape(r.label) + "</extra>"))
        fig.add_trace(go.Scatter(x=[float(lon[0]), float(lon[-1])], y=[float(lat[0]), float(lat[-1])],
                                 mode="markers+text", text=["start", "end"], textposition="top right",
                                 marker={"symbol": ["circle", "square"], "size": 9,
                                         "color": COLORS[i % len(COLORS)]},
                                 name=f"start, end ({r.label})", showlegend=len(drawn) > 1 or i == 0))
        lats.extend([float(np.nanmin(lat)), float(np.nanmax(lat))])
    mission = next((r.mission for r in runs if r.mission is not None), None)
    if mission is not None:
        places = waypoints_deg(mission)
        xs, ys, names = [p[1] for p in places], [p[2] for p in places], [p[0] for p in places]
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="markers+text", text=names, textposition="top center",
                                 marker={"symbol": "triangle-up", "size": 9, "color": "#d62728"}, name="waypoints"))
        lats.extend(ys)
        for j, rl in enumerate(runway_lines(mission)):
            fig.add_trace(go.Scatter(x=list(rl.lon_deg), y=list(rl.lat_deg), mode="lines+text" if rl.used else "lines",
                                     text=[f"runway {rl.name} (used)", ""] if rl.used else None,
                                     textposition="bottom right", line={"color": "#444", "width": 5},
                                     name="runways", legendgroup="runways", showlegend=j == 0,
                                     hovertext=f"runway {rl.name}", hoverinfo="text"))
    mid = 0.5 * (min(lats) + max(lats))
    fig.update_yaxes(title="latitude [deg]", scaleanchor="x", scaleratio=1.0 / max(math.cos(math.radians(mid)), 1e-3))
    fig.update_xaxes(title="longitude [deg]")
    fig.update_layout(title="Ground track" + (f": {html.escape(mission.name)}" if mission is not None else ""),
                      height=650, template="plotly_white", legend={"orientation": "h"})
    return fig


def time_figure(runs: Sequence[PlotRun]) -> object | None:
    """Every panel of :data:`.panels.TIME_PANELS` the runs recorded, stacked on one shared time axis, with
    the sections as numbered bands, the limits as lines and the times the limiter engaged them as marks."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    panels = [p for p in TIME_PANELS if any(values(r.data, s) is not None for r in runs for s in p.series)]
    if not panels:
        return None
    fig = make_subplots(rows=len(panels), cols=1, shared_xaxes=True, vertical_spacing=0.012,
                        subplot_titles=[p.ylabel for p in panels])
    for row, p in enumerate(panels, start=1):
        for i, r in enumerate(runs):
            for c, s in enumerate(p.series):
                y = values(r.data, s)
                if y is None:
                    continue
                tt, yy = thin(r.data.time_s, y)
                name = s.legend if len(runs) == 1 else f"{s.legend} ({r.label})"
                command = "command" in s.legend and len(runs) == 1  # dashed, on top: visible under its result
                fig.add_trace(go.Scattergl(x=_float_list(tt), y=_float_list(yy), mode="lines", name=name,
                                           legendgroup=p.key, line={"color": COLORS[c % len(COLORS)],
                                                                    "dash": "dash" if command else
                                                                    DASHES[i % len(DASHES)],
                                                                    "width": 2.0 if command else 1.3}),
                              row=row, col=1)
        for name in p.limits:
            for r in runs:
                v = limit_value(r.data, name)
                if v is None:
                    continue
                fig.add_hline(y=v, line={"color": "#d62728", "dash": "dash", "width": 1}, row=row, col=1,
                              annotation_text=f"{LIMITS[name][1]} {v:g}" + (f" ({r.label})" if len(runs) > 1 else ""),
                              annotation_position="top left", annotation_font_size=10)
                hits = limit_hits(r.data, name)
                if hits.size:
                    fig.add_trace(go.Scatter(x=_float_list(hits), y=[v] * len(hits), mode="markers",
                                             marker={"symbol": "x", "size": 8, "color": "#d62728"},
                                             name=f"{LIMITS[name][1]} engaged ({len(hits)}x)"
                                             + (f" ({r.label})" if len(runs) > 1 else "")), row=row, col=1)
        fig.update_yaxes(title_text=p.ylabel.split(" [")[0], row=row, col=1)
    _section_bands(fig, runs)
    fig.update_xaxes(title_text="time [s]", row=len(panels), col=1)
    fig.update_layout(height=230 * len(panels) + 120, template="plotly_white", hovermode="x unified",
                      legend={"tracegroupgap": 4, "font": {"size": 10}},
                      title="Over time (one time axis: zoom in any panel; double-click to reset)")
    return fig


def _section_bands(fig: object, runs: Sequence[PlotRun]) -> None:
    """The first run's mission sections as alternating bands over every panel, numbered at the top."""
    r = next((r for r in runs if r.data.get("fcs", "section_index") is not None), None)
    if r is None:
        return
    names = {s.index: s.name for s in r.mission.sections} if r.mission is not None else {}
    for idx, a, b in section_spans(r.data):
        fig.add_vrect(x0=a, x1=b, fillcolor="#888" if idx % 2 else "#ccc", opacity=0.12, line_width=0, layer="below",
                      annotation_text=str(idx), annotation_position="top left", annotation_font_size=9,
                      annotation_hovertext=f"section {idx}: {names.get(idx, '')}", row=1, col=1)
        fig.add_vrect(x0=a, x1=b, fillcolor="#888" if idx % 2 else "#ccc", opacity=0.12, line_width=0,
                      layer="below", row="all", col=1, exclude_empty_subplots=False)


def _sections_table(runs: Sequence[PlotRun]) -> str:
    r = next((r for r in runs if r.mission is not None), None)
    if r is None:
        return ""
    spans: dict[int, list[float]] = {}
    for idx, a, b in section_spans(r.data):
        s = spans.setdefault(idx, [a, b])
        s[1] = b
    rows = "".join(f"<tr><td>{s.index}</td><td>{html.escape(str(s.name))}</td><td>{html.escape(str(s.type))}</td>"
                   f"<td>{'' if s.index not in spans else f'{spans[s.index][0]:.1f}'}</td>"
                   f"<td>{'' if s.index not in spans else f'{spans[s.index][1]:.1f}'}</td></tr>"
                   for s in r.mission.sections)
    return ("<h2>Mission sections (bands in the time panels)</h2><table><tr><th>#</th><th>name</th><th>type</th>"
            f"<th>start [s]</th><th>end [s]</th></tr>{rows}</table>")


def _summary_lines(runs: Sequence[PlotRun]) -> str:
    out = []
    for r in runs:
        info = r.data.info
        fuel = r.data.get("engine", "fuel_burned_kg")
        burned = f"{fuel[-1] - fuel[0]:.2f} kg fuel" if fuel is not None else ""
        out.append(f"<li><b>{html.escape(r.label)}</b>: {html.escape(str(info.get('status', '?')))}, "
                   f"t = {r.data.time_s[-1]:.1f} s, {burned}</li>")
    return "<ul>" + "".join(out) + "</ul>"


def write_html_report(runs: Sequence[PlotRun], path: Path) -> Path | None:
    """Write the report of one run (or of runs compared) to ``path``; None when nothing can be drawn."""
    import plotly.io as pio
    from plotly.offline import get_plotlyjs

    figures = [f for f in (ground_track_figure(runs), time_figure(runs)) if f is not None]
    if not figures:
        return None
    divs = "\n".join(pio.to_html(f, include_plotlyjs=False, full_html=False, config={"displaylogo": False})
                     for f in figures)
    title = "openEMSS: " + " vs ".join(r.label for r in runs)
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>body{{font-family:sans-serif;margin:1em 2em}} table{{border-collapse:collapse;font-size:12px}}
td,th{{border:1px solid #ccc;padding:2px 6px}}</style>
<script type="text/javascript">{get_plotlyjs()}</script></head>
<body><h1>{html.escape(title)}</h1>{_summary_lines(runs)}
<p>Lines: {", ".join(f"{html.escape(r.label)} {DASHES[i % len(DASHES)]}" for i, r in enumerate(runs))}. Each line
shows at most {MAX_POINTS} points (minimum and maximum of each time bucket kept); the results folder holds every
sample.</p>
{divs}
{_sections_table(runs)}
</body></html>
"""
    return atomic_write(path, page)


def variables_figure(runs: Sequence[PlotRun], names: Sequence[str]) -> object:
    """Any recorded columns over time, one panel each on a shared time axis (any system, not only missions)."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=len(names), cols=1, shared_xaxes=True, vertical_spacing=0.02)
    for row, name in enumerate(names, start=1):
        for i, r in enumerate(runs):
            y = r.data.columns.get(name)
            if y is None:
                continue
            tt, yy = thin(r.data.time_s, y)
            fig.add_trace(go.Scattergl(x=_float_list(tt), y=_float_list(yy), mode="lines",
                                       name=name if len(runs) == 1 else f"{name} ({r.label})",
                                       line={"color": COLORS[(row - 1) % len(COLORS)],
                                             "dash": DASHES[i % len(DASHES)]}),
                          row=row, col=1)
        unit = runs[0].data.unit(name)
        fig.update_yaxes(title_text=f"{name} [{unit or '-'}]", row=row, col=1)
    fig.update_xaxes(title_text="time [s]", row=len(names), col=1)
    fig.update_layout(height=220 * len(names) + 120, template="plotly_white", hovermode="x unified")
    return fig


def write_variables_html(runs: Sequence[PlotRun], names: Sequence[str], path: Path) -> Path:
    """A self-contained page of :func:`variables_figure`."""
    import plotly.io as pio

    fig = variables_figure(runs, names)
    return atomic_write(path, pio.to_html(fig, include_plotlyjs=True, full_html=True, config={"displaylogo": False}))
