"""Typed values of the files users write (missions, plans, engine files, studies): one check per kind.

A reader parses its file with :mod:`.safe_yaml` and takes every value through these functions. Each
returns the value typed, or raises :class:`ValueProblem` (a ``ValueError``) whose message says what
was expected and what was given; the reader puts the file and line in front. Refused alike by every
reader:

* a Boolean where a number or a name is (YAML reads ``yes``, ``no``, ``on``, ``off`` as true/false);
* text where a number is (with a hint when the text reads as a number: YAML 1.1 reads ``1e5``,
  without a decimal point, as text);
* null (an empty value), a list or a mapping where a single value is;
* a number that is not finite or does not fit a float (``1e999``, a 401-digit integer), or lies
  outside its range;
* an empty name, and a date where a number or a name is.
"""
from __future__ import annotations

import math
import re
from collections.abc import Iterable
from typing import Any

__all__ = ["ValueProblem", "show", "number", "integer", "name", "text", "flag", "choice", "scalar"]

_NUMBER_TEXT = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$")


class ValueProblem(ValueError):
    """A value of the wrong kind or outside its range; the message says what is allowed."""


def show(v: Any) -> str:
    """A short description of a value as a file gave it, for messages."""
    if v is None:
        return "null (an empty value)"
    if isinstance(v, bool):
        return f"{str(v).lower()} (YAML reads yes/no/on/off as true/false)"
    if isinstance(v, int):
        if abs(v) < 10 ** 40:
            return repr(v)
        digits = len(str(abs(v))) if v.bit_length() < 14_000 else int(v.bit_length() * math.log10(2)) + 1
        return f"an integer of {digits} digits"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, str):
        shown = repr(v if len(v) <= 40 else v[:37] + "...")
        if _NUMBER_TEXT.match(v):
            hint = ("; YAML reads 1e5 and 1.0e5 as text: write 1.0e+5" if re.search(r"[eE]\d", v) else "")
            return f"the text {shown} (write a number without quotes{hint})"
        return f"the text {shown}"
    if isinstance(v, dict):
        return "a mapping"
    if isinstance(v, list | tuple):
        return "a list"
    return f"a {type(v).__name__}"  # a date, bytes


def _bound(x: float) -> str:
    return repr(float(x)) if math.isfinite(x) else ("-inf" if x < 0 else "inf")


def _range(lo: float, hi: float, unit: str) -> str:
    """``[lo, hi] unit`` (a bracket open at an infinite bound)."""
    return f"{'(' if math.isinf(lo) else '['}{_bound(lo)}, {_bound(hi)}{')' if math.isinf(hi) else ']'}" + \
        (f" {unit}" if unit else "")


def number(v: Any, lo: float = -math.inf, hi: float = math.inf, unit: str = "") -> float:
    """``v`` as a finite float in ``[lo, hi]``; an integer is taken, a Boolean or text is not.

    Raises
    ------
    ValueProblem
        Not a number, not finite, too large for a float, or outside ``[lo, hi]``.
    """
    expected = "expected a finite number" + ("" if math.isinf(lo) and math.isinf(hi) else f" in {_range(lo, hi, unit)}")
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise ValueProblem(f"{expected}, got {show(v)}")
    try:
        x = float(v)
    except OverflowError:
        raise ValueProblem(f"{expected}, got {show(v)} (too large for a number)") from None
    if not math.isfinite(x):
        raise ValueProblem(f"{expected}, got {show(v)}")
    if not lo <= x <= hi:
        raise ValueProblem(f"value {show(v)} outside the allowed range {_range(lo, hi, unit)}")
    return x


def integer(v: Any, lo: int, hi: int) -> int:
    """``v`` as an integer in ``[lo, hi]`` (a float, even 3.0, or a Boolean is not one).

    Raises
    ------
    ValueProblem
        Not an integer, or outside ``[lo, hi]``.
    """
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueProblem(f"expected an integer from {lo} to {hi}, got {show(v)}")
    if not lo <= v <= hi:
        raise ValueProblem(f"value {show(v)} outside the allowed range: an integer from {lo} to {hi}")
    return v


def name(v: Any, what: str = "a name") -> str:
    """``v`` as a non-empty name: text, or an integer (YAML reads ``1`` as one), as text.

    Raises
    ------
    ValueProblem
        A Boolean, a float, null, a list or mapping, an empty text.
    """
    if isinstance(v, int) and not isinstance(v, bool) and abs(v) < 10 ** 40:
        return str(v)
    if not isinstance(v, str):
        raise ValueProblem(f"expected {what} (text), got {show(v)}")
    if not v.strip():
        raise ValueProblem(f"expected {what}, got an empty text")
    return v


def text(v: Any, what: str = "text") -> str:
    """``v`` as free text (a description, a note): text or a number, as text.

    Raises
    ------
    ValueProblem
        A Boolean, null, a list or mapping.
    """
    if isinstance(v, str):
        return v
    if isinstance(v, int | float) and not isinstance(v, bool):
        return str(v) if isinstance(v, float) or abs(v) < 10 ** 40 else show(v)
    raise ValueProblem(f"expected {what}, got {show(v)}")


def flag(v: Any) -> bool:
    """``v`` as a Boolean (true or false; YAML's yes/no too).

    Raises
    ------
    ValueProblem
        Anything but true or false (a number, text, null ...).
    """
    if not isinstance(v, bool):
        raise ValueProblem(f"expected true or false, got {show(v)}")
    return v


def choice(v: Any, choices: Iterable[str]) -> str:
    """``v`` as one of the names ``choices``.

    Raises
    ------
    ValueProblem
        Not one of them (a list, a mapping, a Boolean ... included).
    """
    allowed = tuple(choices)
    if not isinstance(v, str) or v not in allowed:
        raise ValueProblem(f"got {show(v)}; allowed: {', '.join(allowed)}")
    return v


def scalar(v: Any) -> bool | int | float | str:
    """``v`` as a single value of any kind (a number fit for a float, a Boolean, text), e.g. a parameter
    value typed later by the variable it sets.

    Raises
    ------
    ValueProblem
        Null, a list, a mapping, a date, a number that is not finite or too large for a float.
    """
    if isinstance(v, bool | str):
        return v
    if isinstance(v, int | float):
        number(v)  # finite and fit for a float
        return v
    raise ValueProblem(f"expected a number, true/false or a text, got {show(v)}")
