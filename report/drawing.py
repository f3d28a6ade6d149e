"""What every figure of the report shares: a run to plot, line styles, legend labels, the sections'
shading and the whole-file save (used by :mod:`.plots` and :mod:`.life`, which import nothing of each other)."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from openemss.models.infra.files import figure_bytes
from openemss.models.mission.mission import Mission
from openemss.orchestrator.results import atomic_write

from .agg import Axes, Figure
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
    """Shade each section's time span in alternating tones; with ``label``, number it above the axes (the
    names go in the figure's legend of sections, :func:`section_legend`, so that nothing is overprinted)."""
    from .panels import section_spans

    spans = section_spans(r.data, r.mission)
    if not spans:
        return
    t = r.data.time_s
    width = max(float(t[-1] - t[0]), 1e-9)
    last_x = -math.inf
    for i, a, b in spans:
        ax.axvspan(a, b, color="0.85" if i % 2 else "0.93", zorder=0, lw=0)
        x = 0.5 * (a + b)
        if label and (x - last_x) / width > 0.012:  # numbers closer than 1.2 % of the axis would touch
            ax.text(x, 1.005, str(i), transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=7,
                    color="0.25", clip_on=False)
            last_x = x
