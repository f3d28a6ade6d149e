"""Errors of the electrical power system: one base class, messages with what, where and what is allowed."""
from __future__ import annotations

__all__ = ["ElectricError", "ParameterError"]


class ElectricError(Exception):
    """Base class of every error of :mod:`openemss.models.electric`."""


class ParameterError(ElectricError, KeyError, ValueError):
    """A parameter is unknown, of the wrong kind, or outside its stated range."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
