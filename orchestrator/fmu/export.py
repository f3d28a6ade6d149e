"""Export a bound system as one FMI 2.0 co-simulation FMU, run by fmpy's container runtime.

The exported FMU holds every component FMU under ``resources/``, a
``resources/container.json`` that wires them, and fmpy's prebuilt
``container_fmu`` library as its binary. The container steps all components
from the same inputs over its fixed internal step, then copies outputs to inputs
(a Jacobi master that exchanges after the step); in initialization mode it copies
every connection once, in the configuration's order, before leaving initialization mode,
and not again before the first step. So the first step runs on the outputs the components
show in Initialization Mode: they must be their initial values there (FMI 2.0 allows a
master to read them), not placeholders filled in on leaving it (ours are:
``fmus/initial_outputs.py``).

The runtime's exchange is one connection at a time (get, then set), in the
configuration's order, so the order matters when an output depends directly on
an input of its own component (direct feedthrough). We write the connections in
reverse Gauss-Seidel order of their source component: every component's outputs
are read before any of its inputs is set, as our Jacobi master does (it gets a
component's outputs right after its step). The stepping then equals our Jacobi
master's. The one difference left is initialization: we iterate the exchange to
a fixed point, the runtime makes one pass, so a feedthrough output is read with
its inputs still at their start values. Give connected inputs consistent start
values (parameter bindings) when that matters; see tests/test_export.py for the
size of the effect on the oscillator example.

Where fmpy falls short, and why we wrap it instead of calling
``fmpy.container_fmu.cli.create_container_fmu`` (fmpy 0.3.32, container format 0.1.0):

- ``write_configuration`` writes a connection's type as the FMI variable type
  (``"Real"``, ``"Integer"``), but the runtime only parses FMI 3 names
  (``"Float64"``, ``"Int32"``): a container of FMI 2.0 components does not even
  instantiate ("unknown variant `Real`"). Enumerations are not mapped at all.
- ``create_container_fmu`` zips the folder it is writing the archive into, so a
  truncated ``Container.zip`` ends up inside every FMU; it extracts each FMU to a
  folder named after the file's stem (two different FMUs called ``Engine.fmu``
  would overwrite each other); it deletes the folder it is given and moves the
  archive with ``os.rename`` (fails across file systems).
- The container runtime exchanges values as they are: no linear transformation,
  no unit conversion, no Boolean/Integer/Enumeration mapping, a single step
  size for every component (no step multiples), and fmpy's writer has no way to
  say otherwise. We refuse those systems instead of exporting something that
  computes a different answer (see :func:`check_exportable`).
- It initializes with one pass of the exchange (above), not to a fixed point, and
  implements neither ``fmi2GetFMUstate`` nor ``fmi2GetStatus`` (``fmi2Discard``
  from a component cannot be told apart from a failed step).

String parameters, inputs and outputs are exported: the runtime sets String start
values and passes ``fmi2GetString``/``fmi2SetString`` through (checked with fmpy
0.3.32 in tests/test_export.py). String *connections* cannot occur: ``bind_system``
refuses them, as our master does not exchange Strings.

So we keep fmpy's model-description writer and its runtime library, and write
the configuration and the archive ourselves, to the runtime's own schema.
"""
from __future__ import annotations

import hashlib
import json
import math
import tempfile
import uuid
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import attrs
from fmpy.model_description import (
    CoSimulation,
    DefaultExperiment,
    ModelDescription,
    ModelVariable,
    SimpleType,
    Unit,
    Unknown,
    write_model_description,
)

from openemss.models.infra.files import write_whole

from ..errors import ConfigurationError
from ..master.algorithm import gauss_seidel_order
from ..results import ResultsError, os_reason
from ..ssp.system import BoundSystem, Link, VariableInfo

#: Container format this writer produces; fmpy's runtime refuses any other.
CONTAINER_VERSION = "0.1.0"
#: FMI 2.0 platform folder -> the runtime library fmpy ships for it.
RUNTIME_BINARIES = {
    "linux64": ("x86_64-linux", "container_fmu.so"),
    "win64": ("x86_64-windows", "container_fmu.dll"),
    "darwin64": ("x86_64-darwin", "container_fmu.dylib"),
}
#: FMI type -> the runtime's variable type (FMI 2.0 Enumerations travel as Integer).
_RUNTIME_TYPE = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}


@dataclass(frozen=True)
class ContainerVariable:
    """One variable of the exported FMU and the component variable behind it.

    Attributes
    ----------
    name : str
        ``component.variable``.
    component : int
        Index of the component in the system.
    variable : VariableInfo
        The component's variable.
    causality : str
        The container variable's causality: ``input``, ``output``, ``parameter`` or ``local``.
    start : float | int | bool | str | None
        Start value the container sets on the component when it is instantiated (None: none).
    """

    name: str
    component: int
    variable: VariableInfo
    causality: str
    start: float | int | bool | str | None


def _connection_name(system: BoundSystem, link_index: int) -> str:
    ln = system.links[link_index]
    src, dst = system.components[ln.source].name, system.components[ln.target].name
    return f"{ln.where}: connection {src}.{ln.source_var.name} -> {dst}.{ln.target_var.name}"


def check_exportable(system: BoundSystem, multiples: Mapping[str, int] | None = None) -> None:
    """Refuse what fmpy's container runtime cannot reproduce.

    Parameters
    ----------
    system : BoundSystem
        The system to export.
    multiples : Mapping[str, int] | None
        Step multiple per component name; every one must be 1.

    Raises
    ------
    ConfigurationError
        Naming each connection with a transformation, unit conversion or value
        mapping (or of a type other than Real, Integer, Boolean, Enumeration) and
        each step multiple other than 1.
    """
    problems: list[str] = []
    for j, ln in enumerate(system.links):
        if not ln.affine.is_identity:
            problems.append(f"{_connection_name(system, j)} has a linear transformation or unit conversion "
                            f"(value * {ln.affine.scale!r} + {ln.affine.offset!r}); fmpy's container copies "
                            "values unchanged")
        if ln.mapping is not None:
            problems.append(f"{_connection_name(system, j)} has a value mapping ({ln.mapping}); fmpy's container "
                            "copies values unchanged")
        if ln.source_var.type_name not in ("Real", "Integer", "Boolean"):
            # bind_system refuses these already; our master could not be compared with the export
            problems.append(f"{_connection_name(system, j)} is a {ln.source_var.type_name} connection (allowed: "
                            "Real, Integer, Boolean, Enumeration)")
    for name, n in sorted((multiples or {}).items()):
        if n != 1:
            problems.append(f"component '{name}' has step multiple {n}; fmpy's container steps every component "
                            "with one fixed step (allowed: 1)")
    if problems:
        more = f" (and {len(problems) - 1} more: " + "; ".join(problems[1:]) + ")" if len(problems) > 1 else ""
        raise ConfigurationError(f"cannot export as a container FMU: {problems[0]}{more}")


def container_variables(system: BoundSystem, expose: Sequence[str] = ()) -> list[ContainerVariable]:
    """The variables the exported FMU shows, in order.

    Every output connector of the SSD (as a container output), every FMU input no
    connection drives (as a container input, start: the bound value or the FMU's),
    every bound parameter (as a container parameter, start: the bound value), then
    the further ``component.variable`` paths of ``expose``. A bound value on a
    connected input or on a local becomes a container ``local`` with that start, so
    the container sets it as our master does (the initial exchange then overrides
    a connected input in both).

    Raises
    ------
    ConfigurationError
        For an unknown path in ``expose``, a connected input in ``expose``, or two
        variables with the same ``component.variable`` name.
    """
    bound = {(p.component, p.variable.vr, p.variable.type_name): p.value for p in system.parameters}
    driven = {(ln.target, ln.target_var.vr, ln.target_var.type_name) for ln in system.links}
    out: list[ContainerVariable] = []
    seen: dict[tuple[int, str], int] = {}

    def add(i: int, v: VariableInfo, causality: str, start: float | int | bool | str | None) -> None:
        if (i, v.name) in seen:
            return
        seen[(i, v.name)] = len(out)
        out.append(ContainerVariable(f"{system.components[i].name}.{v.name}", i, v, causality, start))

    for i, c in enumerate(system.components):
        for k in c.definition.connectors:
            v = c.variables.get(k.name)
            if v is not None and v.causality == "output":
                key = (i, v.vr, v.type_name)
                add(i, v, "output", bound.get(key))
        for v in c.variables.values():
            key = (i, v.vr, v.type_name)
            if v.causality == "input" and key not in driven:
                add(i, v, "input", bound.get(key, v.start))
    for p in system.parameters:
        i, v = p.component, p.variable
        if v.causality in ("parameter", "output"):
            add(i, v, v.causality, p.value)
        else:  # a connected input or a local with initial exact/approx
            add(i, v, "local", p.value)
    for path in expose:
        try:
            i, v = system.variable(path)
        except Exception:  # SystemStructureError: re-raised as a run option error
            raise ConfigurationError(f"cannot expose '{path}': no such variable (write component.variable)") \
                from None
        key = (i, v.vr, v.type_name)
        if v.causality == "input" and key in driven:
            raise ConfigurationError(f"cannot expose '{path}' as an input: a connection drives it")
        if v.causality == "parameter":
            if v.start is None:
                raise ConfigurationError(f"cannot expose '{path}': parameter without a start value")
            add(i, v, "parameter", bound.get(key, v.start))
        elif v.causality == "input":
            add(i, v, "input", bound.get(key, v.start))
        else:  # outputs, locals, calculated parameters: read-only in the container
            add(i, v, "output", None)
    names = [cv.name for cv in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigurationError(f"cannot export: container variable name(s) {', '.join(dup)} are ambiguous "
                                 "(component names with dots)")
    return out


def _literal(value: float | int | bool | str) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(int(value))


def _model_variable(cv: ContainerVariable, system: BoundSystem, types: dict[tuple[int, str], SimpleType],
                    units: Mapping[str, object]) -> ModelVariable:
    v = cv.variable
    md_var = next(mv for mv in system.components[cv.component].model_description.modelVariables
                  if mv.valueReference == v.vr and mv.name == v.name)
    type_name = "Enumeration" if v.enum_items is not None else v.type_name
    mv = ModelVariable(name=cv.name, valueReference=0, type=type_name, causality=cv.causality,
                       description=v.description)
    mv.canHandleMultipleSetPerTimeInstant = False  # a Model Exchange attribute: left out
    if cv.causality == "parameter":
        mv.variability = "tunable" if v.variability == "tunable" else "fixed"
        mv.initial = "exact"
    elif cv.causality == "input":
        mv.variability = v.variability if v.variability in ("continuous", "discrete") else "continuous"
    else:
        mv.variability = v.variability if v.variability in ("continuous", "discrete") else "discrete"
        mv.initial = "calculated" if cv.start is None else "exact"
    if type_name != "Real" and mv.variability == "continuous":
        mv.variability = "discrete"  # FMI 2.0: only Reals are continuous
    if cv.start is not None:
        mv.start = _literal(cv.start)
    if type_name == "Real" and v.unit in units:
        mv.unit = v.unit  # only units the FMUs define, so that the container's UnitDefinitions hold them
    if type_name == "Enumeration" and md_var.declaredType is not None:
        mv.declaredType = types[(cv.component, md_var.declaredType.name)]
    return mv


def _type_definitions(system: BoundSystem, cvs: list[ContainerVariable]) -> dict[tuple[int, str], SimpleType]:
    """Copies of the enumeration types the container variables use, named ``component.Type``."""
    types: dict[tuple[int, str], SimpleType] = {}
    for cv in cvs:
        if cv.variable.enum_items is None:
            continue
        md_var = next(mv for mv in system.components[cv.component].model_description.modelVariables
                      if mv.name == cv.variable.name)
        dt = md_var.declaredType
        if dt is not None and (cv.component, dt.name) not in types:
            types[(cv.component, dt.name)] = attrs.evolve(dt, name=f"{system.components[cv.component].name}."
                                                                    f"{dt.name}")
    return types


def _exchange_order(system: BoundSystem) -> list[Link]:
    """The links in the order the runtime should copy them (see the module docstring)."""
    order = gauss_seidel_order(len(system.components), [(ln.source, ln.target) for ln in system.links]).order
    rank = {c: r for r, c in enumerate(reversed(order))}
    return sorted(system.links, key=lambda ln: rank[ln.source])


def _resource_folders(system: BoundSystem) -> list[str]:
    """One folder under resources/ per FMU file (components sharing a file share it), unique names."""
    by_file: dict[Path, str] = {}
    used: set[str] = set()
    out = []
    for c in system.components:
        key = c.fmu_path.resolve()
        if key not in by_file:
            stem, n = c.fmu_path.stem, 1
            name = stem
            while name in used or name == "container.json":
                n += 1
                name = f"{stem}_{n}"
            used.add(name)
            by_file[key] = name
        out.append(by_file[key])
    return out


def _platforms(system: BoundSystem) -> list[str]:
    """The FMI 2.0 platforms every component has a binary for and fmpy ships the runtime for."""
    import fmpy.container_fmu as container

    root = Path(container.__file__).parent / "binaries"
    ok = []
    for platform, (folder, lib) in RUNTIME_BINARIES.items():
        if not (root / folder / lib).is_file():
            continue
        have = True
        for c in system.components:
            with zipfile.ZipFile(c.fmu_path) as z:
                if not any(n.startswith(f"binaries/{platform}/") and not n.endswith("/") for n in z.namelist()):
                    have = False
                    break
        if have:
            ok.append(platform)
    return ok


def export_container(system: BoundSystem, out: Path, step_size_s: float, expose: Sequence[str] = (),
                     multiples: Mapping[str, int] | None = None, model_name: str | None = None) -> Path:
    """Write the system as one FMI 2.0 co-simulation FMU (fmpy's container runtime).

    Parameters
    ----------
    system : BoundSystem
        The system, resolved against its FMUs (its parameter bindings become start values).
    out : Path
        The ``.fmu`` file to write (replaced atomically if it exists).
    step_size_s : float
        The container's fixed internal step = the master step [s], > 0. An importer
        may only call ``doStep`` with whole multiples of it.
    expose : Sequence[str]
        Further ``component.variable`` paths to show, beyond every output connector,
        every input no connection drives and every bound parameter.
    multiples : Mapping[str, int] | None
        Step multiples of the run being exported; refused unless all are 1.
    model_name : str | None
        ``modelName`` of the container; default: the system's name.

    Returns
    -------
    Path
        ``out``.

    Raises
    ------
    ConfigurationError
        For what the container cannot reproduce (:func:`check_exportable`), a bad
        step size, or a bad ``expose`` path.
    """
    import fmpy.container_fmu as container

    if not (isinstance(step_size_s, (int, float)) and math.isfinite(step_size_s) and step_size_s > 0):
        raise ConfigurationError(f"container step size {step_size_s!r} s: must be a finite number > 0")
    if getattr(container, "__version__", None) != CONTAINER_VERSION:
        raise ConfigurationError(f"fmpy's container runtime is version {getattr(container, '__version__', '?')}, "
                                 f"this exporter writes format {CONTAINER_VERSION} (pin fmpy 0.3.32)")
    check_exportable(system, multiples)
    cvs = container_variables(system, expose)
    folders = _resource_folders(system)
    platforms = _platforms(system)
    if not platforms:
        raise ConfigurationError("cannot export: no platform has both fmpy's container runtime and a binary of "
                                 "every component FMU")

    # container.json, in the runtime's schema (fmpy/native/container-fmu/src/conf.rs)
    config = {
        "containerVersion": CONTAINER_VERSION,
        "instantiationToken": "",
        "fixedStepSize": float(step_size_s),
        "parallelDoStep": False,  # pythonfmu slaves share one interpreter; the runtime's callbacks are not Sync
        "components": [{"fmiMajorVersion": "2", "name": c.name,
                        "instantiationToken": c.model_description.guid,
                        "modelIdentifier": c.model_description.coSimulation.modelIdentifier,
                        "path": folders[i]} for i, c in enumerate(system.components)],
        "variables": [],
        "connections": [],
    }
    for cv in cvs:
        entry: dict[str, object] = {"variableType": _RUNTIME_TYPE[cv.variable.type_name],
                                    "mappings": [{"component": cv.component, "valueReference": cv.variable.vr}]}
        if cv.start is not None:
            entry["start"] = [_literal(cv.start)]
        config["variables"].append(entry)  # type: ignore[union-attr]
    for ln in _exchange_order(system):
        config["connections"].append({  # type: ignore[union-attr]
            "variableType": _RUNTIME_TYPE[ln.source_var.type_name], "srcComponent": ln.source,
            "srcValueReferences": [ln.source_var.vr], "dstComponent": ln.target,
            "dstValueReferences": [ln.target_var.vr], "size": 1})
    digest = hashlib.sha256(json.dumps(config, sort_keys=True).encode()
                            + b"".join(Path(c.fmu_path).read_bytes() for c in system.components)).hexdigest()
    guid = "{" + str(uuid.UUID(digest[:32])) + "}"
    config["instantiationToken"] = guid

    # modelDescription.xml, with fmpy's writer; "time" is the runtime's value reference 0
    types = _type_definitions(system, cvs)
    sysdef = system.definition
    time_var = ModelVariable(name="time", valueReference=0, type="Real", causality="independent",
                             variability="continuous", description="Simulation time [s]")
    time_var.canHandleMultipleSetPerTimeInstant = False
    units: dict[str, Unit] = {}
    for c in system.components:
        for u in c.model_description.unitDefinitions:
            units.setdefault(u.name, u)
    variables = [time_var] + [_model_variable(cv, system, types, units) for cv in cvs]
    for vr, mv in enumerate(variables):
        mv.valueReference = vr
    used_units = {mv.unit for mv in variables if mv.unit}
    outputs = [Unknown(variable=mv) for mv in variables if mv.causality == "output"]
    md = ModelDescription(
        fmiVersion="2.0", modelName=model_name or sysdef.name, instantiationToken=guid,
        description=f"SSP system '{sysdef.name}' as one FMU: {len(system.components)} components, "
                    f"{len(system.links)} connections, fixed step {step_size_s!r} s (fmpy container runtime)",
        generationTool="openEMSS (emss export --container)",
        variableNamingConvention="flat",
        coSimulation=CoSimulation(modelIdentifier="container_fmu", fixedInternalStepSize=float(step_size_s)),
        defaultExperiment=DefaultExperiment(
            startTime=None if sysdef.start_time_s is None else repr(float(sysdef.start_time_s)),
            stopTime=None if sysdef.stop_time_s is None else repr(float(sysdef.stop_time_s)),
            stepSize=repr(float(step_size_s))),
        unitDefinitions=[units[u] for u in sorted(used_units) if u in units],
        typeDefinitions=list(types.values()),
        modelVariables=variables,
        outputs=outputs,
        initialUnknowns=[Unknown(variable=mv) for mv in variables
                         if mv.causality == "output" and mv.initial == "calculated"],
    )

    out = Path(out)
    if out.is_dir() or not out.name:
        raise ConfigurationError(f"--container {out}: is a folder; give the .fmu file to write (e.g. "
                                 f"{out / (sysdef.name + '.fmu')})")
    if out.exists() and not out.is_file() or out.is_symlink():
        raise ConfigurationError(f"--container {out}: exists and is not a regular file; give a new .fmu path")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigurationError(f"--container {out}: cannot create its folder: {os_reason(exc)}") from None
    root = Path(container.__file__).parent / "binaries"

    def write(f: IO[bytes]) -> None:
        with tempfile.TemporaryDirectory(prefix="emss_export_") as tmp:  # removed whatever happens
            xml = Path(tmp) / "modelDescription.xml"
            write_model_description(md, xml)
            with zipfile.ZipFile(f, "w", zipfile.ZIP_DEFLATED) as z:
                z.write(xml, "modelDescription.xml")
                z.writestr("resources/container.json", json.dumps(config, indent=2))
                for platform in platforms:
                    folder, lib = RUNTIME_BINARIES[platform]
                    z.write(root / folder / lib, f"binaries/{platform}/{lib}")
                written: set[str] = set()
                for c, folder in zip(system.components, folders, strict=True):
                    if folder in written:
                        continue
                    written.add(folder)
                    with zipfile.ZipFile(c.fmu_path) as src:
                        for info in src.infolist():
                            if not info.is_dir():
                                z.writestr(f"resources/{folder}/{info.filename}", src.read(info))

    try:  # beside the target under a temporary name, flushed, then renamed over it: whole or not at all
        write_whole(out, write)
    except OSError as exc:
        raise ResultsError(f"cannot write {out}: {os_reason(exc)}") from None
    return out
