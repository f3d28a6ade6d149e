"""The exchange: the value vectors between the slaves, their layout, the transfers, the input modifiers,
and one :meth:`Exchange.probe` for reading any variable.

Every value exchanged between FMUs lives in one preallocated numpy vector per FMI type:
``outputs`` (what the slaves' batched gets write) and ``inputs`` (what their batched sets read).
The layout is computed from the bound system alone (no FMU is loaded for it); :meth:`Exchange.bind`
then points every slave's batched I/O at its slices. A transfer copies connected outputs to inputs
with the connection's conversion (:mod:`.transfer`).

Input modifiers (scenario set, ramp, hold: :meth:`Exchange.modifier`) are held by the slaves and
written into their input buffers right before every batched set (:meth:`.Slave.set_inputs`), so
an algorithm honours them whatever transfers it makes: it cannot forget them. As in libcosim, the
modifiers act where a slave's inputs are set, not on the connections.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ConfigurationError, EmssError
from ..ssp.system_model import BoundSystem, VariableInfo
from .transfer import Segment, Transfer

if TYPE_CHECKING:
    from .slave import Slave

IO_TYPES = ("Real", "Integer", "Boolean")
_DTYPE = {"Real": np.float64, "Integer": np.int32, "Boolean": np.int32}
Value = float | int | bool | str


@dataclass(frozen=True)
class Signal:
    """Where the current value of a recorded variable lives: ``vectors[type].<vector>[index]``."""

    component: str
    variable: VariableInfo
    vector: str  # "outputs" or "inputs"
    index: int

    @property
    def path(self) -> str:
        return f"{self.component}.{self.variable.name}"


@dataclass
class TypeVectors:
    """The exchange vectors of one FMI type."""

    outputs: np.ndarray
    inputs: np.ndarray
    source_index: np.ndarray  # for each input: its source's index in outputs
    out_range: list[tuple[int, int]] = field(default_factory=list)  # per component
    in_range: list[tuple[int, int]] = field(default_factory=list)
    output_names: list[str] = field(default_factory=list)  # component.variable of each output


class InputModifier:
    """Changes one input or tunable parameter during a run (from :meth:`Exchange.modifier`).

    ``override(value)`` replaces the value the master would give it until ``release()``. A
    connected input is overridden where its slave's inputs are set (every algorithm honours
    it) and shown in the input vector; anything else (an unconnected input, a tunable
    parameter) is set on its FMU when the value changes, and keeps its last value when released.
    """

    def __init__(self, exchange: Exchange, path: str, component: int, variable: VariableInfo,
                 input_index: int | None) -> None:
        self.path = path
        self.variable = variable
        self.is_int = variable.type_name != "Real"
        self._exchange = exchange
        self._component = component
        self._index = input_index  # in the input vector of its type, for a connected input
        self._last: float | None = None
        shown = exchange.output_slot(path) if input_index is None else None
        self._shown = shown  # where observers read a directly set variable, if they do

    @property
    def connected(self) -> bool:
        return self._index is not None

    def current(self) -> float:
        """The value the variable has now (the override if there is one)."""
        if self._index is not None:
            held = self._exchange.held(self._component).get((self.variable.type_name, self._index))
            return float(held if held is not None else self._exchange.vectors[self.variable.type_name]
                         .inputs[self._index])
        return float(self._exchange.slaves[self._component].get_value(self.variable))

    def override(self, value: float) -> None:
        if self._index is not None:
            self._exchange.hold(self._component, self.variable.type_name, self._index, value)
            return
        if value != self._last:
            t = self.variable.type_name
            typed: Value = value if t == "Real" else (bool(value) if t == "Boolean" else int(value))
            self._exchange.slaves[self._component].set_value(self.variable, typed)
            self._last = value
        if self._shown is not None:
            self._shown[0][self._shown[1]] = value

    def release(self) -> None:
        if self._index is not None:
            self._exchange.unhold(self._component, self.variable.type_name, self._index)


class Exchange:
    """The exchange vectors of a bound system and everything that reads or writes them.

    Parameters
    ----------
    system : BoundSystem
        The system, resolved against its FMUs.
    record : Sequence[str] | None
        ``component.variable`` paths made available to observers as :attr:`signals`;
        None means every connector of every component.

    Raises
    ------
    ConfigurationError
        If a recorded variable is of a type the exchange does not carry.
    """

    def __init__(self, system: BoundSystem, record: Sequence[str] | None = None) -> None:
        self.system = system
        self.slaves: list[Slave] = []
        self.vectors: dict[str, TypeVectors] = {}
        self.signals: list[Signal] = []
        n = len(system.components)
        self._held: list[dict[tuple[str, int], float]] = [{} for _ in range(n)]
        self.modified = False  # set when an input modifier changed since the last refresh()
        self._layout(record)

    # -- layout -------------------------------------------------------------------------------
    def _recorded_paths(self, record: Sequence[str] | None) -> list[str]:
        if record is not None:
            return list(record)
        return [f"{c.name}.{k.name}" for c in self.system.components for k in c.definition.connectors
                if c.variables.get(k.name) is not None and c.variables[k.name].type_name in IO_TYPES]

    def _layout(self, record: Sequence[str] | None) -> None:
        """Lay out the vectors: per type, each component's gets then its sets, in declaration order."""
        sys_ = self.system
        n = len(sys_.components)
        linked_in = {(ln.target, ln.target_var.type_name, ln.target_var.vr): ln for ln in sys_.links}
        gets: list[dict[str, list[VariableInfo]]] = [{t: [] for t in IO_TYPES} for _ in range(n)]
        sets: list[dict[str, list[VariableInfo]]] = [{t: [] for t in IO_TYPES} for _ in range(n)]

        def add_get(i: int, v: VariableInfo) -> None:
            if all(g.vr != v.vr for g in gets[i][v.type_name]):
                gets[i][v.type_name].append(v)

        for ln in sys_.links:
            add_get(ln.source, ln.source_var)
            sets[ln.target][ln.target_var.type_name].append(ln.target_var)
        recorded: list[tuple[int, VariableInfo]] = []
        for path in self._recorded_paths(record):
            i, v = sys_.variable(path)
            if v.type_name not in IO_TYPES:
                raise ConfigurationError(f"cannot record '{path}': type {v.type_name} (allowed: "
                                         f"{', '.join(IO_TYPES)})")
            recorded.append((i, v))
            if (i, v.type_name, v.vr) not in linked_in:
                add_get(i, v)
        self._gets, self._sets = gets, sets
        per_component: list[list[Segment]] = [[] for _ in range(n)]
        every: list[Segment] = []
        for t in IO_TYPES:
            out_range, in_range, o, u = [], [], 0, 0
            for i in range(n):
                out_range.append((o, o + len(gets[i][t])))
                o += len(gets[i][t])
                in_range.append((u, u + len(sets[i][t])))
                u += len(sets[i][t])
            out_pos = {(i, v.vr): out_range[i][0] + j for i in range(n) for j, v in enumerate(gets[i][t])}
            src = np.zeros(u, dtype=np.intp)
            scale, offset = np.ones(u), np.zeros(u)
            mapped: list[tuple[int, dict[int, int]]] = []
            for i in range(n):
                for j, v in enumerate(sets[i][t]):
                    ln = linked_in[(i, t, v.vr)]
                    k = in_range[i][0] + j
                    src[k] = out_pos[(ln.source, ln.source_var.vr)]
                    scale[k], offset[k] = ln.affine.scale, ln.affine.offset
                    if ln.mapping is not None:
                        mapped.append((k, ln.mapping))
            names = [f"{sys_.components[i].name}.{v.name}" for i in range(n) for v in gets[i][t]]
            vec = TypeVectors(np.zeros(o, dtype=_DTYPE[t]), np.zeros(u, dtype=_DTYPE[t]), src, out_range, in_range,
                              names)
            self.vectors[t] = vec
            every.append(Segment(vec.outputs, src, vec.inputs, scale, offset, tuple(mapped)))
            for i, (a, b) in enumerate(in_range):
                local = tuple((k - a, m) for k, m in mapped if a <= k < b)
                per_component[i].append(Segment(vec.outputs, src[a:b], vec.inputs[a:b], scale[a:b], offset[a:b],
                                                local))
        self.signals = [self._signal(i, v, linked_in) for i, v in recorded]
        self._linked_inputs = {(i, t, v.vr): self.vectors[t].in_range[i][0] + j
                               for t in IO_TYPES for i in range(n) for j, v in enumerate(sets[i][t])}
        self._output_index = {(i, t, v.vr): self.vectors[t].out_range[i][0] + j
                              for t in IO_TYPES for i in range(n) for j, v in enumerate(gets[i][t])}
        self._all = Transfer(every)
        self._to = [Transfer(segs) for segs in per_component]
        self.transfer_all = self._all.__call__  # the algorithms' calls go straight to the transfers

    def _signal(self, i: int, v: VariableInfo, linked_in: dict[tuple[int, str, int], object]) -> Signal:
        name = self.system.components[i].name
        if (i, v.type_name, v.vr) in linked_in:
            a, _ = self.vectors[v.type_name].in_range[i]
            j = next(j for j, s in enumerate(self._sets[i][v.type_name]) if s.vr == v.vr)
            return Signal(name, v, "inputs", a + j)
        a, _ = self.vectors[v.type_name].out_range[i]
        j = next(j for j, g in enumerate(self._gets[i][v.type_name]) if g.vr == v.vr)
        return Signal(name, v, "outputs", a + j)

    def bind(self, slaves: Sequence[Slave]) -> None:
        """Point every (instantiated) slave's batched gets and sets at its slices of the vectors."""
        self.slaves = list(slaves)
        for t, vec in self.vectors.items():
            for i, slave in enumerate(self.slaves):
                a, b = vec.out_range[i]
                slave.bind_io(t, "get", self._gets[i][t], vec.outputs[a:b])
                a, b = vec.in_range[i]
                slave.bind_io(t, "set", self._sets[i][t], vec.inputs[a:b])
        for i in range(len(self.slaves)):
            self._publish(i)
        self.modified = False

    # -- transfers (what the algorithms call) -----------------------------------------------------
    def transfer_to(self, i: int) -> None:
        """Copy the connected inputs of component ``i`` from their sources."""
        self._to[i]()

    # -- input modifiers ----------------------------------------------------------------------
    def modifier(self, path: str, where: str) -> InputModifier:
        """An :class:`InputModifier` of ``component.variable`` (an input or a tunable parameter).

        Raises
        ------
        ConfigurationError
            If the variable does not exist or may not be changed during a run.
        """
        try:
            i, var = self.system.variable(path)
        except EmssError:
            raise ConfigurationError(f"{where}: no variable '{path}' (write component.variable)") from None
        if not (var.causality == "input" or (var.causality == "parameter" and var.variability == "tunable")):
            raise ConfigurationError(f"{where}: '{path}' is {var.causality} ({var.variability}); only inputs and "
                                     "tunable parameters can be changed during a run")
        if var.type_name not in IO_TYPES:
            raise ConfigurationError(f"{where}: '{path}' is a {var.type_name}; allowed: {', '.join(IO_TYPES)}")
        return InputModifier(self, path, i, var, self._linked_inputs.get((i, var.type_name, var.vr)))

    def held(self, i: int) -> dict[tuple[str, int], float]:
        """The overrides of component ``i``'s connected inputs: (type, index in the input vector) -> value."""
        return self._held[i]

    def hold(self, i: int, type_name: str, index: int, value: float) -> None:
        if self._held[i].get((type_name, index)) != value:
            self._held[i][(type_name, index)] = value
            self._publish(i)

    def unhold(self, i: int, type_name: str, index: int) -> None:
        if self._held[i].pop((type_name, index), None) is not None:
            self._publish(i)

    def _publish(self, i: int) -> None:
        """Give slave ``i`` its overrides as (its input vector, index, value) to write before each set."""
        self.modified = True
        if i < len(self.slaves):
            self.slaves[i].modifiers = [(self.vectors[t].inputs, j, v) for (t, j), v in self._held[i].items()]

    @property
    def holding(self) -> bool:
        return any(self._held)

    def refresh(self) -> None:
        """After modifiers changed: every connected input from its connection again (a released one gets
        its connection's value now, not a step later), then the overrides, so that observers see the
        inputs the slaves are given."""
        self.transfer_all()
        for held in self._held:
            for (t, j), v in held.items():
                self.vectors[t].inputs[j] = v
        self.modified = False

    # -- reading ------------------------------------------------------------------------------
    def output_slot(self, path: str) -> tuple[np.ndarray, int] | None:
        """Where the current value of a variable the slaves get is kept, if it is gotten."""
        i, var = self.system.variable(path)
        j = self._output_index.get((i, var.type_name, var.vr))
        return None if j is None else (self.vectors[var.type_name].outputs, j)

    def probe(self, path: str, where: str, numeric: bool = False) -> Callable[[], Value]:
        """A function giving the current value of ``component.variable``, any causality: from the
        output vector when the slaves get it anyway, from the input vector for a connected input
        (overrides included), else one FMI get call (any type, String included; only once the
        slaves are bound). ``numeric`` refuses what is not Real, Integer or Boolean.

        Raises
        ------
        ConfigurationError
            ``"<where> names no variable ..."`` or, with ``numeric``, a variable of another type.
        """
        try:
            i, var = self.system.variable(path)
        except EmssError:
            raise ConfigurationError(f"{where} names no variable '{path}' (write component.variable)") from None
        if numeric and var.type_name not in IO_TYPES:
            raise ConfigurationError(f"{where} needs a Real, Integer or Boolean variable; '{path}' is a "
                                     f"{var.type_name}")
        key = (i, var.type_name, var.vr)
        if key in self._output_index:
            vector, j = self.vectors[var.type_name].outputs, self._output_index[key]
            return lambda: vector[j].item()
        if key in self._linked_inputs:
            vector, j = self.vectors[var.type_name].inputs, self._linked_inputs[key]
            return lambda: vector[j].item()
        return lambda: self.slaves[i].get_value(var)
