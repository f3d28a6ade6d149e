"""Resolve parameter bindings to FMU variables: prefixes, parameter mappings (.ssm), units.

Order of application (later wins): each component's own bindings, then the
system-level bindings (nested systems' bindings with their path as prefix), then
the ``--params`` files, then ``--set``. Within one binding (one parameter set) a variable
is set once: a second value for it (the same name twice, two mapped names, aliases) is a
problem naming both places, never the last silently winning. Within a binding, a name is first prefixed, then looked
up in the binding's parameter mapping: a mapped parameter goes to the mapping
entry's target, through its transformation; an unmapped one keeps its name. A
value whose unit differs from the variable's is converted (unless the mapping
entry suppresses unit conversion), after the transformation, as on connections.
"""
from __future__ import annotations

import math
from collections.abc import Callable

from ..errors import Problem
from .conversion import ConversionError, unit_step
from .model import (
    LinearTransformationDef,
    MappingEntryDef,
    MappingTransformationDef,
    ParameterBindingDef,
    ParameterValue,
)
from .system_model import BoundSystem, ParameterAssignment, VariableInfo
from .units import Unit
from .values import INT32_RANGE


def _coerce(value: float | int | bool | str, type_name: str, var: VariableInfo) -> float | int | bool | str | None:
    """The value converted to the variable's type, or None if the types are incompatible."""
    if type_name == var.type_name:
        return value
    if var.type_name == "Real" and type_name == "Integer":
        return float(value)
    return None


def _out_of_range(value: float | int | bool | str, type_name: str) -> str:
    """What is wrong with a value for an FMI variable of ``type_name`` ('' if nothing): a Real that is
    not finite (a transformation can overflow), an Integer beyond 32 bits (it would wrap silently)."""
    if type_name == "Real" and not math.isfinite(float(value)):  # type: ignore[arg-type]
        return f"value {value} is not a finite number"
    if type_name in ("Integer", "Enumeration") and not INT32_RANGE[0] <= int(value) <= INT32_RANGE[1]:  # type: ignore[arg-type]
        return f"value {value} is outside the range of an FMI Integer ({INT32_RANGE[0]} to {INT32_RANGE[1]})"
    return ""


def _transform(pv: ParameterValue, t: LinearTransformationDef | MappingTransformationDef | None) \
        -> tuple[float | int | bool | str, str]:
    """Apply a mapping entry's transformation to a parameter value; returns (value, type name)."""
    if t is None:
        return pv.value, pv.type_name
    if isinstance(t, LinearTransformationDef):
        if pv.type_name not in ("Real", "Integer"):
            raise ConversionError(f"LinearTransformation on a {pv.type_name} parameter")
        return t.factor * float(pv.value) + t.offset, "Real"
    text = ("true" if pv.value else "false") if pv.type_name == "Boolean" else str(pv.value)
    for source, target in t.entries:
        if source == text:
            text = target
            break
    if t.kind == "Boolean":
        return text in ("true", "1"), "Boolean"
    if t.kind == "Integer":
        try:
            return int(text), "Integer"
        except ValueError:
            raise ConversionError(f"IntegerMappingTransformation gives {text!r}, not an integer") from None
    return text, "String"  # enumeration item name, resolved against the variable below


def _lookup(*scopes: dict[str, Unit]) -> Callable[[str], Unit | None]:
    """Find a unit by name in the first scope that defines it."""
    def find(name: str) -> Unit | None:
        return next((s[name] for s in scopes if name in s), None)
    return find


def resolve_parameters(bound: BoundSystem, bindings: list[tuple[ParameterBindingDef, int | None]],
                       problems: list[Problem]) -> list[ParameterAssignment]:
    """Resolve every parameter value of every binding; later bindings override earlier ones."""
    models = bound.components
    ssd_units = bound.definition.units
    resolved: dict[tuple[int, str, int], ParameterAssignment] = {}
    for binding, owner in bindings:
        first: dict[tuple[int, str, int], str] = {}  # variable -> where this binding set it
        mapping: dict[str, list[MappingEntryDef]] = {}
        for entry in binding.mapping:
            mapping.setdefault(entry.source, []).append(entry)
        for pv in binding.values:
            full = binding.prefix + pv.name
            targets = mapping.get(full) or [MappingEntryDef(full, full, None, False, pv.where)]
            for entry in targets:
                name = entry.target
                if owner is None:
                    hit = bound.split(name)
                    if hit is None:
                        problems.append(Problem(pv.where, f"parameter '{name}': no component of the system "
                                                          "matches (system-level names are component.variable)"))
                        continue
                    idx, var_name = hit
                else:
                    idx, var_name = owner, name
                model = models[idx]
                var = model.variables.get(var_name)
                if var is None:
                    problems.append(Problem(pv.where, f"parameter '{name}': '{model.name}' has no variable "
                                                      f"'{var_name}'"))
                    continue
                if not var.settable_before_init:
                    problems.append(Problem(pv.where, f"parameter '{name}': variable '{model.name}.{var_name}' "
                                                      f"({var.causality}, {var.variability}, initial={var.initial}) "
                                                      "cannot be set by the master"))
                    continue
                try:
                    value, type_name = _transform(pv, entry.transformation)
                    if type_name == "String" and var.enum_items is not None:
                        if value not in var.enum_items:
                            raise ConversionError(f"'{value}' is not an item of the variable's enumeration "
                                                  f"(allowed: {', '.join(sorted(var.enum_items))})")
                        value, type_name = var.enum_items[value], "Integer"  # type: ignore[index]
                    if type_name == "Real" and not entry.suppress_unit_conversion:
                        lookup = _lookup(binding.units, ssd_units, model.units)
                        value = unit_step(pv.unit, model.connector_unit(var.name), lookup)(float(value))
                except ConversionError as exc:
                    problems.append(Problem(pv.where, f"parameter '{name}': {exc}"))
                    continue
                coerced = _coerce(value, type_name, var)
                if coerced is None:
                    problems.append(Problem(pv.where, f"parameter '{name}': {type_name} value for a "
                                                      f"{var.type_name} variable"))
                    continue
                out_of_range = _out_of_range(coerced, var.type_name)
                if out_of_range:
                    problems.append(Problem(pv.where, f"parameter '{name}': {out_of_range}"))
                    continue
                key = (idx, var.type_name, var.vr)
                if key in first:
                    problems.append(Problem(pv.where, f"parameter '{name}': given twice (first at {first[key]}); "
                                                      "give each parameter once"))
                    continue
                first[key] = pv.where
                resolved[key] = ParameterAssignment(idx, var, coerced, pv.where)
    return list(resolved.values())
