"""The interactive report (issue 17): report.html of a run and of two runs compared, self-contained and
offline, loaded in a real headless browser (Debian's Chromium through Playwright): no console error, no
request leaves the file, the figures are drawn (a screenshot with the plots' pixels), the limits shown.

One run of the shipped system (the Munich mission's first 260 s: take-off, climb, the first N1 limit
hit), and one of the reference study's engine for the comparison. The page must read without hovering
(issue 38): Chromium lays it out and every label's box (legend entries, annotations such as the section
numbers and the limits, axis titles, texts on the ground track, tick labels) is measured: no two overlap;
each time panel has a legend of its own beside it, and no two signals share a colour.
"""
from __future__ import annotations

import re
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.cli.main import main

CHROMIUM = Path("/usr/bin/chromium")
#: Chromium here must not reach for the network (updates, sync, QUIC) and needs no sandbox as root.
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]
STOP_S = "260"


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    base = tmp_path_factory.mktemp("html")
    a, b = base / "larzac", base / "refstudy"
    assert main(["run", "--stop-time", STOP_S, "--out", str(a), "--no-pre-run"]) == 0
    assert main(["run", "--stop-time", STOP_S, "--set", "engine.preset=reference_study", "--out", str(b),
                 "--no-pre-run"]) == 0
    return a, b


BROWSER_BOUND_MS = 300_000


def _load_in_browser(page_path: Path, screenshot: Path) -> dict[str, object]:
    sync_api = pytest.importorskip("playwright.sync_api")
    if not CHROMIUM.is_file():
        pytest.fail(f"{CHROMIUM} missing: apt-get install -y chromium (the CI script installs it)")
    errors: list[str] = []
    outside: list[str] = []
    with sync_api.sync_playwright() as p, tempfile.TemporaryDirectory() as profile:
        ctx = p.chromium.launch_persistent_context(profile, executable_path=str(CHROMIUM), headless=True,
                                                   args=CHROMIUM_ARGS, viewport={"width": 1400, "height": 2400})
        try:
            page = ctx.new_page()
            # bounds, never measurements: a 4 MB page with a dozen plots takes minutes to load on a 2-core machine
            # at load 20 (Playwright's 30 s default failed a clean-clone CI run there)
            page.set_default_timeout(BROWSER_BOUND_MS)
            page.set_default_navigation_timeout(BROWSER_BOUND_MS)
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))

            def route(r: object) -> None:
                url = r.request.url  # type: ignore[attr-defined]
                if url.startswith("file:"):
                    r.continue_()  # type: ignore[attr-defined]
                else:
                    outside.append(url)
                    r.abort()  # type: ignore[attr-defined]

            page.route("**/*", route)
            page.goto(page_path.resolve().as_uri())
            page.wait_for_selector(".js-plotly-plot .main-svg")
            page.wait_for_timeout(1000)
            plots = page.locator(".js-plotly-plot").count()
            traces = page.evaluate("Array.from(document.querySelectorAll('.js-plotly-plot')).map(d => d.data.length)")
            axes = page.evaluate("document.querySelectorAll('.js-plotly-plot')[1].layout.xaxis.matches || 'x'")
            overlaps = page.evaluate(OVERLAPS_JS)
            legends = page.evaluate("Array.from(document.querySelectorAll('.js-plotly-plot')).map("
                                    "d => d.querySelectorAll('.infolayer > g[class^=legend]').length)")
            page.screenshot(path=str(screenshot))
        finally:
            ctx.close()
    return {"errors": errors, "outside": outside, "plots": plots, "traces": traces, "axes": axes,
            "overlaps": overlaps, "legends": legends}


#: Every pair of labels of a figure whose boxes, as Chromium laid them out, overlap by more than a pixel
#: either way: their texts and boxes.
OVERLAPS_JS = """() => {
  const sel = ['.legendtext', '.annotation-text', '.g-xtitle text', '.g-ytitle text', '.gtitle',
               '.textpoint text', '.xtick text', '.ytick text'].join(',');
  const out = [];
  for (const plot of document.querySelectorAll('.js-plotly-plot')) {
    const boxes = [];
    for (const el of plot.querySelectorAll(sel)) {
      const r = el.getBoundingClientRect();
      if (r.width < 1 || r.height < 1 || !el.textContent.trim()) continue;
      if (getComputedStyle(el).visibility === 'hidden' || getComputedStyle(el).opacity === '0') continue;
      boxes.push({t: el.textContent, l: r.left, r: r.right, top: r.top, b: r.bottom});
    }
    for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
      const a = boxes[i], c = boxes[j];
      const w = Math.min(a.r, c.r) - Math.max(a.l, c.l), h = Math.min(a.b, c.b) - Math.max(a.top, c.top);
      if (w > 1 && h > 1) out.push([a.t, c.t, Math.round(w), Math.round(h)]);
    }
  }
  return out;
}"""


def _time_panels(page: Path) -> list[str]:
    """The y axes of the time figure, from the page's figure JSON (one per panel)."""
    text = page.read_text(encoding="utf-8")
    return sorted(set(re.findall(r'"(yaxis\d*)":\{', text)))


def test_signals_have_colours_of_their_own_and_commands_lie_under_what_is_flown() -> None:
    """No two signals of the time panels share a colour; in a panel, the commands' traces come first (drawn
    under the flown lines), wider and lighter."""
    from openemss.report.html import COLORS, LIMIT_COLOR, _signal_colors
    from openemss.report.panels import TIME_PANELS, is_command

    colors = _signal_colors(TIME_PANELS)
    assert len(set(colors.values())) == len(colors) == sum(len(p.series) for p in TIME_PANELS)
    assert LIMIT_COLOR not in COLORS
    assert any(is_command(s) for p in TIME_PANELS for s in p.series)


def _drawn(png: Path) -> float:
    """Fraction of the screenshot's pixels that are neither white nor near-white (the figures' lines, bands)."""
    from matplotlib.image import imread

    img = imread(str(png))[..., :3]
    return float(np.mean(np.any(img < 0.9, axis=-1)))


def test_report_of_a_run_is_self_contained_and_loads_without_error(runs: tuple[Path, Path], tmp_path: Path) -> None:
    page = runs[0] / "report.html"
    text = page.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]+src=|<link[^>]+href=", text)  # nothing fetched: plotly.js is inline
    assert "Ground track" in text and "N1 limit" in text and "Tt41 limit" in text
    shot = tmp_path / "report.png"
    seen = _load_in_browser(page, shot)
    assert seen["errors"] == [] and seen["outside"] == []
    assert seen["overlaps"] == [], seen["overlaps"]  # type: ignore[comparison-overlap]
    assert seen["plots"] == 2  # the ground track, and the time panels on one shared time axis
    assert seen["legends"][1] == len(_time_panels(page))  # type: ignore[index]  # one legend per panel
    assert seen["traces"][1] >= 15  # type: ignore[index]
    assert _drawn(shot) > 0.02  # a page of text alone: about 0.005
    keep = Path(tempfile.gettempdir()) / "emss-report-screenshot.png"  # for a look after the test
    shutil.copy2(shot, keep)


def test_comparison_report_of_two_runs(runs: tuple[Path, Path], tmp_path: Path) -> None:
    out = tmp_path / "cmp"
    assert main(["plot", str(runs[0]), str(runs[1]), "--out", str(out)]) == 0
    assert (out / "report.html").is_file() and (out / "thrust.png").is_file()
    seen = _load_in_browser(out / "report.html", tmp_path / "cmp.png")
    assert seen["errors"] == [] and seen["outside"] == []
    assert seen["overlaps"] == [], seen["overlaps"]  # type: ignore[comparison-overlap]
    one = _load_in_browser(runs[0] / "report.html", tmp_path / "one.png")
    assert seen["traces"][1] > one["traces"][1]  # type: ignore[index]  # both runs' lines


def test_the_run_folder_stays_small(runs: tuple[Path, Path]) -> None:
    """The mission's results folder at most 30 MB (issue 17): here 260 s of it, scaled to the whole 3302 s."""
    size = sum(f.stat().st_size for f in runs[0].rglob("*") if f.is_file())
    series = sum(f.stat().st_size for f in (runs[0] / "timeseries.parquet").rglob("*") if f.is_file())
    whole = size - series + series * 3302.0 / float(STOP_S)
    assert whole < 30e6, (size, series)


def test_png_figures_colour_each_signal_as_the_html_report(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every line of the PNG figures over time has its signal's colour of the HTML report (panels.signal_colors):
    no two signals of a figure share one, none is the limits' red, and a signal of both reports has the same
    colour in both (the PNGs drew each panel's lines from matplotlib's C0, C1, ..., so Tt4 was the fuel flow's
    blue, and a fourth line the limits' red)."""
    from matplotlib.colors import to_hex
    from synthetic_runs import N, Runs

    from openemss.report import plots
    from openemss.report.html import LIMIT_COLOR, _signal_colors
    from openemss.report.panels import TIME_PANELS
    from openemss.report.rundata import load_mission, load_run

    cols = {"engine.Tt41_K": np.full(N, 1100.0), "engine.Fn_N": np.full(N, 5e3), "engine.Fg_N": np.full(N, 6e3),
            "engine.SM_fan": np.full(N, 0.2), "engine.SM_hpc": np.full(N, 0.3), "engine.SFC_kg_N_s": np.full(N, 2e-5),
            "fcs.Wf_cmd_kg_s": np.full(N, 0.12), "engine.N1c_pct": np.full(N, 88.0), "fcs.lever_norm": np.full(N, 0.8),
            "airframe.airbrake_pos_norm": np.zeros(N)}
    run = load_run(Runs(tmp_path).make(columns=cols))
    drawn: dict[str, list[tuple[str, str]]] = {}
    real = plots.Figure

    class Spy(real):  # type: ignore[misc, valid-type]
        def savefig(self, fname, *a, **kw):  # noqa: ANN001, ANN002, ANN003, ANN202
            if self.axes and self.axes[-1].get_xlabel() == "time [s]":  # the figures over time
                drawn[Path(str(fname)).name if isinstance(fname, (str, Path)) else str(len(drawn))] = [
                    (ln.get_label(), to_hex(ln.get_color())) for ax in self.axes for ln in ax.get_lines()
                    if not ln.get_label().startswith("_") and ln.get_linestyle() != "None"]
            return super().savefig(fname, *a, **kw)

    monkeypatch.setattr(plots, "Figure", Spy)
    plots.plot_runs([plots.PlotRun(run, load_mission(run)[0], "run")], tmp_path / "png")
    html = {s.legend: c for p in TIME_PANELS for s in p.series
            for (role, var), c in _signal_colors(TIME_PANELS).items() if (s.role, s.variable) == (role, var)}
    assert len(drawn) >= 6
    seen = 0
    for lines in drawn.values():
        signal_lines = [(label, c) for label, c in lines if "limit" not in label]
        colours = [c for _, c in signal_lines]
        assert len(set(colours)) == len(colours), lines
        assert to_hex(LIMIT_COLOR) not in colours and "#d62728" not in colours, lines  # the limits' reds
        seen += len(signal_lines)
    assert seen >= 15
    # the same signal, the same colour: Tt4 and the fuel flow as in the HTML report
    png = {label: c for lines in drawn.values() for label, c in lines}
    assert png["Tt4 burner exit"] == html["Tt4 burner exit"]
    assert png["fuel flow"] == html["fuel flow (engine)"]
    assert png["fuel flow"] != png["Tt4 burner exit"]
