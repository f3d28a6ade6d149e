"""Unit definitions (SSP ``ssc:Unit``, FMI ``UnitDefinitions``) and affine conversions between them.

A unit is SI base-unit exponents plus ``factor`` and ``offset``: a value ``x`` in
the unit is ``factor * x + offset`` in the SI unit of the same dimension (as in
FMI 2.0 section 2.2.2 and SSP 1.0 ``ssc:BaseUnit``). Converting ``x`` from unit A
to unit B is ``(factor_A * x + offset_A - offset_B) / factor_B``, allowed only
when the exponents agree.
"""
from __future__ import annotations

from dataclasses import dataclass

EXPONENT_NAMES = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")


@dataclass(frozen=True)
class Unit:
    """A unit: name, SI base-unit exponents (kg, m, s, A, K, mol, cd, rad), factor and offset."""

    name: str
    exponents: tuple[int, int, int, int, int, int, int, int]
    factor: float = 1.0
    offset: float = 0.0

    def dimension(self) -> str:
        """The dimension as text, e.g. ``kg.m.s-2``; ``1`` when dimensionless."""
        parts = [f"{n}{e if e != 1 else ''}" for n, e in zip(EXPONENT_NAMES, self.exponents, strict=True) if e]
        return ".".join(parts) or "1"


@dataclass(frozen=True)
class Affine:
    """``y = scale * x + offset``."""

    scale: float = 1.0
    offset: float = 0.0

    def __call__(self, x: float) -> float:
        return self.scale * x + self.offset

    def then(self, other: Affine) -> Affine:
        """This map followed by ``other``."""
        return Affine(other.scale * self.scale, other.scale * self.offset + other.offset)

    @property
    def is_identity(self) -> bool:
        return self.scale == 1.0 and self.offset == 0.0


IDENTITY = Affine()


class UnitMismatch(ValueError):
    """Two units of different dimensions were to be converted."""


def conversion(source: Unit, target: Unit) -> Affine:
    """The affine map taking a value in ``source`` to the same quantity in ``target``.

    Raises
    ------
    UnitMismatch
        If the units have different dimensions.
    """
    if source.exponents != target.exponents:
        raise UnitMismatch(f"cannot convert '{source.name}' ({source.dimension()}) to '{target.name}' "
                           f"({target.dimension()}): different dimensions")
    return Affine(source.factor / target.factor, (source.offset - target.offset) / target.factor)


def from_attributes(name: str, attributes: dict[str, str]) -> Unit:
    """A unit from BaseUnit-style attributes (missing exponents are 0, factor 1, offset 0)."""
    exps = tuple(int(attributes.get(n, 0)) for n in EXPONENT_NAMES)
    return Unit(name, exps, float(attributes.get("factor", 1.0)), float(attributes.get("offset", 0.0)))  # type: ignore[arg-type]
