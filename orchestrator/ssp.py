"""Read and validate SSP 1.0 system descriptions: .ssd, .ssv and .ssp archives.

fmpy ships the SSP 1.0 schemas and a reader (``fmpy.ssp.ssd``). We validate with
its schemas, but parse ourselves, because its reader only opens zip archives,
drops the source line of every element (we need it in error messages), skips
``DefaultExperiment`` and ``SimulationInformation``, and silently ignores what it
does not understand. Here, whatever the file holds that the orchestrator does not
apply is reported as a problem naming the element and its line.

References
----------
Modelica Association, "System Structure and Parameterization (SSP) 1.0", 2019.
"""
from __future__ import annotations

import os
import tempfile
import zipfile
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path, PurePosixPath

from lxml import etree

from .errors import Problem, SystemStructureError

NS = {
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "ssm": "http://ssp-standard.org/SSP1/SystemStructureParameterMapping",
    "ssb": "http://ssp-standard.org/SSP1/SystemStructureSignalDictionary",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
}
#: SSP 1.0 has no place for the master's step size; we read the annotation libcosim (OSP) defines.
OSP_ANNOTATION_TYPE = "com.opensimulationplatform"
SSD_FILE_NAME = "SystemStructure.ssd"
FMU_MIME_TYPE = "application/x-fmu-sharedlibrary"
SCALAR_TYPES = ("Real", "Integer", "Boolean", "String")
CONNECTOR_KINDS = ("input", "output", "parameter", "calculatedParameter", "inout")


def _q(prefix: str, local: str) -> str:
    return f"{{{NS[prefix]}}}{local}"


@cache
def _schema(file_name: str) -> etree.XMLSchema:
    """The SSP 1.0 schema shipped with fmpy (loaded once)."""
    import fmpy.ssp

    schema_dir = Path(fmpy.ssp.__file__).parent / "schema"
    return etree.XMLSchema(file=str(schema_dir / file_name))


@dataclass(frozen=True)
class ConnectorDef:
    """A connector of a component or system, as declared in the SSD."""

    name: str
    kind: str
    type_name: str | None  # Real, Integer, Boolean, String; None when the SSD leaves it out
    unit: str | None
    where: str


@dataclass(frozen=True)
class ParameterValue:
    """One parameter value from an .ssv parameter set (inline or file)."""

    name: str
    type_name: str
    value: float | int | bool | str
    unit: str | None
    where: str


@dataclass(frozen=True)
class ParameterBindingDef:
    """A ``ParameterBinding``: a parameter set applied to an element, names prefixed by ``prefix``."""

    prefix: str
    values: tuple[ParameterValue, ...]
    where: str


@dataclass(frozen=True)
class ComponentDef:
    """A ``Component`` element: one FMU instance."""

    name: str
    source: str
    source_path: Path
    connectors: tuple[ConnectorDef, ...]
    bindings: tuple[ParameterBindingDef, ...]
    where: str


@dataclass(frozen=True)
class ConnectionDef:
    """A ``Connection`` from ``start_element.start_connector`` to ``end_element.end_connector``."""

    start_element: str
    start_connector: str
    end_element: str
    end_connector: str
    where: str

    @property
    def start(self) -> str:
        return f"{self.start_element}.{self.start_connector}"

    @property
    def end(self) -> str:
        return f"{self.end_element}.{self.end_connector}"


@dataclass(frozen=True)
class SystemDef:
    """A flat SSP system of FMU components, as read from ``SystemStructure.ssd``.

    Attributes
    ----------
    start_time_s, stop_time_s : float | None
        From ``DefaultExperiment`` [s], None when absent.
    step_size_s : float | None
        Master step [s] from the DefaultExperiment's OSP annotation
        (``osp:Algorithm/osp:FixedStepAlgorithm@baseStepSize``, as libcosim reads it), None when absent.
    """

    name: str
    ssd_path: Path
    components: tuple[ComponentDef, ...]
    connections: tuple[ConnectionDef, ...]
    bindings: tuple[ParameterBindingDef, ...]
    start_time_s: float | None = None
    stop_time_s: float | None = None
    step_size_s: float | None = None
    archive_dir: tempfile.TemporaryDirectory[str] | None = field(default=None, compare=False, repr=False)

    def component(self, name: str) -> ComponentDef:
        """The component called ``name``; KeyError if there is none."""
        for c in self.components:
            if c.name == name:
                return c
        raise KeyError(name)


def _where(path: Path, element: etree._Element) -> str:
    return f"{path}:{element.sourceline}"


def _parse_xml(path: Path, schema_file: str, problems: list[Problem]) -> etree._Element | None:
    """Parse and schema-validate one XML file; record problems and return None when unusable."""
    if not path.is_file():
        problems.append(Problem(str(path), "file not found"))
        return None
    try:
        tree = etree.parse(str(path), etree.XMLParser(resolve_entities=False, no_network=True))
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if exc.lineno is not None else "?"
        problems.append(Problem(f"{path}:{line}", f"malformed XML: {exc.msg}"))
        return None
    schema = _schema(schema_file)
    if not schema.validate(tree):
        for entry in schema.error_log:
            problems.append(Problem(f"{path}:{entry.line}", f"not valid against the SSP 1.0 schema: {entry.message}"))
        return None
    return tree.getroot()


def _typed_value(type_name: str, text: str) -> float | int | bool | str:
    if type_name == "Real":
        return float(text)
    if type_name == "Integer":
        return int(text)
    if type_name == "Boolean":
        return text.strip() in ("true", "1")
    return text


def _parameter_set(root: etree._Element, path: Path, problems: list[Problem]) -> tuple[ParameterValue, ...]:
    values: list[ParameterValue] = []
    for p in root.iterfind("ssv:Parameters/ssv:Parameter", NS):
        for child in p:
            if not isinstance(child.tag, str) or child.tag == _q("ssc", "Annotations"):
                continue
            type_name = etree.QName(child).localname
            where = _where(path, child)
            if type_name not in SCALAR_TYPES:
                problems.append(Problem(where, f"parameter '{p.get('name')}': type {type_name} is not supported "
                                               f"(allowed: {', '.join(SCALAR_TYPES)})"))
                continue
            values.append(ParameterValue(p.get("name"), type_name, _typed_value(type_name, child.get("value")),
                                         child.get("unit"), where))
    for u in root.iterfind("ssv:Units/ssc:Unit", NS):
        problems.append(Problem(_where(path, u), "unit definitions in parameter sets are not applied yet"))
    return tuple(values)


def read_ssv(path: Path) -> tuple[ParameterValue, ...]:
    """Read an .ssv parameter set file.

    Raises
    ------
    SystemStructureError
        With every problem found (missing file, malformed, schema-invalid, unsupported type).
    """
    problems: list[Problem] = []
    root = _parse_xml(Path(path), "SystemStructureParameterValues.xsd", problems)
    values = _parameter_set(root, Path(path), problems) if root is not None else ()
    if problems:
        raise SystemStructureError(problems)
    return values


def _bindings(element: etree._Element, path: Path, base_dir: Path,
              problems: list[Problem]) -> tuple[ParameterBindingDef, ...]:
    bindings: list[ParameterBindingDef] = []
    for b in element.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
        where = _where(path, b)
        values: list[ParameterValue] = []
        btype = b.get("type", "application/x-ssp-parameter-set")
        if btype != "application/x-ssp-parameter-set":
            problems.append(Problem(where, f"parameter binding type '{btype}' is not supported "
                                           "(allowed: application/x-ssp-parameter-set)"))
        source = b.get("source")
        if source is not None:
            ssv_path = base_dir / source
            try:
                values.extend(read_ssv(ssv_path))
            except SystemStructureError as exc:
                problems.extend(exc.problems)
        for s in b.iterfind("ssd:ParameterValues/ssv:ParameterSet", NS):
            values.extend(_parameter_set(s, path, problems))
        for m in b.iterfind("ssd:ParameterMapping", NS):
            problems.append(Problem(_where(path, m), "ParameterMapping is not applied yet; remove it or "
                                                     "rename the parameters in the parameter set"))
        bindings.append(ParameterBindingDef(b.get("prefix", ""), tuple(values), where))
    return tuple(bindings)


def _connectors(element: etree._Element, path: Path, problems: list[Problem]) -> tuple[ConnectorDef, ...]:
    connectors: list[ConnectorDef] = []
    for c in element.iterfind("ssd:Connectors/ssd:Connector", NS):
        type_name: str | None = None
        unit: str | None = None
        for child in c:
            if not isinstance(child.tag, str):
                continue
            local = etree.QName(child).localname
            if etree.QName(child).namespace == NS["ssc"] and local in SCALAR_TYPES + ("Enumeration", "Binary"):
                if local not in SCALAR_TYPES:
                    problems.append(Problem(_where(path, child), f"connector '{c.get('name')}': type {local} is "
                                                                 f"not supported (allowed: {', '.join(SCALAR_TYPES)})"))
                type_name = local
                unit = child.get("unit")
        connectors.append(ConnectorDef(c.get("name"), c.get("kind"), type_name, unit, _where(path, c)))
    return tuple(connectors)


def _unsupported(root: etree._Element, path: Path, problems: list[Problem]) -> None:
    """Report the SSP features this orchestrator does not apply, instead of silently dropping them."""
    checks = (
        ("ssd:System/ssd:Elements/ssd:System", "nested systems are not supported yet; flatten the system"),
        ("ssd:System/ssd:Elements/ssd:SignalDictionaryReference", "signal dictionaries are not supported yet"),
        ("ssd:System/ssd:SignalDictionaries", "signal dictionaries are not supported yet"),
        ("ssd:System/ssd:Connectors/ssd:Connector", "system-level connectors are not supported yet"),
        ("ssd:Enumerations", "enumeration definitions are not supported yet"),
    )
    for xpath, message in checks:
        for e in root.iterfind(xpath, NS):
            problems.append(Problem(_where(path, e), message))
    for conn in root.iterfind("ssd:System/ssd:Connections/ssd:Connection", NS):
        for child in conn:
            if isinstance(child.tag, str) and child.tag != _q("ssc", "Annotations") and \
                    etree.QName(child).localname.endswith("Transformation"):
                problems.append(Problem(_where(path, child), f"connection transformation "
                                                             f"{etree.QName(child).localname} is not applied yet"))


def _osp_step_size(experiment: etree._Element | None, path: Path, problems: list[Problem]) -> float | None:
    if experiment is None:
        return None
    for a in experiment.iterfind("ssd:Annotations/ssc:Annotation", NS):
        if a.get("type") != OSP_ANNOTATION_TYPE:
            continue
        for fixed in a.iter(f"{{{NS['osp']}}}FixedStepAlgorithm"):
            try:
                step = float(fixed.get("baseStepSize", ""))
            except ValueError:
                problems.append(Problem(_where(path, fixed), "FixedStepAlgorithm needs a numeric baseStepSize [s]"))
                return None
            if not step > 0:
                problems.append(Problem(_where(path, fixed), f"baseStepSize {step} s must be positive"))
                return None
            return step
    return None


def _float_attr(element: etree._Element | None, name: str) -> float | None:
    if element is None or element.get(name) is None:
        return None
    return float(element.get(name))


def read_ssd(path: Path, archive_dir: tempfile.TemporaryDirectory[str] | None = None) -> SystemDef:
    """Read and validate ``SystemStructure.ssd`` (a file path).

    FMU sources and .ssv files are resolved relative to the SSD's folder.

    Raises
    ------
    SystemStructureError
        With every problem found.
    """
    path = Path(path)
    problems: list[Problem] = []
    root = _parse_xml(path, "SystemStructureDescription.xsd", problems)
    if root is None:
        raise SystemStructureError(problems)
    base_dir = path.parent
    _unsupported(root, path, problems)
    system = root.find("ssd:System", NS)

    components: list[ComponentDef] = []
    for c in system.iterfind("ssd:Elements/ssd:Component", NS):
        where = _where(path, c)
        ctype = c.get("type", FMU_MIME_TYPE)
        if ctype != FMU_MIME_TYPE:
            problems.append(Problem(where, f"component '{c.get('name')}': type '{ctype}' is not supported "
                                           f"(allowed: {FMU_MIME_TYPE})"))
        impl = c.get("implementation", "any")
        if impl not in ("any", "CoSimulation"):
            problems.append(Problem(where, f"component '{c.get('name')}': implementation '{impl}' is not "
                                           "supported (allowed: CoSimulation)"))
        source = c.get("source")
        components.append(ComponentDef(
            name=c.get("name"), source=source, source_path=(base_dir / source).resolve(),
            connectors=_connectors(c, path, problems), bindings=_bindings(c, path, base_dir, problems),
            where=where))

    connections = tuple(
        ConnectionDef(e.get("startElement", ""), e.get("startConnector"), e.get("endElement", ""),
                      e.get("endConnector"), _where(path, e))
        for e in system.iterfind("ssd:Connections/ssd:Connection", NS))
    experiment = root.find("ssd:DefaultExperiment", NS)
    step_size_s = _osp_step_size(experiment, path, problems)
    if problems:
        raise SystemStructureError(problems)
    return SystemDef(
        name=system.get("name"), ssd_path=path, components=tuple(components), connections=connections,
        bindings=_bindings(system, path, base_dir, problems),
        start_time_s=_float_attr(experiment, "startTime"), stop_time_s=_float_attr(experiment, "stopTime"),
        step_size_s=step_size_s, archive_dir=archive_dir)


def extract_archive(archive: Path) -> tempfile.TemporaryDirectory[str]:
    """Extract an .ssp archive into a new temporary folder, refusing unsafe entries.

    Every entry is checked before anything is written: absolute paths, ``..``
    components, drive letters and symbolic links are refused, so nothing can be
    written outside the extraction folder.
    """
    archive = Path(archive)
    try:
        zf = zipfile.ZipFile(archive)
    except (OSError, zipfile.BadZipFile) as exc:
        raise SystemStructureError([Problem(str(archive), f"not a readable .ssp (zip) archive: {exc}")]) from None
    with zf:
        problems: list[Problem] = []
        for info in zf.infolist():
            name = info.filename
            parts = PurePosixPath(name.replace("\\", "/")).parts
            is_link = (info.external_attr >> 16) & 0o170000 == 0o120000
            if name.startswith(("/", "\\")) or ".." in parts or (parts and ":" in parts[0]) or is_link:
                problems.append(Problem(f"{archive}!{name}", "unsafe archive entry (absolute path, '..' or link); "
                                                             "entries must stay inside the archive"))
        if SSD_FILE_NAME not in zf.namelist():
            problems.append(Problem(str(archive), f"archive has no {SSD_FILE_NAME} at its root"))
        if problems:
            raise SystemStructureError(problems)
        tmp = tempfile.TemporaryDirectory(prefix="emss_ssp_")
        root = os.path.realpath(tmp.name)
        for info in zf.infolist():
            target = os.path.realpath(os.path.join(root, info.filename))
            if os.path.commonpath([root, target]) != root:  # defence in depth after the checks above
                tmp.cleanup()
                raise SystemStructureError([Problem(f"{archive}!{info.filename}", "entry escapes the archive")])
            zf.extract(info, root)
    return tmp


def load_system(location: Path | str) -> SystemDef:
    """Load a system from a folder holding ``SystemStructure.ssd``, an .ssd file, or an .ssp archive."""
    location = Path(location)
    if location.is_dir():
        return read_ssd(location / SSD_FILE_NAME)
    if location.suffix.lower() == ".ssp":
        if not location.is_file():
            raise SystemStructureError([Problem(str(location), "file not found")])
        tmp = extract_archive(location)
        try:
            return read_ssd(Path(tmp.name) / SSD_FILE_NAME, archive_dir=tmp)
        except SystemStructureError:
            tmp.cleanup()
            raise
    if location.suffix.lower() == ".ssd" or location.is_file():
        return read_ssd(location)
    raise SystemStructureError([Problem(str(location), "no such system: expected a folder holding "
                                                       f"{SSD_FILE_NAME}, an .ssd file or an .ssp archive")])
