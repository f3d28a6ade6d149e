"""Bind an SSP system description to its FMUs: variables, value references, checks.

``bind_system`` reads every FMU's modelDescription.xml once, checks that the SSD
agrees with it (connectors exist, kinds and types match, connections go from an
output to an input, one connection per input, units agree) and resolves every
parameter value to a value reference. All problems are collected before failing.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from fmpy import read_model_description
from fmpy.model_description import ModelDescription

from .errors import Problem, SystemStructureError
from .ssp import ComponentDef, ParameterBindingDef, ParameterValue, SystemDef, read_ssv

#: FMI 2.0 variable types as the orchestrator buffers them (Enumeration travels as Integer).
BUFFER_TYPE = {"Real": "Real", "Integer": "Integer", "Enumeration": "Integer", "Boolean": "Boolean", "String": "String"}


@dataclass(frozen=True)
class VariableInfo:
    """One FMU variable, with what the orchestrator needs in the hot loop."""

    name: str
    vr: int
    type_name: str  # Real, Integer, Boolean, String (Enumeration mapped to Integer)
    causality: str
    variability: str
    initial: str | None
    start: float | int | bool | str | None
    unit: str | None
    description: str | None

    @property
    def settable_before_init(self) -> bool:
        """FMI 2.0: may the master set it between instantiate and exitInitializationMode?"""
        if self.variability == "constant":
            return False
        return self.causality == "input" or self.initial in ("exact", "approx")


@dataclass
class ComponentModel:
    """A component bound to its FMU's model description."""

    definition: ComponentDef
    model_description: ModelDescription
    variables: dict[str, VariableInfo]

    @property
    def name(self) -> str:
        return self.definition.name

    @property
    def fmu_path(self) -> Path:
        return self.definition.source_path


@dataclass(frozen=True)
class Link:
    """A resolved connection: output of one component to input of another."""

    source: int  # component index
    source_var: VariableInfo
    target: int
    target_var: VariableInfo
    where: str


@dataclass(frozen=True)
class ParameterAssignment:
    """A start or parameter value to set on a component before initialization."""

    component: int
    variable: VariableInfo
    value: float | int | bool | str
    where: str


@dataclass
class BoundSystem:
    """An SSP system whose components, connections and parameters are resolved against the FMUs."""

    definition: SystemDef
    components: list[ComponentModel]
    links: list[Link]
    parameters: list[ParameterAssignment] = field(default_factory=list)

    def index(self, component_name: str) -> int:
        for i, c in enumerate(self.components):
            if c.name == component_name:
                return i
        raise KeyError(component_name)

    def variable(self, path: str) -> tuple[int, VariableInfo]:
        """Resolve ``component.variable`` (the variable name may itself contain dots)."""
        comp, _, var = path.partition(".")
        try:
            i = self.index(comp)
            return i, self.components[i].variables[var]
        except KeyError:
            raise SystemStructureError([Problem(path, "no such variable: expected component.variable "
                                                      "with a component of this system")]) from None


def _variables(md: ModelDescription) -> dict[str, VariableInfo]:
    out: dict[str, VariableInfo] = {}
    for v in md.modelVariables:
        start = v.start
        if start is not None and v.type in ("Real", "Integer", "Enumeration", "Boolean"):
            start = {"Real": float, "Integer": int, "Enumeration": int}.get(v.type, lambda s: s in ("true", "1"))(start)
        unit = v.unit if v.unit is not None else (v.declaredType.unit if v.declaredType is not None else None)
        out[v.name] = VariableInfo(v.name, v.valueReference, BUFFER_TYPE.get(v.type, v.type), v.causality,
                                   v.variability, v.initial, start, unit, v.description)
    return out


def _load_component(c: ComponentDef, cache: dict[Path, ModelDescription], problems: list[Problem]) \
        -> ComponentModel | None:
    if not c.source_path.is_file():
        problems.append(Problem(c.where, f"component '{c.name}': FMU file '{c.source}' not found "
                                         f"(looked for {c.source_path})"))
        return None
    md = cache.get(c.source_path)
    if md is None:
        try:
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
    model = ComponentModel(c, md, _variables(md))
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
        if k.type_name is not None and k.type_name != v.type_name:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' is {k.type_name} but the FMU "
                                             f"variable is {v.type_name}"))
        if k.unit is not None and v.unit is not None and k.unit != v.unit:
            problems.append(Problem(k.where, f"connector '{c.name}.{k.name}' has unit '{k.unit}' but the FMU "
                                             f"variable has unit '{v.unit}'"))
    return model


def _connector_unit(c: ComponentModel, name: str) -> str | None:
    for k in c.definition.connectors:
        if k.name == name and k.unit is not None:
            return k.unit
    v = c.variables.get(name)
    return v.unit if v is not None else None


def _links(sysdef: SystemDef, comps: dict[str, tuple[int, ComponentModel]], problems: list[Problem]) -> list[Link]:
    links: list[Link] = []
    seen_targets: dict[str, str] = {}
    for conn in sysdef.connections:
        ends: list[tuple[int, ComponentModel, VariableInfo] | None] = []
        for elem, conn_name in ((conn.start_element, conn.start_connector), (conn.end_element, conn.end_connector)):
            if elem not in comps:
                problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: no component "
                                                    f"named '{elem}'" if elem else
                                        f"connection {conn.start} -> {conn.end}: system connectors are not "
                                        "supported yet"))
                ends.append(None)
                continue
            idx, model = comps[elem]
            if not any(k.name == conn_name for k in model.definition.connectors):
                problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: component '{elem}' "
                                                    f"declares no connector '{conn_name}'"))
            var = model.variables.get(conn_name)
            if var is None:
                ends.append(None)
                continue
            ends.append((idx, model, var))
        if ends[0] is None or ends[1] is None:
            continue
        (si, sm, sv), (ti, tm, tv) = ends  # type: ignore[misc]
        if sv.causality != "output":
            problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: the start must be an "
                                                f"output, '{conn.start}' is {sv.causality}"))
        if tv.causality != "input":
            problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: the end must be an "
                                                f"input, '{conn.end}' is {tv.causality}"))
        if sv.type_name != tv.type_name:
            problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: type mismatch, "
                                                f"{sv.type_name} to {tv.type_name}"))
        su, tu = _connector_unit(sm, sv.name), _connector_unit(tm, tv.name)
        if su is not None and tu is not None and su != tu:
            problems.append(Problem(conn.where, f"connection {conn.start} -> {conn.end}: units differ "
                                                f"('{su}' to '{tu}') and unit conversion is not applied yet"))
        if conn.end in seen_targets:
            problems.append(Problem(conn.where, f"input '{conn.end}' has two incoming connections (the other at "
                                                f"{seen_targets[conn.end]}); an input takes exactly one"))
        else:
            seen_targets[conn.end] = conn.where
        links.append(Link(si, sv, ti, tv, conn.where))
    return links


def _coerce(value: ParameterValue, var: VariableInfo) -> float | int | bool | str | None:
    """The value converted to the variable's type, or None if the types are incompatible."""
    if value.type_name == var.type_name:
        return value.value
    if var.type_name == "Real" and value.type_name == "Integer":
        return float(value.value)
    return None


def _resolve_parameters(bindings: list[tuple[ParameterBindingDef, int | None]], models: list[ComponentModel],
                        problems: list[Problem]) -> list[ParameterAssignment]:
    """Resolve parameter values to variables; later bindings override earlier ones."""
    by_name = {m.name: i for i, m in enumerate(models)}
    resolved: dict[tuple[int, str, int], ParameterAssignment] = {}
    for binding, owner in bindings:
        for pv in binding.values:
            full = binding.prefix + pv.name
            if owner is None:
                comp, _, var_name = full.partition(".")
                if comp not in by_name:
                    problems.append(Problem(pv.where, f"parameter '{full}': no component '{comp}' in the system "
                                                      "(system-level names are component.variable)"))
                    continue
                idx = by_name[comp]
            else:
                idx, var_name = owner, full
            var = models[idx].variables.get(var_name)
            if var is None:
                problems.append(Problem(pv.where, f"parameter '{full}': '{models[idx].name}' has no variable "
                                                  f"'{var_name}'"))
                continue
            if not var.settable_before_init:
                problems.append(Problem(pv.where, f"parameter '{full}': variable '{models[idx].name}.{var_name}' "
                                                  f"({var.causality}, {var.variability}, initial={var.initial}) "
                                                  "cannot be set by the master"))
                continue
            value = _coerce(pv, var)
            if value is None:
                problems.append(Problem(pv.where, f"parameter '{full}': {pv.type_name} value for a "
                                                  f"{var.type_name} variable"))
                continue
            if pv.unit is not None and var.unit is not None and pv.unit != var.unit:
                problems.append(Problem(pv.where, f"parameter '{full}': unit '{pv.unit}' but the variable's "
                                                  f"unit is '{var.unit}' (unit conversion is not applied yet)"))
                continue
            resolved[(idx, var.type_name, var.vr)] = ParameterAssignment(idx, var, value, pv.where)
    return list(resolved.values())


def bind_system(sysdef: SystemDef, parameter_files: list[Path] | tuple[Path, ...] = ()) -> BoundSystem:
    """Resolve a system against its FMUs; ``parameter_files`` (.ssv, system-level names) override the SSD.

    Raises
    ------
    SystemStructureError
        With every problem found in the SSD, the FMUs and the parameter files.
    """
    problems: list[Problem] = []
    cache: dict[Path, ModelDescription] = {}
    names: set[str] = set()
    models: list[ComponentModel] = []
    for c in sysdef.components:
        if c.name in names:
            problems.append(Problem(c.where, f"two components are named '{c.name}'; names must be unique"))
        names.add(c.name)
        m = _load_component(c, cache, problems)
        if m is not None:
            models.append(m)
    comps = {m.name: (i, m) for i, m in enumerate(models)}
    links = _links(sysdef, comps, problems)
    bindings: list[tuple[ParameterBindingDef, int | None]] = []
    for i, m in enumerate(models):
        bindings.extend((b, i) for b in m.definition.bindings)
    bindings.extend((b, None) for b in sysdef.bindings)
    for f in parameter_files:
        try:
            bindings.append((ParameterBindingDef("", read_ssv(Path(f)), str(f)), None))
        except SystemStructureError as exc:
            problems.extend(exc.problems)
    parameters = _resolve_parameters(bindings, models, problems) if len(models) == len(sysdef.components) else []
    if problems:
        raise SystemStructureError(problems)
    return BoundSystem(sysdef, models, links, parameters)
