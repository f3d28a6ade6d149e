"""What a system bound to its FMUs is: variables, components, links, parameter assignments (types only).

Kept apart from :mod:`.system` (which builds them by reading the FMUs) so that the parameter
resolver, the exchange, the slaves and the algorithms can name these types without importing the
binder, and the binder can import the parameter resolver: no import cycle.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from fmpy.model_description import ModelDescription

from ..errors import Problem, SystemStructureError
from .model import ComponentDef, SystemDef
from .units import IDENTITY, Affine, Unit

#: FMI 2.0 variable types as the orchestrator buffers them (Enumeration travels as Integer).
BUFFER_TYPE = {"Real": "Real", "Integer": "Integer", "Enumeration": "Integer", "Boolean": "Boolean", "String": "String"}


@dataclass(frozen=True)
class VariableInfo:
    """One FMU variable, with what the orchestrator needs in the hot loop."""

    name: str
    vr: int
    type_name: str  # Real, Integer, Boolean, String (Enumeration travels as Integer)
    causality: str
    variability: str
    initial: str | None
    start: float | int | bool | str | None
    unit: str | None
    description: str | None
    enum_items: dict[str, int] | None = None  # for Enumeration variables: item name -> value

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
    units: dict[str, Unit] = field(default_factory=dict)  # the FMU's UnitDefinitions
    shown_fmu: str = ""  # the FMU as the user knows it, for messages (``archive.ssp!resources/x.fmu``)

    @property
    def name(self) -> str:
        return self.definition.name

    @property
    def fmu_path(self) -> Path:
        return self.definition.source_path

    def connector_unit(self, name: str) -> str | None:
        """The unit of a connector: the SSD's if declared, else the FMU variable's."""
        for k in self.definition.connectors:
            if k.name == name and k.unit is not None:
                return k.unit
        v = self.variables.get(name)
        return v.unit if v is not None else None


@dataclass(frozen=True)
class Link:
    """A resolved connection: output of one component to input of another.

    ``affine`` converts Real values (transformations and units composed);
    ``mapping`` maps Boolean/Integer/Enumeration values (None: unchanged).
    """

    source: int  # component index
    source_var: VariableInfo
    target: int
    target_var: VariableInfo
    where: str
    affine: Affine = IDENTITY
    mapping: dict[int, int] | None = None


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

    def split(self, path: str) -> tuple[int, str] | None:
        """Split ``component.variable`` at the longest component name (names may contain dots)."""
        best: tuple[int, str] | None = None
        for i, c in enumerate(self.components):
            if path.startswith(c.name + ".") and (best is None or len(c.name) > len(self.components[best[0]].name)):
                best = (i, path[len(c.name) + 1:])
        return best

    def variable(self, path: str) -> tuple[int, VariableInfo]:
        """Resolve ``component.variable``."""
        hit = self.split(path)
        if hit is not None and hit[1] in self.components[hit[0]].variables:
            return hit[0], self.components[hit[0]].variables[hit[1]]
        raise SystemStructureError([Problem(path, "no such variable: expected component.variable "
                                                  "with a component of this system")])
