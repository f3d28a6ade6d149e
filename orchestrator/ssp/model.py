"""What SSP 1.0 files say, as frozen dataclasses: the model shared by the reader, the flattener
and the writer."""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import Problem
from .units import Unit


@dataclass(frozen=True)
class Origin:
    """Where the files of a system come from, for messages and confinement: a folder (``archive`` None),
    or the ``.ssp`` archive the user gave, extracted into the folder ``root`` (a real path).

    Every message names a file as the user knows it: ``archive.ssp!SystemStructure.ssd``, never
    the temporary folder the archive was extracted into (removed when the run ends).
    """

    archive: Path | None = None
    root: str = ""

    def inside(self, path: Path | str) -> bool:
        """Whether ``path`` (after ``..`` and links) is inside the archive; always True for a folder."""
        if self.archive is None:
            return True
        real = os.path.realpath(path)
        return real == self.root or real.startswith(self.root.rstrip(os.sep) + os.sep)

    def shown(self, path: Path | str) -> str:
        """``path`` as the user knows it: as given, or ``archive.ssp!entry`` for a file of the archive."""
        if self.archive is None or not self.inside(path):
            return str(path)
        return f"{self.archive}!{Path(os.path.relpath(os.path.realpath(path), self.root)).as_posix()}"


@dataclass(frozen=True)
class ConnectorDef:
    """A connector of a component, system or signal dictionary reference."""

    name: str
    kind: str
    type_name: str | None  # Real, Integer, Boolean, String, Enumeration; None when left out
    unit: str | None
    where: str
    enumeration: str | None = None  # for Enumeration connectors: the SSD enumeration's name


@dataclass(frozen=True)
class LinearTransformationDef:
    """``end = factor * start + offset`` (``ssc:LinearTransformation``)."""

    factor: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class MappingTransformationDef:
    """A Boolean, Integer or Enumeration value map (``ssc:*MappingTransformation``), values as text."""

    kind: str  # Boolean, Integer, Enumeration
    entries: tuple[tuple[str, str], ...]
    where: str


Transformation = LinearTransformationDef | MappingTransformationDef


@dataclass(frozen=True)
class MappingEntryDef:
    """One ``ssm:MappingEntry``: parameter ``source`` of the set goes to ``target``."""

    source: str
    target: str
    transformation: Transformation | None
    suppress_unit_conversion: bool
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
    """A ``ParameterBinding``: a parameter set applied to an element, names prefixed by ``prefix``,
    renamed and transformed by its parameter mapping, with the set's own unit definitions."""

    prefix: str
    values: tuple[ParameterValue, ...]
    where: str
    mapping: tuple[MappingEntryDef, ...] = ()
    units: dict[str, Unit] = field(default_factory=dict)


@dataclass(frozen=True)
class ComponentDef:
    """A ``Component`` element: one FMU instance (``name`` is its dotted path once flattened)."""

    name: str
    source: str
    source_path: Path
    connectors: tuple[ConnectorDef, ...]
    bindings: tuple[ParameterBindingDef, ...]
    where: str


@dataclass(frozen=True)
class ConnectionDef:
    """A ``Connection``; an empty element name means the enclosing system's own connector."""

    start_element: str
    start_connector: str
    end_element: str
    end_connector: str
    where: str
    transformation: Transformation | None = None
    suppress_unit_conversion: bool = False

    @property
    def start(self) -> str:
        return f"{self.start_element}.{self.start_connector}" if self.start_element else self.start_connector

    @property
    def end(self) -> str:
        return f"{self.end_element}.{self.end_connector}" if self.end_element else self.end_connector


@dataclass(frozen=True)
class DictionaryEntryDef:
    """One signal of a signal dictionary."""

    name: str
    type_name: str | None
    unit: str | None


@dataclass(frozen=True)
class SignalDictionaryDef:
    """A ``SignalDictionary`` (inline or .ssb file): named signals shared across a system."""

    name: str
    entries: dict[str, DictionaryEntryDef]
    units: dict[str, Unit]
    where: str


@dataclass(frozen=True)
class DictionaryReferenceDef:
    """A ``SignalDictionaryReference`` element: its connectors are signals of a dictionary."""

    name: str
    dictionary: str
    connectors: tuple[ConnectorDef, ...]
    where: str


@dataclass(frozen=True)
class SystemNode:
    """A ``System`` element as written, before flattening."""

    name: str
    connectors: tuple[ConnectorDef, ...]
    bindings: tuple[ParameterBindingDef, ...]
    components: tuple[ComponentDef, ...]
    systems: tuple[SystemNode, ...]
    references: tuple[DictionaryReferenceDef, ...]
    connections: tuple[ConnectionDef, ...]
    dictionaries: tuple[SignalDictionaryDef, ...]
    where: str


@dataclass(frozen=True)
class Hop:
    """One connection on the way from an FMU output to an FMU input (through system connectors
    and signal dictionaries), with the units at its two ends."""

    transformation: Transformation | None
    suppress_unit_conversion: bool
    start_unit: str | None
    end_unit: str | None
    where: str


@dataclass(frozen=True)
class FlatConnection:
    """An end-to-end connection between two FMU components of the flattened system."""

    start_element: str
    start_connector: str
    end_element: str
    end_connector: str
    hops: tuple[Hop, ...]

    @property
    def start(self) -> str:
        return f"{self.start_element}.{self.start_connector}"

    @property
    def end(self) -> str:
        return f"{self.end_element}.{self.end_connector}"

    @property
    def where(self) -> str:
        return self.hops[-1].where


@dataclass(frozen=True)
class SystemDef:
    """A flat SSP system of FMU components, as read from ``SystemStructure.ssd``.

    Attributes
    ----------
    components : tuple[ComponentDef, ...]
        Every FMU component, named by its dotted path below the top system.
    connections : tuple[FlatConnection, ...]
        End-to-end connections between components.
    bindings : tuple[ParameterBindingDef, ...]
        System-level bindings (names ``path.to.component.variable``).
    units : dict[str, Unit]
        The SSD's unit definitions.
    enumerations : dict[str, dict[str, int]]
        The SSD's enumeration definitions (item name -> value), checked against the FMUs'.
    start_time_s, stop_time_s : float | None
        From ``DefaultExperiment`` [s], None when absent.
    step_size_s : float | None
        Master step [s] from the DefaultExperiment's OSP annotation
        (``osp:Algorithm/osp:FixedStepAlgorithm@baseStepSize``, as libcosim reads it), None when absent.
    origin : Origin
        The folder or ``.ssp`` archive the files come from; ``origin.shown(path)`` names a file in messages.
    """

    name: str
    ssd_path: Path
    components: tuple[ComponentDef, ...]
    connections: tuple[FlatConnection, ...]
    bindings: tuple[ParameterBindingDef, ...]
    units: dict[str, Unit] = field(default_factory=dict)
    enumerations: dict[str, dict[str, int]] = field(default_factory=dict)
    start_time_s: float | None = None
    stop_time_s: float | None = None
    step_size_s: float | None = None
    archive_dir: tempfile.TemporaryDirectory[str] | None = field(default=None, compare=False, repr=False)
    problems: tuple[Problem, ...] = ()  # found while flattening; bind_system reports them with its own
    origin: Origin = field(default_factory=Origin)  # the folder or archive the files come from (for messages)

    def component(self, name: str) -> ComponentDef:
        """The component called ``name``; KeyError if there is none."""
        for c in self.components:
            if c.name == name:
                return c
        raise KeyError(name)
