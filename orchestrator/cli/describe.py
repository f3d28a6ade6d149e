"""What a system lets a user set: every parameter of its FMUs with type, unit, default, range and description.

Read from each FMU's model description (fmpy): causality ``parameter`` (fixed or tunable), the start
value as the default, ``min``/``max`` (the variable's, else its declared type's) as the range, the unit
as :func:`.timeseries.columns_of` finds it; the value bound by the SSD or the parameter sets when it
differs from the default.
"""
from __future__ import annotations

from typing import Any

from ..scenarios.timeseries import unit_from_description
from ..ssp.system import BoundSystem


def parameters(bound: BoundSystem) -> list[dict[str, Any]]:
    """One entry per settable parameter: ``name`` (component.variable), ``type``, ``unit``, ``default``,
    ``min``, ``max`` (None where the FMU gives none), ``value`` (bound by the SSD or the parameter sets,
    None where the default holds), ``variability`` (``fixed``: before initialization; ``tunable``: during
    the run too), ``description``."""
    bound_values = {(p.component, p.variable.name): p.value for p in bound.parameters}
    out = []
    for i, c in enumerate(bound.components):
        for mv in c.model_description.modelVariables:
            if mv.causality != "parameter" or mv.variability == "constant":
                continue
            dt = mv.declaredType
            unit = mv.unit or (dt.unit if dt is not None else None) or unit_from_description(mv.description)
            lo = mv.min if mv.min is not None else (getattr(dt, "min", None) if dt is not None else None)
            hi = mv.max if mv.max is not None else (getattr(dt, "max", None) if dt is not None else None)
            out.append({"name": f"{c.name}.{mv.name}", "type": mv.type, "unit": unit or "", "default": mv.start,
                        "min": lo, "max": hi, "value": bound_values.get((i, mv.name)),
                        "variability": mv.variability, "description": mv.description or ""})
    return out


def parameter_lines(rows: list[dict[str, Any]]) -> list[str]:
    """The table of :func:`parameters` as text lines."""
    w = max((len(r["name"]) for r in rows), default=10)
    lines = [f"{'parameter':<{w}}  {'type':<8} {'unit':<10} {'default':>14} {'range':<23} {'set to':<14} description",
             "-" * (w + 90)]
    for r in rows:
        rng = "" if r["min"] is None and r["max"] is None else f"[{'-inf' if r['min'] is None else r['min']}, {'inf' if r['max'] is None else r['max']}]"
        val = "" if r["value"] is None or str(r["value"]) == str(r["default"]) else str(r["value"])
        default = str(r["default"]) if r["default"] is not None else ""
        if len(default) > 14:
            default = "..." + default[-11:]
        lines.append(f"{r['name']:<{w}}  {r['type']:<8} {r['unit']:<10} {default:>14} {rng:<23} {val[-14:]:<14} "
                     f"{r['description']}" + (" (tunable)" if r["variability"] == "tunable" else ""))
    return lines
