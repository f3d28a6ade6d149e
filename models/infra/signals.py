"""Signal tables: one row per variable a model exposes (name, causality, unit, description, accessor).

Each model package keeps one table of its signals (``models/engine/engine_signals.py``,
``models/airframe/airframe_signals.py``, ``models/fcs/fcs_signals.py``). The FMU of the model
(``fmus/``) registers its FMI variables from it, with the FMI ``unit`` and the UnitDefinitions
(:func:`si_unit`), and reads and writes the model through the ``accessor`` column; ``ssp/generate.py``
takes the connectors of the system from the same FMUs. A variable is therefore added in one place:
one row in the model's table (and, for an input, the use of it in the model).

Units are written as text in SI symbols: products with a space or ``.``, quotients with ``/``,
powers as ``m2``, ``m^2`` or ``s^-1``, parentheses (``1/(rad s)``, ``kg/s^2/%``). ``1`` (or ``-``)
is dimensionless. :func:`si_unit` turns one into the eight FMI 2.0 base-unit exponents (kg, m, s,
A, K, mol, cd, rad; FMI 2.0 section 2.2.2) and a factor to the coherent SI unit. No library is
used here because the FMI base units keep ``rad`` as a dimension of its own, which the unit
libraries (pint, astropy) treat as dimensionless, and because the model packages, vendored into
the FMUs, must not depend on more than they already do.

References
----------
FMI 2.0.4, section 2.2.2 "Definition of Units (UnitDefinitions)".
BIPM, "The International System of Units (SI)", 9th ed., 2019, tables 2 to 4 and 8.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

__all__ = ["Signal", "BASE_UNITS", "si_unit", "check_table", "UnitError", "DEPARTURE"]

#: The departure runway of the mission, which the flight control publishes (its outputs ``departure_<q>``) and the
#: airframe starts on (its inputs of the same names): quantity, unit, what. Here, because both model packages
#: name them and neither may import the other.
DEPARTURE: tuple[tuple[str, str, str], ...] = (
    ("lat_deg", "deg", "Threshold latitude"), ("lon_deg", "deg", "Threshold longitude"),
    ("heading_deg", "deg", "True heading"), ("elevation_m", "m", "Threshold elevation"))

#: The FMI 2.0 base units, in the order of the BaseUnit exponents.
BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")

# symbol -> (exponents over BASE_UNITS, factor to the coherent SI unit)
_SYMBOLS: dict[str, tuple[tuple[int, ...], float]] = {
    "kg": ((1, 0, 0, 0, 0, 0, 0, 0), 1.0), "m": ((0, 1, 0, 0, 0, 0, 0, 0), 1.0),
    "s": ((0, 0, 1, 0, 0, 0, 0, 0), 1.0), "A": ((0, 0, 0, 1, 0, 0, 0, 0), 1.0),
    "K": ((0, 0, 0, 0, 1, 0, 0, 0), 1.0), "mol": ((0, 0, 0, 0, 0, 1, 0, 0), 1.0),
    "cd": ((0, 0, 0, 0, 0, 0, 1, 0), 1.0), "rad": ((0, 0, 0, 0, 0, 0, 0, 1), 1.0),
    "N": ((1, 1, -2, 0, 0, 0, 0, 0), 1.0), "Pa": ((1, -1, -2, 0, 0, 0, 0, 0), 1.0),
    "W": ((1, 2, -3, 0, 0, 0, 0, 0), 1.0), "J": ((1, 2, -2, 0, 0, 0, 0, 0), 1.0),
    "V": ((1, 2, -3, -1, 0, 0, 0, 0), 1.0), "Hz": ((0, 0, -1, 0, 0, 0, 0, 0), 1.0),
    "deg": ((0, 0, 0, 0, 0, 0, 0, 1), math.pi / 180.0),
    "rpm": ((0, 0, -1, 0, 0, 0, 0, 1), 2.0 * math.pi / 60.0),
    "%": ((0, 0, 0, 0, 0, 0, 0, 0), 0.01), "1": ((0, 0, 0, 0, 0, 0, 0, 0), 1.0),
    # standard acceleration of gravity (CGPM 1901), for load factors and accelerations in g
    "g": ((0, 1, -2, 0, 0, 0, 0, 0), 9.80665),
}
_TOKEN = re.compile(r"\s*(?:(?P<sym>[A-Za-z%]+|1)(?:\^?(?P<exp>-?\d+))?|(?P<op>[/().*]))")


class UnitError(ValueError):
    """A unit text that :func:`si_unit` cannot read."""


@dataclass(frozen=True)
class Signal:
    """One variable of a model as an FMU exposes it.

    Attributes
    ----------
    name : str
        The variable's name, the same in the model's table, the FMU, the SSD and the results
        (``snake_case`` with its unit as suffix, DESIGN.md).
    causality : str
        ``input``, ``output`` or ``parameter``.
    unit : str
        Its unit (:func:`si_unit` reads it); ``1`` for a dimensionless quantity. Only Real
        signals carry one.
    description : str
        What it is, without the unit (the FMU appends it in brackets).
    type : str
        ``Real``, ``Boolean``, ``Integer`` or ``String``.
    start : float, bool, int, str or None
        The value the FMU starts with: its default, which is the shipped configuration (the system
        binds only what differs). None: the FMU computes it (from the model's own data).
    accessor : str or None
        Where the FMU reads an output from the model: an attribute path of the model's result
        (``targets.alt_cmd_m``) or a field of its value vector; None: the signal's own name.
    variability : str or None
        ``fixed``, ``tunable``, ``discrete`` or ``continuous``; None: ``fixed`` for a parameter,
        ``continuous`` for a Real input or output, ``discrete`` otherwise.
    min, max : float or None
        The allowed range of a Real or Integer variable (its FMI ``min``/``max``), None where unbounded.
    """

    name: str
    causality: str
    unit: str
    description: str
    type: str = "Real"
    start: float | bool | int | str | None = None
    accessor: str | None = None
    variability: str | None = None
    min: float | None = None
    max: float | None = None

    @property
    def source(self) -> str:
        """The accessor, or the name when none is given."""
        return self.accessor or self.name

    @property
    def fmi_variability(self) -> str:
        if self.variability is not None:
            return self.variability
        if self.causality == "parameter":
            return "fixed"
        return "continuous" if self.type == "Real" else "discrete"

    def described(self) -> str:
        """The description with its unit in brackets (``[-]`` when dimensionless), as FMUs show it."""
        unit = "-" if self.unit in ("1", "-", "") else self.unit
        return f"{self.description} [{unit}]"


def si_unit(text: str) -> tuple[tuple[int, ...], float]:
    """The base-unit exponents (kg, m, s, A, K, mol, cd, rad) and the factor to SI of a unit text.

    Parameters
    ----------
    text : str
        A unit such as ``kg/(N s)``, ``rpm/s``, ``kg m2``, ``1/(rad s)``, ``%`` or ``-``.

    Returns
    -------
    tuple
        ``(exponents, factor)``: a value ``x`` in the unit is ``factor * x`` in SI.

    Raises
    ------
    UnitError
        For a symbol that is not known or text that is not a unit.
    """
    if text.strip() in ("-", ""):
        text = "1"
    tokens: list[tuple[str, str, int]] = []
    pos = 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            if text[pos:].strip() == "":
                break
            raise UnitError(f"unit '{text}': cannot read '{text[pos:]}' (SI symbols, ' ' or '.', '/', "
                            "powers as m2 or s^-1, parentheses)")
        pos = m.end()
        if m.group("op"):
            tokens.append(("op", m.group("op"), 0))
        else:
            sym = m.group("sym")
            if sym not in _SYMBOLS:
                raise UnitError(f"unit '{text}': unknown symbol '{sym}' (known: {', '.join(_SYMBOLS)})")
            tokens.append(("sym", sym, int(m.group("exp") or 1)))
    exps, factor, rest = _product(tokens, text)
    if rest:
        raise UnitError(f"unit '{text}': unbalanced parentheses")
    return exps, factor


def _product(tokens: list[tuple[str, str, int]], text: str) -> tuple[tuple[int, ...], float, list]:
    """Parse ``term (('.'|' '|'/') term)*`` up to a closing parenthesis; returns what is left."""
    exps, factor, sign = [0] * len(BASE_UNITS), 1.0, 1
    while tokens:
        kind, val, power = tokens.pop(0)
        if kind == "op" and val == ")":
            return tuple(exps), factor, [(kind, val, power), *tokens]
        if kind == "op" and val in "./*":
            sign = -1 if val == "/" else sign
            continue
        if kind == "op" and val == "(":
            e, f, tokens = _product(tokens, text)
            if not tokens or tokens[0][1] != ")":
                raise UnitError(f"unit '{text}': unbalanced parentheses")
            tokens = tokens[1:]
        else:
            e, f = _SYMBOLS[val]
            e, f = tuple(x * power for x in e), f ** power
        exps = [a + sign * b for a, b in zip(exps, e, strict=True)]
        factor *= f ** sign
        sign = 1
    return tuple(exps), factor, []


def check_table(rows: tuple[Signal, ...], where: str) -> tuple[Signal, ...]:
    """The table itself, after checking it: unique names, known causality and type, readable units."""
    seen: set[str] = set()
    for r in rows:
        if r.name in seen:
            raise ValueError(f"{where}: signal '{r.name}' is listed twice")
        seen.add(r.name)
        if r.causality not in ("input", "output", "parameter"):
            raise ValueError(f"{where}: signal '{r.name}': causality '{r.causality}' (input, output, parameter)")
        if r.type not in ("Real", "Boolean", "Integer", "String"):
            raise ValueError(f"{where}: signal '{r.name}': type '{r.type}' (Real, Boolean, Integer, String)")
        si_unit(r.unit)
    return rows
