"""Errors raised by the flight control system (FCS) package.

A small hierarchy: every error of the FCS is an :class:`FcsError`, so a caller
(an FMU adapter, the CLI) can catch them all at once. Messages name what was
wrong, where (parameter set, section) and what is allowed. A mission file's problems are the mission's
(:class:`openemss.models.mission.errors.MissionError`).
"""

from __future__ import annotations

__all__ = ["FcsError", "ParameterError"]


class FcsError(Exception):
    """Base class of every error raised by the flight control system."""


class ParameterError(FcsError, KeyError, ValueError):
    """A tunable parameter is unknown, or its value is outside the allowed range.

    Also a :class:`KeyError` (unknown name) and a :class:`ValueError` (bad value),
    so ordinary Python guards catch it.
    """

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
