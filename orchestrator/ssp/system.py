"""Bind an SSP system description to its FMUs: variables, value references, conversions, checks.

``bind_system`` reads every FMU's modelDescription.xml once, checks that the SSD
agrees with it (connectors exist, kinds, types and units match, connections go
from an output to an input), composes each connection's transformations and
unit conversions, and resolves every parameter value to a value reference. All
problems are collected before failing.
"""
from __future__ import annotations

import zipfile
from collections.abc import Sequence
from pathlib import Path

from fmpy import read_model_description
from fmpy.model_description import ModelDescription

from ..errors import Problem, SystemStructureError
from ..results import archive_problems
from .conversion import ConversionError, discrete_path, real_path
from .model import ComponentDef, FlatConnection, Origin, ParameterBindingDef, ParameterValue, SystemDef
from .parameters import resolve_parameters
from .read import read_ssv
from .system_model import (  # re-exported: the types of a bound system are named through this module too
    BUFFER_TYPE,
    BoundSystem,
    ComponentModel,
    Link,
    ParameterAssignment,
    VariableInfo,
)
from .units import Unit, from_attributes

__all__ = ["BUFFER_TYPE", "BoundSystem", "ComponentModel", "Link", "ParameterAssignment", "VariableInfo",
           "bind_system"]


def _variables(md: ModelDescription) -> dict[str, VariableInfo]:
    out: dict[str, VariableInfo] = {}
    for v in md.modelVariables:
        start = v.start
        if start is not None and v.type in ("Real", "Integer", "Enumeration", "Boolean"):
            start = {"Real": float, "Integer": int, "Enumeration": int}.get(v.type, lambda s: s in ("true", "1"))(start)
        dt = v.declaredType
        unit = v.unit if v.unit is not None else (dt.unit if dt is not None else None)
        items = {i.name: int(i.value) for i in dt.items} if v.type == "Enumeration" and dt is not None else None
        out[v.name] = VariableInfo(v.name, v.valueReference, BUFFER_TYPE.get(v.type, v.type), v.causality,
                                   v.variability, v.initial, start, unit, v.description, items)
    return out


def _fmu_units(md: ModelDescription) -> dict[str, Unit]:
    out = {}
    for u in md.unitDefinitions:
        b = u.baseUnit
        attrs = {} if b is None else {n: getattr(b, n) for n in ("kg", "m", "s", "A", "K", "mol", "cd", "rad",
                                                                  "factor", "offset")}
        out[u.name] = from_attributes(u.name, attrs)
    return out


def _load_component(c: ComponentDef, cache: dict[Path, ModelDescription], enumerations: dict[str, dict[str, int]],
                    origin: Origin, problems: list[Problem]) -> ComponentModel | None:
    if not c.source_path.is_file():
        problems.append(Problem(c.where, f"component '{c.name}': FMU file '{c.source}' not found "
                                         f"(looked for {origin.shown(c.source_path)})"))
        return None
    md = cache.get(c.source_path)
    if md is None:
        try:  # an FMU beyond the limits of an archive (a zip bomb) is refused here, before anything runs
            with zipfile.ZipFile(c.source_path) as zf:
                bad = archive_problems(zf, origin.shown(c.source_path))
            if bad:
                problems.extend(Problem(where, f"component '{c.name}': {what}") for where, what in bad)
                return None
            md = read_model_description(str(c.source_path), validate=False)
        except Exception as exc:  # fmpy raises bare Exception for unreadable FMUs
            problems.append(Problem(c.where, f"component '{c.name}': cannot read FMU '{c.source}': {exc}"))
            return None
        cache[c.source_path] = md
    if md.fmiVersion != "2.0":
        problems.append(Problem(c.where, f"component '{c.name}': FMI {md.fmiVersion} is not supported "
                                         "(allowed: FMI 2.0 co-simulation)"))
        return None
    if md.coSimulation is None:
        problems.append(Problem(c.where, f"component '{c.name}': FMU has no co-simulation interface"))
        return None
    model = ComponentModel(c, md, _variables(md), _fmu_units(md), origin.shown(c.source_path))
    for k in c.connectors:
        v = model.variables.get(k.name)
        if v is None:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' is not a variable of FMU "
                                             f"'{c.source}'"))
            continue
        kind_ok = k.kind == v.causality or (k.kind == "inout" and v.causality in ("input", "output"))
        if not kind_ok:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' has kind '{k.kind}' but the FMU "
                                             f"variable has causality '{v.causality}'"))
        fmu_type = "Enumeration" if v.enum_items is not None else v.type_name
        if k.type_name is not None and k.type_name != fmu_type:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' is {k.type_name} but the FMU "
                                             f"variable is {fmu_type}"))
        if k.enumeration in enumerations and v.enum_items is not None and enumerations[k.enumeration] != v.enum_items:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}': enumeration '{k.enumeration}' of the "
                                             f"SSD differs from the FMU's ({enumerations[k.enumeration]} against "
                                             f"{v.enum_items})"))
        if k.unit is not None and v.unit is not None and k.unit != v.unit:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' has unit '{k.unit}' but the FMU "
                                             f"variable has unit '{v.unit}'"))
    return model


def _link(conn: FlatConnection, comps: dict[str, tuple[int, ComponentModel]], ssd_units: dict[str, Unit],
          problems: list[Problem]) -> Link | None:
    (si, sm), (ti, tm) = comps[conn.start_element], comps[conn.end_element]
    sv, tv = sm.variables.get(conn.start_connector), tm.variables.get(conn.end_connector)
    if sv is None or tv is None:
        return None  # reported as a connector that is not in the FMU
    ok = True
    if sv.causality != "output":
        problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: the start must be an "
                                            f"output, '{conn.start}' is {sv.causality}"))
        ok = False
    if tv.causality != "input":
        problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: the end must be an "
                                            f"input, '{conn.end}' is {tv.causality}"))
        ok = False
    if sv.type_name != tv.type_name:
        problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: type mismatch, "
                                            f"{sv.type_name} to {tv.type_name}"))
        return None
    if sv.type_name not in ("Real", "Integer", "Boolean"):
        problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: {sv.type_name} connections "
                                            "are not supported (allowed: Real, Integer, Boolean, Enumeration)"))
        return None

    def lookup(name: str) -> Unit | None:
        return ssd_units.get(name) or sm.units.get(name) or tm.units.get(name)

    try:
        if sv.type_name == "Real":
            affine = real_path(conn.hops, sm.connector_unit(sv.name), tm.connector_unit(tv.name), lookup)
            return Link(si, sv, ti, tv, conn.where, affine=affine) if ok else None
        kind = "Enumeration" if sv.enum_items is not None else sv.type_name
        mapping = discrete_path(conn.hops, kind, sv.enum_items, tv.enum_items)
        if kind == "Enumeration" and mapping is None and sv.enum_items != tv.enum_items:
            raise ConversionError("the two enumerations differ; add an EnumerationMappingTransformation")
        return Link(si, sv, ti, tv, conn.where, mapping=mapping) if ok else None
    except ConversionError as exc:
        problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: {exc}"))
        return None


def bind_system(sysdef: SystemDef, parameter_files: list[Path] | tuple[Path, ...] = (),
                model_descriptions: dict[Path, ModelDescription] | None = None,
                settings: Sequence[ParameterValue] = ()) -> BoundSystem:
    """Resolve a system against its FMUs; ``parameter_files`` (.ssv, system-level names) override the SSD,
    and ``settings`` (system-level names, one parameter set: ``--set``) override them.

    Raises
    ------
    SystemStructureError
        With every problem found in the SSD, the FMUs and the parameter files.

    ``model_descriptions`` (FMU path -> its model description) is filled with the FMUs read, and
    read from: binding the same system again with other parameter files reads no FMU twice.
    """
    problems: list[Problem] = list(sysdef.problems)
    cache = model_descriptions if model_descriptions is not None else {}
    names: set[str] = set()
    models: list[ComponentModel] = []
    for c in sysdef.components:
        if c.name in names:
            problems.append(Problem(c.where, f"two components are named '{c.name}'; names must be unique"))
        names.add(c.name)
        m = _load_component(c, cache, sysdef.enumerations, sysdef.origin, problems)
        if m is not None:
            models.append(m)
    comps = {m.name: (i, m) for i, m in enumerate(models)}
    links = [ln for conn in sysdef.connections
             if conn.start_element in comps and conn.end_element in comps
             for ln in [_link(conn, comps, sysdef.units, problems)] if ln is not None]
    bindings: list[tuple[ParameterBindingDef, int | None]] = []
    for i, m in enumerate(models):
        bindings.extend((b, i) for b in m.definition.bindings)
    bindings.extend((b, None) for b in sysdef.bindings)
    for f in parameter_files:
        try:
            values, units = read_ssv(Path(f))
            bindings.append((ParameterBindingDef("", values, str(f), (), units), None))
        except SystemStructureError as exc:
            problems.extend(exc.problems)
    if settings:
        bindings.append((ParameterBindingDef("", tuple(settings), settings[0].where), None))
    bound = BoundSystem(sysdef, models, links)
    if len(models) == len(sysdef.components):
        bound.parameters = resolve_parameters(bound, bindings, problems)
    if problems:
        raise SystemStructureError(problems)
    return bound
