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
allowed.

References
----------
QGroundControl plan file format, https://docs.qgroundcontrol.com/master/en/qgc-dev-guide/file_formats/plan.html;
MAVLink common message set, MAV_CMD_NAV_WAYPOINT (16), MAV_CMD_NAV_LOITER_TURNS (18),
MAV_CMD_NAV_LAND (21), MAV_CMD_NAV_TAKEOFF (22), https://mavlink.io/en/messages/common.html.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..common import safe_yaml
from .errors import MissionError
from .geo import LatLon
from .marks import Context as _Ctx
from .sections import REGISTRY, Field
from .marks import Lines as _Lines
from .tecs import SpeedCommand, SpeedKind
from .weather import WEATHER_KEYS, Weather, parse_weather

__all__ = ["SECTION_TYPES", "SECTION_FIELDS", "Section", "Mission", "load_mission", "parse_mission",
           "speed_from_mapping", "departure_runway"]

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

    Fields are SI as in the file, with runways as :class:`~.approach.Runway`,
    waypoints as :class:`~.geo.LatLon`, speeds as :class:`~.tecs.SpeedCommand`.
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
                         f"got {m!r}")
    key, val = next(iter(m.items()))
    kind, (lo, hi) = kinds[key]
    x = _number(val, lo, hi)
    return SpeedCommand(x, kind)


def _number(v: Any, lo: float, hi: float) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(float(v)):
        raise ValueError(f"expected a number in [{lo}, {hi}], got {v!r}")
    if not lo <= float(v) <= hi:
        raise ValueError(f"value {v} outside the allowed range [{lo}, {hi}]")
    return float(v)


def _places(doc: dict, ctx: _Ctx) -> tuple[dict, dict]:
    from .approach import Runway  # local import: approach imports guidance, keep mission light

    places = doc.get("places", {}) or {}
    if not isinstance(places, dict):
        raise ctx.fail(("places",), "places: expected a mapping with 'runways' and 'waypoints'")
    unknown = set(places) - {"runways", "waypoints"}
    if unknown:
        raise ctx.fail(("places", sorted(unknown)[0]), f"places: unknown key '{sorted(unknown)[0]}'; "
                       "allowed: runways, waypoints")
    runways: dict[str, Runway] = {}
    for name, r in (places.get("runways") or {}).items():
        path = ("places", "runways", name)
        if not isinstance(r, dict):
            raise ctx.fail(path, f"runway '{name}': expected a mapping with {', '.join(_RUNWAY_KEYS)}")
        vals = {}
        for key, (lo, hi) in _RUNWAY_KEYS.items():
            if key not in r and key in ("length_m", "width_m"):
                continue
            if key not in r:
                raise ctx.fail(path, f"runway '{name}': missing field '{key}'")
            try:
                vals[key] = _number(r[key], lo, hi)
            except ValueError as e:
                raise ctx.fail(path + (key,), f"runway '{name}' field '{key}': {e}") from None
        extra = set(r) - set(_RUNWAY_KEYS) - {"source", "uncertainty"}
        if extra:
            raise ctx.fail(path + (sorted(extra)[0],), f"runway '{name}': unknown field '{sorted(extra)[0]}'; "
                           f"allowed: {', '.join(_RUNWAY_KEYS)}, source, uncertainty")
        runways[name] = Runway(str(name), LatLon.from_deg(vals["threshold_lat_deg"], vals["threshold_lon_deg"]),
                               math.radians(vals["heading_deg"]), vals["elevation_m"],
                               vals.get("length_m", 3000.0), vals.get("width_m", 45.0))
    waypoints: dict[str, LatLon] = {}
    for name, w in (places.get("waypoints") or {}).items():
        path = ("places", "waypoints", name)
        if not isinstance(w, dict) or set(w) - set(_WP_KEYS) - {"note"} or not set(_WP_KEYS) <= set(w):
            raise ctx.fail(path, f"waypoint '{name}': expected {{lat_deg, lon_deg}} (and an optional note), got {w!r}")
        try:
            waypoints[str(name)] = LatLon.from_deg(*(_number(w[k], *_WP_KEYS[k]) for k in _WP_KEYS))
        except ValueError as e:
            raise ctx.fail(path, f"waypoint '{name}': {e}") from None
    return runways, waypoints


def _field(kind: str, spec: Any, v: Any, runways: dict, waypoints: dict) -> Any:
    if kind == "number":
        return _number(v, *spec)
    if kind == "bool":
        if not isinstance(v, bool):
            raise ValueError(f"expected true or false, got {v!r}")
        return v
    if kind == "choice":
        if v not in spec:
            raise ValueError(f"got {v!r}; allowed: {', '.join(spec)}")
        return v
    if kind == "speed":
        return speed_from_mapping(v)
    if kind == "runway":
        if v not in runways:
            raise ValueError(f"unknown runway {v!r}; defined runways: {', '.join(runways) or '(none)'}")
        return runways[v]
    if kind == "waypoint":
        if v not in waypoints:
            raise ValueError(f"unknown waypoint {v!r}; defined waypoints: {', '.join(waypoints) or '(none)'}")
        return waypoints[v]
    if kind == "waypoints":
        if not isinstance(v, list) or not v:
            raise ValueError("expected a non-empty list of waypoint names")
        out = []
        for w in v:
            if w not in waypoints:
                raise ValueError(f"unknown waypoint {w!r}; defined waypoints: {', '.join(waypoints) or '(none)'}")
            out.append(waypoints[w])
        return tuple(out)
    if kind == "commands":
        if not isinstance(v, list) or not v:
            raise ValueError("expected a non-empty list of {t_s, lever, pitch_deg, bank_deg}")
        pts = []
        for c in v:
            if not isinstance(c, dict) or set(c) != set(_CUSTOM_KEYS):
                raise ValueError(f"each command needs exactly {', '.join(_CUSTOM_KEYS)}, got {c!r}")
            pts.append(tuple(_number(c[k], *_CUSTOM_KEYS[k]) for k in _CUSTOM_KEYS))
        if any(b[0] <= a[0] for a, b in zip(pts, pts[1:], strict=False)):
            raise ValueError("command times t_s must increase")
        return tuple(pts)
    raise AssertionError(kind)


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
    unknown = set(doc) - {"mission", "places", "sections", *WEATHER_KEYS}
    if unknown:
        k = sorted(unknown)[0]
        raise ctx.fail((k,), f"unknown top-level key '{k}'; allowed: mission, places, sections, "
                       f"{', '.join(WEATHER_KEYS)}")
    head = doc.get("mission") or {}
    if not isinstance(head, dict) or "name" not in head:
        raise ctx.fail(("mission",), "mission: expected a mapping with 'name' (and 'description')")
    runways, waypoints = _places(doc, ctx)
    secs = doc.get("sections")
    if not isinstance(secs, list) or not secs:
        raise ctx.fail(("sections",), "sections: expected a non-empty list of sections")
    sections = []
    for i, s in enumerate(secs):
        path = ("sections", i)
        if not isinstance(s, dict) or "type" not in s:
            raise ctx.fail(path, f"section {i}: expected a mapping with a 'type' ({', '.join(REGISTRY)})")
        typ = s["type"]
        if typ not in REGISTRY:
            raise ctx.fail(path + ("type",), f"section {i}: unknown section type {typ!r}; "
                           f"allowed: {', '.join(REGISTRY)}")
        spec = REGISTRY[typ].fields
        where = f"section {i} ({typ})"
        extra = set(s) - set(spec) - {"type", "name"}
        if extra:
            k = sorted(extra)[0]
            raise ctx.fail(path + (k,), f"{where}: unknown field '{k}'; allowed: {', '.join(spec)}, name")
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
        sections.append(Section(i, typ, str(s.get("name", typ)), tuple(fields)))
    return Mission(str(head["name"]), str(head.get("description", "")), tuple(runways.items()),
                   tuple(waypoints.items()), tuple(sections), source, parse_weather(doc, ctx.fail, source))


def load_mission(path: str | Path) -> Mission:
    """Read and validate a mission file (YAML, or a QGroundControl ``.plan``)."""
    p = Path(path)
    try:
        text = safe_yaml.read_text(p, "mission file")
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    if p.suffix == ".plan":
        from .qgc import plan_to_yaml

        return parse_mission(plan_to_yaml(text, str(p)), str(p) + " (converted)")
    return parse_mission(text, str(p))


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
