"""How a mission run flew its plan: per section, the targets against what was flown; the planned holds; the ILS.

For every section flown to targets (its type's ``conformance`` is ``targets``, models/fcs/sections.py: waypoint,
orbit, level, G-turn sections) with an altitude, the summary gives:

* ``target``: the section's altitude [m] and speed (its kind: ``mach`` [-], ``cas_m_s`` or
  ``tas_m_s`` [m/s]), as the mission file states them. A waypoint section's altitude is a
  constraint at its end (where its last leg ends; with fly-by, where the turn there begins).
* ``achieved``: altitude and speed at the section's end, i.e. at the sample where the next
  section begins (``end_time_s`` of the section table), and the errors there.
* ``time_to_capture_s``: from the section's start to the first sample within the capture band
  of the target (altitude CAPTURE_BAND_M, speed SPEED_BAND); None if never.
* ``worst_after_capture``: the largest deviation from the target, signed (the flown value
  minus the target), from the capture to the section's end, counted from the first sample
  within a tenth of the band (1 m; the capture's own approach is no deviation). A descent
  captures its altitude at the bottom of its path, so for a descent this covers the level-off
  and the level part before the fix.

Holds are the stretches where the FCS's ``vnav_mode`` reports HOLD (code 5, a planned hold
at a fix, :mod:`openemss.models.fcs.vertical`). The ILS is taken from ``ils_phase``: the
altitude where the glide slope was captured (GS, code 4) against the landing's approach
altitude; how far the localizer capture crossed the centre line (the cross-track from the
recorded position in the runway's threshold plane, after LOC, code 3), and how far the
aircraft rose above the glide path after capturing it. The glide path follows the FCS's
ILS geometry (``approach.gs_angle_rad``, ``approach.tch_m``).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from openemss.models.common.airspeed import cas_from_tas
from openemss.models.fcs.approach import APPROACH_PHASES, ApproachParams, ils_deviation
from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.vertical import VNAV_MODES
from openemss.models.mission.geo import LatLon
from openemss.models.mission.mission import Mission, Section
from openemss.models.mission.sections import APPROACH, REGISTRY, TARGETS
from openemss.models.mission.speed import SpeedKind

from .rundata import RunData, parameter_float

__all__ = ["CAPTURE_BAND_M", "SPEED_BAND", "SETTLE_FRACTION", "section_conformance", "holds", "ils_conformance",
           "HOLD_CODE"]

#: An altitude within this of its target counts as captured [m].
CAPTURE_BAND_M = 10.0
#: A speed within this of its target counts as captured, by kind [-] or [m/s].
SPEED_BAND = {"mach": 0.005, "cas_m_s": 1.5, "tas_m_s": 1.5}
#: The worst deviation after capture is taken from the first sample within this fraction of the band (1 m, Mach
#: 0.0005, 0.15 m/s), so that the capture's own approach is not counted as a deviation [-].
SETTLE_FRACTION = 0.1
HOLD_CODE = VNAV_MODES.index("HOLD")
_GS, _LOC = APPROACH_PHASES.index("GS"), APPROACH_PHASES.index("LOC")
_SPEED_KEY = {SpeedKind.MACH: "mach", SpeedKind.CAS: "cas_m_s", SpeedKind.TAS: "tas_m_s"}


def _speed_signal(run: RunData, kind: SpeedKind) -> np.ndarray | None:
    """The flown speed in the target's kind: the airframe's Mach, CAS or TAS (CAS from TAS and the ISA when the
    airframe records no CAS)."""
    if kind is SpeedKind.MACH:
        return run.get("airframe", "mach")
    if kind is SpeedKind.CAS:
        cas = run.get("airframe", "cas_m_s")
        if cas is not None:
            return cas
        tas, alt = run.get("airframe", "tas_m_s"), run.get("airframe", "alt_m")
        if tas is None or alt is None:
            return None
        return np.array([cas_from_tas(v, isa(h)) for v, h in zip(tas, alt, strict=True)])
    return run.get("airframe", "tas_m_s")


def _track(t: np.ndarray, y: np.ndarray, target: float, band: float, i0: int, i_end: int) -> dict[str, Any]:
    """Capture and deviations of ``y`` against ``target`` over samples [i0, i_end] (i_end: the section's end)."""
    err = y[i0:i_end + 1] - target
    inside = np.flatnonzero(np.abs(err) <= band)
    out: dict[str, Any] = {"achieved": float(y[i_end]), "error_at_end": float(err[-1]),
                           "time_to_capture_s": None, "worst_after_capture": None}
    if inside.size:
        out["time_to_capture_s"] = float(t[i0 + int(inside[0])] - t[i0])
        settled = np.flatnonzero(np.abs(err) <= SETTLE_FRACTION * band)
        k = int(settled[0]) if settled.size else int(inside[0])
        after = err[k:]
        j = int(np.argmax(np.abs(after)))
        out["worst_after_capture"] = float(after[j])
    return out


def section_conformance(run: RunData, sec: Section, i0: int, i_end: int) -> dict[str, Any] | None:
    """Targets and what was flown of ``sec`` active from sample ``i0`` to its end at sample ``i_end``; None for a
    section whose type is not flown to targets (its ``conformance`` is not ``targets``: rolling, take-off,
    landing, custom) or that has no altitude."""
    alt_target = sec.get("altitude_m")
    alt = run.get("airframe", "alt_m")
    if alt_target is None or alt is None or REGISTRY[sec.type].conformance != TARGETS:
        return None
    t = run.time_s
    out: dict[str, Any] = {"altitude": {"target_m": float(alt_target),
                                        **_suffix(_track(t, alt, alt_target, CAPTURE_BAND_M, i0, i_end), "_m")}}
    speed = sec.get("speed")
    if speed is not None:
        key = _SPEED_KEY[speed.kind]
        flown = _speed_signal(run, speed.kind)
        out["speed"] = {"kind": key, "target": float(speed.value)}
        if flown is not None:
            out["speed"].update(_track(t, flown, speed.value, SPEED_BAND[key], i0, i_end))
    at = sec.get("altitude_at")
    out["altitude"]["constraint_at"] = "end" if at is None else f"waypoint {at.lat_deg:.5f} N {at.lon_deg:.5f} E"
    return out


def _suffix(d: dict[str, Any], unit: str) -> dict[str, Any]:
    return {(k + unit if k != "time_to_capture_s" else k): v for k, v in d.items()}


def holds(run: RunData, mission: Mission | None) -> list[dict[str, Any]]:
    """Every stretch of vertical mode HOLD: section, start and end [s], duration [s], height lost [m]."""
    mode, idx, alt = run.get("fcs", "vnav_mode"), run.get("fcs", "section_index"), run.get("airframe", "alt_m")
    if mode is None or idx is None:
        return []
    t = run.time_s
    on = np.rint(mode).astype(int) == HOLD_CODE
    edges = np.flatnonzero(np.diff(np.concatenate(([0], on.astype(int), [0]))))
    names = {s.index: s.name for s in mission.sections} if mission is not None else {}
    out = []
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        last = b - 1
        i = int(round(idx[a]))
        out.append({"section": i, "name": names.get(i), "start_time_s": float(t[a]), "end_time_s": float(t[last]),
                    "duration_s": float(t[last] - t[a]),
                    "height_lost_m": None if alt is None else float(alt[a] - alt[last])})
    return out


def ils_conformance(run: RunData, mission: Mission | None) -> dict[str, Any] | None:
    """The ILS capture of the (first) approach section (its type's ``conformance`` is ``approach``: a landing), or
    None without an ``ils_phase`` record or such a section."""
    phase = run.get("fcs", "ils_phase")
    lat, lon, alt = (run.get("airframe", k) for k in ("lat_deg", "lon_deg", "alt_m"))
    land = next((s for s in mission.sections if REGISTRY[s.type].conformance == APPROACH), None) \
        if mission is not None else None
    if phase is None or land is None or lat is None or lon is None or alt is None:
        return None
    ph = np.rint(phase).astype(int)
    t, rwy = run.time_s, land["runway"]
    fcs = run.roles.fcs or ""
    ap = ApproachParams.from_file()
    gs_angle = parameter_float(run, fcs, "approach.gs_angle_rad") or ap.gs_angle_rad
    tch = parameter_float(run, fcs, "approach.tch_m") or ap.tch_m
    ap = ApproachParams.from_file(gs_angle_rad=gs_angle, tch_m=tch)
    out: dict[str, Any] = {"runway": rwy.name, "approach_altitude_m": float(land["approach_altitude_m"]),
                           "loc_capture_time_s": None, "loc_capture_xtk_m": None, "loc_overshoot_m": None,
                           "gs_capture_time_s": None, "gs_capture_altitude_m": None, "gs_capture_error_m": None,
                           "gs_overshoot_m": None}
    loc = np.flatnonzero((ph == _LOC) | (ph == _GS))
    if loc.size:
        dev = [ils_deviation(rwy, ap, LatLon.from_deg(float(lat[i]), float(lon[i])), float(alt[i])) for i in loc]
        xtk = np.array([d.loc_m for d in dev])
        side = math.copysign(1.0, xtk[0]) if xtk[0] != 0.0 else 1.0
        out.update(loc_capture_time_s=float(t[loc[0]]), loc_capture_xtk_m=float(xtk[0]),
                   loc_overshoot_m=float(max(np.max(-side * xtk), 0.0)))
    gs = np.flatnonzero(ph == _GS)
    if gs.size:
        h = np.array([ils_deviation(rwy, ap, LatLon.from_deg(float(lat[i]), float(lon[i])), float(alt[i])).gs_m
                      for i in gs])
        side = math.copysign(1.0, h[0]) if h[0] != 0.0 else -1.0
        out.update(gs_capture_time_s=float(t[gs[0]]), gs_capture_altitude_m=float(alt[gs[0]]),
                   gs_capture_error_m=float(alt[gs[0]] - land["approach_altitude_m"]),
                   gs_overshoot_m=float(max(np.max(-side * h), 0.0)))
    return out
