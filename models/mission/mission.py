"""Mission files: a documented YAML format of stacked sections, its validation, and
the import of QGroundControl ``.plan`` files.

Format (see ``missions/munich.yaml`` for a complete example)::

    mission: {name: str, description: str}          # description optional
    places:
      runways:                                       # named runway directions
        EDDM_26R: {threshold_lat_deg: 48.36, threshold_lon_deg: 11.81, heading_deg: 262.5,
                   elevation_m: 448, length_m: 4000, width_m: 60}
      waypoints:
        A: {lat_deg: 48.40, lon_deg: 11.55}
    sections:                                        # flown in this order
      - {type: Rolling, runway: EDDM_08R, lever: 1.0, rotate_cas_m_s: 62}
      - {type: TakeOff, runway: EDDM_08R, pitch_deg: 10, climb_speed: {cas_m_s: 80},
         until_height_agl_m: 300}
      - {type: WaypointFollowing, waypoints: [A, B], altitude_m: 5000, speed: {mach: 0.6}}
      - {type: WaypointFollowing, waypoints: [C, D], altitude_m: 2500, altitude_at: C,
         speed: {mach: 0.5}}                         # altitude due at C (default: the last)
      - {type: Orbiting, center: C, radius_m: 10000, direction: clockwise, turns: 2,
         altitude_m: 2500, speed: {mach: 0.6}}
      - {type: GTurns, load_factor: 2.0, heading_change_deg: 360, direction: right}
      - {type: Levelling, altitude_m: 5000, speed: {mach: 0.6}}
      - {type: Landing, runway: EDDM_26R, approach_altitude_m: 1200, approach_speed: {cas_m_s: 65}}
      - {type: Custom, duration_s: 60, commands: [{t_s: 0, lever: 0.8, pitch_deg: 3, bank_deg: 0}]}
    wind: {layers: [{alt_m: 450, from_deg: 240, speed_kt: 8}, {alt_m: 1500, from_deg: 260, speed_kt: 20}]}
    turbulence: {severity: light, seed: 7}           # wind and turbulence optional: see .weather

A speed is a mapping with exactly one of ``mach`` [-], ``cas_m_s`` or ``tas_m_s``
[m/s]. Every section may have a ``name``. The fields of each section type, with
their units, ranges and defaults, and the completion criterion of each type
are declared by its class in :mod:`.sections` (:data:`SECTION_FIELDS` is their view).

Validation collects nothing silently: the first problem raises a
:class:`MissionError` whose message names the file and line (from the YAML
node marks), the section (index and type) and the field, and says what is
allowed. Every value is typed where it is read (:mod:`openemss.models.infra.values`:
numbers finite and in range, names as text, no Boolean, null, list or mapping where
a single value is), and the route is checked as a whole: two consecutive fixes of a
leg that coincide or are antipodal (no great-circle course between them) are refused
here, not when the aircraft reaches them.

References
----------
QGroundControl plan file format, https://docs.qgroundcontrol.com/master/en/qgc-dev-guide/file_formats/plan.html;
MAVLink common message set, MAV_CMD_NAV_WAYPOINT (16), MAV_CMD_NAV_LOITER_TURNS (18),
MAV_CMD_NAV_LAND (21), MAV_CMD_NAV_TAKEOFF (22), https://mavlink.io/en/messages/common.html.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..infra import safe_yaml, values
from .errors import MissionError
from .geo import LatLon, leg_problem
from .marks import Context as _Ctx
from .marks import Lines as _Lines
from .marks import check_notes
from .qgc import convert_plan
from .runway import Runway
from .sections import REGISTRY, Field
from .speed import SpeedCommand, SpeedKind
from .weather import WEATHER_KEYS, Weather, parse_weather

__all__ = ["SECTION_TYPES", "SECTION_FIELDS", "Section", "Mission", "load_mission", "parse_mission",
           "parse_mission_file", "speed_from_mapping", "departure_runway"]

#: The fields of each section type (a view on :data:`.sections.REGISTRY`, where each type's class
#: declares them): field -> (kind, required, default, (min, max) or choices, unit and help).
SECTION_FIELDS: dict[str, dict[str, Field]] = {name: cls.fields for name, cls in REGISTRY.items()}
SECTION_TYPES: tuple[str, ...] = tuple(REGISTRY)
_CUSTOM_KEYS = {"t_s": (0.0, 36000.0), "lever": (0.0, 1.0), "pitch_deg": (-20.0, 30.0), "bank_deg": (-80.0, 80.0)}
_RUNWAY_KEYS = {"threshold_lat_deg": (-90.0, 90.0), "threshold_lon_deg": (-180.0, 180.0),
                "heading_deg": (0.0, 360.0), "elevation_m": (-400.0, 5000.0),
                "length_m": (100.0, 6000.0), "width_m": (5.0, 100.0)}
_WP_KEYS = {"lat_deg": (-90.0, 90.0), "lon_deg": (-180.0, 180.0)}


@dataclass(frozen=True, slots=True)
class Section:
    """One mission section: its type, name, index and validated fields.

    Fields are SI as in the file, with runways as :class:`~.runway.Runway`,
    waypoints as :class:`~.geo.LatLon`, speeds as :class:`~.speed.SpeedCommand`.
    """

    index: int
    type: str
    name: str
    fields: tuple[tuple[str, Any], ...]

    def __getitem__(self, key: str) -> Any:
        for k, v in self.fields:
            if k == key:
                return v
        raise KeyError(f"section {self.index} ({self.type}) has no field '{key}'")

    def get(self, key: str, default: Any = None) -> Any:
        """Field value or ``default``."""
        try:
            return self[key]
        except KeyError:
            return default


@dataclass(frozen=True, slots=True)
class Mission:
    """A validated mission."""

    name: str
    description: str
    runways: tuple[tuple[str, Any], ...]
    waypoints: tuple[tuple[str, LatLon], ...]
    sections: tuple[Section, ...]
    source: str
    #: winds aloft and turbulence of the top-level ``wind`` and ``turbulence`` keys (:mod:`.weather`)
    weather: Weather | None = None

    def waypoint(self, name: str) -> LatLon:
        """Waypoint by name."""
        return dict(self.waypoints)[name]

    def runway(self, name: str) -> Any:
        """Runway by name."""
        return dict(self.runways)[name]


def speed_from_mapping(m: Any) -> SpeedCommand:
    """SpeedCommand from ``{mach: x}``, ``{cas_m_s: x}`` or ``{tas_m_s: x}`` (raises ValueError)."""
    kinds = {"mach": (SpeedKind.MACH, (0.05, 0.95)), "cas_m_s": (SpeedKind.CAS, (10.0, 350.0)),
             "tas_m_s": (SpeedKind.TAS, (10.0, 350.0))}
    if not isinstance(m, dict) or len(m) != 1 or next(iter(m)) not in kinds:
        raise ValueError("a speed is a mapping with exactly one of mach [-], cas_m_s or tas_m_s [m/s], "
                         f"got {values.show(m) if not isinstance(m, dict) else 'keys ' + ', '.join(map(str, m))}")
    key, val = next(iter(m.items()))
    kind, (lo, hi) = kinds[key]
    return SpeedCommand(values.number(val, lo, hi), kind)


def _mapping(ctx: _Ctx, path: tuple, v: Any, what: str) -> dict:
    """``v`` as a mapping (an absent or empty value: an empty one)."""
    if v is None:
        return {}
    if not isinstance(v, dict):
        raise ctx.fail(path, f"{what}: expected a mapping, got {values.show(v)}")
    return v


def _place_name(ctx: _Ctx, path: tuple, key: Any, what: str) -> str:
    try:
        return values.name(key, f"a {what} name")
    except ValueError as e:
        raise ctx.fail(path, f"{what} {key!r}: {e}") from None


def _places(doc: dict, ctx: _Ctx) -> tuple[dict, dict]:
    places = doc.get("places", {}) or {}
    if not isinstance(places, dict):
        raise ctx.fail(("places",), "places: expected a mapping with 'runways' and 'waypoints'")
    unknown = sorted(map(str, set(places) - {"runways", "waypoints"}))
    if unknown:
        raise ctx.fail(("places", unknown[0]), f"places: unknown key '{unknown[0]}'; allowed: runways, waypoints")
    runways: dict[str, Runway] = {}
    for key, r in _mapping(ctx, ("places", "runways"), places.get("runways"), "places: runways").items():
        path = ("places", "runways", key)
        name = _place_name(ctx, path, key, "runway")
        if not isinstance(r, dict):
            raise ctx.fail(path, f"runway '{name}': expected a mapping with {', '.join(_RUNWAY_KEYS)}, "
                           f"got {values.show(r)}")
        extra = sorted(map(str, set(r) - set(_RUNWAY_KEYS) - {"source", "uncertainty"}))
        if extra:
            raise ctx.fail(path + (extra[0],), f"runway '{name}': unknown field '{extra[0]}'; "
                           f"allowed: {', '.join(_RUNWAY_KEYS)}, source, uncertainty")
        vals = {}
        for k, (lo, hi) in _RUNWAY_KEYS.items():
            if k not in r and k in ("length_m", "width_m"):
                continue
            if k not in r:
                raise ctx.fail(path, f"runway '{name}': missing field '{k}'")
            try:
                vals[k] = values.number(r[k], lo, hi)
            except ValueError as e:
                raise ctx.fail(path + (k,), f"runway '{name}' field '{k}': {e}") from None
        check_notes(r, ("source", "uncertainty"), f"runway '{name}'", path, ctx.fail)
        if name in runways:
            raise ctx.fail(path, f"runway '{name}' is defined twice (keys {key!r} and {str(key)!r} name the same "
                           "runway); give each name once")
        runways[name] = Runway(name, LatLon.from_deg(vals["threshold_lat_deg"], vals["threshold_lon_deg"]),
                               math.radians(vals["heading_deg"]), vals["elevation_m"],
                               vals.get("length_m", 3000.0), vals.get("width_m", 45.0))
    waypoints: dict[str, LatLon] = {}
    for key, w in _mapping(ctx, ("places", "waypoints"), places.get("waypoints"), "places: waypoints").items():
        path = ("places", "waypoints", key)
        name = _place_name(ctx, path, key, "waypoint")
        if not isinstance(w, dict) or set(w) - set(_WP_KEYS) - {"note"} or not set(_WP_KEYS) <= set(w):
            got = values.show(w) if not isinstance(w, dict) else "fields " + ", ".join(map(str, w))
            raise ctx.fail(path, f"waypoint '{name}': expected {{lat_deg, lon_deg}} (and an optional note), got {got}")
        coords = []
        for k, (lo, hi) in _WP_KEYS.items():
            try:
                coords.append(values.number(w[k], lo, hi))
            except ValueError as e:
                raise ctx.fail(path + (k,), f"waypoint '{name}' field '{k}': {e}") from None
        check_notes(w, ("note",), f"waypoint '{name}'", path, ctx.fail)
        if name in waypoints:
            raise ctx.fail(path, f"waypoint '{name}' is defined twice (keys {key!r} and {str(key)!r} name the same "
                           "waypoint); give each name once")
        waypoints[name] = LatLon.from_deg(*coords)
    return runways, waypoints


def _field(kind: str, spec: Any, v: Any, runways: dict, waypoints: dict) -> Any:
    if kind == "number":
        return values.number(v, *spec)
    if kind == "bool":
        return values.flag(v)
    if kind == "choice":
        return values.choice(v, spec)
    if kind == "speed":
        return speed_from_mapping(v)
    if kind == "runway":
        return _ref(v, runways, "runway")
    if kind == "waypoint":
        return _ref(v, waypoints, "waypoint")
    if kind == "waypoints":
        if not isinstance(v, list) or not v:
            raise ValueError(f"expected a non-empty list of waypoint names, got {values.show(v)}")
        return tuple(_ref(w, waypoints, "waypoint") for w in v)
    if kind == "commands":
        if not isinstance(v, list) or not v:
            raise ValueError(f"expected a non-empty list of {{t_s, lever, pitch_deg, bank_deg}}, got {values.show(v)}")
        pts = []
        for i, c in enumerate(v):
            if not isinstance(c, dict) or set(c) != set(_CUSTOM_KEYS):
                got = values.show(c) if not isinstance(c, dict) else "fields " + ", ".join(map(str, c))
                raise ValueError(f"command {i}: each command needs exactly {', '.join(_CUSTOM_KEYS)}, got {got}")
            pt = []
            for k, rng in _CUSTOM_KEYS.items():
                try:
                    pt.append(values.number(c[k], *rng))
                except ValueError as e:
                    raise ValueError(f"command {i} '{k}': {e}") from None
            pts.append(tuple(pt))
        if any(b[0] <= a[0] for a, b in zip(pts, pts[1:], strict=False)):
            raise ValueError("command times t_s must increase")
        return tuple(pts)
    raise AssertionError(kind)


def _ref(v: Any, defined: dict, what: str) -> Any:
    """The place a field names (a runway or a waypoint)."""
    key = values.name(v, f"a {what} name")
    if key not in defined:
        raise ValueError(f"unknown {what} {key!r}; defined {what}s: {', '.join(defined) or '(none)'}")
    return defined[key]


def _route(sections: list[Section], raw: list[dict], ctx: _Ctx) -> None:
    """Refuse a leg between two fixes with no great-circle course: consecutive waypoints of a section (its type's
    field of kind ``waypoints``), and with fly-by the last one and where the next section begins (its turn is
    anticipated towards it)."""
    for k, sec in enumerate(sections):
        route = next((n for n, f in REGISTRY[sec.type].fields.items() if f[0] == "waypoints"), None)
        if route is None:
            continue
        fixes = list(sec[route])
        nxt = REGISTRY[sections[k + 1].type].entry_fix(sections[k + 1]) if k + 1 < len(sections) else None
        if sec.get("fly_by") and nxt is not None:
            fixes.append(nxt)
        for i, (a, b) in enumerate(zip(fixes, fixes[1:], strict=False)):
            problem = leg_problem(a, b)
            if problem is None:
                continue
            names = [values.name(w) for w in raw[k][route]]
            names.append(f"where section {k + 1} ({sections[k + 1].type}) begins" if k + 1 < len(sections) else "")
            first, second = names[i], names[i + 1]
            raise ctx.fail(("sections", sec.index, route),
                           f"section {sec.index} ({sec.type}) field '{route}': the leg from {first} to "
                           f"{second} {problem}")


def parse_mission(text: str, source: str = "<mission>") -> Mission:
    """Validate the YAML ``text`` of a mission (``source`` names it in errors).

    Raises
    ------
    MissionError
        For the first problem found, with file:line, section and field.
    """
    try:  # the project's one YAML reader: duplicate keys, alias bombs, NaN refused with file:line
        doc = safe_yaml.load(text, source)
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    ctx = _Ctx(source, _Lines(text))
    if not isinstance(doc, dict):
        raise ctx.fail((), "a mission file is a mapping with 'mission', 'places' and 'sections'")
    unknown = sorted(map(str, set(doc) - {"mission", "places", "sections", *WEATHER_KEYS}))
    if unknown:
        raise ctx.fail((unknown[0],), f"unknown top-level key '{unknown[0]}'; allowed: mission, places, sections, "
                       f"{', '.join(WEATHER_KEYS)}")
    head = doc.get("mission") or {}
    if not isinstance(head, dict) or "name" not in head:
        raise ctx.fail(("mission",), "mission: expected a mapping with 'name' (and 'description')")
    extra = sorted(map(str, set(head) - {"name", "description"}))
    if extra:
        raise ctx.fail(("mission", extra[0]), f"mission: unknown key '{extra[0]}'; allowed: name, description")
    try:
        title = values.text(head["name"], "the mission's name (text)")
        description = "" if head.get("description") is None else values.text(head["description"])
    except ValueError as e:
        raise ctx.fail(("mission",), f"mission: {e}") from None
    runways, waypoints = _places(doc, ctx)
    secs = doc.get("sections")
    if not isinstance(secs, list) or not secs:
        raise ctx.fail(("sections",), f"sections: expected a non-empty list of sections, got {values.show(secs)}")
    sections = []
    for i, s in enumerate(secs):
        path = ("sections", i)
        if not isinstance(s, dict) or "type" not in s:
            raise ctx.fail(path, f"section {i}: expected a mapping with a 'type' ({', '.join(REGISTRY)})")
        typ = s["type"]
        if not isinstance(typ, str) or typ not in REGISTRY:
            got = repr(typ) if isinstance(typ, str) else values.show(typ)
            raise ctx.fail(path + ("type",), f"section {i}: unknown section type {got}; allowed: {', '.join(REGISTRY)}")
        spec = REGISTRY[typ].fields
        where = f"section {i} ({typ})"
        extra = sorted(map(str, set(s) - set(spec) - {"type", "name"}))
        if extra:
            raise ctx.fail(path + (extra[0],), f"{where}: unknown field '{extra[0]}'; allowed: {', '.join(spec)}, name")
        try:
            name = values.text(s["name"], "a section name (text)") if "name" in s else typ
        except ValueError as e:
            raise ctx.fail(path + ("name",), f"{where} field 'name': {e}") from None
        fields: list[tuple[str, Any]] = []
        for key, (kind, required, default, rng, help_) in spec.items():
            if key not in s:
                if required:
                    raise ctx.fail(path, f"{where}: missing field '{key}' ({help_})")
                fields.append((key, default))
                continue
            try:
                fields.append((key, _field(kind, rng, s[key], runways, waypoints)))
            except ValueError as e:
                raise ctx.fail(path + (key,), f"{where} field '{key}': {e}") from None
        problem = REGISTRY[typ].check(dict(fields), s)
        if problem is not None:
            key, what = problem
            raise ctx.fail(path + ((key,) if key else ()), f"{where}{f' field {key!r}' if key else ''}: {what}")
        sections.append(Section(i, typ, name, tuple(fields)))
    _route(sections, secs, ctx)
    return Mission(title, description, tuple(runways.items()),
                   tuple(waypoints.items()), tuple(sections), source, parse_weather(doc, ctx.fail, source))


def load_mission(path: str | Path) -> Mission:
    """Read and validate a mission file (YAML, or a QGroundControl ``.plan``)."""
    p = Path(path)
    try:
        text = safe_yaml.read_text(p, "mission file")
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    return parse_mission_file(text, str(p))


def parse_mission_file(text: str, source: str) -> Mission:
    """Validate the text of a mission file named ``source``: a QGroundControl plan when ``source`` ends in
    ``.plan`` (converted, errors naming the plan's lines), else a mission YAML file."""
    if not source.endswith(".plan"):
        return parse_mission(text, source)
    converted, locate = convert_plan(text, source)
    try:
        return dataclasses.replace(parse_mission(converted, f"{source} (converted)"), source=source)
    except MissionError as exc:
        raise locate(exc) from None


def departure_runway(mission: Mission) -> Any:
    """The runway of the mission's first section that names one (its take-off roll), or None.

    The FMUs start on it by default (the airframe's position, the flight control's input starts),
    so that the runway's data are written once, in the mission file.
    """
    for s in mission.sections:
        rwy = s.get("runway")
        if rwy is not None:
            return rwy
    return None
