"""Errors raised by the engine model.

A small hierarchy: every error of the engine model is a :class:`ModelError`, so a
caller (an FMU adapter, the CLI) can catch them all at once; the subclasses say
what went wrong. Messages name what was wrong, where (the function or
component), and what is allowed.
"""

from __future__ import annotations

__all__ = ["ModelError", "OutOfRangeError", "ConvergenceError", "FlameoutError"]


class ModelError(Exception):
    """Base class of every error raised by the engine model."""


class OutOfRangeError(ModelError, ValueError):
    """An input lies outside the range in which a model or its data are valid.

    Also a :class:`ValueError`, so code that guards against bad values in the
    ordinary Python way catches it too.
    """


class ConvergenceError(ModelError):
    """An iterative solution did not converge within its iteration limit."""


class FlameoutError(ModelError):
    """The burner is out (e.g. its tanks could not deliver the fuel): the engine cannot be stepped on."""
