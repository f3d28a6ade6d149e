"""Parameter values as text, checked where they enter: an SSV attribute, a ``--set`` value.

One grammar for every way a value reaches an FMU variable, stricter than Python's own
``float`` and ``int`` (which take ``nan``, ``1_000``, Arabic-Indic digits and, for ``int``,
refuse more than 4300 digits with a message about Python): a Real is a finite decimal number
that does not underflow to zero, an Integer is a run of ASCII digits inside the range of an
FMI 2.0 Integer, a Boolean is ``true``, ``false``, ``1`` or ``0``. A String is taken as given,
if it is text an FMU can take (no NUL, no control characters, no bytes that are not UTF-8).
"""
from __future__ import annotations

import math
import re

__all__ = ["INT32_RANGE", "ValueT", "is_file_parameter", "parse_value", "short"]

INT32_RANGE = (-(2 ** 31), 2 ** 31 - 1)  #: values of an FMI 2.0 Integer (fmi2Integer is a C int)
ValueT = bool | int | float | str

_REAL = re.compile(r"[+-]?(?:(\d+)(?:\.(\d*))?|\.(\d+))(?:[eE][+-]?\d+)?", re.ASCII)
_INTEGER = re.compile(r"[+-]?\d+", re.ASCII)
#: What an FMI String (UTF-8, NUL-terminated) and an .ssv file (XML 1.0) cannot hold: NUL and other
#: control characters, lone surrogates (the bytes of a command line that are not UTF-8), U+FFFE/U+FFFF.
_NOT_TEXT = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_NON_FINITE = ("nan", "inf", "infinity")
_BOOLEANS = {"true": True, "false": False, "1": True, "0": False}
#: The suffix of a String variable that names a file (house naming: ``mission_file``, ``weather_file``).
FILE_SUFFIX = "_file"


def parse_value(type_name: str, text: str) -> ValueT:
    """``text`` as a value of the FMI type ``type_name`` (Real, Integer, Enumeration, Boolean, String).

    Raises
    ------
    ValueError
        Saying what is wrong and what is allowed, without the text (the caller names it and where it
        was given), e.g. ``not a finite number (allowed: ...)``.
    """
    if type_name == "String":
        bad = _NOT_TEXT.search(text)
        if bad is not None:
            raise ValueError(f"not text an FMU can take: character {bad.group()!r} at position {bad.start()} "
                             "(allowed: Unicode text without NUL, control characters other than tab and newline, "
                             "or bytes that are not UTF-8)")
        return text
    t = text.strip()
    if type_name == "Real":
        m = _REAL.fullmatch(t)
        if m is None and t.lower().lstrip("+-") not in _NON_FINITE:
            raise ValueError("not a number (allowed: a finite decimal number, e.g. 1.5e3)")
        value = float(t)
        if not math.isfinite(value):
            raise ValueError("not a finite number (allowed: a decimal number of magnitude below 1.8e308)")
        if value == 0.0 and any(c in "123456789" for g in m.groups() if g for c in g):
            raise ValueError("too small for a Real: it would be 0 (allowed: magnitudes from 4.9e-324, or 0)")
        return value
    if type_name in ("Integer", "Enumeration"):
        lo, hi = INT32_RANGE
        if _INTEGER.fullmatch(t) is None:
            raise ValueError(f"not an integer (allowed: decimal digits, e.g. 42, from {lo} to {hi})")
        digits = t.lstrip("+-").lstrip("0")
        if len(digits) > len(str(hi)) or not lo <= int(t) <= hi:
            raise ValueError(f"outside the range of an FMI Integer ({lo} to {hi})")
        return int(t)
    if type_name == "Boolean":
        value_b = _BOOLEANS.get(t.lower())
        if value_b is None:
            raise ValueError("not a Boolean (allowed: true, false, 1, 0)")
        return value_b
    raise ValueError(f"of type {type_name}, which cannot be given as a value (allowed: Real, Integer, Boolean, "
                     "String)")


def is_file_parameter(name: str, type_name: str) -> bool:
    """Whether a variable names a file: a String whose name ends in ``_file``. Only such a value given
    relative to the working directory (``--set``) is made absolute; every other String stays as given."""
    return type_name == "String" and name.endswith(FILE_SUFFIX)


def short(text: str, limit: int = 40) -> str:
    """``text`` quoted for a message, cut when long (a 401-digit number stays one short line)."""
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"
