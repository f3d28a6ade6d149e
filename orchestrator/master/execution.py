"""The execution: owns time, the slaves and the run; each macro step: algorithm, manipulators, observers.

Time is ``t0 + k*h`` with an integer macro-step counter ``k``, never an accumulated sum. The
parts, as in libcosim: the **exchange** (:mod:`.exchange`: the value vectors, their layout, the
transfers, the input modifiers and the probe) between the **slaves** (:mod:`.slave`), an
**algorithm** (:mod:`.algorithm`, chosen by name in :mod:`.algorithm_registry`) that steps them
and moves the values, **manipulators** (scenarios) that change inputs through the exchange's
modifiers, **observers** that read through the exchange, and a stop condition (:mod:`.condition`).
"""
from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from ..errors import ConfigurationError, EmssError, InitializationError
from ..results import RunInterrupted
from ..ssp.system_model import BoundSystem
from . import algorithm_registry
from .algorithm import Algorithm, StepOrder, step_order
from .condition import StopCondition
from .exchange import IO_TYPES, Exchange, Signal, TypeVectors
from .slave import FmuLog, Slave

__all__ = ["DEFAULT_RATE_HZ", "IO_TYPES", "MAX_RATE_HZ", "MAX_STEPS", "MAX_STEP_MULTIPLE", "MIN_RATE_HZ",
           "Execution", "Manipulator", "Observer", "Signal", "TypeVectors", "check_rate"]

MIN_RATE_HZ = 0.1
MAX_RATE_HZ = 100.0
DEFAULT_RATE_HZ = 20.0
MAX_STEPS = 10 ** 9  #: macro steps of one run at the most (578 days simulated at 20 Hz)
MAX_STEP_MULTIPLE = 1000  #: a component steps at least every 1000th macro step (10 s at 100 Hz, 10000 s at 0.1 Hz)


class Manipulator(Protocol):
    """Changes inputs during a run (scenarios, fault injection): attached after initialization;
    ``apply`` is called with the time of every macro step, before the next step, and acts through
    the modifiers of ``execution.exchange`` (:meth:`.Exchange.modifier`)."""

    def attach(self, execution: Execution) -> None: ...
    def apply(self, time_s: float) -> None: ...


class Observer(Protocol):
    """Watches an execution: called after initialization and after every macro step."""

    def start(self, execution: Execution) -> None: ...
    def sample(self, k: int, time_s: float) -> None: ...
    def finish(self, execution: Execution, error: BaseException | None) -> None: ...


def check_rate(rate_hz: float) -> float:
    """Return the communication step [s] for a rate [Hz] in the allowed range."""
    if not (isinstance(rate_hz, (int, float)) and math.isfinite(rate_hz)) or not \
            MIN_RATE_HZ <= rate_hz <= MAX_RATE_HZ:
        raise ConfigurationError(f"communication rate {rate_hz} Hz is out of range "
                                 f"(allowed: {MIN_RATE_HZ} to {MAX_RATE_HZ} Hz)")
    return 1.0 / rate_hz


def check_multiples(system: BoundSystem, multiples: dict[str, int] | None) -> list[int]:
    """One step multiple per component (1 where none is given), checked."""
    names = [c.name for c in system.components]
    multiples = dict(multiples or {})
    unknown = sorted(set(multiples) - set(names))
    if unknown:
        raise ConfigurationError(f"step multiple for unknown component(s) {', '.join(unknown)} "
                                 f"(components: {', '.join(names)})")
    bad = {k: v for k, v in multiples.items() if not isinstance(v, int) or not 1 <= v <= MAX_STEP_MULTIPLE}
    if bad:
        raise ConfigurationError(f"step multiples must be integers from 1 to {MAX_STEP_MULTIPLE}, got {bad}")
    return [multiples.get(n, 1) for n in names]


class Execution:
    """Runs a bound system with a master algorithm over an exchange.

    Parameters
    ----------
    system : BoundSystem
        The system, resolved against its FMUs.
    algorithm : str | Algorithm
        A name of :mod:`.algorithm_registry` (``"jacobi"``, ``"gauss-seidel"``, ...), made for
        ``system`` with ``multiples``; or an algorithm object, whose own multiples are used.
    exchange : Exchange | None
        The exchange vectors; None lays them out for ``system`` with ``record``.
    rate_hz : float | None
        Communication rate [Hz], 0.1 to 100; None takes the SSD's step (OSP annotation) or 20 Hz.
    multiples : dict[str, int] | None
        Step multiple per component name (a component steps every n-th macro step).
    record : Sequence[str] | None
        ``component.variable`` paths made available to observers as signals;
        None means every connector of every component (only without ``exchange``).
    start_time_s : float | None
        Start time [s]; None takes the SSD's DefaultExperiment or 0.
    """

    def __init__(self, system: BoundSystem, algorithm: str | Algorithm = algorithm_registry.DEFAULT,
                 exchange: Exchange | None = None, *, rate_hz: float | None = None,
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
        if isinstance(algorithm, Algorithm):
            if multiples:
                raise ConfigurationError("give step multiples to the algorithm object, not to the execution")
            if len(algorithm.multiples) != len(system.components):
                raise ConfigurationError(f"algorithm {algorithm.name} has {len(algorithm.multiples)} step "
                                         f"multiples for {len(system.components)} components")
            self.algorithm = algorithm
        else:
            self.algorithm = algorithm_registry.create(algorithm, system, check_multiples(system, multiples))
        self.multiples = list(self.algorithm.multiples)
        self.order: StepOrder = step_order(system)
        if exchange is not None and record is not None:
            raise ConfigurationError("give the recorded paths to the exchange, not to the execution")
        self.exchange = exchange if exchange is not None else Exchange(system, record)
        if self.exchange.system is not system:
            raise ConfigurationError("the exchange was laid out for another system")
        # The algorithms' transfer calls go straight to the exchange (no call in between).
        self.transfer_all = self.exchange.transfer_all
        self.transfer_to = self.exchange.transfer_to
        self.log = FmuLog.shared()
        self.slaves = [Slave(c, self.log, m) for c, m in zip(system.components, self.multiples, strict=True)]
        #: Why an FMU ended the simulation itself (fmi2Discard with fmi2Terminated; :meth:`.Slave._step_refused`)
        self._ended: list[str] = []
        for s in self.slaves:
            s.on_end = self._ended.append
        self._states: list[object | None] = [None] * len(self.slaves)
        self.k = 0
        self.observers: list[Observer] = []
        self._initialized = False
        self.manipulators: list[Manipulator] = []
        self._stop: StopCondition | None = None
        self.stopped_by = ""  # the stop condition, or the FMU that ended the simulation, that ended the run early
        self._signal = 0  # a signal that asked the run to stop (see request_stop)
        #: perf_counter() [s] as the first step began and as the last one ended (None before the steps), and the
        #: process's CPU time [s] (process_time()) at both
        self.stepping_started: float | None = None
        self.stepping_ended: float | None = None
        self.stepping_cpu: tuple[float, float] = (0.0, 0.0)

    # -- set-up -----------------------------------------------------------------------------
    @property
    def vectors(self) -> dict[str, TypeVectors]:
        """The exchange vectors per FMI type (see :class:`.Exchange`)."""
        return self.exchange.vectors

    @property
    def signals(self) -> list[Signal]:
        """The recorded variables and where their values live (see :class:`.Exchange`)."""
        return self.exchange.signals

    def time_at(self, k: int) -> float:
        """Simulation time [s] of macro step ``k``."""
        return self.start_time_s + k * self.step_size_s

    @property
    def time_s(self) -> float:
        return self.time_at(self.k)

    @property
    def initialized(self) -> bool:
        """Whether every FMU left Initialization Mode (the run may step)."""
        return self._initialized

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
        stop = StopCondition(condition, "--until")
        stop.attach(self.exchange)
        self._stop = stop

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

    def save_state(self, i: int) -> None:
        """Keep the FMU state of component ``i`` (fmi2GetFMUstate), for :meth:`restore_state`."""
        self._states[i] = self.slaves[i].get_state(self._states[i])

    def restore_state(self, i: int) -> None:
        """Put component ``i`` back in the state of its last :meth:`save_state` (fmi2SetFMUstate)."""
        self.slaves[i].set_state(self._states[i])

    def inputs_of(self, i: int) -> list[np.ndarray]:
        """Views of component ``i``'s connected inputs in the exchange, per type (Real, Integer, Boolean)."""
        return [v.inputs[a:b] for v in self.vectors.values() for a, b in [v.in_range[i]]]

    @property
    def observed(self) -> bool:
        """Whether anything samples the exchange vectors after a step (observers or manipulators)."""
        return bool(self.observers or self.manipulators)

    def _manipulate(self, time_s: float) -> None:
        for m in self.manipulators:
            m.apply(time_s)
        ex = self.exchange
        if ex.modified or ex.holding:
            ex.refresh()

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
        self.exchange.bind(self.slaves)
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
            until = self._stop.holds if self._stop is not None else None
            ended = self._ended
            self.stepping_started, cpu0 = time.perf_counter(), time.process_time()
            self.stepping_cpu = (cpu0, cpu0)
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
                if ended:  # an FMU ended the simulation in this step: the run is complete (FMI 2.0, 4.2.3)
                    self.stopped_by = "; ".join(ended)
                    break
                if until is not None and until():
                    self.stopped_by = str(self._stop)
                    break
            else:
                if self._signal:
                    raise RunInterrupted(self._signal, self.time_s)
        except BaseException as exc:
            error = exc
            raise
        finally:
            if self.stepping_started is not None:
                self.stepping_ended = time.perf_counter()
                self.stepping_cpu = (self.stepping_cpu[0], time.process_time())
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
        for i, s in enumerate(self.slaves):
            if self._states[i] is not None:
                s.free_state(self._states[i])
                self._states[i] = None
            s.free()
        if terminate_error is not None:
            raise terminate_error
        if finish_error is not None and error is None:
            raise finish_error

    @property
    def stepping_s(self) -> float:
        """Wall time [s] from the first step's start to the last step's end (0 before the steps)."""
        if self.stepping_started is None or self.stepping_ended is None:
            return 0.0
        return self.stepping_ended - self.stepping_started

    def stats(self) -> dict[str, dict[str, float]]:
        """Per component: steps, wall time [s] in doStep, get and set, and the batched sets left out because
        their values were those last sent (:meth:`.Slave.set_inputs`)."""
        return {s.name: {"steps": s.stats.steps, "do_step_s": s.stats.do_step_s, "get_s": s.stats.get_s,
                         "set_s": s.stats.set_s, "sets_skipped": s.stats.sets_skipped} for s in self.slaves}

