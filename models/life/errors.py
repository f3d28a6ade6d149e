"""Errors of the life models."""
from __future__ import annotations


class LifeDataError(ValueError):
    """A life data file (material curves, stresses, thresholds) that cannot be used: the message names the file,
    the entry and what is allowed."""
