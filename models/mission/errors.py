"""Errors of the mission package: a mission or weather file that is invalid, a geometric request without an answer.

Both are ``ValueError``s (bad input). Messages name what was wrong, where (file:line, section, field) and what is
allowed. The FCS's own errors are :class:`openemss.models.fcs.errors.FcsError`; a caller that reads a mission and
flies it catches both.
"""

from __future__ import annotations

__all__ = ["MissionError", "GeometryError"]


class MissionError(ValueError):
    """A mission file (YAML or QGroundControl .plan) or a weather file is invalid.

    The message names the file and line, the section (index and type) and the field, and says what is
    allowed.
    """


class GeometryError(ValueError):
    """A geometric request has no answer (e.g. coincident points for a bearing)."""
