"""Cycle studies on any engine file: design values varied over a grid, each combination designed again.

An engine file's value is named ``element.attribute`` (``comp.PR``, ``fan.BPR``, ``burner.Tt_K``),
``shaft.attribute`` (``lp.load_W``), ``design.attribute`` (``design.Fn_N``) or ``fuel.attribute``. :func:`with_values`
gives the engine with some of them changed, each checked as the file reader checks it (:func:`.element_kinds.
check_attr`: type, unit, range); :func:`design_sweep` designs every combination of a grid (the file's own sizing:
at equal thrust when the design gives ``Fn_N``, at equal flow when it gives ``W_kg_s``). A combination that cannot be
designed is a row with NaN and the reason, not the end of the study.

This is SPEC.md's parametric study generalised from the two-spool turbofan (:mod:`.cycle_study`, which also keeps the
jet velocity ratio by adjusting the fan) to any architecture: what is held is what the file holds.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any

from ..infra import values
from .element_kinds import DESIGN_ATTRS, FUEL_ATTRS, KINDS, SHAFT_ATTRS, Attr, check_attr
from .engine_file import EngineDef, EngineFileError
from .engine_graph import EngineGraph
from .errors import ModelError

__all__ = ["with_values", "check_grid", "design_sweep", "SweepRow", "SWEEP_COLUMNS"]

#: Performance columns of a sweep's rows, after the varied values (SI units in the names).
SWEEP_COLUMNS = ("Fn_N", "Fg_N", "W_kg_s", "Wf_kg_s", "SFC_kg_N_s", "OPR")


@dataclass(frozen=True)
class SweepRow:
    """One combination of a sweep: the varied values, the design's performance (NaN if it failed) and a note."""

    values: Mapping[str, float]
    performance: Mapping[str, float]
    note: str


def _spec(eng: EngineDef, key: str, where: str) -> tuple[str, str, Attr]:
    owner, dot, attr = key.partition(".")
    if not dot or not attr:
        raise EngineFileError(f"{where}: {key!r}: name a value as element.attribute, shaft.attribute, "
                              "design.attribute or fuel.attribute")
    if owner in eng.elements:
        spec = KINDS[eng.elements[owner].kind].attrs
    elif owner in eng.shafts:
        spec = SHAFT_ATTRS
    elif owner in ("design", "fuel"):
        spec = DESIGN_ATTRS if owner == "design" else FUEL_ATTRS
    else:
        raise EngineFileError(f"{where}: {key!r}: no element or shaft {owner!r} in {eng.file} (elements: "
                              f"{', '.join(eng.elements)}; shafts: {', '.join(eng.shafts) or 'none'}; or design, fuel)")
    if attr not in spec:
        raise EngineFileError(f"{where}: {key!r}: {owner!r} has no attribute {attr!r}; allowed: {', '.join(spec)}")
    if spec[attr].type not in ("number", "int"):
        raise EngineFileError(f"{where}: {key!r}: only numbers can be varied ({attr!r} is {spec[attr].type})")
    return owner, attr, spec[attr]


def with_values(eng: EngineDef, changes: Mapping[str, Any], where: str = "values") -> EngineDef:
    """The engine `eng` with the values `changes` (``owner.attribute`` -> value) replaced, each checked.

    Raises
    ------
    EngineFileError
        An unknown name, or a value of the wrong type or out of range: one line naming `where` and what is allowed.
    """
    elements, shafts = dict(eng.elements), dict(eng.shafts)
    design, fuel = dict(eng.design), dict(eng.fuel)
    for key, v in changes.items():
        owner, attr, a = _spec(eng, key, where)
        try:
            v = check_attr(a, v)
        except values.ValueProblem as exc:
            raise EngineFileError(f"{where}: {key}: {exc}") from None
        if owner in elements:
            e = elements[owner]
            elements[owner] = replace(e, attrs=MappingProxyType({**e.attrs, attr: v}))
        elif owner in shafts:
            s = shafts[owner]
            shafts[owner] = replace(s, attrs=MappingProxyType({**s.attrs, attr: v}))
        elif owner == "design":
            design[attr] = v
            if attr in ("W_kg_s", "Fn_N"):             # the one sizing value given replaces the other
                design["Fn_N" if attr == "W_kg_s" else "W_kg_s"] = None
        else:
            fuel[attr] = v
    return replace(eng, elements=MappingProxyType(elements), shafts=MappingProxyType(shafts),
                   design=MappingProxyType(design), fuel=MappingProxyType(fuel))


def check_grid(eng: EngineDef, grid: Sequence[tuple[str, Sequence[float]]]) -> None:
    """Every name and value of `grid` checked against the engine file (:class:`.engine_file.EngineFileError`)."""
    if not grid:
        raise EngineFileError("--vary: give at least one value to vary, e.g. --vary comp.PR 10 12 14")
    for name, vs in grid:
        for v in vs:
            with_values(eng, {name: v}, f"--vary {name}")


def design_sweep(eng: EngineDef, grid: Sequence[tuple[str, Sequence[float]]]) -> list[SweepRow]:
    """Design the engine at every combination of `grid` ((name, values) pairs, the first varying slowest).

    Raises
    ------
    EngineFileError
        A name or value the engine file cannot take (checked for every value before anything is designed).
    """
    check_grid(eng, grid)
    rows = []
    for combo in itertools.product(*(vs for _, vs in grid)):
        vals = {name: float(v) for (name, _), v in zip(grid, combo, strict=True)}
        try:
            d = EngineGraph(with_values(eng, vals, "--vary")).design()
            perf = {c: float(getattr(d, c)) for c in SWEEP_COLUMNS}
            note = ""
        except ModelError as exc:
            perf, note = {c: math.nan for c in SWEEP_COLUMNS}, str(exc).replace("\n", " ")
        rows.append(SweepRow(MappingProxyType(vals), MappingProxyType(perf), note))
    return rows
