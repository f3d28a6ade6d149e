"""Loading a map file into its interpolating map, on the shipped grid or on the grid extended for
sub-idle operation.

Kept apart from :mod:`.maps` (the map classes and the file reader) so that the extension
(:mod:`.map_extension`, which reads :class:`.maps.MapData`) and the loading that uses it import in
one direction only: ``maps`` <- ``map_extension`` <- ``map_loading``.
"""
from __future__ import annotations

from pathlib import Path

from .map_extension import extend_map_data
from .maps import DEFAULT_EXTRAPOLATION, CompressorMap, MapData, TurbineMap, load_map_data

__all__ = ["load_map", "load_compressor_map", "load_turbine_map"]


def _data(name_or_path: str | Path, extended: bool) -> MapData:
    data = load_map_data(name_or_path)
    if extended:
        data = extend_map_data(data)
    return data


def load_map(name_or_path: str | Path, extrapolation: float = DEFAULT_EXTRAPOLATION,
             extended: bool = False) -> CompressorMap | TurbineMap:
    """Load a map file (:func:`load_map_data`) and build its interpolating map; with `extended`, on the
    grid extended for sub-idle operation (:func:`.map_extension.extend_map_data`)."""
    data = _data(name_or_path, extended)
    if data.kind == "compressor":
        return CompressorMap(data, extrapolation)
    return TurbineMap(data, extrapolation)


def load_compressor_map(name_or_path: str | Path, extrapolation: float = DEFAULT_EXTRAPOLATION,
                        extended: bool = False) -> CompressorMap:
    """:func:`load_map` for a compressor map (raises ModelError for another kind)."""
    return CompressorMap(_data(name_or_path, extended), extrapolation)


def load_turbine_map(name_or_path: str | Path, extrapolation: float = DEFAULT_EXTRAPOLATION,
                     extended: bool = False) -> TurbineMap:
    """:func:`load_map` for a turbine map (raises ModelError for another kind)."""
    return TurbineMap(_data(name_or_path, extended), extrapolation)
