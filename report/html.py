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

from .panels import (
    COLORS,
    LIMITS,
    TIME_PANELS,
    Panel,
    is_command,
    limit_hits,
    limit_value,
    runway_lines,
    section_spans,
    signal_colors,
    values,
    waypoints_deg,
)
from .plots import PlotRun

MAX_POINTS = 4000  #: points per line in the page at most
DASHES = ("solid", "dash", "dot", "dashdot")
#: The limits' colour (none of :data:`.panels.COLORS`).
LIMIT_COLOR = "#FB0D0D"
REPORT = "report.html"
#: Least distance between two section numbers over the time axis, as a fraction of it (two digits at 9 px on
#: a plot about 1000 px wide take about 1.4 %); closer numbers go to a second row, then are left out (the
#: sections' table below the figures names every section).
BAND_LABEL_GAP = 0.02


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
                                 mode="markers", marker={"symbol": ["circle", "square-open"], "size": 10,
                                                         "color": COLORS[i % len(COLORS)]},
                                 name=f"start (circle), end (square): {r.label}", hovertext=["start", "end"],
                                 hoverinfo="text"))
        lats.extend([float(np.nanmin(lat)), float(np.nanmax(lat))])
    mission = next((r.mission for r in runs if r.mission is not None), None)
    if mission is not None:
        places = waypoints_deg(mission)
        xs, ys, names = [p[1] for p in places], [p[2] for p in places], [p[0] for p in places]
        lons = [float(v) for r in drawn for v in (np.nanmin(r.data.get("airframe", "lon_deg")),
                                                  np.nanmax(r.data.get("airframe", "lon_deg")))]
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="markers+text", text=names,
                                 textposition=label_positions(xs, ys, names, lons + xs, lats + ys),
                                 marker={"symbol": "triangle-up", "size": 9, "color": "#d62728"}, name="waypoints"))
        lats.extend(ys)
        for rl in runway_lines(mission):  # named in the legend: a name on the map would cross the track
            fig.add_trace(go.Scatter(x=list(rl.lon_deg), y=list(rl.lat_deg), mode="lines",
                                     line={"color": "#000" if rl.used else "#999", "width": 5},
                                     name=f"runway {rl.name} (used)" if rl.used else "runways",
                                     legendgroup=rl.name if rl.used else "runways",
                                     showlegend=rl.used or not any(o.name == "runways" for o in fig.data),
                                     hovertext=f"runway {rl.name}", hoverinfo="text"))
    mid = 0.5 * (min(lats) + max(lats))
    fig.update_yaxes(title="latitude [deg]", scaleanchor="x", scaleratio=1.0 / max(math.cos(math.radians(mid)), 1e-3))
    fig.update_xaxes(title="longitude [deg]")
    fig.update_layout(title="Ground track" + (f": {html.escape(mission.name)}" if mission is not None else ""),
                      height=650, template="plotly_white", legend={"orientation": "h"})
    return fig


def _signal_colors(panels: Sequence[Panel]) -> dict[tuple[str, str], str]:
    """One colour per signal (none shared between panels), the same in every report and in the PNG figures
    (:func:`.panels.signal_colors`)."""
    return signal_colors([(s.role, s.variable) for p in panels for s in p.series])


def _legend_key(row: int) -> str:
    return "legend" if row == 1 else f"legend{row}"


#: The ground track's plot area as laid out [px] (650 px high figure, a page about 1400 px wide), and the size
#: of a label's character and line at 12 px: enough to place the waypoints' numbers apart.
MAP_PX = (1100.0, 450.0)
CHAR_PX, LINE_PX = 7.5, 15.0


def label_positions(xs: Sequence[float], ys: Sequence[float], texts: Sequence[str], all_lon: Sequence[float],
                    all_lat: Sequence[float]) -> list[str]:
    """A text position per waypoint (above, below, right or left of its marker) so that no label covers
    another label or another waypoint's marker, on the map's scale at its true aspect ratio (:data:`MAP_PX`)."""
    lat0, lat1 = min(all_lat), max(all_lat)
    k = math.cos(math.radians(0.5 * (lat0 + lat1)))
    span_y = max(lat1 - lat0, 1e-6)
    span_x = max((max(all_lon) - min(all_lon)) * k, 1e-6)
    px = min(MAP_PX[0] / span_x, MAP_PX[1] / span_y)  # px per degree of latitude
    pts = [(x * k * px, y * px) for x, y in zip(xs, ys, strict=True)]
    boxes = [(x - 6, x + 6, y - 6, y + 6) for x, y in pts]  # the markers
    out = []
    for (x, y), text in zip(pts, texts, strict=True):
        w, h = CHAR_PX * len(text), LINE_PX
        options = {"top center": (x - w / 2, x + w / 2, y + 6, y + 6 + h),
                   "bottom center": (x - w / 2, x + w / 2, y - 6 - h, y - 6),
                   "middle right": (x + 7, x + 7 + w, y - h / 2, y + h / 2),
                   "middle left": (x - 7 - w, x - 7, y - h / 2, y + h / 2)}
        free = [name for name, b in options.items()
                if not any(b[0] < o[1] and o[0] < b[1] and b[2] < o[3] and o[2] < b[3] for o in boxes
                           if o != (x - 6, x + 6, y - 6, y + 6))]
        pos = free[0] if free else "top center"
        boxes.append(options[pos])
        out.append(pos)
    return out


def time_figure(runs: Sequence[PlotRun]) -> object | None:
    """Every panel of :data:`.panels.TIME_PANELS` the runs recorded, stacked on one shared time axis, each with
    its own legend beside it and its own colours; the sections as numbered bands, the limits as lines and the
    times the limiter engaged them as marks. Commands are drawn first, wide and light, so that what is flown
    is drawn over them."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    panels = [p for p in TIME_PANELS if any(values(r.data, s) is not None for r in runs for s in p.series)]
    if not panels:
        return None
    fig = make_subplots(rows=len(panels), cols=1, shared_xaxes=True, vertical_spacing=0.012)
    colors = _signal_colors(panels)
    for row, p in enumerate(panels, start=1):
        legend = _legend_key(row)
        order = sorted(((i, r, s) for i, r in enumerate(runs) for s in p.series), key=lambda e: not is_command(e[2]))
        for i, r, s in order:  # commands first: under what is flown
            y = values(r.data, s)
            if y is None:
                continue
            tt, yy = thin(r.data.time_s, y)
            command = is_command(s)
            fig.add_trace(go.Scattergl(x=_float_list(tt), y=_float_list(yy), mode="lines", legend=legend,
                                       name=s.legend if len(runs) == 1 else f"{s.legend} ({r.label})",
                                       opacity=0.45 if command else 1.0,
                                       line={"color": colors[(s.role, s.variable)], "dash": DASHES[i % len(DASHES)],
                                             "width": 3.5 if command else 1.3}), row=row, col=1)
        _limits(fig, runs, p, row)
        fig.update_yaxes(title_text=p.ylabel, title_font_size=11, row=row, col=1)
    _section_bands(fig, runs)
    fig.update_xaxes(title_text="time [s]", row=len(panels), col=1)
    legends = {}
    for row in range(1, len(panels) + 1):
        domain = fig.layout[f"yaxis{'' if row == 1 else row}"].domain
        legends[_legend_key(row)] = {"x": 1.01, "xanchor": "left", "y": domain[1], "yanchor": "top",
                                     "font": {"size": 10}, "bgcolor": "rgba(255,255,255,0.8)"}
    fig.update_layout(height=230 * len(panels) + 120, template="plotly_white", hovermode="x unified",
                      margin={"r": 230}, title="Over time (one time axis: zoom in any panel; double-click to reset)",
                      **legends)
    return fig


def _limits(fig: object, runs: Sequence[PlotRun], p: Panel, row: int) -> None:
    """The panel's limits: one dashed line per value (one label naming the runs that share it, labels of
    different values at alternate ends of the axis) and an x where the fuel controller engaged it."""
    import plotly.graph_objects as go

    for name in p.limits:
        by_value: dict[float, list[str]] = {}
        for r in runs:
            v = limit_value(r.data, name)
            if v is not None:
                by_value.setdefault(v, []).append(r.label)
        for j, (v, labels) in enumerate(by_value.items()):
            whose = f" ({', '.join(labels)})" if len(runs) > 1 else ""
            fig.add_hline(y=v, line={"color": LIMIT_COLOR, "dash": "dash", "width": 1}, row=row, col=1,
                          annotation_text=f"{LIMITS[name][1]} {v:g}{whose}", annotation_font_size=10,
                          annotation_position=("top left", "top right", "bottom left", "bottom right")[j % 4])
        for r in runs:
            v = limit_value(r.data, name)
            hits = limit_hits(r.data, name)
            if v is None or not hits.size:
                continue
            fig.add_trace(go.Scatter(x=_float_list(hits), y=[v] * len(hits), mode="markers", legend=_legend_key(row),
                                     marker={"symbol": "x", "size": 8, "color": LIMIT_COLOR},
                                     name=f"{LIMITS[name][1]} engaged ({len(hits)}x)"
                                     + (f" ({r.label})" if len(runs) > 1 else "")), row=row, col=1)


def _section_bands(fig: object, runs: Sequence[PlotRun]) -> None:
    """The first run's mission sections as alternating bands over every panel, numbered as the mission
    numbers them at the top of the first panel (numbers that would touch go to a second row, or are left
    out: the table names every section)."""
    r = next((r for r in runs if r.data.get("fcs", "section_index") is not None), None)
    if r is None:
        return
    names = {s.index: s.name for s in r.mission.sections} if r.mission is not None else {}
    spans = section_spans(r.data, r.mission)
    t = r.data.time_s
    width = max(float(t[-1] - t[0]), 1e-9)
    last = [-math.inf, -math.inf]  # the last number placed in each of the two rows
    for idx, a, b in spans:
        fig.add_vrect(x0=a, x1=b, fillcolor="#888" if idx % 2 else "#ccc", opacity=0.12, line_width=0,
                      layer="below", row="all", col=1, exclude_empty_subplots=False)
        x = 0.5 * (a + b)
        level = next((k for k in (0, 1) if (x - last[k]) / width > BAND_LABEL_GAP), None)
        if level is None:
            continue
        last[level] = x
        fig.add_annotation(x=x, y=1.0, xref="x", yref="y domain", yanchor="top", showarrow=False,
                           yshift=-12 * level, text=str(idx), font={"size": 9, "color": "#333"},
                           hovertext=f"section {idx}: {html.escape(str(names.get(idx, '')))}")


def _sections_table(runs: Sequence[PlotRun]) -> str:
    """The mission's sections: number (as on the bands), name, type, and per run start, end and fuel burned."""
    from .summary import sections_table

    r = next((r for r in runs if r.mission is not None), None)
    if r is None:
        return ""
    tables = []
    for run in runs:
        idx, wf = run.data.get("fcs", "section_index"), run.data.get("engine", "Wf_kg_s")
        tables.append({} if idx is None or wf is None else {
            row["index"]: row for row in sections_table(run.data.time_s, idx, wf, None, False)})
    several = len(runs) > 1

    def cells(row: dict[str, object] | None) -> str:
        if row is None or row["start_time_s"] is None:
            return "<td></td><td></td><td></td>"
        return (f"<td>{row['start_time_s']:.1f}</td><td>{row['end_time_s']:.1f}</td>"
                f"<td>{row['fuel_burned_kg']:.2f}</td>")

    head = "".join(f"<th>start [s]{f' ({html.escape(x.label)})' if several else ''}</th><th>end [s]</th>"
                   f"<th>fuel [kg]</th>" for x in runs)
    rows = "".join(f"<tr><td>{s.index}</td><td>{html.escape(str(s.name))}</td><td>{html.escape(str(s.type))}</td>"
                   + "".join(cells(t.get(s.index)) for t in tables) + "</tr>" for s in r.mission.sections)
    return ("<h2>Mission sections (numbered as the bands in the time panels)</h2><table><tr><th>#</th><th>name</th>"
            f"<th>type</th>{head}</tr>{rows}</table>")


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

    from .life import life_html

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
{life_html(runs)}
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
