"""``summary.json`` of a mission run: time, fuel, limits hit, landing and every mission section.

Conventions
-----------
Sampled signals are held *before* their sample: the value recorded at ``t[k]`` is the one
that held over ``(t[k-1], t[k]]``. That is exact for the engine's fuel flow, which is the
flow it burned over the step ending at the sample (its counter ``fuel_burned_kg`` adds
``fuel_flow * h`` at every step), so with every step recorded the integral of the fuel
flow equals the counter's increase to round-off; with ``--record-every N`` it is a
rectangle rule over N steps. A mission section owns the intervals that *start* while it
is active: ``(t[k], t[k+1]]`` belongs to the section recorded at ``t[k]``.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from openemss.models.mission.geo import LatLon, local_ne_m
from openemss.models.mission.mission import Mission

from .conformance import holds, ils_conformance, section_conformance
from .electric import electric_summary
from .life import life_summary
from .rundata import RunData, parameter, parameter_float
from .series import flag_stats, held_increments

#: Ground speed below which the aircraft counts as stopped [m/s] (the FCS's ``lateral.v_stop_m_s`` default).
STOPPED_M_S = 0.5
#: A limited quantity within this fraction below its limit counts as "at the limit" when the FCS does
#: not report its limiter (inferred from the signal: about 3.5 K at Tt41_max 1400 K).
LIMIT_BAND = 0.0025
#: Engine Boolean outputs reported as limits when recorded.
ENGINE_FLAGS = ("surge", "flameout", "overspeed", "fuel_limited", "solver_failed")
#: FCS limiters: (name, code of the FCS's Integer output ``fuel_limiter`` (0 the lever's demand, 1 the Tt41
#: limit, 2 the N1 limit), FCS input signal, FCS limit parameter).
FCS_LIMITERS = (("Tt41_limit", 1, "Tt41_K", "fuel_control.Tt41_max_K"),
                ("N1_limit", 2, "N1_pct", "fuel_control.N1_max_pct"))


def sections_table(time_s: np.ndarray, index: np.ndarray, Wf_kg_s: np.ndarray,
                   sections: Sequence[tuple[str | None, str | None]] | None, completed: bool) -> list[dict[str, Any]]:
    """One entry per mission section: time span, fuel burned and status.

    Parameters
    ----------
    time_s, index, Wf_kg_s : numpy.ndarray
        Sample times [s], the FCS's active section index [-] and the engine's fuel flow [kg/s].
    sections : sequence of (name, type), or None
        The mission's sections; None lists the indices seen, unnamed.
    completed : bool
        Whether the FCS reported the whole mission completed.

    Returns
    -------
    list of dict
        ``index``, ``name``, ``type``, ``start_time_s``, ``end_time_s``, ``duration_s``,
        ``fuel_burned_kg``, ``status`` (``completed``, ``active`` or ``not reached``).
    """
    idx = np.rint(index).astype(int)
    owner = idx[:-1]  # section of each interval (t[k], t[k+1]]
    dt = np.diff(time_s)
    fuel = held_increments(time_s, Wf_kg_s)
    last = int(idx[-1])
    if sections is None:
        sections = [(None, None)] * (int(idx.max()) + 1)
    out = []
    for i, (name, typ) in enumerate(sections):
        seen = np.flatnonzero(idx == i)
        mine = owner == i
        if len(seen):
            start = float(time_s[seen[0]])
            after = np.flatnonzero((idx != i) & (np.arange(len(idx)) > seen[-1]))
            end = float(time_s[after[0]]) if len(after) else float(time_s[-1])
        elif (idx > i).any():  # passed within one sample (completed on entry)
            start = end = float(time_s[np.argmax(idx > i)])
        else:
            start = end = None
        if completed or last > i:
            status = "completed"
        elif last == i:
            status = "active"
        else:
            status = "not reached"
        out.append({"index": i, "name": name, "type": typ, "start_time_s": start, "end_time_s": end,
                    "duration_s": float(dt[mine].sum()), "fuel_burned_kg": float(fuel[mine].sum()),
                    "status": status})
    return out


def runway_position(lat_deg: float, lon_deg: float, runway: Any) -> tuple[float, float, bool]:
    """Along-track [m] from the threshold and cross-track [m, right positive] of a point, and
    whether it lies on the runway's paved rectangle (0 to length, within half the width)."""
    thr = runway.threshold
    n, e = local_ne_m(thr, LatLon.from_deg(lat_deg, lon_deg), runway.elevation_m)
    h = runway.heading_rad
    along = n * math.cos(h) + e * math.sin(h)
    cross = -n * math.sin(h) + e * math.cos(h)
    return along, cross, bool(0.0 <= along <= runway.length_m and abs(cross) <= runway.width_m / 2.0)


def landing_state(run: RunData, mission: Mission | None) -> dict[str, Any]:
    """Whether the run ended landed: airborne at some time, then on the ground, stopped, on a runway."""
    on_ground, gs = run.get("airframe", "on_ground"), run.get("airframe", "gs_m_s")
    lat, lon = run.get("airframe", "lat_deg"), run.get("airframe", "lon_deg")
    state: dict[str, Any] = {"airborne": None, "on_ground": None, "ground_speed_m_s": None, "runway": None,
                             "along_m": None, "cross_m": None}
    if on_ground is None:
        return {"landed": False, **state}
    state.update(airborne=bool((on_ground < 0.5).any()), on_ground=bool(on_ground[-1] > 0.5))
    if gs is not None:
        state["ground_speed_m_s"] = float(gs[-1])
    if mission is not None and lat is not None and lon is not None:
        for name, rwy in mission.runways:
            along, cross, inside = runway_position(float(lat[-1]), float(lon[-1]), rwy)
            if inside:
                state.update(runway=name, along_m=along, cross_m=cross)
                break
    stopped = state["ground_speed_m_s"] is not None and abs(state["ground_speed_m_s"]) < STOPPED_M_S
    landed = bool(state["airborne"] and state["on_ground"] and stopped and state["runway"] is not None)
    return {"landed": landed, **state}


def limits_hit(run: RunData) -> dict[str, dict[str, Any]]:
    """Every limit the run's signals can tell: engine flags, and the fuel controller's limiters
    (reported by the FCS, or else inferred from the limited signal and the limit parameter)."""
    t = run.time_s
    out: dict[str, dict[str, Any]] = {}
    for flag in ENGINE_FLAGS:
        col = run.get("engine", flag)
        if col is not None:
            out[flag] = {**flag_stats(t, col), "source": f"{run.roles.engine}.{flag}"}
    fcs = run.roles.fcs
    if fcs is None:
        return out
    selected = run.get("fcs", "fuel_limiter")
    for name, code, signal, param in FCS_LIMITERS:
        if selected is not None:
            out[name] = {**flag_stats(t, selected == code), "source": f"{fcs}.fuel_limiter == {code}"}
            continue
        value, limit = run.get("fcs", signal), parameter_float(run, fcs, param)
        if value is not None and limit is not None:
            out[name] = {**flag_stats(t, value >= limit * (1.0 - LIMIT_BAND)), "limit": limit,
                         "source": f"inferred: {fcs}.{signal} within {LIMIT_BAND:.2%} of {fcs}.{param}"}
    return out


#: Engine flags that mean the engine could not compute its outputs (the run went on with a held state).
DEGRADED_FLAGS = ("solver_failed",)


def degraded(run: RunData) -> list[str]:
    """One line per condition under which a model held its outputs instead of computing them
    (the engine's ``solver_failed``, when the run was let go on with it); empty for a sound run."""
    t = run.time_s
    out = []
    for flag in DEGRADED_FLAGS:
        col = run.get("engine", flag)
        if col is not None and np.any(col > 0.5):
            st = flag_stats(t, col)
            out.append(f"{run.roles.engine}.{flag} set {st['count']} time(s), first at t = {st['first_time_s']:g} s: "
                       "the engine held its last good state there")
    return out


def flameout(run: RunData) -> dict[str, Any] | None:
    """When the engine's burner first went out and why (its ``flameout_cause``, else its ``flameout`` flag), or
    None if it never did (or neither is recorded)."""
    from openemss.models.engine.engine_signals import FLAMEOUT_CAUSES

    t = run.time_s
    cause, flag = run.get("engine", "flameout_cause"), run.get("engine", "flameout")
    col, name = (cause, "flameout_cause") if cause is not None else (flag, "flameout")
    if col is None or not np.any(col > 0.5):
        return None
    k = int(np.argmax(col > 0.5))
    code = int(round(float(col[k]))) if cause is not None else None
    text = FLAMEOUT_CAUSES[code] if code is not None and 0 < code < len(FLAMEOUT_CAUSES) else "not recorded"
    return {"time_s": float(t[k]), "cause": text, "cause_code": code, "source": f"{run.roles.engine}.{name}"}


def takeoff_mass(run: RunData) -> dict[str, Any] | None:
    """The aircraft's mass at the start against its maximum take-off mass (``above_mtow``: the line saying by how
    much, else None; ``mtow_kg`` None for an aircraft without one, or one that cannot be read again here); None
    when the airframe's ``mass_kg`` is not recorded."""
    from openemss.models.airframe.aircraft import DEFAULT_AIRCRAFT, load_aircraft
    from openemss.models.airframe.errors import AirframeError
    from openemss.models.airframe.loading import above_mtow

    mass = run.get("airframe", "mass_kg")
    if mass is None or not len(mass):
        return None
    m0 = float(mass[0])
    name = parameter(run, run.roles.airframe, "aircraft") if run.roles.airframe else None
    try:
        ac = load_aircraft(name or DEFAULT_AIRCRAFT)
    except AirframeError:  # a folder given relative to the FMU's resources: not found from here
        ac = None
    return {"takeoff_kg": m0, "mtow_kg": ac.mtom_kg if ac is not None else None,
            "above_mtow": (above_mtow(m0, ac) or None) if ac is not None else None,
            "source": f"{run.roles.airframe}.mass_kg"}


def _finite(x: Any) -> Any:
    """JSON-safe: non-finite floats become None, recursively."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_finite(v) for v in x]
    return x


def _with_conformance(run: RunData, mission: Mission | None, table: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Add each section's ``conformance`` (:mod:`.conformance`) to the section table: its targets against the
    flown altitude and speed, from its first sample to its end (the next section's first sample)."""
    t = run.time_s
    for row in table:
        row["conformance"] = None
        if mission is None or row["start_time_s"] is None or row["index"] >= len(mission.sections):
            continue
        i0 = int(np.searchsorted(t, row["start_time_s"]))
        i1 = min(int(np.searchsorted(t, row["end_time_s"])), len(t) - 1)
        if i1 > i0:
            row["conformance"] = section_conformance(run, mission.sections[row["index"]], i0, i1)
    return table


def summarize(run: RunData, mission: Mission | None) -> dict[str, Any]:
    """The summary of a mission run (see the README's Results section for the keys and units).

    Requires the FCS's ``section_index`` and the engine's ``Wf_kg_s`` and ``fuel_burned_kg``.
    """
    t = run.time_s
    idx, wf, burned = run.get("fcs", "section_index"), run.get("engine", "Wf_kg_s"), \
        run.get("engine", "fuel_burned_kg")
    if idx is None or wf is None or burned is None:
        raise ValueError("summarize needs the FCS's section_index and the engine's Wf_kg_s and fuel_burned_kg")
    n = len(mission.sections) if mission is not None else None
    done_col = run.get("fcs", "mission_completed")
    if done_col is not None:
        completed = bool(done_col[-1] > 0.5)
    else:
        completed = n is not None and int(round(idx[-1])) >= n
    sections = [(s.name, s.type) for s in mission.sections] if mission is not None else None
    integral = float(held_increments(t, wf).sum())
    counter = float(burned[-1] - burned[0])
    tt4 = run.get("engine", "Tt4_K")
    k4 = int(np.nanargmax(tt4)) if tt4 is not None and np.isfinite(tt4).any() else None
    info = run.info
    landing = landing_state(run, mission)
    return _finite({
        "run": run.name,
        "system": info.get("system"),
        "status": info.get("status", "unknown"),
        "error": info.get("error"),
        "timeseries_note": run.note or None,
        "mission": None if mission is None else {"name": mission.name, "source": mission.source,
                                                 "sections": len(mission.sections)},
        "mission_completed": completed,
        "landed": landing.pop("landed"),
        "landing": landing,
        "sim_time_s": float(t[-1] - t[0]),
        "wall_time_s": info.get("wall_time_s"),
        "realtime_factor": info.get("realtime_factor"),
        "fuel_burned_kg": counter,
        "fuel_flow_integral_kg": integral,
        "fuel_balance_error_kg": integral - counter,
        "max_Tt4_K": None if k4 is None else float(tt4[k4]),
        "max_Tt4_time_s": None if k4 is None else float(t[k4]),
        "limits_hit": limits_hit(run),
        "flameout": flameout(run),
        "mass": takeoff_mass(run),
        "degraded": degraded(run),
        "sections": _with_conformance(run, mission, sections_table(t, idx, wf, sections, completed)),
        "holds": holds(run, mission),
        "ils": ils_conformance(run, mission),
        "electric": electric_summary(run),
        "life": life_summary(run),
    })
