"""UPERA airframe: JSBSim aircraft files generated from the geometry, and a thin SI adapter.

Public API: :class:`~.adapter.Airframe` (the adapter) and :class:`~.adapter.AirframeState`,
:func:`~.trim.trim_level` and :class:`~.trim.TrimResult`, :func:`~.geometry.load_geometry`,
:func:`~.aero.aero_model`, and the errors. JSBSim is imported only when an ``Airframe`` is made.
"""
from __future__ import annotations

from .adapter import Airframe, AirframeState
from .aero import AeroModel, aero_model
from .errors import AirframeError, OutOfEnvelopeError, TrimError
from .geometry import Geometry, load_geometry
from .trim import TrimResult, trim_level

__all__ = ["Airframe", "AirframeState", "trim_level", "TrimResult", "AeroModel", "aero_model", "Geometry",
           "load_geometry", "AirframeError", "OutOfEnvelopeError", "TrimError"]
