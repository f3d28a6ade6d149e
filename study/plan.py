"""From a study to its cases: every combination of variant, grid point, mission and scenario.

The parameter values are checked against the system before any case runs: each
``component.variable`` must exist and be a parameter or input, and each value is
typed as that FMU variable (Real, Integer, Boolean, String).
"""
from __future__ import annotations

import itertools
import re
from pathlib import Path

from .case import CaseDef, ValueT, definition_digest
from .spec import StudyDef, StudyError, Variant

__all__ = ["prepare_system", "expand_cases", "typed_value"]

FMI_INT_MIN, FMI_INT_MAX = -(2**31), 2**31 - 1  #: an FMI 2.0 Integer is a 32-bit C int


def prepare_system(system: Path) -> None:
    """Build the FMUs of the project's own systems (ssp/ and ssp/hybrid/, the oscillator example) once, before
    the cases run, as ``emss run`` does (:func:`openemss.orchestrator.cli.api.ensure_project_fmus`); cases
    running at the same time must not."""
    from openemss.orchestrator.cli.api import ensure_project_fmus

    ensure_project_fmus(system, report=lambda m: None)


def typed_value(type_name: str, value: ValueT, where: str) -> ValueT:
    """`value` as the Python type of an FMU variable of `type_name` (Real, Integer, Enumeration, Boolean, String)."""
    if type_name == "Real" and isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    if type_name in ("Integer", "Enumeration") and not isinstance(value, bool) and (
            isinstance(value, int) or (isinstance(value, float) and value.is_integer())):
        if not FMI_INT_MIN <= value <= FMI_INT_MAX:
            raise StudyError(f"{where}: {value!r} is outside the range of an FMI {type_name} "
                             f"[{FMI_INT_MIN}, {FMI_INT_MAX}]")
        return int(value)
    if type_name == "Boolean" and isinstance(value, bool):
        return value
    if type_name == "String" and isinstance(value, str | int | float) and not isinstance(value, bool):
        return str(value)
    raise StudyError(f"{where}: {value!r} is not a valid {type_name} value")


def _label(value: ValueT) -> str:
    text = f"{value:g}" if isinstance(value, float) else str(value).lower() if isinstance(value, bool) else str(value)
    return re.sub(r"[^A-Za-z0-9_.+-]+", "_", text)[:40]


def expand_cases(study: StudyDef) -> list[CaseDef]:
    """Every case of `study`, named after what distinguishes it, with its digest.

    Raises
    ------
    StudyError
        A parameter that is not a variable of the system, or a value of the wrong type.
    """
    from openemss.orchestrator.errors import EmssError
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    prepare_system(study.system)
    try:
        bound = bind_system(load_system(study.system), list(study.params))
    except EmssError as exc:
        raise StudyError(f"{study.where('system')}: {str(exc).splitlines()[0]}") from None

    def typed(path: str, value: ValueT, field_name: str) -> ValueT:
        where = study.where(field_name)
        try:
            _, var = bound.variable(path)
        except EmssError:
            raise StudyError(f"{where}: '{path}' is not a variable of system {bound.definition.name} "
                             f"(components: {', '.join(c.name for c in bound.components)})") from None
        if var.causality not in ("parameter", "input") or var.variability == "constant":
            raise StudyError(f"{where}: '{path}' is a {var.causality} ({var.variability}); only parameters "
                             "and inputs can be set")
        return typed_value(var.type_name, value, f"{where}: '{path}'")

    base_values = [(k, typed(k, v, f"values.{k}")) for k, v in study.values]
    variants = study.variants or (Variant(""),)
    for i, var in enumerate(variants):
        for k, v in var.values:
            typed(k, v, f"variants[{i}].values.{k}")
    grid_axes = [[(k, typed(k, v, f"grid.{k}")) for v in vals] for k, vals in study.grid]
    if study.missions:
        typed(study.mission_parameter, "x", "mission_parameter")
    missions: list[tuple[str, Path | None]] = list(study.missions) or [("", None)]
    scenarios: list[tuple[str, Path | None]] = list(study.scenarios) or [("", None)]
    short = {k: k.split(".")[-1] for k, _ in study.grid}
    if len(set(short.values())) < len(short):
        short = {k: k for k in short}
    cases: list[CaseDef] = []
    cache: dict[Path, str] = {}
    for var, point, (mname, mpath), (sname, spath) in itertools.product(
            variants, itertools.product(*grid_axes), missions, scenarios):
        values = dict(base_values)
        values.update((k, typed(k, v, f"variants.{var.name}.values.{k}")) for k, v in var.values)
        values.update(point)
        if mpath is not None:
            values[study.mission_parameter] = str(mpath)
        labels = [("variant", var.name)] if var.name else []
        labels += [(k, _label(v)) for k, v in point]
        labels += [("mission", mname)] if mname else []
        labels += [("scenario", sname)] if sname else []
        name = "-".join(lab if dim in ("variant", "mission", "scenario") else f"{short[dim]}={lab}"
                        for dim, lab in labels) or "case"
        case = CaseDef(name=name, labels=tuple(labels), system=str(study.system),
                       params=tuple(str(p) for p in (*study.params, *var.params)),
                       values=tuple(values.items()), scenario=str(spath) if spath else None,
                       stop_time_s=study.stop_time_s, rate_hz=study.rate_hz, algorithm=study.algorithm,
                       record=study.record, record_every=study.record_every, pre_run=study.pre_run,
                       figures=study.figures)
        files = [study.system, *study.params, *var.params, *(p for p in (mpath, spath) if p is not None)]
        digest = definition_digest(case, files, cache)
        cases.append(CaseDef(**{**case.__dict__, "digest": digest}))
    names = [c.name for c in cases]
    if len(set(names)) < len(names):  # labels shortened to the same text: number them
        cases = [CaseDef(**{**c.__dict__, "name": f"{i:03d}-{c.name}"}) for i, c in enumerate(cases)]
    return cases
