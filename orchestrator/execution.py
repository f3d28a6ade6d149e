"""The execution: owns time, the slaves and the value vectors; runs initialization and steps.

Time is ``t0 + k*h`` with an integer macro-step counter ``k``, never an
accumulated sum. Every value exchanged between FMUs lives in one preallocated
numpy vector per FMI type: ``outputs`` (what the slaves' batched gets write) and
``inputs`` (what their batched sets read); a transfer is one ``numpy.take``.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from .algorithm import ALGORITHMS, Algorithm, GaussSeidel, Jacobi, StepOrder, gauss_seidel_order
from .errors import ConfigurationError, EmssError, InitializationError
from .manipulators import Condition, parse_condition, reader
from .results import RunInterrupted
from .slave import FmuLog, Slave
from .system import BoundSystem, VariableInfo
from .transfer import Transfer

MIN_RATE_HZ = 0.1
MAX_RATE_HZ = 100.0
DEFAULT_RATE_HZ = 20.0
MAX_STEPS = 10 ** 9  #: macro steps of one run at the most (578 days simulated at 20 Hz)
MAX_STEP_MULTIPLE = 1000  #: a component steps at least every 1000th macro step (10 s at 100 Hz, 10000 s at 0.1 Hz)
IO_TYPES = ("Real", "Integer", "Boolean")
_DTYPE = {"Real": np.float64, "Integer": np.int32, "Boolean": np.int32}


class Manipulator(Protocol):
    """Changes inputs during a run (scenarios, fault injection): attached after initialization;
    ``apply`` is called with the time of every macro step before the step, and returns the
    overrides of connected inputs (vector, index, value) to re-apply after every transfer."""

    def attach(self, execution: Execution) -> None: ...
    def apply(self, time_s: float) -> list[tuple[np.ndarray, int, float]]: ...


class Observer(Protocol):
    """Watches an execution: called after initialization and after every macro step."""

    def start(self, execution: Execution) -> None: ...
    def sample(self, k: int, time_s: float) -> None: ...
    def finish(self, execution: Execution, error: BaseException | None) -> None: ...


@dataclass(frozen=True)
class Signal:
    """Where the current value of a recorded variable lives: ``vector[type][index]``."""

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


def check_rate(rate_hz: float) -> float:
    """Return the communication step [s] for a rate [Hz] in the allowed range."""
    if not (isinstance(rate_hz, (int, float)) and math.isfinite(rate_hz)) or not \
            MIN_RATE_HZ <= rate_hz <= MAX_RATE_HZ:
        raise ConfigurationError(f"communication rate {rate_hz} Hz is out of range "
                                 f"(allowed: {MIN_RATE_HZ} to {MAX_RATE_HZ} Hz)")
    return 1.0 / rate_hz


class Execution:
    """Runs a bound system with a chosen master algorithm.

    Parameters
    ----------
    system : BoundSystem
        The system, resolved against its FMUs.
    rate_hz : float | None
        Communication rate [Hz], 0.1 to 100; None takes the SSD's step (OSP annotation) or 20 Hz.
    algorithm : str
        ``"jacobi"`` or ``"gauss-seidel"``.
    multiples : dict[str, int] | None
        Step multiple per component name (a component steps every n-th macro step).
    record : Sequence[str] | None
        ``component.variable`` paths made available to observers as signals;
        None means every connector of every component.
    start_time_s : float | None
        Start time [s]; None takes the SSD's DefaultExperiment or 0.
    """

    def __init__(self, system: BoundSystem, rate_hz: float | None = None, algorithm: str = "jacobi",
                 multiples: dict[str, int] | None = None, record: Sequence[str] | None = None,
                 start_time_s: float | None = None, max_init_iterations: int = 50) -> None:
        self.system = system
        sysdef = system.definition
        if rate_hz is None:
            rate_hz = 1.0 / sysdef.step_size_s if sysdef.step_size_s else DEFAULT_RATE_HZ
        self.rate_hz = float(rate_hz)
        self.step_size_s = check_rate(self.rate_hz)
        self.start_time_s = float(start_time_s if start_time_s is not None else (sysdef.start_time_s or 0.0))
        self.max_init_iterations = max_init_iterations
        names = [c.name for c in system.components]
        multiples = dict(multiples or {})
        unknown = sorted(set(multiples) - set(names))
        if unknown:
            raise ConfigurationError(f"step multiple for unknown component(s) {', '.join(unknown)} "
                                     f"(components: {', '.join(names)})")
        bad = {k: v for k, v in multiples.items() if not isinstance(v, int) or not 1 <= v <= MAX_STEP_MULTIPLE}
        if bad:
            raise ConfigurationError(f"step multiples must be integers from 1 to {MAX_STEP_MULTIPLE}, got {bad}")
        self.multiples = [multiples.get(n, 1) for n in names]
        self.order: StepOrder = gauss_seidel_order(len(names), [(ln.source, ln.target) for ln in system.links])
        if algorithm == "jacobi":
            self.algorithm: Algorithm = Jacobi(self.multiples)
        elif algorithm == "gauss-seidel":
            self.algorithm = GaussSeidel(self.multiples, self.order)
        else:
            raise ConfigurationError(f"unknown algorithm '{algorithm}' (allowed: {', '.join(ALGORITHMS)})")
        self.log = FmuLog.shared()
        self.slaves = [Slave(c, self.log, m) for c, m in zip(system.components, self.multiples, strict=False)]
        self.k = 0
        self.observers: list[Observer] = []
        self.signals: list[Signal] = []
        self.vectors: dict[str, TypeVectors] = {}
        self._record = record
        self._initialized = False
        self.manipulators: list[Manipulator] = []
        self._until_cond: Condition | None = None
        self._until: Callable[[], bool] | None = None
        self.stopped_by = ""  # the stop condition that ended the run early, if one did
        self._signal = 0  # a signal that asked the run to stop (see request_stop)
        self._overrides: list[tuple[np.ndarray, int, float]] = []
        self._linked_inputs: dict[tuple[int, str, int], int] = {}  # (component, type, vr) -> index in inputs

    # -- set-up -----------------------------------------------------------------------------
    def time_at(self, k: int) -> float:
        """Simulation time [s] of macro step ``k``."""
        return self.start_time_s + k * self.step_size_s

    @property
    def time_s(self) -> float:
        return self.time_at(self.k)

    def request_stop(self, signum: int) -> None:
        """Ask :meth:`run` to end after the current step with :class:`RunInterrupted` (safe to call from a
        signal handler: it only sets a flag, so no FMU call is cut in the middle)."""
        self._signal = signum

    def add_observer(self, observer: Observer) -> None:
        self.observers.append(observer)

    def add_manipulator(self, manipulator: Manipulator) -> None:
        self.manipulators.append(manipulator)

    def stop_when(self, condition: str) -> None:
        """End :meth:`run` after the first step at which ``condition`` holds (``component.variable OP
        number``, e.g. ``"fcs.mission_completed == 1"``), before its stop time; :attr:`stopped_by`
        then names the condition.

        Raises
        ------
        ConfigurationError
            If the condition cannot be read or names no variable of the system.
        """
        self._until_cond = parse_condition(condition, "--until")
        if self._initialized:
            self._arm_until()

    def _arm_until(self) -> None:
        """Resolve the stop condition's variable (once the exchange vectors exist)."""
        cond = self._until_cond
        if cond is not None:
            read = reader(self, cond.path, "--until")
            self._until = lambda: cond.holds(read())

    def input_slot(self, path: str, where: str) -> tuple[str, int] | tuple[Slave, VariableInfo]:
        """Where a manipulator writes ``component.variable``: ``(type, index)`` in the input vectors
        for a connected input, else ``(slave, variable)`` to be set directly (an unconnected input
        or a tunable parameter).

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
        key = (i, var.type_name, var.vr)
        if key in self._linked_inputs:
            return var.type_name, self._linked_inputs[key]
        return self.slaves[i], var

    def output_slot(self, path: str) -> tuple[np.ndarray, int] | None:
        """Where the current value of a variable the slaves get is kept, if it is gotten."""
        i, var = self.system.variable(path)
        vec = self.vectors.get(var.type_name)
        if vec is None:
            return None
        name = f"{self.system.components[i].name}.{var.name}"
        return (vec.outputs, vec.output_names.index(name)) if name in vec.output_names else None

    def _recorded_paths(self) -> list[str]:
        if self._record is not None:
            return list(self._record)
        return [f"{c.name}.{k.name}" for c in self.system.components for k in c.definition.connectors
                if c.variables.get(k.name) is not None and c.variables[k.name].type_name in IO_TYPES]

    def _build_vectors(self) -> None:
        """Lay out the exchange vectors and bind every slave's batched I/O to slices of them."""
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
        for path in self._recorded_paths():
            i, v = sys_.variable(path)
            if v.type_name not in IO_TYPES:
                raise ConfigurationError(f"cannot record '{path}': type {v.type_name} (allowed: "
                                         f"{', '.join(IO_TYPES)})")
            recorded.append((i, v))
            if (i, v.type_name, v.vr) not in linked_in:
                add_get(i, v)
        for t in IO_TYPES:
            out_range, in_range, o, u = [], [], 0, 0
            for i in range(n):
                out_range.append((o, o + len(gets[i][t])))
                o += len(gets[i][t])
                in_range.append((u, u + len(sets[i][t])))
                u += len(sets[i][t])
            out_pos = {(i, v.vr): out_range[i][0] + j for i in range(n) for j, v in enumerate(gets[i][t])}
            src = np.zeros(u, dtype=np.intp)
            for i in range(n):
                for j, v in enumerate(sets[i][t]):
                    ln = linked_in[(i, t, v.vr)]
                    src[in_range[i][0] + j] = out_pos[(ln.source, ln.source_var.vr)]
            names = [f"{sys_.components[i].name}.{v.name}" for i in range(n) for v in gets[i][t]]
            vec = TypeVectors(np.zeros(o, dtype=_DTYPE[t]), np.zeros(u, dtype=_DTYPE[t]), src, out_range, in_range,
                              names)
            self.vectors[t] = vec
            for i, slave in enumerate(self.slaves):
                a, b = out_range[i]
                slave.bind_io(t, "get", gets[i][t], vec.outputs[a:b])
                a, b = in_range[i]
                slave.bind_io(t, "set", sets[i][t], vec.inputs[a:b])
        self.signals = []
        for i, v in recorded:
            t = v.type_name
            vec = self.vectors[t]
            if (i, t, v.vr) in linked_in:
                a, _ = vec.in_range[i]
                j = next(j for j, s in enumerate(sets[i][t]) if s.vr == v.vr)
                self.signals.append(Signal(sys_.components[i].name, v, "inputs", a + j))
            else:
                a, _ = vec.out_range[i]
                j = next(j for j, g in enumerate(gets[i][t]) if g.vr == v.vr)
                self.signals.append(Signal(sys_.components[i].name, v, "outputs", a + j))
        self._linked_inputs = {
            (i, t, v.vr): self.vectors[t].in_range[i][0] + j
            for t in IO_TYPES for i in range(n) for j, v in enumerate(sets[i][t])}
        self._transfers: list[Transfer] = []
        self._slave_transfers: list[list[Transfer]] = [[] for _ in range(n)]
        pairs: list[list[tuple[np.ndarray, int, np.ndarray, int, tuple[float, float] | None]]] = [[] for _ in range(n)]
        mapped_slaves: set[int] = set()
        for t, vec in self.vectors.items():
            scale = np.ones(len(vec.inputs))
            offset = np.zeros(len(vec.inputs))
            mapped: list[tuple[int, dict[int, int]]] = []
            for i in range(n):
                for j, v in enumerate(sets[i][t]):
                    ln = linked_in[(i, t, v.vr)]
                    k = vec.in_range[i][0] + j
                    scale[k], offset[k] = ln.affine.scale, ln.affine.offset
                    if ln.mapping is not None:
                        mapped.append((k, ln.mapping))
            if len(vec.inputs):
                self._transfers.append(Transfer(vec.outputs, vec.source_index, vec.inputs, scale, offset, mapped))
            for i, (a, b) in enumerate(vec.in_range):
                if b > a:
                    local = [(k - a, m) for k, m in mapped if a <= k < b]
                    self._slave_transfers[i].append(Transfer(vec.outputs, vec.source_index[a:b], vec.inputs[a:b],
                                                             scale[a:b], offset[a:b], local))
                    for k in range(a, b):
                        linear = None if scale[k] == 1.0 and offset[k] == 0.0 else (float(scale[k]), float(offset[k]))
                        pairs[i].append((vec.inputs, k, vec.outputs, int(vec.source_index[k]), linear))
                    if local:
                        mapped_slaves.add(i)
        # One element loop per component across all types, for components with a few plain inputs
        # (Gauss-Seidel transfers per component: one Python loop costs less than a numpy call per type).
        self._slave_pairs = [p if len(p) <= 8 and i not in mapped_slaves else None for i, p in enumerate(pairs)]

    # -- coupling interface used by the algorithms ---------------------------------------------
    def step_component(self, i: int, k: int) -> None:
        t = self.time_at(k)
        self.slaves[i].do_step(t, self.time_at(k + self.multiples[i]) - t)

    def get_outputs(self, i: int) -> None:
        self.slaves[i].get_outputs()

    def advance(self, i: int, k: int) -> None:
        """Set the inputs of component ``i``, step it over one macro step from ``k``, get its outputs."""
        t = self.start_time_s + k * self.step_size_s
        self.slaves[i].advance(t, self.start_time_s + (k + 1) * self.step_size_s - t)

    def set_inputs(self, i: int) -> None:
        self.slaves[i].set_inputs()

    def transfer_to(self, i: int) -> None:
        pairs = self._slave_pairs[i]
        if pairs is not None:
            for inputs, k, outputs, src, linear in pairs:
                inputs[k] = outputs[src] if linear is None else outputs[src] * linear[0] + linear[1]
        else:
            for transfer in self._slave_transfers[i]:
                transfer()
        for vec, j, value in self._overrides:
            vec[j] = value

    @property
    def observed(self) -> bool:
        """Whether anything samples the exchange vectors after a step (observers or manipulators)."""
        return bool(self.observers or self.manipulators)

    def transfer_all(self) -> None:
        for transfer in self._transfers:
            transfer()
        for vec, j, value in self._overrides:
            vec[j] = value

    def _manipulate(self, time_s: float) -> None:
        had = bool(self._overrides)
        self._overrides = [o for m in self.manipulators for o in m.apply(time_s)]
        if had:  # a released input must get its connection's value back now, not one step later
            self.transfer_all()

    # -- running ----------------------------------------------------------------------------
    def initialize(self, stop_time_s: float | None = None) -> None:
        """Instantiate, apply parameters, iterate outputs to inputs to a fixed point, exit initialization.

        Raises
        ------
        SlaveError
            When an FMU fails; InitializationError when the exchange does not settle.
        """
        for s in self.slaves:
            s.instantiate()
        self._build_vectors()
        for s in self.slaves:
            s.setup_experiment(self.start_time_s, stop_time_s)
        for p in self.system.parameters:
            self.slaves[p.component].set_value(p.variable, p.value)
        for s in self.slaves:
            s.enter_initialization_mode()
        self._settle()
        for s in self.slaves:
            s.exit_initialization_mode()
        for s in self.slaves:
            s.get_outputs()
        self.transfer_all()
        self._initialized = True
        for m in self.manipulators:
            m.attach(self)
        self._arm_until()
        self._manipulate(self.start_time_s)
        for o in self.observers:
            o.start(self)
        for o in self.observers:
            o.sample(0, self.start_time_s)

    def _settle(self, rtol: float = 1e-10, atol: float = 1e-12) -> None:
        """Exchange outputs to inputs in initialization mode until nothing changes."""
        previous: dict[str, np.ndarray] | None = None
        changed: dict[str, np.ndarray] = {}
        for _ in range(self.max_init_iterations):
            for s in self.slaves:
                s.get_outputs()
            current = {t: v.outputs.copy() for t, v in self.vectors.items()}
            if previous is not None:
                changed = {t: ~np.isclose(current[t], previous[t], rtol=rtol, atol=atol, equal_nan=True)
                           for t in current}
                if not any(c.any() for c in changed.values()):
                    return
            previous = current
            self.transfer_all()
            for s in self.slaves:
                s.set_inputs()
        unsettled = [name for t, vec in self.vectors.items() if t in changed
                     for name, moving in zip(vec.output_names, changed[t], strict=False) if moving]
        raise InitializationError(f"initialization did not reach a fixed point in {self.max_init_iterations} "
                                  f"exchanges; still changing: {', '.join(unsettled)}")

    def run(self, stop_time_s: float) -> None:
        """Initialize (if needed) and step until ``stop_time_s`` [s]; observers see every step.

        On failure the observers are finished with the error (so recorders keep what
        they have) and the error is raised again.
        """
        error: BaseException | None = None
        try:
            if not (isinstance(stop_time_s, (int, float)) and math.isfinite(stop_time_s)):
                raise ConfigurationError(f"stop time {stop_time_s} s is not a finite number")
            if stop_time_s < self.start_time_s:
                raise ConfigurationError(f"stop time {stop_time_s} s is before the start time "
                                         f"{self.start_time_s} s")
            if not self._initialized:
                self.initialize(stop_time_s)
            n_steps = math.ceil((stop_time_s - self.start_time_s) / self.step_size_s - 1e-9)
            if n_steps > MAX_STEPS:
                raise ConfigurationError(f"stop time {stop_time_s:g} s is {n_steps:.3g} steps of "
                                         f"{self.step_size_s:g} s, more than {MAX_STEPS:.0e}; allowed: up to "
                                         f"{self.start_time_s + MAX_STEPS * self.step_size_s:.6g} s at this rate")
            step = self.algorithm.step
            observers = [o.sample for o in self.observers]
            manipulate = self._manipulate if self.manipulators else None
            until = self._until
            for k in range(self.k, n_steps):
                if self._signal:
                    raise RunInterrupted(self._signal, self.time_s)
                step(self, k)
                self.k = k + 1
                t = self.time_at(k + 1)
                if manipulate is not None:
                    manipulate(t)
                for sample in observers:
                    sample(k + 1, t)
                if until is not None and until():
                    self.stopped_by = str(self._until_cond)
                    break
            else:
                if self._signal:
                    raise RunInterrupted(self._signal, self.time_s)
        except BaseException as exc:
            error = exc
            raise
        finally:
            self._finish(error)

    def _finish(self, error: BaseException | None) -> None:
        terminate_error: EmssError | None = None
        if error is None:
            for s in self.slaves:
                if s.fmu is not None:
                    try:
                        s.terminate()
                    except EmssError as exc:
                        terminate_error = terminate_error or exc
        finish_error: EmssError | None = None
        for o in self.observers:  # every observer closes its files, even when one of them cannot
            try:
                o.finish(self, error or terminate_error)
            except EmssError as exc:
                finish_error = finish_error or exc
        for s in self.slaves:
            s.free()
        if terminate_error is not None:
            raise terminate_error
        if finish_error is not None and error is None:
            raise finish_error

    def stats(self) -> dict[str, dict[str, float]]:
        """Per component: steps and wall time [s] in doStep, get and set."""
        return {s.name: {"steps": s.stats.steps, "do_step_s": s.stats.do_step_s, "get_s": s.stats.get_s,
                         "set_s": s.stats.set_s} for s in self.slaves}

