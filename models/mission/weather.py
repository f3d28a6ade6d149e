"""Winds aloft and turbulence of a mission: the ``wind`` and ``turbulence`` keys of a mission file.

Format (top-level keys of a mission file, or of a weather file that holds only them)::

    wind:
      layers:                                  # at least one; altitudes increasing
        - {alt_m: 450,  from_deg: 240, speed_kt: 8}
        - {alt_m: 1500, from_deg: 260, speed_kt: 20}
        - {alt_m: 7500, from_deg: 270, speed_m_s: 10.3}
    turbulence: {severity: light, seed: 7}     # light | moderate | severe | none, or 0 to 7

A layer gives the wind at an altitude above mean sea level [m]: the true direction it blows
*from* [deg] (meteorological convention, 270 = a west wind blowing towards the east) and its
speed, exactly one of ``speed_m_s`` [m/s] or ``speed_kt`` [kt]. Between layers the wind's
north and east components are interpolated linearly in altitude (components, not direction and
speed: a wind veering through north interpolates without a jump); below the lowest layer and
above the highest the nearest layer's wind holds. Every layer may carry a ``note``.

Turbulence is JSBSim's MIL-F-8785C model (Dryden spectrum; ``atmosphere/turb-type`` 3) [1]_ [2]_:
``severity`` is the probability-of-exceedance curve of MIL-F-8785C figure 7 that sets the
intensity above 2000 ft, 0 (off) to 7, or a name with JSBSim's reference values [2]_: ``light``
= 3, ``moderate`` = 4, ``severe`` = 6. ``wind_20ft_m_s`` or ``wind_20ft_kt`` (optional) is the wind
speed 20 ft above ground that sets the intensity below 1000 ft (MIL-F-8785C figure 11); by default
the reference value of the severity: 15 kt for severities 1 to 3, 30 kt for 4 and 5, 45 kt for 6
and 7 [2]_. ``seed`` (integer >= 0, default 0) seeds JSBSim's random generator, so a run is
repeated exactly.

The flight control system reads these keys with the rest of its mission (and the feasibility
check uses the wind); the airframe, which owns the atmosphere, applies them when its
``weather_file`` parameter names the file (:func:`load_weather`).

References
----------
.. [1] MIL-F-8785C, *Military Specification: Flying Qualities of Piloted Airplanes*, 1980,
   sect. 3.7 (atmospheric disturbances), figures 7, 10 and 11.
.. [2] JSBSim, ``src/models/atmosphere/FGWinds.h`` (class documentation: turbulence intensities
   light/moderate/severe = severity 3/4/6 with 15/30/45 kt at 20 ft), github.com/JSBSim-Team/jsbsim.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..infra import safe_yaml, values
from .errors import MissionError
from .marks import Context, Lines, check_notes

__all__ = ["WindLayer", "WindProfile", "Turbulence", "Weather", "WEATHER_KEYS", "SEVERITIES", "KT_M_S",
           "parse_weather", "parse_weather_text", "load_weather"]

KT_M_S = 1852.0 / 3600.0  # [m/s per kt], exact by definition of the knot
#: Top-level keys of a mission file that this module reads.
WEATHER_KEYS = ("wind", "turbulence")
#: Named turbulence severities (JSBSim's reference values) and the default wind at 20 ft of each [kt].
SEVERITIES: dict[str, int] = {"none": 0, "light": 3, "moderate": 4, "severe": 6}
_W20_KT = (0.0, 15.0, 15.0, 15.0, 30.0, 30.0, 45.0, 45.0)  # by severity 0..7
_ALT_RANGE_M = (-400.0, 20000.0)
_SPEED_RANGE = {"speed_m_s": (0.0, 100.0), "speed_kt": (0.0, 200.0)}
_W20_RANGE = {"wind_20ft_m_s": (0.0, 50.0), "wind_20ft_kt": (0.0, 100.0)}
_MISSION_KEYS = ("mission", "places", "sections")

Fail = Callable[[tuple, str], Exception]


@dataclass(frozen=True, slots=True)
class WindLayer:
    """The wind at one altitude.

    Attributes
    ----------
    alt_m : float
        Altitude above mean sea level [m].
    from_deg : float
        True direction the wind blows from [deg].
    speed_m_s : float
        Wind speed [m/s].
    """

    alt_m: float
    from_deg: float
    speed_m_s: float

    @property
    def north_m_s(self) -> float:
        """Wind velocity towards north [m/s]."""
        return -self.speed_m_s * math.cos(math.radians(self.from_deg))

    @property
    def east_m_s(self) -> float:
        """Wind velocity towards east [m/s]."""
        return -self.speed_m_s * math.sin(math.radians(self.from_deg))


@dataclass(frozen=True, slots=True)
class WindProfile:
    """Winds aloft: layers by increasing altitude, components interpolated linearly between them."""

    layers: tuple[WindLayer, ...]

    def ne_m_s(self, alt_m: float) -> tuple[float, float]:
        """Wind velocity (towards north, towards east) [m/s] at altitude ``alt_m`` [m] MSL."""
        ls = self.layers
        if alt_m <= ls[0].alt_m:
            return ls[0].north_m_s, ls[0].east_m_s
        for lo, hi in zip(ls, ls[1:], strict=False):
            if alt_m <= hi.alt_m:
                f = (alt_m - lo.alt_m) / (hi.alt_m - lo.alt_m)
                return (lo.north_m_s + f * (hi.north_m_s - lo.north_m_s),
                        lo.east_m_s + f * (hi.east_m_s - lo.east_m_s))
        return ls[-1].north_m_s, ls[-1].east_m_s

    def ned_m_s(self, alt_m: float) -> tuple[float, float, float]:
        """Wind velocity north, east, down [m/s] at ``alt_m`` [m] MSL (winds aloft are horizontal)."""
        n, e = self.ne_m_s(alt_m)
        return n, e, 0.0

    @property
    def max_speed_m_s(self) -> float:
        """Strongest wind of the layers [m/s] (interpolation never exceeds it)."""
        return max(layer.speed_m_s for layer in self.layers)


@dataclass(frozen=True, slots=True)
class Turbulence:
    """MIL-F-8785C turbulence as JSBSim models it.

    Attributes
    ----------
    severity : int
        Probability-of-exceedance curve, 0 (off) to 7 [-].
    wind_20ft_m_s : float
        Wind speed 20 ft above ground, the low-altitude intensity [m/s].
    seed : int
        Seed of JSBSim's random generator [-].
    label : str
        How the file named it (``light``, ``3``, ...).
    """

    severity: int
    wind_20ft_m_s: float
    seed: int
    label: str


@dataclass(frozen=True, slots=True)
class Weather:
    """The weather of a mission file: winds aloft and turbulence, either may be absent."""

    wind: WindProfile | None
    turbulence: Turbulence | None
    source: str

    def describe(self) -> str:
        """One line for messages, e.g. ``wind 10-20 kt, light turbulence (severity 3, seed 7)``."""
        parts = []
        if self.wind is not None:
            speeds = [layer.speed_m_s / KT_M_S for layer in self.wind.layers]
            span = f"{min(speeds):.0f}" if max(speeds) - min(speeds) < 0.5 else f"{min(speeds):.0f}-{max(speeds):.0f}"
            parts.append(f"wind {span} kt in {len(speeds)} layer(s)")
        if self.turbulence is not None and self.turbulence.severity > 0:
            t = self.turbulence
            name = t.label if t.label in SEVERITIES else f"severity {t.severity}"
            parts.append(f"{name} turbulence (severity {t.severity}, seed {t.seed})")
        return ", ".join(parts) or "still air"


def _one_of(m: Mapping, choices: Mapping[str, tuple[float, float]], what: str, path: tuple, fail: Fail,
            required: bool) -> tuple[str, float] | None:
    given = [k for k in choices if k in m]
    if len(given) > 1 or (required and not given):
        raise fail(path, f"{what}: give exactly one of {', '.join(choices)}")
    if not given:
        return None
    key = given[0]
    try:
        return key, values.number(m[key], *choices[key])
    except ValueError as e:
        raise fail(path + (key,), f"{what} field '{key}': {e}") from None


def _wind(w: Any, fail: Fail) -> WindProfile:
    path = ("wind",)
    if not isinstance(w, dict) or "layers" not in w:
        raise fail(path, "wind: expected a mapping with 'layers' (and an optional note, source)")
    extra = sorted(map(str, set(w) - {"layers", "note", "source"}))
    if extra:
        raise fail(path + (extra[0],), f"wind: unknown key '{extra[0]}'; allowed: layers, note, source")
    check_notes(w, ("note", "source"), "wind", path, fail)
    raw = w["layers"]
    if not isinstance(raw, list) or not raw:
        raise fail(path + ("layers",), "wind field 'layers': expected a non-empty list of "
                   "{alt_m, from_deg, speed_m_s or speed_kt}")
    allowed = {"alt_m", "from_deg", "note", *_SPEED_RANGE}
    layers: list[WindLayer] = []
    for i, layer in enumerate(raw):
        lp = path + ("layers", i)
        what = f"wind layer {i}"
        if not isinstance(layer, dict):
            raise fail(lp, f"{what}: expected a mapping {{alt_m, from_deg, speed_m_s or speed_kt}}, "
                       f"got {values.show(layer)}")
        extra = sorted(map(str, set(layer) - allowed))
        if extra:
            raise fail(lp + (extra[0],), f"{what}: unknown field '{extra[0]}'; allowed: alt_m, from_deg, "
                       "speed_m_s, speed_kt, note")
        check_notes(layer, ("note",), what, lp, fail)
        vals = {}
        for key, rng in (("alt_m", _ALT_RANGE_M), ("from_deg", (0.0, 360.0))):
            if key not in layer:
                raise fail(lp, f"{what}: missing field '{key}'")
            try:
                vals[key] = values.number(layer[key], *rng)
            except ValueError as e:
                raise fail(lp + (key,), f"{what} field '{key}': {e}") from None
        key, speed = _one_of(layer, _SPEED_RANGE, what, lp, fail, required=True)  # type: ignore[misc]
        layers.append(WindLayer(vals["alt_m"], vals["from_deg"], speed * (KT_M_S if key == "speed_kt" else 1.0)))
        if i and layers[-1].alt_m <= layers[-2].alt_m:
            raise fail(lp + ("alt_m",), f"{what} field 'alt_m': altitudes must increase from layer to layer "
                       f"({layers[-1].alt_m:g} m after {layers[-2].alt_m:g} m)")
    return WindProfile(tuple(layers))


def _turbulence(t: Any, fail: Fail) -> Turbulence:
    path = ("turbulence",)
    allowed = {"severity", "seed", "note", *_W20_RANGE}
    if not isinstance(t, dict) or "severity" not in t:
        raise fail(path, "turbulence: expected a mapping with 'severity' (light, moderate, severe, none or 0 to 7), "
                   "optional 'seed' and 'wind_20ft_m_s' or 'wind_20ft_kt'")
    extra = sorted(map(str, set(t) - allowed))
    if extra:
        raise fail(path + (extra[0],), f"turbulence: unknown field '{extra[0]}'; allowed: severity, seed, "
                   "wind_20ft_m_s, wind_20ft_kt, note")
    check_notes(t, ("note",), "turbulence", path, fail)
    sev = t["severity"]
    if isinstance(sev, str) and sev in SEVERITIES:
        severity, label = SEVERITIES[sev], sev
    elif isinstance(sev, int) and not isinstance(sev, bool) and 0 <= sev <= 7:
        severity, label = int(sev), str(sev)
    else:
        raise fail(path + ("severity",), f"turbulence field 'severity': got {values.show(sev)}; allowed: "
                   f"{', '.join(SEVERITIES)} or an integer 0 to 7")
    seed = t.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= 2 ** 31 - 1:
        raise fail(path + ("seed",), f"turbulence field 'seed': expected an integer 0 to {2 ** 31 - 1}, got {values.show(seed)}")
    w20 = _one_of(t, _W20_RANGE, "turbulence", path, fail, required=False)
    if w20 is None:
        w20_m_s = _W20_KT[severity] * KT_M_S
    else:
        w20_m_s = w20[1] * (KT_M_S if w20[0] == "wind_20ft_kt" else 1.0)
    return Turbulence(severity, w20_m_s, int(seed), label)


def parse_weather(doc: Mapping[str, Any], fail: Fail, source: str) -> Weather | None:
    """The ``wind`` and ``turbulence`` keys of a parsed YAML document ``doc``; None when it has neither.

    ``fail(path, what)`` makes the exception to raise for a problem at the key path ``path``
    (e.g. ``("wind", "layers", 2, "alt_m")``), so the caller reports the file and line.
    """
    if not any(k in doc for k in WEATHER_KEYS):
        return None
    wind = _wind(doc["wind"], fail) if "wind" in doc else None
    turb = _turbulence(doc["turbulence"], fail) if "turbulence" in doc else None
    return Weather(wind, turb, source)


def load_weather(path: str | Path) -> Weather:
    """Read the weather of a mission file, or of a file holding only ``wind`` and ``turbulence``.

    A mission's other keys (``mission``, ``places``, ``sections``) are left to the mission
    reader; any other top-level key is refused. A file with neither key gives still air.

    Raises
    ------
    MissionError
        One line with the file and line of the problem and what is allowed.
    """
    p = Path(path)
    try:
        text = safe_yaml.read_text(p, "weather file")
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    return parse_weather_text(text, str(p))


def parse_weather_text(text: str, source: str) -> Weather:
    """The weather of the YAML ``text`` of a mission or weather file (``source`` names it in errors);
    see :func:`load_weather`."""
    try:  # the project's one YAML reader: duplicate keys, alias bombs, NaN refused with file:line
        doc = safe_yaml.load(text, source)
    except safe_yaml.YamlError as e:
        raise MissionError(str(e)) from None
    ctx = Context(source, Lines(text))
    if doc is None:
        doc = {}
    if not isinstance(doc, dict):
        raise ctx.fail((), "a weather file is a mapping with 'wind' and/or 'turbulence' (or a mission file)")
    extra = sorted(map(str, set(doc) - set(WEATHER_KEYS) - set(_MISSION_KEYS)))
    if extra:
        raise ctx.fail((extra[0],), f"unknown top-level key '{extra[0]}'; allowed: {', '.join(WEATHER_KEYS)} "
                       f"(and a mission's {', '.join(_MISSION_KEYS)})")
    return parse_weather(doc, ctx.fail, source) or Weather(None, None, source)
