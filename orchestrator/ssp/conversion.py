"""What a value undergoes between two connected FMU variables: transformations and unit conversions.

Each connection on the way (a ``Hop``) first applies its transformation to the
value in its start connector's unit, then converts from the start unit to the end
unit, unless ``suppressUnitConversion`` is set (SSP 1.0: with it, "the linear
transformation is performed instead of any unit conversions, whereas otherwise the
linear transformation is performed in addition to any unit conversions"). For
Real values every hop is affine, so the whole path is one ``Affine``. Boolean,
Integer and Enumeration values go through value maps (mapping transformations);
a value missing from a map is passed unchanged, as SSP 1.0 specifies.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

from .read import Hop, LinearTransformationDef, MappingTransformationDef
from .units import IDENTITY, Affine, Unit, UnitMismatch, conversion

UnitLookup = Callable[[str], Unit | None]


class ConversionError(ValueError):
    """A connection path that cannot be converted (unknown unit, wrong dimension, wrong transformation)."""


def unit_step(start: str | None, end: str | None, lookup: UnitLookup) -> Affine:
    """The conversion from unit name ``start`` to ``end``; identity when either is unknown or both equal."""
    if start is None or end is None or start == end:
        return IDENTITY
    a, b = lookup(start), lookup(end)
    missing = [n for n, u in ((start, a), (end, b)) if u is None]
    if missing:
        raise ConversionError(f"unit '{missing[0]}' is not defined (define it in the SSD's Units or the FMU's "
                              "UnitDefinitions)")
    try:
        return conversion(a, b)  # type: ignore[arg-type]
    except UnitMismatch as exc:
        raise ConversionError(str(exc)) from None


def real_path(hops: Sequence[Hop], source_unit: str | None, target_unit: str | None, lookup: UnitLookup) -> Affine:
    """Compose the hops of a Real connection into one affine map (FMU units at both ends)."""
    total = IDENTITY
    for i, hop in enumerate(hops):
        start = hop.start_unit if hop.start_unit is not None else (source_unit if i == 0 else None)
        end = hop.end_unit if hop.end_unit is not None else (target_unit if i == len(hops) - 1 else None)
        t = hop.transformation
        if isinstance(t, MappingTransformationDef):
            raise ConversionError(f"{t.kind}MappingTransformation on a Real connection (allowed: "
                                  "LinearTransformation)")
        if isinstance(t, LinearTransformationDef):
            total = total.then(Affine(t.factor, t.offset))
        if not hop.suppress_unit_conversion:
            total = total.then(unit_step(start, end, lookup))
    return total


def _typed(kind: str, text: str, enum_items: dict[str, int] | None) -> int:
    """A mapping entry's text as the integer that travels (Boolean 0/1, Integer, Enumeration value)."""
    if kind == "Boolean":
        if text not in ("true", "false", "1", "0"):
            raise ConversionError(f"'{text}' is not a Boolean (allowed: true, false)")
        return 1 if text in ("true", "1") else 0
    if kind == "Integer":
        try:
            return int(text)
        except ValueError:
            raise ConversionError(f"'{text}' is not an Integer") from None
    if enum_items is None or text not in enum_items:
        allowed = ", ".join(sorted(enum_items)) if enum_items else "none declared"
        raise ConversionError(f"'{text}' is not an item of the enumeration (allowed: {allowed})")
    return enum_items[text]


def discrete_path(hops: Sequence[Hop], kind: str, source_items: dict[str, int] | None,
                  target_items: dict[str, int] | None) -> dict[int, int] | None:
    """Compose the value maps of a Boolean/Integer/Enumeration connection; None when there is none.

    ``kind`` is the FMU variables' type; enumeration maps name items of the
    source's enumeration on the left and of the target's on the right.
    """
    total: dict[int, int] | None = None
    for hop in hops:
        t = hop.transformation
        if t is None:
            continue
        if isinstance(t, LinearTransformationDef):
            raise ConversionError(f"LinearTransformation on a {kind} connection (allowed: "
                                  f"{kind}MappingTransformation)")
        if t.kind != kind:
            raise ConversionError(f"{t.kind}MappingTransformation on a {kind} connection")
        step = {_typed(kind, s, source_items): _typed(kind, d, target_items) for s, d in t.entries}
        if total is None:
            total = step
        else:  # values mapped earlier go on through this map; the rest are mapped directly
            total = {k: step.get(v, v) for k, v in total.items()} | {k: v for k, v in step.items() if k not in total}
    return total
