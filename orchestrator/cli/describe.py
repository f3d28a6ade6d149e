"""What a system lets a user set: every parameter of its FMUs with type, unit, default, range and description.

Read from each FMU's model description (fmpy): causality ``parameter`` (fixed or tunable), the start
value as the default, ``min``/``max`` (the variable's, else its declared type's) as the range, the unit
as :func:`.timeseries.columns_of` finds it; the value bound by the SSD or the parameter sets when it
differs from the default.
"""
from __future__ import annotations

from typing import Any

from ..recording.timeseries import unit_from_description
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


def _bound(v: Any, missing: str) -> str:
    return missing if v is None else f"{v:g}" if isinstance(v, float) else str(v)


def range_text(lo: Any, hi: Any) -> str:
    """``[lo, hi]`` of a parameter (``-inf``/``inf`` for a missing bound; a bound of 0 is 0), or ``""``."""
    return "" if lo is None and hi is None else f"[{_bound(lo, '-inf')}, {_bound(hi, 'inf')}]"


def parameter_lines(rows: list[dict[str, Any]]) -> list[str]:
    """The table of :func:`parameters` as text lines; every value whole (the columns as wide as their longest
    entry), the description last."""
    def shown(v: Any) -> str:
        return "" if v is None else f"{v:.17g}" if isinstance(v, float) else str(v)

    cells = []
    for r in rows:
        default = shown(r["default"])
        val = "" if r["value"] is None or shown(r["value"]) == default else shown(r["value"])
        cells.append((r["name"], r["type"], r["unit"], default, range_text(r["min"], r["max"]), val,
                      r["description"] + (" (tunable)" if r["variability"] == "tunable" else "")))
    head = ("parameter", "type", "unit", "default", "range", "set to", "description")
    widths = [max([len(h), *(len(c[i]) for c in cells)]) for i, h in enumerate(head[:-1])]

    def line(c: tuple[str, ...]) -> str:
        return "  ".join(f"{x:<{w}}" for x, w in zip(c, widths, strict=False)) + "  " + c[-1]

    return [line(head), "-" * (sum(widths) + 2 * len(widths) + len(head[-1])), *(line(c) for c in cells)]
