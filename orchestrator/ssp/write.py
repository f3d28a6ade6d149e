"""Build SSP 1.0 systems in Python and write them: .ssd, .ssv, .ssm and .ssp archives.

Every file written is validated against the SSP 1.0 schemas before it is left on
disk; a file that does not validate is a bug here and raises. Connectors can be
taken from an FMU's modelDescription.xml (``connectors_from_fmu``), so system files
generated from the FMUs cannot drift from them.

Example
-------
>>> sys = SystemBuilder("Demo")
>>> a = sys.component("a", "resources/Gain.fmu")
>>> a.connector("y_real", "output", "Real", unit="degC")
>>> b = sys.component("b", "resources/Gain.fmu")
>>> b.connector("u_real", "input", "Real", unit="K")
>>> sys.unit("degC", K=1, offset=273.15); sys.unit("K", K=1)
>>> sys.connect("a.y_real", "b.u_real")
>>> sys.write("demo")  # doctest: +SKIP
"""
from __future__ import annotations

import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from .read import NS, OSP_ANNOTATION_TYPE, SSD_FILE_NAME, _schema
from .units import EXPONENT_NAMES

ParameterValueT = float | int | bool | str
SCHEMAS = {"ssd": "SystemStructureDescription.xsd", "ssv": "SystemStructureParameterValues.xsd",
           "ssm": "SystemStructureParameterMapping.xsd"}


def _e(parent: etree._Element | None, ns: str, tag: str, /, **attrib: str | None) -> etree._Element:
    q = f"{{{NS[ns]}}}{tag}"
    clean = {k: v for k, v in attrib.items() if v is not None}
    return etree.Element(q, clean, nsmap=NS) if parent is None else etree.SubElement(parent, q, clean)


def _type_name(value: ParameterValueT) -> str:
    if isinstance(value, bool):
        return "Boolean"
    if isinstance(value, int):
        return "Integer"
    if isinstance(value, float):
        return "Real"
    return "String"


def _text(value: ParameterValueT) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


@dataclass
class ParameterSet:
    """Parameter values (name -> value, optionally (value, unit) for Reals) for an .ssv file or inline."""

    name: str
    values: dict[str, ParameterValueT | tuple[float, str]] = field(default_factory=dict)

    def element(self, parent: etree._Element | None = None) -> etree._Element:
        root = _e(parent, "ssv", "ParameterSet", version="1.0", name=self.name)
        params = _e(root, "ssv", "Parameters")
        for name, value in self.values.items():
            p = _e(params, "ssv", "Parameter", name=name)
            if isinstance(value, tuple):
                _e(p, "ssv", "Real", value=repr(float(value[0])), unit=value[1])
            else:
                _e(p, "ssv", _type_name(value), value=_text(value))
        return root


@dataclass
class MappingEntry:
    """An .ssm entry: parameter ``source`` of the set goes to ``target``, optionally linearly transformed."""

    source: str
    target: str
    factor: float | None = None
    offset: float | None = None


@dataclass
class Binding:
    """A ParameterBinding: inline values or an .ssv file, optional prefix and .ssm mapping."""

    values: ParameterSet
    inline: bool = True
    file_name: str | None = None
    prefix: str | None = None
    mapping: list[MappingEntry] = field(default_factory=list)
    mapping_file: str | None = None


@dataclass
class ComponentBuilder:
    """A component (FMU) of a system being built."""

    name: str
    source: str
    connectors: list[tuple[str, str, str, str | None]] = field(default_factory=list)
    bindings: list[Binding] = field(default_factory=list)

    def connector(self, name: str, kind: str, type_name: str = "Real", unit: str | None = None) -> ComponentBuilder:
        """Declare a connector (kind: input, output, parameter, calculatedParameter)."""
        self.connectors.append((name, kind, type_name, unit))
        return self

    def parameters(self, values: dict[str, ParameterValueT | tuple[float, str]], file_name: str | None = None,
                   mapping: list[MappingEntry] | None = None, mapping_file: str | None = None) -> ComponentBuilder:
        """Bind parameter values: inline, or written to ``file_name`` (.ssv) next to the SSD."""
        self.bindings.append(Binding(ParameterSet(f"{self.name}_parameters", dict(values)), file_name is None,
                                     file_name, None, list(mapping or []), mapping_file))
        return self


@dataclass
class Connection:
    start: str
    end: str
    factor: float | None = None
    offset: float | None = None
    suppress_unit_conversion: bool = False
    mapping: tuple[str, list[tuple[str, str]]] | None = None  # (Boolean|Integer|Enumeration, entries)


class SystemBuilder:
    """Build a flat system of FMU components and write it as SSP 1.0 files.

    Parameters
    ----------
    name : str
        Name of the system (and of the SSD).
    """

    def __init__(self, name: str) -> None:
        self.name = name
        self.components: list[ComponentBuilder] = []
        self.connections: list[Connection] = []
        self.units: dict[str, dict[str, float]] = {}
        self.bindings: list[Binding] = []
        self.start_time_s: float | None = None
        self.stop_time_s: float | None = None
        self.step_size_s: float | None = None

    def component(self, name: str, source: str) -> ComponentBuilder:
        """Add a component; ``source`` is the FMU path relative to the SSD (e.g. resources/X.fmu)."""
        c = ComponentBuilder(name, source)
        self.components.append(c)
        return c

    def unit(self, name: str, factor: float = 1.0, offset: float = 0.0, **exponents: int) -> SystemBuilder:
        """Define a unit: SI exponents (kg, m, s, A, K, mol, cd, rad), factor and offset."""
        bad = set(exponents) - set(EXPONENT_NAMES)
        if bad:
            raise ValueError(f"unknown base units {sorted(bad)} (allowed: {', '.join(EXPONENT_NAMES)})")
        self.units[name] = {**{k: float(v) for k, v in exponents.items()}, "factor": factor, "offset": offset}
        return self

    def connect(self, start: str, end: str, factor: float | None = None, offset: float | None = None,
                suppress_unit_conversion: bool = False,
                mapping: tuple[str, list[tuple[str, str]]] | None = None) -> SystemBuilder:
        """Connect ``component.output`` to ``component.input``, optionally with a transformation."""
        self.connections.append(Connection(start, end, factor, offset, suppress_unit_conversion, mapping))
        return self

    def parameters(self, values: dict[str, ParameterValueT | tuple[float, str]], file_name: str | None = None,
                   prefix: str | None = None) -> SystemBuilder:
        """Bind system-level parameter values (names component.variable, or bare names with a prefix)."""
        self.bindings.append(Binding(ParameterSet(f"{self.name}_parameters", dict(values)), file_name is None,
                                     file_name, prefix))
        return self

    def experiment(self, start_time_s: float = 0.0, stop_time_s: float | None = None,
                   step_size_s: float | None = None) -> SystemBuilder:
        """The DefaultExperiment; the step goes in the OSP annotation libcosim reads."""
        self.start_time_s, self.stop_time_s, self.step_size_s = start_time_s, stop_time_s, step_size_s
        return self

    # -- writing ---------------------------------------------------------------------------------
    def _bindings(self, parent: etree._Element, bindings: list[Binding], files: dict[str, etree._Element]) -> None:
        if not bindings:
            return
        pbs = _e(parent, "ssd", "ParameterBindings")
        for b in bindings:
            pb = _e(pbs, "ssd", "ParameterBinding", prefix=b.prefix, source=None if b.inline else b.file_name)
            if b.inline:
                b.values.element(_e(pb, "ssd", "ParameterValues"))
            else:
                files[b.file_name] = b.values.element()  # type: ignore[index]
            if b.mapping:
                root = _e(None, "ssm", "ParameterMapping", version="1.0")
                for m in b.mapping:
                    entry = _e(root, "ssm", "MappingEntry", source=m.source, target=m.target)
                    if m.factor is not None or m.offset is not None:
                        _e(entry, "ssc", "LinearTransformation", factor=repr(m.factor if m.factor is not None else 1.0),
                           offset=repr(m.offset if m.offset is not None else 0.0))
                if b.mapping_file:
                    files[b.mapping_file] = root
                    _e(pb, "ssd", "ParameterMapping", source=b.mapping_file)
                else:
                    _e(pb, "ssd", "ParameterMapping").append(root)

    def documents(self) -> dict[str, etree._Element]:
        """Every file of the system as XML elements: ``SystemStructure.ssd`` and the .ssv/.ssm files."""
        files: dict[str, etree._Element] = {}
        root = _e(None, "ssd", "SystemStructureDescription", version="1.0", name=self.name)
        system = _e(root, "ssd", "System", name=self.name)
        self._bindings(system, self.bindings, files)
        elements = _e(system, "ssd", "Elements")
        for c in self.components:
            comp = _e(elements, "ssd", "Component", name=c.name, source=c.source)
            if c.connectors:
                conns = _e(comp, "ssd", "Connectors")
                for name, kind, type_name, unit in c.connectors:
                    k = _e(conns, "ssd", "Connector", name=name, kind=kind)
                    _e(k, "ssc", type_name, unit=unit if type_name == "Real" else None)
            self._bindings(comp, c.bindings, files)
        if self.connections:
            conns = _e(system, "ssd", "Connections")
            for cn in self.connections:
                se, sc = cn.start.split(".", 1)
                ee, ec = cn.end.split(".", 1)
                e = _e(conns, "ssd", "Connection", startElement=se, startConnector=sc, endElement=ee, endConnector=ec,
                       suppressUnitConversion="true" if cn.suppress_unit_conversion else None)
                if cn.factor is not None or cn.offset is not None:
                    _e(e, "ssc", "LinearTransformation", factor=repr(cn.factor if cn.factor is not None else 1.0),
                       offset=repr(cn.offset if cn.offset is not None else 0.0))
                elif cn.mapping is not None:
                    kind, entries = cn.mapping
                    m = _e(e, "ssc", f"{kind}MappingTransformation")
                    for s, t in entries:
                        _e(m, "ssc", "MapEntry", source=s, target=t)
        if self.units:
            units = _e(root, "ssd", "Units")
            for name, attrs in self.units.items():
                u = _e(units, "ssc", "Unit", name=name)
                base = {k: (str(int(v)) if k in EXPONENT_NAMES else repr(v)) for k, v in attrs.items()
                        if not (k == "factor" and v == 1.0) and not (k == "offset" and v == 0.0)}
                _e(u, "ssc", "BaseUnit", **base)
        if self.start_time_s is not None or self.stop_time_s is not None or self.step_size_s is not None:
            de = _e(root, "ssd", "DefaultExperiment",
                    startTime=None if self.start_time_s is None else repr(float(self.start_time_s)),
                    stopTime=None if self.stop_time_s is None else repr(float(self.stop_time_s)))
            if self.step_size_s is not None:
                ann = _e(_e(de, "ssd", "Annotations"), "ssc", "Annotation", type=OSP_ANNOTATION_TYPE)
                algo = _e(ann, "osp", "Algorithm")
                _e(algo, "osp", "FixedStepAlgorithm", baseStepSize=repr(float(self.step_size_s)))
        files[SSD_FILE_NAME] = root
        for name, element in files.items():
            kind = "ssd" if name == SSD_FILE_NAME else etree.QName(element).namespace.rsplit("/", 1)[-1]
            schema_key = {"SystemStructureDescription": "ssd", "SystemStructureParameterValues": "ssv",
                          "SystemStructureParameterMapping": "ssm"}.get(kind, kind)
            schema = _schema(SCHEMAS[schema_key])
            if not schema.validate(etree.ElementTree(element)):
                raise AssertionError(f"written {name} is not valid SSP 1.0: {schema.error_log.last_error}")
        return files

    def write(self, folder: Path | str) -> Path:
        """Write the SSD and its parameter files into ``folder``; returns the SSD path."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        for name, element in self.documents().items():
            (folder / name).write_bytes(etree.tostring(element, xml_declaration=True, encoding="UTF-8",
                                                       pretty_print=True))
        return folder / SSD_FILE_NAME

    def write_archive(self, path: Path | str, resources: dict[str, Path] | None = None) -> Path:
        """Write an .ssp archive: the SSD, its parameter files and ``resources`` (archive name -> file)."""
        path = Path(path)
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
            for name, element in self.documents().items():
                zf.writestr(name, etree.tostring(element, xml_declaration=True, encoding="UTF-8", pretty_print=True))
            for name, file in (resources or {}).items():
                zf.write(file, name)
        return path


def connectors_from_fmu(fmu: Path | str, names: list[str] | None = None,
                        units: dict[str, str] | None = None) -> list[tuple[str, str, str, str | None]]:
    """Connectors (name, kind, type, unit) of an FMU's inputs, outputs and parameters, from its
    modelDescription.xml; ``names`` selects and orders them, ``units`` supplies units the FMU lacks."""
    from fmpy import read_model_description

    md = read_model_description(str(fmu), validate=False)
    by_name = {v.name: v for v in md.modelVariables
               if v.causality in ("input", "output", "parameter", "calculatedParameter")}
    chosen = names if names is not None else list(by_name)
    missing = [n for n in chosen if n not in by_name]
    if missing:
        raise KeyError(f"{fmu} has no input, output or parameter named {', '.join(missing)}")
    out = []
    for n in chosen:
        v = by_name[n]
        unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None) or (units or {}).get(n)
        out.append((n, v.causality, v.type, unit))
    return out
