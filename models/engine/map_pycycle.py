"""pyCycle's map modules read as data: the literal arrays of ``pycycle/maps/*.py``, never imported or executed.

A pyCycle map module assigns the attributes of one ``MapData`` object (``HPCMap.NcMap = np.array([...])``,
``HPCMap.defaults['RlineMap'] = 2.05``...). :func:`parse_map_module` reads those assignments with :mod:`ast`
(``ast.literal_eval`` of the literals only), :func:`read_pycycle_map` turns them into this package's
:class:`.maps.MapData` in the source's units (corrected flow lbm/s, turbine flow parameter
lbm sqrt(degR)/(s psia), as our JSON maps store them): the ``alphaMap`` plane of the map's design
(``defaults['alphaMap']``, else the first), the design speed and R-line or pressure ratio of ``defaults``, the
surge R-line ``RlineStall``.

Reference: OpenMDAO/pyCycle, ``pycycle/maps/`` (Apache-2.0); the map format of ``pycycle/maps/map_data.py``.
"""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType
from typing import Any

from .errors import ModelError
from .maps import MapData, MapSource
from .pycycle_module import parse_map_module

__all__ = ["parse_map_module", "read_pycycle_map"]


def _plane(d: dict[str, Any], key: str) -> list[list[float]]:
    """The table `key` in the design's alphaMap plane (a 2-D table as it is)."""
    t = d[key]
    if t and isinstance(t[0], list) and t[0] and isinstance(t[0][0], list):
        alphas = d.get("alphaMap", [0.0])
        a = d["defaults"].get("alphaMap", alphas[0])
        return t[alphas.index(a) if a in alphas else 0]
    return t


def read_pycycle_map(path: str | Path, kind: str) -> MapData:
    """A pyCycle map module as :class:`.maps.MapData`.

    Raises
    ------
    ModelError
        Not a map module (no literal axes and tables), or of the other kind than `kind`.
    """
    p = Path(path)
    try:
        d = parse_map_module(p.read_text(encoding="utf-8"))
    except (SyntaxError, ValueError, UnicodeDecodeError) as exc:
        raise ModelError(f"pyCycle map {p}: cannot be read as a map module: {exc}") from None
    found = "compressor" if "NcMap" in d else "turbine" if "NpMap" in d else None
    if found is None:
        raise ModelError(f"pyCycle map {p}: no NcMap (compressor) or NpMap (turbine) array found")
    if found != kind:
        raise ModelError(f"pyCycle map {p} is a {found} map; a {kind} map is needed here")
    dflt = d["defaults"]
    src = MapSource("OpenMDAO/pyCycle format", "", str(p), str(p), "as stated with the file", "pyCycle map module")
    try:
        if found == "compressor":
            tables = {k: _plane(d, k) for k in ("WcMap", "PRmap", "effMap")}
            speed, line = ("NcMap", d["NcMap"], dflt.get("NcMap", 1.0)), ("RlineMap", d["RlineMap"],
                                                                           dflt.get("RlineMap", 2.0))
            surge: float | None = float(d.get("RlineStall", d["RlineMap"][0]))
            units = {"NcMap": "-", "RlineMap": "-", "WcMap": "lbm/s", "PRmap": "-", "effMap": "-"}
        else:
            tables = {k: _plane(d, k) for k in ("WpMap", "effMap")}
            speed, line = ("NpMap", d["NpMap"], dflt.get("NpMap", 100.0)), ("PRmap", d["PRmap"],
                                                                            dflt.get("PRmap", 5.0))
            surge = None
            units = {"NpMap": "rpm/sqrt(degR)", "PRmap": "-", "WpMap": "lbm*sqrt(degR)/(s*psia)", "effMap": "-"}
        sv, lv = tuple(float(v) for v in speed[1]), tuple(float(v) for v in line[1])
        tabs = {k: tuple(tuple(float(v) for v in row) for row in t) for k, t in tables.items()}
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise ModelError(f"pyCycle map {p}: missing or malformed array: {exc!r}") from None
    for k, t in tabs.items():
        if len(t) != len(sv) or any(len(r) != len(lv) for r in t):
            raise ModelError(f"pyCycle map {p}: table {k} is not {len(sv)} x {len(lv)} ({speed[0]} x {line[0]})")
    return MapData(p.stem, found, "", src, speed[0], sv, float(speed[2]), line[0], lv, float(line[2]),  # type: ignore[arg-type]
                   surge, MappingProxyType(tabs), MappingProxyType(units), p)
