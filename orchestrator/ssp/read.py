"""Read and validate SSP 1.0 system descriptions: .ssd, .ssv, .ssm, .ssb and .ssp archives.

fmpy ships the SSP 1.0 schemas and a reader (``fmpy.ssp.ssd``). We validate with
its schemas, but parse ourselves, because its reader only opens zip archives,
drops the source line of every element (we need it in error messages), skips
``DefaultExperiment``, looks for ``LinearTransformation`` in the wrong namespace,
leaves the mapping transformations as a TODO, and silently ignores what it does
not understand. Here every element the orchestrator does not apply is reported
as a problem naming the element and its line.

The result of reading is a tree (``SystemNode``); ``flatten.flatten`` turns it
into the flat list of FMU components and end-to-end connections the master runs.

References
----------
Modelica Association, "System Structure and Parameterization (SSP) 1.0", 2019.
"""
from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from lxml import etree

from ..errors import Problem, SystemStructureError
from .archive import SSD_FILE_NAME, extract_archive
from .flatten import flatten
from .model import (
    ComponentDef,
    ConnectionDef,
    ConnectorDef,
    DictionaryEntryDef,
    DictionaryReferenceDef,
    FlatConnection,
    Hop,
    LinearTransformationDef,
    MappingEntryDef,
    MappingTransformationDef,
    Origin,
    ParameterBindingDef,
    ParameterValue,
    SignalDictionaryDef,
    SystemDef,
    SystemNode,
    Transformation,
)
from .units import Unit, from_attributes
from .values import parse_value

__all__ = ["ComponentDef", "ConnectionDef", "ConnectorDef", "FlatConnection", "Hop", "LinearTransformationDef",
           "MappingEntryDef", "MappingTransformationDef", "ParameterBindingDef", "ParameterValue", "SystemDef",
           "SystemNode", "load_system", "read_ssd", "read_ssv", "read_ssm", "extract_archive", "SSD_FILE_NAME"]

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
MAX_XML_BYTES = 64 * 1024 ** 2  #: largest SSP XML file read [bytes]
FMU_MIME_TYPE = "application/x-fmu-sharedlibrary"
SCALAR_TYPES = ("Real", "Integer", "Boolean", "String", "Enumeration")
MAPPINGS = {"BooleanMappingTransformation": "Boolean", "IntegerMappingTransformation": "Integer",
            "EnumerationMappingTransformation": "Enumeration"}


_FOLDER = Origin()  #: the files of a system in a folder: named as given, references not confined


def _q(prefix: str, local: str) -> str:
    return f"{{{NS[prefix]}}}{local}"


@cache
def _schema(file_name: str) -> etree.XMLSchema:
    """The SSP 1.0 schema shipped with fmpy (loaded once)."""
    import fmpy.ssp

    schema_dir = Path(fmpy.ssp.__file__).parent / "schema"
    return etree.XMLSchema(file=str(schema_dir / file_name))


# -- parsing ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _File:
    """A file being read: where it is (``path``) and where the user knows it from (``origin``);
    ``str()`` names it in messages (``archive.ssp!SystemStructure.ssd`` for a file of an archive)."""

    path: Path
    origin: Origin

    def __str__(self) -> str:
        return self.origin.shown(self.path)

    def referenced(self, element: etree._Element, problems: list[Problem]) -> _File | None:
        """The file named by ``element``'s ``source`` (relative to this file's folder); None, with a problem,
        when it lies outside the archive this file belongs to (``..``, an absolute path)."""
        source = element.get("source", "")
        path = self.path.parent / source
        if not self.origin.inside(path):
            problems.append(Problem(_where(self, element), f"source '{source}' lies outside the archive "
                                                           f"{self.origin.archive}: the files an .ssp refers to "
                                                           "must be inside it"))
            return None
        return _File(path, self.origin)


def _where(f: _File, element: etree._Element) -> str:
    return f"{f}:{element.sourceline}"


def _parse_xml(f: _File, schema_file: str, problems: list[Problem]) -> etree._Element | None:
    """Parse and schema-validate one XML file; record problems and return None when unusable."""
    path = f.path
    if not path.is_file():
        problems.append(Problem(str(f), "file not found"))
        return None
    try:
        size = path.stat().st_size
        if size > MAX_XML_BYTES:
            problems.append(Problem(str(f), f"{size // 1024 ** 2} MiB, larger than {MAX_XML_BYTES // 1024 ** 2} "
                                            "MiB; refused"))
            return None
        tree = etree.parse(str(path), etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False))
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if exc.lineno is not None else "?"
        problems.append(Problem(f"{f}:{line}", f"malformed XML: {exc.msg}"))
        return None
    except OSError as exc:
        problems.append(Problem(str(f), f"cannot read: {exc.strerror or exc}"))
        return None
    if tree.docinfo.doctype or tree.docinfo.internalDTD is not None:  # entities (XXE, billion laughs)
        dtd = tree.docinfo.internalDTD
        problems.append(Problem(f"{f}:1", "a DOCTYPE (DTD or entity declarations) is not allowed in SSP "
                                             "files" + (f" (declares {', '.join(e.name for e in dtd.iterentities())})"
                                                        if dtd is not None and list(dtd.iterentities()) else "")))
        return None
    schema = _schema(schema_file)
    if not schema.validate(tree):
        for entry in schema.error_log:
            problems.append(Problem(f"{f}:{entry.line}", "not valid against the SSP 1.0 schema: "
                                                         + _without_namespaces(entry.message)))
        return None
    return tree.getroot()


def _without_namespaces(message: str) -> str:
    """A schema message with ``{http://ssp-standard.org/...}Name`` written as ``ssv:Name``."""
    for prefix, uri in NS.items():
        message = message.replace(f"{{{uri}}}", f"{prefix}:")
    return message


def _finite(element: etree._Element, name: str, default: float, f: _File, problems: list[Problem],
            nonzero: bool = False) -> float:
    """The attribute ``name`` of ``element`` as a finite number (``default`` when absent); a NaN, an
    infinity, a number that underflows to 0 (or, with ``nonzero``, a zero) is recorded as a problem
    naming the element's line."""
    text = element.get(name)
    if text is None:
        return default
    try:
        value = float(parse_value("Real", text))
    except ValueError as exc:
        why = str(exc)
    else:
        if not (nonzero and value == 0.0):
            return value
        why = "0 is not allowed here (allowed: a finite number other than 0)"
    problems.append(Problem(_where(f, element), f"{etree.QName(element).localname} {name}={text!r}: {why}"))
    return default


def _units(element: etree._Element | None, prefix: str, f: _File, problems: list[Problem]) -> dict[str, Unit]:
    """``<prefix>:Units/ssc:Unit`` definitions below ``element`` (a factor of 0 or a non-finite
    factor or offset is a problem)."""
    if element is None:
        return {}
    out: dict[str, Unit] = {}
    for u in element.iterfind(f"{prefix}:Units/ssc:Unit", NS):
        if u.get("name") in out:
            problems.append(Problem(_where(f, u), f"unit '{u.get('name')}' is defined twice"))
            continue
        base = u.find("ssc:BaseUnit", NS)
        attrs = dict(base.attrib) if base is not None else {}
        if base is not None:
            attrs["factor"] = str(_finite(base, "factor", 1.0, f, problems, nonzero=True))
            attrs["offset"] = str(_finite(base, "offset", 0.0, f, problems))
        out[u.get("name")] = from_attributes(u.get("name"), attrs)
    return out


def _transformation(element: etree._Element, f: _File, problems: list[Problem]) -> Transformation | None:
    """The transformation child (ssc namespace) of a connection or mapping entry, if any."""
    lin = element.find("ssc:LinearTransformation", NS)
    if lin is not None:
        return LinearTransformationDef(_finite(lin, "factor", 1.0, f, problems),
                                       _finite(lin, "offset", 0.0, f, problems))
    for local, kind in MAPPINGS.items():
        m = element.find(f"ssc:{local}", NS)
        if m is not None:
            entries = tuple((e.get("source"), e.get("target")) for e in m.iterfind("ssc:MapEntry", NS))
            return MappingTransformationDef(kind, entries, _where(f, m))
    return None


def _parameter_set(root: etree._Element, f: _File, problems: list[Problem]) -> tuple[ParameterValue, ...]:
    values: list[ParameterValue] = []
    for p in root.iterfind("ssv:Parameters/ssv:Parameter", NS):
        for child in p:
            if not isinstance(child.tag, str) or child.tag == _q("ssc", "Annotations"):
                continue
            type_name = etree.QName(child).localname
            where = _where(f, child)
            if type_name not in ("Real", "Integer", "Boolean", "String"):
                problems.append(Problem(where, f"parameter '{p.get('name')}': type {type_name} is not supported "
                                               "(allowed: Real, Integer, Boolean, String)"))
                continue
            try:
                value = parse_value(type_name, child.get("value"))
            except ValueError as exc:
                problems.append(Problem(where, f"parameter '{p.get('name')}': {type_name} "
                                               f"value={child.get('value')!r}: {exc}"))
                continue
            values.append(ParameterValue(p.get("name"), type_name, value, child.get("unit"), where))
    return tuple(values)


def read_ssv(path: Path, origin: Origin = _FOLDER) -> tuple[tuple[ParameterValue, ...], dict[str, Unit]]:
    """Read an .ssv parameter set file: its values and its unit definitions (``origin``: the archive
    it belongs to, for messages).

    Raises
    ------
    SystemStructureError
        With every problem found (missing file, malformed, schema-invalid, unsupported type, a value
        that is not a finite number or an integer in range).
    """
    problems: list[Problem] = []
    f = _File(Path(path), origin)
    root = _parse_xml(f, "SystemStructureParameterValues.xsd", problems)
    values = _parameter_set(root, f, problems) if root is not None else ()
    if problems:
        raise SystemStructureError(problems)
    units = _units(root, "ssv", f, problems) if root is not None else {}
    if problems:
        raise SystemStructureError(problems)
    return values, units


def _mapping_entries(root: etree._Element, f: _File, problems: list[Problem]) -> tuple[MappingEntryDef, ...]:
    return tuple(MappingEntryDef(m.get("source"), m.get("target"), _transformation(m, f, problems),
                                 m.get("suppressUnitConversion", "false") in ("true", "1"), _where(f, m))
                 for m in root.iterfind("ssm:MappingEntry", NS))


def read_ssm(path: Path, origin: Origin = _FOLDER) -> tuple[MappingEntryDef, ...]:
    """Read an .ssm parameter mapping file."""
    problems: list[Problem] = []
    f = _File(Path(path), origin)
    root = _parse_xml(f, "SystemStructureParameterMapping.xsd", problems)
    entries = _mapping_entries(root, f, problems) if root is not None else ()
    if problems:
        raise SystemStructureError(problems)
    return entries


def _bindings(element: etree._Element, f: _File, problems: list[Problem]) -> tuple[ParameterBindingDef, ...]:
    bindings: list[ParameterBindingDef] = []
    for b in element.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
        where = _where(f, b)
        values: list[ParameterValue] = []
        units: dict[str, Unit] = {}
        btype = b.get("type", "application/x-ssp-parameter-set")
        if btype != "application/x-ssp-parameter-set":
            problems.append(Problem(where, f"parameter binding type '{btype}' is not supported "
                                           "(allowed: application/x-ssp-parameter-set)"))
        if b.get("sourceBase", "SSD") != "SSD":
            problems.append(Problem(where, "sourceBase 'component' is not supported (allowed: SSD)"))
        ssv = f.referenced(b, problems) if b.get("source") is not None else None
        if ssv is not None:
            try:
                file_values, units = read_ssv(ssv.path, ssv.origin)
                values.extend(file_values)
            except SystemStructureError as exc:
                problems.extend(exc.problems)
        for s in b.iterfind("ssd:ParameterValues/ssv:ParameterSet", NS):
            values.extend(_parameter_set(s, f, problems))
            units.update(_units(s, "ssv", f, problems))
        mapping: list[MappingEntryDef] = []
        for m in b.iterfind("ssd:ParameterMapping", NS):
            ssm = f.referenced(m, problems) if m.get("source") is not None else None
            if ssm is not None:
                try:
                    mapping.extend(read_ssm(ssm.path, ssm.origin))
                except SystemStructureError as exc:
                    problems.extend(exc.problems)
            for inline in m.iterfind("ssm:ParameterMapping", NS):
                mapping.extend(_mapping_entries(inline, f, problems))
        bindings.append(ParameterBindingDef(b.get("prefix", ""), tuple(values), where, tuple(mapping), units))
    return tuple(bindings)


def _connectors(element: etree._Element, f: _File) -> tuple[ConnectorDef, ...]:
    connectors: list[ConnectorDef] = []
    for c in element.iterfind("ssd:Connectors/ssd:Connector", NS):
        type_name: str | None = None
        unit: str | None = None
        enumeration: str | None = None
        for child in c:
            if isinstance(child.tag, str) and etree.QName(child).namespace == NS["ssc"] and \
                    etree.QName(child).localname in SCALAR_TYPES + ("Binary",):
                type_name = etree.QName(child).localname
                unit = child.get("unit")
                enumeration = child.get("name") if type_name == "Enumeration" else None
        connectors.append(ConnectorDef(c.get("name"), c.get("kind"), type_name, unit, _where(f, c), enumeration))
    return tuple(connectors)


def _dictionary(d: etree._Element, f: _File, problems: list[Problem]) -> SignalDictionaryDef | None:
    if d.get("source") is not None:
        dfile = f.referenced(d, problems)
        if dfile is None:
            return None
        root = _parse_xml(dfile, "SystemStructureSignalDictionary.xsd", problems)
    else:
        dfile, root = f, d.find("ssb:SignalDictionary", NS)
    if root is None:
        return None
    entries = {}
    for e in root.iterfind("ssb:DictionaryEntry", NS):
        type_name, unit = None, None
        for child in e:
            if isinstance(child.tag, str) and etree.QName(child).localname in SCALAR_TYPES:
                type_name, unit = etree.QName(child).localname, child.get("unit")
        entries[e.get("name")] = DictionaryEntryDef(e.get("name"), type_name, unit)
    return SignalDictionaryDef(d.get("name"), entries, _units(root, "ssb", dfile, problems), _where(f, d))


def _system(s: etree._Element, f: _File, problems: list[Problem]) -> SystemNode:
    components: list[ComponentDef] = []
    for c in s.iterfind("ssd:Elements/ssd:Component", NS):
        where = _where(f, c)
        ctype = c.get("type", FMU_MIME_TYPE)
        if ctype != FMU_MIME_TYPE:
            problems.append(Problem(where, f"component '{c.get('name')}': type '{ctype}' is not supported "
                                           f"(allowed: {FMU_MIME_TYPE})"))
        impl = c.get("implementation", "any")
        if impl not in ("any", "CoSimulation"):
            problems.append(Problem(where, f"component '{c.get('name')}': implementation '{impl}' is not "
                                           "supported (allowed: CoSimulation)"))
        fmu = f.referenced(c, problems)
        components.append(ComponentDef(c.get("name"), c.get("source"), (fmu.path if fmu else f.path).resolve(),
                                       _connectors(c, f), _bindings(c, f, problems), where))
    references = tuple(DictionaryReferenceDef(r.get("name"), r.get("dictionary"), _connectors(r, f),
                                              _where(f, r))
                       for r in s.iterfind("ssd:Elements/ssd:SignalDictionaryReference", NS))
    connections = tuple(
        ConnectionDef(e.get("startElement", ""), e.get("startConnector"), e.get("endElement", ""),
                      e.get("endConnector"), _where(f, e), _transformation(e, f, problems),
                      e.get("suppressUnitConversion", "false") in ("true", "1"))
        for e in s.iterfind("ssd:Connections/ssd:Connection", NS))
    dictionaries = tuple(d for d in (_dictionary(d, f, problems)
                                     for d in s.iterfind("ssd:SignalDictionaries/ssd:SignalDictionary", NS))
                         if d is not None)
    systems = tuple(_system(sub, f, problems) for sub in s.iterfind("ssd:Elements/ssd:System", NS))
    return SystemNode(s.get("name"), _connectors(s, f), _bindings(s, f, problems),
                      tuple(components), systems, references, connections, dictionaries, _where(f, s))


def _osp_step_size(experiment: etree._Element | None, f: _File, problems: list[Problem]) -> float | None:
    if experiment is None:
        return None
    for a in experiment.iterfind("ssd:Annotations/ssc:Annotation", NS):
        if a.get("type") != OSP_ANNOTATION_TYPE:
            continue
        for fixed in a.iter(f"{{{NS['osp']}}}FixedStepAlgorithm"):
            try:
                step = float(fixed.get("baseStepSize", ""))
            except ValueError:
                problems.append(Problem(_where(f, fixed), "FixedStepAlgorithm needs a numeric baseStepSize [s]"))
                return None
            if not (step > 0 and math.isfinite(step)):
                problems.append(Problem(_where(f, fixed), f"baseStepSize {step} s must be positive"))
                return None
            return step
    return None


def _float_attr(element: etree._Element | None, name: str, f: _File, problems: list[Problem]) -> float | None:
    if element is None or element.get(name) is None:
        return None
    return _finite(element, name, math.nan, f, problems)


def _enumerations(root: etree._Element, f: _File, problems: list[Problem]) -> dict[str, dict[str, int]]:
    """The SSD's enumerations (name -> item name -> value); a name or an item given twice is a problem."""
    out: dict[str, dict[str, int]] = {}
    for e in root.iterfind("ssd:Enumerations/ssc:Enumeration", NS):
        if e.get("name") in out:
            problems.append(Problem(_where(f, e), f"enumeration '{e.get('name')}' is defined twice"))
            continue
        items: dict[str, int] = {}
        for i in e.iterfind("ssc:Item", NS):
            if i.get("name") in items:
                problems.append(Problem(_where(f, i), f"enumeration '{e.get('name')}': item '{i.get('name')}' "
                                                      "is given twice"))
            items[i.get("name")] = int(i.get("value"))  # an xs:int, checked by the schema
        out[e.get("name")] = items
    return out


def read_ssd(path: Path, archive_dir: tempfile.TemporaryDirectory[str] | None = None,
             origin: Origin = _FOLDER) -> SystemDef:
    """Read, validate and flatten ``SystemStructure.ssd`` (a file path; ``origin``: the archive it was
    extracted from, which messages name and which its references must not leave).

    FMU sources, .ssv, .ssm and .ssb files are resolved relative to the SSD's folder.
    Problems of the file itself raise here; problems found while flattening the
    connections are kept in ``SystemDef.problems`` and raised by ``bind_system``
    together with those it finds against the FMUs, so that all are listed at once.

    Raises
    ------
    SystemStructureError
        With every problem found in the files.
    """
    path = Path(path)
    f = _File(path, origin)
    problems: list[Problem] = []
    root = _parse_xml(f, "SystemStructureDescription.xsd", problems)
    if root is None:
        raise SystemStructureError(problems)
    enumerations = _enumerations(root, f, problems)
    tree = _system(root.find("ssd:System", NS), f, problems)
    experiment = root.find("ssd:DefaultExperiment", NS)
    step_size_s = _osp_step_size(experiment, f, problems)
    start_time_s = _float_attr(experiment, "startTime", f, problems)
    stop_time_s = _float_attr(experiment, "stopTime", f, problems)
    units = _units(root, "ssd", f, problems)
    if problems:
        raise SystemStructureError(problems)
    components, connections, bindings = flatten(tree, problems)
    pending = [tree]
    while pending:  # units defined by signal dictionaries serve where the SSD defines none of that name
        node = pending.pop()
        for d in node.dictionaries:
            for name, unit in d.units.items():
                units.setdefault(name, unit)
        pending.extend(node.systems)
    return SystemDef(
        name=tree.name, ssd_path=path, components=components, connections=connections, bindings=bindings,
        units=units, enumerations=enumerations, start_time_s=start_time_s,
        stop_time_s=stop_time_s, step_size_s=step_size_s, archive_dir=archive_dir,
        problems=tuple(problems), origin=origin)


def load_system(location: Path | str) -> SystemDef:
    """Load a system from a folder holding ``SystemStructure.ssd``, an .ssd file, or an .ssp archive.

    An archive is extracted into a temporary folder that lives as long as the returned system;
    messages name its files ``archive.ssp!entry``, and its references must stay inside it.
    """
    location = Path(location)
    if location.is_dir():
        return read_ssd(location / SSD_FILE_NAME)
    if location.suffix.lower() == ".ssp":
        if not location.is_file():
            raise SystemStructureError([Problem(str(location), "file not found")])
        tmp = extract_archive(location)
        try:
            return read_ssd(Path(tmp.name) / SSD_FILE_NAME, archive_dir=tmp,
                            origin=Origin(location, os.path.realpath(tmp.name)))
        except SystemStructureError:
            tmp.cleanup()
            raise
    if location.suffix.lower() == ".ssd" or location.is_file():
        return read_ssd(location)
    raise SystemStructureError([Problem(str(location), "no such system: expected a folder holding "
                                                       f"{SSD_FILE_NAME}, an .ssd file or an .ssp archive")])
