"""Import of QGroundControl ``.plan`` files (JSON) into our YAML mission format.

Mapping of MAVLink mission items (``mission.items``, ``SimpleItem`` only):

* MAV_CMD_NAV_TAKEOFF (22): a runway ``HOME`` at ``plannedHomePosition``, heading to
  the take-off item's position (or to the next waypoint), becomes a Rolling and a
  TakeOff section climbing to the item's altitude.
* MAV_CMD_NAV_WAYPOINT (16): consecutive waypoints at one altitude become one
  WaypointFollowing section; a new altitude starts a new section.
* MAV_CMD_NAV_LOITER_TURNS (18): an Orbiting section; param1 = turns, param3 = radius
  [m] (positive clockwise, negative counter-clockwise, MAVLink convention).
* MAV_CMD_NAV_LAND (21): a Landing section on a runway ``LAND`` whose threshold is
  the land point, aligned with the course from the previous item.

Altitudes: frame 3 (MAV_FRAME_GLOBAL_RELATIVE_ALT) adds the home altitude, frame 0
(MAV_FRAME_GLOBAL) is above mean sea level. Speeds are the plan's ``cruiseSpeed``
(taken as true airspeed) or the defaults of ``data/qgc_defaults.yaml``; other
items raise a clear error naming the item.

References
----------
QGroundControl Developer Guide, "Plan File Format"; MAVLink common message set.
"""

from __future__ import annotations

import math
from importlib import resources
from typing import Any

import yaml

from ..common import safe_yaml
from .errors import MissionError
from .geo import LatLon, initial_bearing_rad

__all__ = ["plan_to_yaml", "MAV_CMD"]

MAV_CMD = {"WAYPOINT": 16, "LOITER_TURNS": 18, "LAND": 21, "TAKEOFF": 22}
_FRAME_GLOBAL, _FRAME_RELATIVE = 0, 3


def _defaults() -> dict[str, float]:
    pkg = __package__ or __name__.rpartition(".")[0]
    text = resources.files(pkg).joinpath("data", "qgc_defaults.yaml").read_text(encoding="utf-8")
    return safe_yaml.load(text, "qgc_defaults.yaml")["qgc_defaults"]


def plan_to_yaml(text: str, source: str = "<plan>") -> str:
    """Convert the JSON text of a QGroundControl plan into mission YAML.

    Raises
    ------
    MissionError
        If the plan is not valid JSON, has no mission items, or has an item we cannot map.
    """
    d = _defaults()
    try:
        plan = safe_yaml.load_json(text, source)
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    try:
        mission = plan["mission"]
        items = mission["items"]
        home_lat, home_lon, home_alt = (float(x) for x in mission["plannedHomePosition"][:3])
    except (KeyError, TypeError, ValueError):
        raise MissionError(f"{source}: a .plan needs mission.items and mission.plannedHomePosition "
                           "[lat, lon, alt]") from None
    cruise = float(mission.get("cruiseSpeed") or d["cruise_tas_m_s"])
    if cruise < 30.0:  # a multicopter plan's cruise speed: fly ours
        cruise = d["cruise_tas_m_s"]
    home = LatLon.from_deg(home_lat, home_lon)
    waypoints: dict[str, dict[str, float]] = {}
    runways: dict[str, dict[str, float]] = {}
    sections: list[dict[str, Any]] = []
    parsed = []
    for n, it in enumerate(items):
        if it.get("type") != "SimpleItem":
            raise MissionError(f"{source}: mission item {n}: type {it.get('type')!r} is not supported; "
                               "allowed: SimpleItem (complex items such as surveys are not flown)")
        cmd = it.get("command")
        params = it.get("params") or []
        if cmd not in MAV_CMD.values() or len(params) < 7:
            raise MissionError(f"{source}: mission item {n}: MAV_CMD {cmd!r} is not supported; "
                               f"allowed: {', '.join(f'{k} ({v})' for k, v in MAV_CMD.items())}")
        frame = it.get("frame", _FRAME_RELATIVE)
        if frame not in (_FRAME_GLOBAL, _FRAME_RELATIVE):
            raise MissionError(f"{source}: mission item {n}: frame {frame} not supported; allowed: 0 (AMSL), "
                               "3 (relative to home)")
        lat, lon, alt = float(params[4]), float(params[5]), float(params[6])
        alt_amsl = alt + (home_alt if frame == _FRAME_RELATIVE else 0.0)
        parsed.append((n, cmd, params, lat, lon, alt_amsl))

    def course_to_next(k: int, frm: LatLon) -> float:
        for _, _, _, la, lo, _ in parsed[k + 1:]:
            p = LatLon.from_deg(la, lo)
            if p != frm:
                return math.degrees(initial_bearing_rad(frm, p))
        raise MissionError(f"{source}: take-off needs a later item to give the runway direction")

    prev = home
    for k, (n, cmd, params, lat, lon, alt) in enumerate(parsed):
        pos = LatLon.from_deg(lat, lon)
        if cmd == MAV_CMD["TAKEOFF"]:
            hdg = course_to_next(k, home)
            runways["HOME"] = {"threshold_lat_deg": home_lat, "threshold_lon_deg": home_lon, "heading_deg": hdg % 360,
                               "elevation_m": home_alt, "length_m": d["runway_length_m"],
                               "width_m": d["runway_width_m"]}
            sections.append({"type": "Rolling", "name": f"item {n} take-off roll", "runway": "HOME",
                             "rotate_cas_m_s": d["rotate_cas_m_s"]})
            sections.append({"type": "TakeOff", "name": f"item {n} take-off", "runway": "HOME",
                             "pitch_deg": d["takeoff_pitch_deg"], "climb_speed": {"cas_m_s": d["climb_cas_m_s"]},
                             "until_height_agl_m": max(alt - home_alt, 20.0)})
            prev = home
            continue
        if cmd == MAV_CMD["WAYPOINT"]:
            name = f"WP{n}"
            waypoints[name] = {"lat_deg": lat, "lon_deg": lon}
            last = sections[-1] if sections else None
            if last and last["type"] == "WaypointFollowing" and last["altitude_m"] == alt:
                last["waypoints"].append(name)
            else:
                sections.append({"type": "WaypointFollowing", "name": f"item {n} waypoints", "waypoints": [name],
                                 "altitude_m": alt, "speed": {"tas_m_s": cruise}})
        elif cmd == MAV_CMD["LOITER_TURNS"]:
            name = f"WP{n}"
            waypoints[name] = {"lat_deg": lat, "lon_deg": lon}
            radius = float(params[2])
            if radius == 0.0:
                raise MissionError(f"{source}: mission item {n} (LOITER_TURNS): param3 radius is 0; "
                                   "give the orbit radius [m] (negative for counter-clockwise)")
            sections.append({"type": "Orbiting", "name": f"item {n} loiter", "center": name,
                             "radius_m": abs(radius), "direction": "clockwise" if radius > 0 else "counterclockwise",
                             "turns": float(params[0]), "altitude_m": alt, "speed": {"tas_m_s": cruise}})
        elif cmd == MAV_CMD["LAND"]:
            if prev == pos:
                raise MissionError(f"{source}: mission item {n} (LAND): needs a preceding item to give the "
                                   "approach direction")
            hdg = math.degrees(initial_bearing_rad(prev, pos)) % 360
            runways["LAND"] = {"threshold_lat_deg": lat, "threshold_lon_deg": lon, "heading_deg": hdg,
                               "elevation_m": alt, "length_m": d["runway_length_m"], "width_m": d["runway_width_m"]}
            sections.append({"type": "Landing", "name": f"item {n} landing", "runway": "LAND",
                             "approach_altitude_m": alt + d["approach_height_m"],
                             "approach_speed": {"cas_m_s": d["approach_cas_m_s"]}})
        prev = pos
    doc = {"mission": {"name": str(plan.get("name", source)), "description": f"converted from {source}"},
           "places": {"runways": runways, "waypoints": waypoints}, "sections": sections}
    return yaml.safe_dump(doc, sort_keys=False)
