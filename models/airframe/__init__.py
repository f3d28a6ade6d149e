"""UPERA airframe: JSBSim aircraft files generated from the geometry, and a thin SI adapter.

Public API: :class:`Airframe` (adapter), :class:`AirframeState`, :func:`trim_level`,
:class:`TrimResult`, :func:`load_geometry`, :class:`AeroModel`, and the errors.
"""
from __future__ import annotations

from .errors import AirframeError, OutOfEnvelopeError, TrimError
from .geometry import Geometry, load_geometry

__all__ = ["AirframeError", "OutOfEnvelopeError", "TrimError", "Geometry", "load_geometry"]
