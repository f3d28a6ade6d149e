"""Where the mission says the flight starts, and the take-off run staying on its runway.

The mission file is the one source of the start: a mission whose first section is a ground run on a
runway (a section type with ``departs_from_runway``: Rolling, TakeOff) starts on that runway, at rest
or rolling, on the ground. The flight control sees the aircraft's first state at its first step, in
any host, and refuses a start elsewhere (:func:`check_departure`) with one line naming both
positions, instead of flying the mission from wherever the airframe was put (an aircraft started on
another runway would ground-loop towards the mission's centre line and leave from the grass).

During the ground run (:func:`check_on_runway`) an aircraft that leaves the paved runway (past its
far end, or off its side) has not lifted off where the mission said: the flight control fails with
the distance run and the speeds, instead of flying on from the grass until something else breaks.

Tolerances (stated here, once):

* lateral: the runway's half width, from its centre line;
* along: from :data:`START_BEFORE_THRESHOLD_M` before the threshold to the far end;
* heading: within :data:`START_HEADING_TOL_DEG` of the runway's;
* height: the aircraft's altitude within :data:`START_HEIGHT_TOL_M` of the runway's elevation (its
  centre of gravity stands about a metre above the ground on its wheels), and on the ground.
"""
from __future__ import annotations

import math
from typing import Any

from ..mission.geo import wrap_pi
from .errors import FcsError
from .state import AircraftState

__all__ = ["START_BEFORE_THRESHOLD_M", "START_HEADING_TOL_DEG", "START_HEIGHT_TOL_M", "check_departure",
           "check_on_runway"]

#: How far before the threshold (on the runway's extension: a blast pad, a displaced threshold) a start may be [m].
START_BEFORE_THRESHOLD_M = 60.0
#: Largest difference between the aircraft's and the runway's heading at the start [deg].
START_HEADING_TOL_DEG = 10.0
#: Largest difference between the aircraft's altitude and the runway's elevation at the start [m].
START_HEIGHT_TOL_M = 30.0


def _where(x: AircraftState) -> str:
    return (f"{math.degrees(x.pos.lat_rad):.5f} N {math.degrees(x.pos.lon_rad):.5f} E, {x.alt_m:.1f} m, heading "
            f"{math.degrees(x.psi_rad) % 360.0:.1f} deg")


def _runway(rwy: Any) -> str:
    return (f"{rwy.name} (threshold {math.degrees(rwy.threshold.lat_rad):.5f} N "
            f"{math.degrees(rwy.threshold.lon_rad):.5f} E, {rwy.elevation_m:.1f} m, heading "
            f"{math.degrees(rwy.heading_rad) % 360.0:.1f} deg, {rwy.length_m:g} x {rwy.width_m:g} m)")


def check_departure(rwy: Any, x: AircraftState, section: str, source: str) -> None:
    """Refuse a first state that is not on the mission's departure runway `rwy` (see the module).

    Parameters
    ----------
    rwy : Runway
        The runway of the mission's first section.
    x : AircraftState
        The aircraft's state at the flight control's first step.
    section, source : str
        The section (for the message) and the mission file.

    Raises
    ------
    FcsError
        One line naming the aircraft's position and the runway's, and what is off.
    """
    along, cross = rwy.local(x.pos)
    dpsi = math.degrees(abs(wrap_pi(x.psi_rad - rwy.heading_rad)))
    off = []
    if not x.on_ground:
        off.append("in the air, not on the ground")
    if not -START_BEFORE_THRESHOLD_M <= along <= rwy.length_m or abs(cross) > rwy.width_m / 2.0:
        off.append(f"{along:.0f} m along and {cross:.0f} m right of its centre line (on it: {-START_BEFORE_THRESHOLD_M:g}"
                   f" to {rwy.length_m:g} m along, within {rwy.width_m / 2.0:g} m)")
    if not dpsi <= START_HEADING_TOL_DEG:
        off.append(f"heading {dpsi:.1f} deg off the runway's (at most {START_HEADING_TOL_DEG:g} deg)")
    if not abs(x.alt_m - rwy.elevation_m) <= START_HEIGHT_TOL_M:
        off.append(f"{x.alt_m - rwy.elevation_m:.1f} m above the runway's elevation (at most "
                   f"{START_HEIGHT_TOL_M:g} m)")
    if off:
        raise FcsError(f"fcs: {source}: the mission starts with {section} on runway {_runway(rwy)}, but the aircraft "
                       f"starts at {_where(x)}: {'; '.join(off)}; start the aircraft on that runway (the airframe's "
                       "lat0_deg, lon0_deg, heading0_deg, alt0_m) or give the mission that starts where it is")


def check_on_runway(rwy: Any, x: AircraftState, t_s: float, section: str, cas_m_s: float, rotate: str) -> None:
    """Refuse an aircraft on the ground that has left the paved runway `rwy` during a ground run.

    Parameters
    ----------
    cas_m_s : float
        Calibrated airspeed [m/s] (for the message).
    rotate : str
        What the section waits for to lift off (for the message).

    Raises
    ------
    FcsError
        One line: where it left the runway, the distance run, its speeds.
    """
    if not x.on_ground:
        return
    along, cross = rwy.local(x.pos)
    if along > rwy.length_m:
        what = f"ran off the far end of runway {rwy.name} ({rwy.length_m:g} m long) without lifting off"
    elif abs(cross) > rwy.width_m / 2.0:
        what = (f"left the side of runway {rwy.name} ({cross:.1f} m {'right' if cross > 0 else 'left'} of its centre "
                f"line, half width {rwy.width_m / 2.0:g} m), {along:.0f} m from its threshold")
    else:
        return
    raise FcsError(f"fcs: t = {t_s:.2f} s: {section}: the aircraft {what}, on the ground at {cas_m_s:.1f} m/s "
                   f"calibrated airspeed ({rotate}), {math.hypot(x.vn_m_s, x.ve_m_s):.1f} m/s ground speed")
