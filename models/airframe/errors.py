"""Errors raised by the airframe model.

Every error of the airframe is an :class:`AirframeError`, so a caller (the FMU,
the CLI) can catch them all at once. Messages say what was wrong, where, and
what is allowed.
"""
from __future__ import annotations

__all__ = ["AirframeError", "CalibrationError", "FuelExhaustedError", "LossOfAircraftError", "OutOfEnvelopeError",
           "TrimError"]


class AirframeError(Exception):
    """Base class of every error raised by the airframe model."""


class OutOfEnvelopeError(AirframeError, ValueError):
    """An input lies outside the range in which the model is valid (names the range)."""


class TrimError(AirframeError):
    """The trim solver found no steady level flight at the requested condition."""


class LossOfAircraftError(AirframeError):
    """The aircraft hit the ground outside the landing envelope: the simulation cannot go on."""


class CalibrationError(AirframeError):
    """Calibration data or a calibration file that cannot be used (one line: what, where, allowed)."""


class FuelExhaustedError(AirframeError):
    """The fuel flow input asks the tank for more fuel than it holds: an engine burning from it must flame out."""
