"""What the run reports show over time: panels of signals found by role, and the engine's limits.

One list for the static plots (:mod:`.plots`) and the interactive report (:mod:`.html`), so both show
the same quantities under the same names.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from openemss.models.mission.geo import from_local_ne
from openemss.models.mission.mission import Mission

from .rundata import RunData, parameter_float


@dataclass(frozen=True)
class Series:
    """One line: the column ``<component of role>.variable``, its legend and a transform for display."""

    role: str
    variable: str
    legend: str
    transform: Callable[[np.ndarray], np.ndarray] | None = None


@dataclass(frozen=True)
class Panel:
    """A panel over time: its y label with the unit, its lines, and the limits drawn on it."""

    key: str
    ylabel: str
    series: tuple[Series, ...]
    limits: tuple[str, ...] = ()  # names in LIMITS


def _deg(y: np.ndarray) -> np.ndarray:
    return np.degrees(y)


def _mg_per_N_s(y: np.ndarray) -> np.ndarray:
    return y * 1e6


def heading_deg(y: np.ndarray) -> np.ndarray:
    """Heading in [0, 360) deg with a gap (NaN) where it wraps, so no line joins 359 and 0."""
    h = np.mod(np.degrees(y), 360.0)
    out = h.copy()
    out[1:][np.abs(np.diff(h)) > 180.0] = np.nan
    return out


#: SFC is shown below this [mg/(N s)]: near zero thrust it grows without bound (and means nothing).
SFC_SHOWN_MAX_MG_N_S = 200.0
SFC_LABEL = f"SFC [mg/(N s)], shown below {SFC_SHOWN_MAX_MG_N_S:g}"


def _sfc_shown(y: np.ndarray) -> np.ndarray:
    """SFC [mg/(N s)], blank where the engine gives no meaningful value (no thrust: SFC <= 0 or above
    :data:`SFC_SHOWN_MAX_MG_N_S`); the axis says so (:data:`SFC_LABEL`)."""
    v = y * 1e6
    return np.where((v > 0) & (v < SFC_SHOWN_MAX_MG_N_S), v, np.nan)


#: The limits a panel may draw: name -> (FCS parameter holding it, legend, the signal it limits).
LIMITS = {
    "Tt41_max": ("fuel_control.Tt41_max_K", "Tt41 limit", ("engine", "Tt41_K")),
    "N1_max": ("fuel_control.N1_max_pct", "N1 limit", ("engine", "N1_pct")),
}

TIME_PANELS = (
    Panel("altitude", "altitude MSL [m]", (Series("airframe", "alt_m", "flown"),
                                           Series("fcs", "alt_cmd_m", "commanded"))),
    Panel("mach", "Mach [-]", (Series("airframe", "mach", "flown"), Series("fcs", "mach_cmd", "commanded"))),
    Panel("thrust", "net thrust [kN]", (Series("engine", "Fn_N", "net thrust", lambda y: y / 1e3),
                                        Series("engine", "Fg_N", "gross thrust", lambda y: y / 1e3))),
    Panel("fuel_flow", "fuel flow [kg/s]", (Series("engine", "Wf_kg_s", "fuel flow (engine)"),
                                            Series("fcs", "Wf_cmd_kg_s", "fuel flow command (FCS)"))),
    Panel("temperatures", "temperature [K]", (Series("engine", "Tt4_K", "Tt4 burner exit"),
                                              Series("engine", "Tt41_K", "Tt41 HPT rotor inlet")), ("Tt41_max",)),
    Panel("spools", "spool speed [%]", (Series("engine", "N1_pct", "N1 fan"), Series("engine", "N2_pct", "N2 core"),
                                        Series("engine", "N1c_pct", "N1c corrected fan speed")), ("N1_max",)),
    Panel("surge", "surge margin [-]", (Series("engine", "SM_fan", "fan"), Series("engine", "SM_hpc", "HPC"))),
    Panel("sfc", SFC_LABEL, (Series("engine", "SFC_kg_N_s", "SFC", _sfc_shown),)),
    Panel("lever", "airbrake, lever [-]", (Series("airframe", "airbrake_pos_norm", "airbrake"),
                                           Series("fcs", "lever_norm", "thrust lever"))),
    Panel("attitude", "attitude [deg]", (Series("airframe", "phi_rad", "roll phi", _deg),
                                         Series("airframe", "theta_rad", "pitch theta", _deg))),
    Panel("heading", "heading [deg]", (Series("airframe", "psi_rad", "heading psi", heading_deg),)),
)

#: Run colours of the ground track, and the signals' colours over time, one per signal of the reports (none
#: shared, the HTML report's and the PNG figures' the same): tab10 without its red (the limits' colour) and
#: darker or lighter shades of tab20b/c, ordered so that the two or three signals of a panel, which take
#: consecutive entries, differ in hue.
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#17becf", "#393b79", "#bcbd22", "#e377c2",
          "#637939", "#3182bd", "#8c6d31", "#7b4173", "#31a354", "#843c39", "#636363", "#fd8d3c", "#756bb1",
          "#6baed6", "#7f7f7f", "#e6550d", "#000000", "#5254a3", "#b5cf6b", "#e7ba52")


def signal_colors(extra: Sequence[tuple[str, str]] = ()) -> dict[tuple[str, str], str]:
    """One colour per signal ``(role, variable)``: those of :data:`TIME_PANELS` in their order, then ``extra``
    (signals only some figures draw), each its own entry of :data:`COLORS` while they last."""
    keys = list(dict.fromkeys([*((s.role, s.variable) for p in TIME_PANELS for s in p.series), *extra]))
    return {k: COLORS[i % len(COLORS)] for i, k in enumerate(keys)}


def values(run: RunData, s: Series) -> np.ndarray | None:
    """The series' values as shown (transformed), or None when the run did not record it."""
    y = run.get(s.role, s.variable)
    if y is None:
        return None
    return s.transform(y) if s.transform is not None else y


def limit_value(run: RunData, name: str) -> float | None:
    """The value of a limit in this run (its FCS parameter), or None."""
    fcs = run.roles.fcs
    return None if fcs is None else parameter_float(run, fcs, LIMITS[name][0])


def limit_hits(run: RunData, name: str) -> np.ndarray:
    """Times [s] at which the FCS's fuel limiter engaged this limit (``fuel_limiter`` 1: Tt41, 2: N1)."""
    code = {"Tt41_max": 1, "N1_max": 2}[name]
    lim = run.get("fcs", "fuel_limiter")
    if lim is None:
        return np.empty(0)
    on = np.rint(lim).astype(int) == code
    starts = np.flatnonzero(on & ~np.concatenate(([False], on[:-1])))
    return run.time_s[starts]


def is_command(s: Series) -> bool:
    """Whether a series is a command (drawn under what is flown, so that the flown line stays visible)."""
    return "command" in s.legend


def section_spans(run: RunData, mission: Mission | None = None) -> list[tuple[int, float, float]]:
    """(section index, start time, end time) of every stretch of one active section; with the mission, only
    its sections (the index after the last one means the mission is completed: no section)."""
    idx = run.get("fcs", "section_index")
    if idx is None:
        return []
    if mission is not None:
        known = {s.index for s in mission.sections}
        return [span for span in section_spans(run) if span[0] in known]
    t = run.time_s
    idx = np.rint(idx).astype(int)
    change = np.flatnonzero(np.diff(idx)) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [len(t) - 1]))
    return [(int(idx[a]), float(t[a]), float(t[b])) for a, b in zip(starts, ends, strict=True)]


@dataclass(frozen=True)
class RunwayLine:
    """A runway as drawn: its name, threshold to end in longitude and latitude [deg], whether the mission uses it."""

    name: str
    lon_deg: tuple[float, float]
    lat_deg: tuple[float, float]
    used: bool


def waypoints_deg(mission: Mission) -> list[tuple[str, float, float]]:
    """The mission's waypoints as (label, longitude, latitude [deg]): numbered, with the name when it is not WPk."""
    out = []
    for k, (name, p) in enumerate(mission.waypoints, start=1):
        out.append((f"{k}" if name == f"WP{k}" else f"{k} {name}", math.degrees(p.lon_rad), math.degrees(p.lat_rad)))
    return out


def runway_lines(mission: Mission) -> list[RunwayLine]:
    """The mission's runways from threshold to end; ``used`` for those a section flies from or to."""
    used = {getattr(sec.get("runway"), "name", None) for sec in mission.sections}
    out = []
    for name, rwy in mission.runways:
        end = from_local_ne(rwy.threshold, rwy.length_m * math.cos(rwy.heading_rad),
                            rwy.length_m * math.sin(rwy.heading_rad), rwy.elevation_m)
        out.append(RunwayLine(name, (math.degrees(rwy.threshold.lon_rad), math.degrees(end.lon_rad)),
                              (math.degrees(rwy.threshold.lat_rad), math.degrees(end.lat_rad)), name in used))
    return out
