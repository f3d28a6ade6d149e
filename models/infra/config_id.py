"""Identities of configurations, and the cache of what is generated from them.

A component's *configuration identity* is a digest of exactly the inputs that determine what is derived
from it (an aircraft's files and masses, an engine's design parameters and maps): two configurations with
the same identity give the same derived data. The airframe and engine FMUs publish theirs as Integer
outputs (``airframe_config_id``, ``engine_config_id``: FMI 2.0 Integers are 32-bit, so the first 31 bits of
the SHA-256 digest, positive; 0 means "unknown"); the flight control checks its performance data against
them (:mod:`openemss.models.fcs.performance`), and the data generated for a pair of them are cached by
:func:`database_key` in :func:`cache_dir` (``$OPENEMSS_PERF_CACHE``, else the user's cache folder), outside
any results folder and the user's files.

A 31-bit identity tells two configurations apart with a chance of 1 in 2^31 of a collision per pair; the
full digest (:func:`digest`) is kept in the generated file for the record.
"""
from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["digest", "as_config_id", "database_key", "cache_dir", "CACHE_ENV", "UNKNOWN_ID",
           "LIMIT_NAMES"]

#: Environment variable naming the folder of the generated performance data (default: the user's cache folder).
CACHE_ENV = "OPENEMSS_PERF_CACHE"
#: The identity of a configuration not known (an unconnected input).
UNKNOWN_ID = 0
#: The fuel controller's parameters (``fuel_control.<name>``, models/fcs/data/fuel_control.yaml) that set the
#: maximum thrust of the performance data: the N1c demand at lever 1, the N1 and Tt41 limits.
LIMIT_NAMES = ("k_delta_pct", "N1_max_pct", "Tt41_max_K")


def _canonical(value: Any) -> Any:
    """``value`` as JSON-able data with a single spelling: mappings sorted, tuples as lists, floats by repr."""
    if isinstance(value, Mapping):
        return {str(k): _canonical(v) for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    if isinstance(value, float):
        return repr(value)  # 17 significant digits: the float itself, not a rounding of it
    if value is None or isinstance(value, (bool, int, str)):
        return value
    raise TypeError(f"config_id: cannot digest a {type(value).__name__}")


def digest(what: str, value: Any, files: Iterable[Path] = ()) -> str:
    """SHA-256 hex digest of a kind ``what``, a JSON-able ``value`` (numbers, strings, nested mappings and
    sequences) and the bytes of ``files`` (each by its name and content, in the order given)."""
    h = hashlib.sha256(what.encode())
    h.update(json.dumps(_canonical(value), sort_keys=True, separators=(",", ":")).encode())
    for f in files:
        h.update(b"\0" + Path(f).name.encode() + b"\0" + Path(f).read_bytes())
    return h.hexdigest()


def as_config_id(hex_digest: str) -> int:
    """The Integer identity of a digest: its first 31 bits, never 0 (:data:`UNKNOWN_ID`)."""
    return int(hex_digest[:8], 16) & 0x7FFFFFFF or 1


def database_key(airframe_id: int, engine_id: int, limits: Mapping[str, float]) -> str:
    """Name of the performance data generated for an airframe and an engine (their identities) with the fuel
    controller's ``limits`` (:data:`LIMIT_NAMES`: the lever's N1c gain and the N1 and Tt41 limits, which set the
    maximum thrust)."""
    limits = {n: float(limits[n]) for n in LIMIT_NAMES}
    return f"{int(airframe_id):08x}-{int(engine_id):08x}-{digest('limits', dict(limits))[:12]}"


def cache_dir() -> Path:
    """The folder of the generated performance data: ``$OPENEMSS_PERF_CACHE``, else
    ``$XDG_CACHE_HOME/openemss/performance`` (``~/.cache/openemss/performance``)."""
    root = os.environ.get(CACHE_ENV)
    if root:
        return Path(root)
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "openemss" / "performance"
