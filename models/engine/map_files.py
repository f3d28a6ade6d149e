"""Maps named by an engine file: shipped names and files in our JSON, NPSS's or pyCycle's format, scaled to the
design point.

An element's ``map`` attribute is a shipped map name (``axi5``: ``models/engine/maps/axi5.json``) or a file,
relative to the engine file: ``.json`` (our format, :func:`.maps.load_map_data`), ``.map``/``.npss``/``.txt``
(NPSS's table syntax, :mod:`.map_npss`) or ``.py`` or ``.py.txt`` (a pyCycle map module, read as data by
:mod:`.map_pycycle`, never imported). Each becomes a :class:`.maps.MapData` (one map type), is extended below
its lowest speed line (:mod:`.map_extension`, attribute ``map_extended``) and is scaled as pyCycle does: the
map's design point (its own, or ``map_Nc_rel`` and ``map_line``) onto the design's corrected flow, pressure
ratio, efficiency and corrected speed (:mod:`.map_scaled`). A map that does not cover the
design point it is asked to place is refused with the file and line of the element's ``map``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .engine_file import ElementDef, EngineDef, EngineFileError
from .errors import ModelError
from .map_extension import extend_map_data
from .map_scaled import ScaledCompressorMap, ScaledTurbineMap
from .maps import MAP_DIR, CompressorMap, MapData, TurbineMap, load_map_data

__all__ = ["map_data_of", "scaled_map"]

_CACHE: dict[tuple[str, float], MapData] = {}


def map_data_of(ref: str, base: Path, kind: str) -> MapData:
    """The map `ref` (a shipped name or a file relative to `base`) as :class:`.maps.MapData`; for NPSS and pyCycle
    files `kind` ("compressor" or "turbine") says which table to read."""
    p = Path(ref)
    if p.suffix == "" and len(p.parts) == 1:
        return load_map_data(ref)
    path = p if p.is_absolute() else base / p
    if not path.is_file():
        raise ModelError(f"map file {path} does not exist (shipped maps: "
                         f"{', '.join(sorted(q.stem for q in MAP_DIR.glob('*.json')))})")
    key = (str(path.resolve()), path.stat().st_mtime)
    if key not in _CACHE:
        if path.suffix == ".json":
            _CACHE[key] = load_map_data(path)
        elif path.suffix == ".py" or path.name.endswith(".py.txt"):
            from .map_pycycle import read_pycycle_map
            _CACHE[key] = read_pycycle_map(path, kind)
        else:
            from .map_npss import read_npss_map
            _CACHE[key] = read_npss_map(path, kind)
    return _CACHE[key]


def scaled_map(eng: EngineDef, el: ElementDef, design: dict[str, float]) -> Any:
    """The map of turbomachine `el` scaled to its design values `design` (``Wc_kg_s``, ``PR``, ``eta``,
    ``Nc_rpm``).

    Raises
    ------
    EngineFileError
        The map cannot be read, is of the other kind, or does not cover the design point placed on it.
    """
    a = el.attrs
    kind = "turbine" if el.kind == "turbine" else "compressor"
    where = eng.where(el.name, "map")
    try:
        data = map_data_of(a["map"], Path(eng.file).parent, kind)
        if data.kind != kind:
            raise ModelError(f"map {a['map']!r} is a {data.kind} map; a {el.kind} needs a {kind} map")
        if a["map_extended"]:
            data = extend_map_data(data)
        m: Any = (CompressorMap if kind == "compressor" else TurbineMap)(data, a["map_extrapolation"])
    except ModelError as exc:
        raise EngineFileError(f"{where}{exc}") from None
    n = a["map_Nc_rel"] if a["map_Nc_rel"] is not None else m.nc_rel_design
    lo, hi = data.speed_values[0] / data.speed_design, data.speed_values[-1] / data.speed_design
    if not lo <= n <= hi:
        raise EngineFileError(f"{where}the map {a['map']!r} does not cover the design point: relative corrected speed "
                              f"{n:g} is outside its speed lines {lo:g} to {hi:g}")
    y = a["map_line"]
    if kind == "compressor":
        rl = data.line_design if y is None else y
        for what, r in (("design", rl), ("held", a.get("held_Rline"))):
            if r is not None and not data.line_values[0] <= r <= data.line_values[-1]:
                raise EngineFileError(f"{where}the map {a['map']!r} does not cover the {what} point: R-line {r:g} is "
                                      f"outside its lines {data.line_values[0]:g} to {data.line_values[-1]:g}")
        try:
            return ScaledCompressorMap.from_design(m, design["Wc_kg_s"], design["PR"], design["eta"],
                                                   design["Nc_rpm"], n, m.beta_of_rline(rl))
        except ModelError as exc:
            raise EngineFileError(f"{where}{exc}") from None
    pr = data.line_design if y is None else y
    if not data.line_values[0] <= pr <= data.line_values[-1]:
        raise EngineFileError(f"{where}the map {a['map']!r} does not cover the design point: pressure ratio {pr:g} is "
                              f"outside its range {data.line_values[0]:g} to {data.line_values[-1]:g}")
    try:
        return ScaledTurbineMap.from_design(m, design["Wc_kg_s"], design["PR"], design["eta"], design["Nc_rpm"], n, pr)
    except ModelError as exc:
        raise EngineFileError(f"{where}{exc}") from None
