"""The identity of an engine's configuration: what its steady performance depends on.

:func:`engine_digest` hashes exactly the inputs of a preset engine's steady states (the performance data of the
flight control are generated from them, :mod:`openemss.models.performance`): every design parameter (the
name aside), the component maps the off-design model scales (:func:`.offdesign.scaled_maps`'s, the booster's
only when there is one) and the gas properties' data; :func:`engine_file_digest` those of an engine file's: the
file, every map its elements name, the gas properties' data and the thrust scale. The engine FMU publishes it as
``engine_config_id`` (:func:`openemss.models.infra.config_id.as_config_id`). Not in it: the health deltas (the
performance data are the new engine's), the limits and start settings of ``data/engine.json`` (the flight
control's own limits set the maximum thrust).
"""
from __future__ import annotations

import dataclasses
import inspect
from pathlib import Path

from ..infra.config_id import as_config_id, digest
from .design_params import EngineParams, TurbofanParams
from .engine_file import engine_path, read_engine_file
from .maps import _map_file
from .offdesign import scaled_maps
from .thermo import DATA_FILE as THERMO_FILE

__all__ = ["engine_digest", "engine_config_id", "engine_file_digest", "engine_file_config_id"]


def _map_files(params: EngineParams) -> list[Path]:
    """The map files :func:`.offdesign.scaled_maps` reads for this engine (its default map names)."""
    names = {k: p.default for k, p in inspect.signature(scaled_maps).parameters.items()
             if isinstance(p.default, str)}
    if not (isinstance(params, TurbofanParams) and params.PR_booster > 1.0):
        names.pop("booster", None)
    return [_map_file(n) for n in names.values()]


def engine_digest(params: EngineParams) -> str:
    """SHA-256 hex digest of the engine's configuration (see the module docstring)."""
    values = {f.name: getattr(params, f.name) for f in dataclasses.fields(params) if f.name != "name"}
    values["bleeds"] = [dataclasses.asdict(b) for b in params.bleeds]
    return digest(type(params).__name__, values, [*_map_files(params), THERMO_FILE])


def engine_config_id(params: EngineParams) -> int:
    """The engine's identity as the FMU's Integer output ``engine_config_id``."""
    return as_config_id(engine_digest(params))


def engine_file_digest(engine_file: str | Path, thrust_scale: float = 1.0) -> str:
    """SHA-256 hex digest of an engine file (a path or a shipped name) flown at ``thrust_scale``: the file's and its
    maps' bytes, the gas properties' data and the scale.

    Raises
    ------
    EngineFileError
        For a file that cannot be read as an engine file (one line).
    """
    eng = read_engine_file(engine_file)
    base = Path(eng.file).parent
    maps = []
    for ref in sorted({str(e.attrs["map"]) for e in eng.elements.values() if e.attrs.get("map")}):
        p = Path(ref)  # as .map_files.map_data_of finds it: a shipped name, else a file relative to the engine file
        maps.append(_map_file(ref) if p.suffix == "" and len(p.parts) == 1 else p if p.is_absolute() else base / p)
    return digest("engine_file", {"thrust_scale": float(thrust_scale)},
                  [engine_path(engine_file), *(m for m in maps if m.is_file()), THERMO_FILE])


def engine_file_config_id(engine_file: str | Path, thrust_scale: float = 1.0) -> int:
    """An engine file's identity as the FMU's Integer output ``engine_config_id``."""
    return as_config_id(engine_file_digest(engine_file, thrust_scale))
