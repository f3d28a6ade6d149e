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
from collections.abc import Callable
from importlib import resources
from typing import Any

import yaml

from ..infra import safe_yaml, values
from .errors import MissionError
from .geo import LatLon, initial_bearing_rad, leg_problem

__all__ = ["plan_to_yaml", "convert_plan", "MAV_CMD"]

MAV_CMD = {"WAYPOINT": 16, "LOITER_TURNS": 18, "LAND": 21, "TAKEOFF": 22}
_FRAME_GLOBAL, _FRAME_RELATIVE = 0, 3


def _defaults() -> dict[str, float]:
    pkg = __package__ or __name__.rpartition(".")[0]
    text = resources.files(pkg).joinpath("data", "qgc_defaults.yaml").read_text(encoding="utf-8")
    return safe_yaml.load(text, "qgc_defaults.yaml")["qgc_defaults"]


def _line(m: Any, key: str, default: int = 1) -> int:
    """The line of ``key`` in a mapping read by :func:`.safe_yaml.load_json` (``default`` if unknown)."""
    lines = getattr(m, "lines", {})
    return lines.get(key, min(lines.values(), default=default))


class _Plan:
    """A plan being read: its file, and where each part of the converted mission came from."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.origin: dict[tuple[str, ...], tuple[int, str]] = {}  # converted path -> (plan line, what)

    def fail(self, line: int, what: str) -> MissionError:
        return MissionError(f"{self.source}:{line}: {what}")

    def number(self, v: Any, lo: float, hi: float, line: int, what: str) -> float:
        try:
            return values.number(v, lo, hi)
        except ValueError as e:
            raise self.fail(line, f"{what}: {e}") from None


def _convert(text: str, source: str) -> tuple[str, _Plan]:
    d = _defaults()
    try:
        plan = safe_yaml.load_json(text, source)
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    rd = _Plan(source)
    need = "a .plan is a JSON object with mission.items and mission.plannedHomePosition [lat, lon, alt]"
    mission = plan.get("mission") if isinstance(plan, dict) else None
    if not isinstance(mission, dict) or "items" not in mission or "plannedHomePosition" not in mission:
        raise rd.fail(_line(plan, "mission") if isinstance(plan, dict) else 1, need)
    items, home_pos = mission["items"], mission["plannedHomePosition"]
    home_line = _line(mission, "plannedHomePosition")
    if not isinstance(home_pos, list) or len(home_pos) < 3:
        raise rd.fail(home_line, f"mission.plannedHomePosition: expected [lat, lon, alt], got {values.show(home_pos)}")
    home_lat = rd.number(home_pos[0], -90.0, 90.0, home_line, "mission.plannedHomePosition latitude [deg]")
    home_lon = rd.number(home_pos[1], -180.0, 180.0, home_line, "mission.plannedHomePosition longitude [deg]")
    home_alt = rd.number(home_pos[2], -400.0, 9000.0, home_line, "mission.plannedHomePosition altitude [m]")
    if not isinstance(items, list) or not items:
        raise rd.fail(_line(mission, "items"), f"mission.items: expected a non-empty list of mission items, got "
                      f"{values.show(items)}")
    cruise = d["cruise_tas_m_s"]
    if mission.get("cruiseSpeed") is not None:
        cruise = rd.number(mission["cruiseSpeed"], 0.0, 350.0, _line(mission, "cruiseSpeed"),
                           "mission.cruiseSpeed [m/s]") or cruise
    if cruise < 30.0:  # a multicopter plan's cruise speed: fly ours
        cruise = d["cruise_tas_m_s"]
    home = LatLon.from_deg(home_lat, home_lon)
    waypoints: dict[str, dict[str, float]] = {}
    runways: dict[str, dict[str, float]] = {}
    sections: list[dict[str, Any]] = []
    parsed = []
    for n, it in enumerate(items):
        if not isinstance(it, dict):
            raise rd.fail(_line(mission, "items"), f"mission item {n}: expected an object, got {values.show(it)}")
        line = _line(it, "command")
        if it.get("type") != "SimpleItem":
            raise rd.fail(_line(it, "type"), f"mission item {n}: type {values.show(it.get('type'))} is not supported; "
                          "allowed: SimpleItem (complex items such as surveys are not flown)")
        cmd = it.get("command")
        params = it.get("params")
        if isinstance(cmd, bool) or cmd not in MAV_CMD.values():
            raise rd.fail(line, f"mission item {n}: MAV_CMD {values.show(cmd)} is not supported; "
                          f"allowed: {', '.join(f'{k} ({v})' for k, v in MAV_CMD.items())}")
        if not isinstance(params, list) or len(params) != 7:
            raise rd.fail(_line(it, "params"), f"mission item {n}: params: expected a list of 7 values "
                          f"(MAVLink param1 to param7), got {values.show(params)}")
        frame = it.get("frame", _FRAME_RELATIVE)
        if isinstance(frame, bool) or frame not in (_FRAME_GLOBAL, _FRAME_RELATIVE):
            raise rd.fail(_line(it, "frame"), f"mission item {n}: frame {values.show(frame)} not supported; "
                          "allowed: 0 (AMSL), 3 (relative to home)")
        at = _line(it, "params")
        lat = rd.number(params[4], -90.0, 90.0, at, f"mission item {n}: param5 latitude [deg]")
        lon = rd.number(params[5], -180.0, 180.0, at, f"mission item {n}: param6 longitude [deg]")
        alt = rd.number(params[6], -400.0, 20000.0, at, f"mission item {n}: param7 altitude [m]")
        alt_amsl = alt + (home_alt if frame == _FRAME_RELATIVE else 0.0)
        parsed.append((n, cmd, params, lat, lon, alt_amsl, line))

    def course_to_next(k: int, frm: LatLon) -> float:
        for _, _, _, la, lo, _, _ in parsed[k + 1:]:
            p = LatLon.from_deg(la, lo)
            if leg_problem(frm, p) is None:
                return math.degrees(initial_bearing_rad(frm, p))
        raise rd.fail(parsed[k][6], f"mission item {parsed[k][0]} (TAKEOFF): needs a later item away from home "
                      "(neither on it nor antipodal) to give the runway direction")

    prev = home
    for k, (n, cmd, params, lat, lon, alt, line) in enumerate(parsed):
        pos = LatLon.from_deg(lat, lon)
        at = _line(items[n], "params")
        if cmd == MAV_CMD["TAKEOFF"]:
            hdg = course_to_next(k, home)
            runways["HOME"] = {"threshold_lat_deg": home_lat, "threshold_lon_deg": home_lon, "heading_deg": hdg % 360,
                               "elevation_m": home_alt, "length_m": d["runway_length_m"],
                               "width_m": d["runway_width_m"]}
            rd.origin[("places", "runways", "HOME")] = (home_line, f"mission item {n} (TAKEOFF) at home")
            rd.origin[("sections", str(len(sections)))] = (line, f"mission item {n} (TAKEOFF)")
            sections.append({"type": "Rolling", "name": f"item {n} take-off roll", "runway": "HOME",
                             "rotate_cas_m_s": d["rotate_cas_m_s"]})
            rd.origin[("sections", str(len(sections)))] = (line, f"mission item {n} (TAKEOFF)")
            sections.append({"type": "TakeOff", "name": f"item {n} take-off", "runway": "HOME",
                             "pitch_deg": d["takeoff_pitch_deg"], "climb_speed": {"cas_m_s": d["climb_cas_m_s"]},
                             "until_height_agl_m": max(alt - home_alt, 20.0)})
            prev = home
            continue
        if cmd == MAV_CMD["WAYPOINT"]:
            name = f"WP{n}"
            waypoints[name] = {"lat_deg": lat, "lon_deg": lon}
            rd.origin[("places", "waypoints", name)] = (at, f"mission item {n} (WAYPOINT)")
            last = sections[-1] if sections else None
            if last and last["type"] == "WaypointFollowing" and last["altitude_m"] == alt:
                last["waypoints"].append(name)
            else:
                rd.origin[("sections", str(len(sections)))] = (line, f"mission item {n} (WAYPOINT)")
                sections.append({"type": "WaypointFollowing", "name": f"item {n} waypoints", "waypoints": [name],
                                 "altitude_m": alt, "speed": {"tas_m_s": cruise}})
        elif cmd == MAV_CMD["LOITER_TURNS"]:
            name = f"WP{n}"
            waypoints[name] = {"lat_deg": lat, "lon_deg": lon}
            rd.origin[("places", "waypoints", name)] = (at, f"mission item {n} (LOITER_TURNS)")
            radius = rd.number(params[2], -1e5, 1e5, at, f"mission item {n} (LOITER_TURNS): param3 radius [m]")
            if radius == 0.0:
                raise rd.fail(at, f"mission item {n} (LOITER_TURNS): param3 radius is 0; "
                              "give the orbit radius [m] (negative for counter-clockwise)")
            turns = rd.number(params[0], 0.0, 1e3, at, f"mission item {n} (LOITER_TURNS): param1 turns")
            rd.origin[("sections", str(len(sections)))] = (line, f"mission item {n} (LOITER_TURNS)")
            sections.append({"type": "Orbiting", "name": f"item {n} loiter", "center": name,
                             "radius_m": abs(radius), "direction": "clockwise" if radius > 0 else "counterclockwise",
                             "turns": turns, "altitude_m": alt, "speed": {"tas_m_s": cruise}})
        elif cmd == MAV_CMD["LAND"]:
            problem = leg_problem(prev, pos)
            if problem is not None:
                raise rd.fail(at, f"mission item {n} (LAND): the approach from the preceding item {problem}; the "
                              "approach direction needs a preceding item away from the land point")
            hdg = math.degrees(initial_bearing_rad(prev, pos)) % 360
            runways["LAND"] = {"threshold_lat_deg": lat, "threshold_lon_deg": lon, "heading_deg": hdg,
                               "elevation_m": alt, "length_m": d["runway_length_m"], "width_m": d["runway_width_m"]}
            rd.origin[("places", "runways", "LAND")] = (at, f"mission item {n} (LAND)")
            rd.origin[("sections", str(len(sections)))] = (line, f"mission item {n} (LAND)")
            sections.append({"type": "Landing", "name": f"item {n} landing", "runway": "LAND",
                             "approach_altitude_m": alt + d["approach_height_m"],
                             "approach_speed": {"cas_m_s": d["approach_cas_m_s"]}})
        prev = pos
    name = plan.get("name", source)
    doc = {"mission": {"name": name if isinstance(name, str) else source, "description": f"converted from {source}"},
           "places": {"runways": runways, "waypoints": waypoints}, "sections": sections}
    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=False), rd


def plan_to_yaml(text: str, source: str = "<plan>") -> str:
    """Convert the JSON text of a QGroundControl plan into mission YAML.

    Raises
    ------
    MissionError
        If the plan is not valid JSON, has no mission items, or has an item we cannot map; with the
        plan's file and line.
    """
    return _convert(text, source)[0]


def convert_plan(text: str, source: str = "<plan>") -> tuple[str, Callable[[MissionError], MissionError]]:
    """The mission YAML of a QGroundControl plan (:func:`plan_to_yaml`), and the function that turns an error of
    that YAML read as ``source (converted)`` into one naming the plan's line and mission item.

    Raises
    ------
    MissionError
        A plan that cannot be converted (:func:`plan_to_yaml`).
    """
    from .marks import Lines

    converted, rd = _convert(text, source)
    tag = f"{source} (converted)"

    def locate(exc: MissionError) -> MissionError:
        head, _, rest = str(exc).partition(": ")
        line = head.removeprefix(tag + ":")
        if not head.startswith(tag) or not line.isdigit():
            return exc
        paths = [p for p, n in Lines(converted).map.items() if n == int(line)]
        for path in sorted(paths, key=len):
            for depth in (3, 2):
                origin = rd.origin.get(tuple(str(x) for x in path[:depth]))
                if origin is not None:
                    return MissionError(f"{source}:{origin[0]}: {origin[1]}: {rest}")
        return MissionError(f"{source}: {rest} (in the mission converted from the plan)")

    return converted, locate
