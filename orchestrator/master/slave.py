"""One FMU instance (fmpy's FMU2Slave) with batched, pre-resolved I/O.

fmpy's convenience calls (``getReal(vrs)``) build new ctypes arrays and a Python
list on every call. In the hot loop we call fmpy's low-level FMI functions
directly with value-reference arrays built once and value buffers that are
views on the execution's preallocated numpy vectors: one get and one set per
type per step, no allocation, no dict lookups.
"""
from __future__ import annotations

import atexit
import collections
import json
import os
import shutil
import tempfile
import time
import zipfile
from collections.abc import Callable
from ctypes import Array, byref, c_double, c_int, c_size_t, c_uint, c_void_p
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy import extract
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2FMUstate,
)

from ..errors import SlaveError
from ..results import check_archive
from ..ssp.system_model import ComponentModel, VariableInfo
from . import pool

_STATUS = ("ok", "warning", "discard", "error", "fatal", "pending")
_FMI2_LAST_SUCCESSFUL_TIME, _FMI2_TERMINATED = 2, 3  #: fmi2StatusKind values (FMI 2.0, section 4.2.3)
_EXTRACTED: dict[tuple[str, int, int], str] = {}
#: The record build-fmus writes into an FMU's resources folder (fmu/build.py) and its key saying that the FMU's
#: instances may be freed after any failure, fmi2Fatal included (fmu/lifecycle.py: pythonfmu reports every
#: Python exception as fmi2Fatal, after which FMI 2.0 allows no call to an FMU that does not say so)
BUILD_RECORD = "openemss_build.json"
FREE_AFTER_FAILURE = "free_after_failure"


def frees_after_failure(unzip_dir: str | Path) -> bool:
    """Whether the FMU extracted in ``unzip_dir`` says its instances may be freed after fmi2Fatal."""
    try:
        record = json.loads((Path(unzip_dir) / "resources" / BUILD_RECORD).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(record, dict) and record.get(FREE_AFTER_FAILURE) is True


def extracted(fmu_path: Path) -> str:
    """The folder where an FMU file is extracted, once per file (path, size, mtime) and process.

    Every instance of the same FMU then loads the same shared library (dlopen of
    one path), as FMI 2.0 intends for multiple instances. Extracting per instance
    would load a separate copy of the library each time, and since libraries are
    never unloaded (see ``Slave.free``), a long test session or a study would
    accumulate hundreds of copies of the same code in the process.
    """
    path = Path(fmu_path).resolve()
    st = path.stat()
    key = (str(path), st.st_size, st.st_mtime_ns)
    folder = _EXTRACTED.get(key)
    if folder is None or not Path(folder).is_dir():
        with zipfile.ZipFile(path) as zf:  # a zip bomb is refused before anything is written
            check_archive(zf, path)
        folder = extract(str(path), unzipdir=tempfile.mkdtemp(prefix="emss_fmu_"))
        _EXTRACTED[key] = folder
    return folder


@atexit.register
def _remove_extractions() -> None:
    for folder in _EXTRACTED.values():
        shutil.rmtree(folder, ignore_errors=True)
_MAX_MESSAGES = 20


class FmuLog:
    """Collects the messages FMUs send to the logger callback, per instance name.

    The messages are kept so that a failing call can be reported with what the
    FMU said (for a pythonfmu slave: the Python exception).
    """

    _shared: FmuLog | None = None

    @classmethod
    def shared(cls) -> FmuLog:
        """The process-wide logger. It is never freed: an FMU may keep the callback
        pointer for as long as the process lives."""
        if cls._shared is None:
            cls._shared = cls()
        return cls._shared

    def __init__(self) -> None:
        self.messages: dict[str, collections.deque[str]] = collections.defaultdict(
            lambda: collections.deque(maxlen=_MAX_MESSAGES))
        #: per instance, the FMI status its last message was logged with
        self.last_status: dict[str, int] = {}
        from fmpy import calloc, free
        from fmpy.logging import addLoggerProxy

        self.callbacks = fmi2CallbackFunctions()
        self._logger = fmi2CallbackLoggerTYPE(self._log)
        self.callbacks.logger = self._logger
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        # fmpy's native proxy formats the variadic message before it reaches Python.
        addLoggerProxy(byref(self.callbacks))

    def _log(self, env: object, instance: bytes | None, status: int, category: bytes | None,
             message: bytes | None) -> None:
        name = instance.decode("utf-8", "replace") if instance else "?"
        text = message.decode("utf-8", "replace") if message else ""
        self.messages[name].append(text.strip())
        self.last_status[name] = status

    def last(self, instance: str) -> str:
        """The most telling recent message of an instance, on one line."""
        msgs = [m for m in self.messages.get(instance, ()) if m]
        if not msgs:
            return ""
        # A Python traceback ends with the exception line; keep that one.
        lines = [ln.strip() for ln in msgs[-1].splitlines() if ln.strip()]
        return lines[-1] if lines else ""


@dataclass
class IoBuffers:
    """Value references and value buffers of one type for one direction of one slave."""

    vrs: Array  # type: ignore[type-arg]
    values: Array  # type: ignore[type-arg]
    count: int


@dataclass
class StepStats:
    """Wall time [s] spent in each kind of call of one slave."""

    do_step_s: float = 0.0
    get_s: float = 0.0
    set_s: float = 0.0
    steps: int = 0
    #: Batched sets left out because the batch held the values last sent (see :meth:`Slave.set_inputs`).
    sets_skipped: int = 0


_CTYPE = {"Real": c_double, "Integer": c_int, "Boolean": c_int}
_FUNC_SUFFIX = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean"}


def _array_view(ctype: type, vector: np.ndarray) -> Array:  # type: ignore[type-arg]
    """A ctypes array sharing memory with a contiguous numpy slice."""
    return (ctype * len(vector)).from_buffer(vector)


@dataclass
class Slave:
    """A component instance: an FMU2Slave plus its pre-resolved I/O.

    Parameters
    ----------
    model : ComponentModel
        The component bound to its model description.
    log : FmuLog
        Shared logger receiving the FMU's messages.
    """

    model: ComponentModel
    log: FmuLog
    multiple: int = 1
    stats: StepStats = field(default_factory=StepStats)

    def __post_init__(self) -> None:
        self.name = self.model.name
        self._unzip_dir: str | None = None
        self.fmu: FMU2Slave | None = None
        self._inputs: list[tuple[object, tuple[object, ...], str, IoBuffers]] = []
        self._outputs: list[tuple[object, tuple[object, ...], str, IoBuffers]] = []
        #: Per input batch, the bytes it held when last sent; None when the FMU's inputs are not known
        #: to hold them (nothing sent yet, or a call that may have changed them since).
        self._sent: list[bytes | None] = []
        self.time_s: float | None = None
        self.fatal = False
        #: The FMU says its instances may be freed after fmi2Fatal (:func:`frees_after_failure`)
        self.free_after_fatal = False
        #: The instance's run ended with fmi2Terminate returning OK: it may go to the pool (:mod:`.pool`)
        self._clean_end = False
        #: The instance came from the pool (fmi2Reset instead of fmi2Instantiate)
        self.reused = False
        #: Input modifiers (see :mod:`.exchange`): (input vector, index, value) written before every set.
        self.modifiers: list[tuple[np.ndarray, int, float]] = []
        #: Told, with its reason, when the FMU ends the simulation itself (:meth:`_step_refused`); the
        #: execution gives its own list's append. None: such an end fails the step
        self.on_end: Callable[[str], None] | None = None

    # -- life cycle -------------------------------------------------------------------------
    def instantiate(self) -> None:
        """Extract the FMU into its own folder, load it and call fmi2Instantiate."""
        md = self.model.model_description
        self._clean_end = self.reused = False
        self.log.messages.pop(self.name, None)  # what an earlier instance of this name said is not this one's
        try:
            self._unzip_dir = extracted(self.model.fmu_path)
            self.free_after_fatal = frees_after_failure(self._unzip_dir)
            self.fmu = self._from_pool(md.guid) if pool.enabled() else None
            if self.fmu is None:
                self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=self._unzip_dir,
                                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName=self.name)
                self.fmu.instantiate(callbacks=self.log.callbacks, loggingOn=True)
        except Exception as exc:
            raise SlaveError(self.name, "fmi2Instantiate", None, self._said(self.log.last(self.name) or str(exc))) \
                from None
        self._do_step_fn = self.fmu._functions["fmi2DoStep"]
        self._component = self.fmu.component
        self._forget_sent()

    def _from_pool(self, guid: str) -> FMU2Slave | None:
        """A pooled instance of this FMU and name, reset (fmi2Reset); None when there is none or its reset
        fails (that instance is then freed, and a new one is made)."""
        fmu = pool.take(pool.key(self.model.fmu_path, guid, self.name))
        if fmu is None:
            return None
        try:
            fmu.reset()
        except Exception:  # an FMU that cannot reset: freed, and the run instantiates a new one
            try:
                fmu.fmi2FreeInstance(fmu.component)
            except Exception:  # freeing is the last call to it
                pass
            return None
        self.reused = True
        return fmu

    def _guard(self, call: str, fn, *args: object) -> None:  # type: ignore[no-untyped-def]
        """Run an fmpy call; turn its exception into a SlaveError naming this component."""
        try:
            fn(*args)
        except Exception as exc:
            self.fatal = self.fatal or getattr(exc, "status", None) == 4
            raise SlaveError(self.name, call, self.time_s, self._said(self.log.last(self.name) or str(exc))) from None

    def _said(self, detail: str) -> str:
        """What the FMU said, with the folder it was extracted into (temporary) named as the FMU the user
        gave: ``/tmp/emss_fmu_x/resources/m.yaml`` as ``ssp/resources/Fcs.fmu!resources/m.yaml``."""
        if not self._unzip_dir or not detail:
            return detail
        folder = str(self._unzip_dir)
        fmu = self.model.shown_fmu or str(self.model.fmu_path)
        for f in dict.fromkeys((folder, os.path.realpath(folder))):
            detail = detail.replace(f.rstrip("/") + "/", f"{fmu}!")
        return detail

    def _forget_sent(self) -> None:
        """Send every input batch again at the next set (the FMU's inputs may no longer hold them)."""
        self._sent = [None] * len(self._inputs)

    def setup_experiment(self, start_time_s: float, stop_time_s: float | None) -> None:
        self.time_s = None
        self._forget_sent()
        self._guard("fmi2SetupExperiment", self.fmu.setupExperiment, None, start_time_s, stop_time_s)

    def enter_initialization_mode(self) -> None:
        self._forget_sent()
        self._guard("fmi2EnterInitializationMode", self.fmu.enterInitializationMode)

    def exit_initialization_mode(self) -> None:
        self._forget_sent()
        self._guard("fmi2ExitInitializationMode", self.fmu.exitInitializationMode)

    def set_value(self, var: VariableInfo, value: float | int | bool | str) -> None:
        """Set one variable (parameters and start values; not for the hot loop)."""
        self._forget_sent()
        fn = {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "Boolean": self.fmu.setBoolean,
              "String": self.fmu.setString}[var.type_name]
        self._guard(f"fmi2Set{var.type_name} of '{var.name}'", fn, [var.vr], [value])

    def get_value(self, var: VariableInfo) -> float | int | bool | str:
        """Get one variable (not for the hot loop)."""
        fn = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger, "Boolean": self.fmu.getBoolean,
              "String": self.fmu.getString}[var.type_name]
        out: list[object] = []
        self._guard(f"fmi2Get{var.type_name} of '{var.name}'", lambda: out.extend(fn([var.vr])))
        return out[0]  # type: ignore[return-value]

    def get_state(self, previous: object | None = None) -> object:
        """The FMU's state (fmi2GetFMUstate), written over ``previous`` when given (FMI 2.0 allows it)."""
        state = previous if previous is not None else fmi2FMUstate()
        self._guard("fmi2GetFMUstate", self.fmu.fmi2GetFMUstate, self.fmu.component, byref(state))
        return state

    def set_state(self, state: object) -> None:
        """Put the FMU back in a state from :meth:`get_state` (fmi2SetFMUstate); the state brings its
        own input values, so every input batch is sent again at the next set."""
        self._forget_sent()
        self._guard("fmi2SetFMUstate", self.fmu.fmi2SetFMUstate, self.fmu.component, state)

    def free_state(self, state: object) -> None:
        """Free a state from :meth:`get_state`; never raises (the instance may have failed)."""
        if self.fmu is not None and (not self.fatal or self.free_after_fatal):
            try:
                self.fmu.fmi2FreeFMUstate(self.fmu.component, byref(state))
            except Exception:  # a failed FMU may refuse; the state goes with the instance
                pass

    def terminate(self) -> None:
        self._guard("fmi2Terminate", self.fmu.terminate)
        self._clean_end = True

    def free(self) -> None:
        """Free the instance (or, with the pool enabled and the run ended cleanly, keep it there: :mod:`.pool`)
        and forget its extraction folder; never raises.

        The shared library stays loaded: a pythonfmu FMU runs in this interpreter, and
        unloading its library while Python still holds objects it created crashes the
        process at the next garbage collection. After a fatal status FMI 2.0 allows no
        further call at all, so such an instance is left alone, unless its FMU says it may be
        freed (ours do: :func:`frees_after_failure`); after any other failure it is freed.
        """
        if self.fmu is not None and self._clean_end and not self.fatal and pool.enabled():
            try:
                if pool.give(pool.key(self.model.fmu_path, self.model.model_description.guid, self.name), self.fmu):
                    self.fmu = None  # kept for the next run of this FMU: reset there, not instantiated
            except OSError:  # the FMU file is gone: nothing would take this instance again
                pass
        if self.fmu is not None:
            if not self.fatal or self.free_after_fatal:
                try:
                    self.fmu.fmi2FreeInstance(self.fmu.component)
                except Exception:  # a failed FMU may refuse to be freed; nothing more to do
                    pass
            self.fmu = None
        self._unzip_dir = None  # the extraction is shared and stays until the process ends

    # -- batched I/O ------------------------------------------------------------------------
    def bind_io(self, type_name: str, direction: str, variables: list[VariableInfo], buffer: np.ndarray) -> None:
        """Attach a slice of the execution's vector to a batched get or set of one type.

        ``buffer`` must be a contiguous numpy slice of dtype float64 (Real) or int32
        (Integer, Boolean) with one element per variable, in the order given.
        """
        if not variables:
            return
        n = len(variables)
        vrs = (c_uint * n)(*[v.vr for v in variables])
        io = IoBuffers(vrs, _array_view(_CTYPE[type_name], buffer), n)
        fname = f"fmi2{'Get' if direction == 'get' else 'Set'}{_FUNC_SUFFIX[type_name]}"
        # A function object of our own, without fmpy's argtypes: every argument is a ctypes
        # object built here once, so the per-call conversion fmpy declares (about 0.45 us per
        # call, measured in benchmarks/) is not needed.
        fn = self.fmu.dll[fname]
        fn.restype = c_int
        args = (c_void_p(self._component), io.vrs, c_size_t(n), io.values)
        entry = (fn, args, fname, io)
        (self._outputs if direction == "get" else self._inputs).append(entry)
        self._forget_sent()

    def _batch(self, entries: list[tuple[object, tuple[object, ...], str, IoBuffers]]) -> None:
        for fn, args, fname, _ in entries:
            status = fn(*args)  # type: ignore[operator]
            if status > 1:
                self._failed(fname, status)

    def _send(self) -> None:
        """The batched sets, each left out when its values are, byte for byte, those it sent last.

        An FMI 2.0 input keeps the value last set until the master sets it again, so a batch that
        has not changed need not be sent; through pythonfmu a call costs about
        3 us inside a mission (the C layer takes the GIL and builds Python lists), a comparison
        of the bytes about 0.2 us. Bytes, not numbers, are compared: a change from -0.0
        to 0.0 is sent, and a NaN that stays is not sent again every step.
        """
        sent = self._sent
        for k, (fn, args, fname, io) in enumerate(self._inputs):
            now = bytes(io.values)
            if now == sent[k]:
                self.stats.sets_skipped += 1
                continue
            status = fn(*args)  # type: ignore[operator]
            if status > 1:
                self._failed(fname, status)
            sent[k] = now

    def _modify(self) -> None:
        for vector, index, value in self.modifiers:
            vector[index] = value

    def set_inputs(self) -> None:
        """One fmi2Set<Type> per type, from the bound buffers, with the input modifiers applied first."""
        t0 = time.perf_counter()
        if self.modifiers:
            self._modify()
        self._send()
        self.stats.set_s += time.perf_counter() - t0

    def get_outputs(self) -> None:
        """One fmi2Get<Type> per type, into the bound buffers."""
        t0 = time.perf_counter()
        self._batch(self._outputs)
        self.stats.get_s += time.perf_counter() - t0

    def do_step(self, time_s: float, step_s: float) -> None:
        """fmi2DoStep from ``time_s`` [s] over ``step_s`` [s]."""
        self.time_s = time_s
        t0 = time.perf_counter()
        status = self._do_step_fn(self._component, time_s, step_s, 1)
        self.stats.do_step_s += time.perf_counter() - t0
        self.stats.steps += 1
        if status > 1:
            self._step_refused(status)

    def advance(self, time_s: float, step_s: float) -> None:
        """set_inputs, do_step and get_outputs in one call (what Gauss-Seidel does per component)."""
        stats = self.stats
        t0 = time.perf_counter()
        if self.modifiers:
            self._modify()
        self._send()
        t1 = time.perf_counter()
        self.time_s = time_s
        status = self._do_step_fn(self._component, time_s, step_s, 1)
        t2 = time.perf_counter()
        stats.steps += 1
        if status > 1:
            stats.set_s += t1 - t0
            stats.do_step_s += t2 - t1
            self._step_refused(status)
        self._batch(self._outputs)
        t3 = time.perf_counter()
        stats.set_s += t1 - t0
        stats.do_step_s += t2 - t1
        stats.get_s += t3 - t2

    def _step_refused(self, status: int) -> None:
        """fmi2DoStep did not return OK: the FMU's own end of the simulation, or a failure.

        FMI 2.0 (section 4.2.3): a step that returns ``fmi2Discard`` with ``fmi2GetBooleanStatus(fmi2Terminated)``
        true is the FMU asking to end the simulation (the Modelica Reference FMUs' Stair does so at its last
        count): the slave stays readable at ``fmi2LastSuccessfulTime`` and :attr:`on_end` is told, with the time
        and what the FMU logged, so that the run ends as completed. Any other status fails the step, and so
        does a discard whose last message the FMU logged as an error: pythonfmu's slaves discard a step that
        failed (``do_step`` returned False after logging why) and say terminated.
        """
        if (status == 2 and self.on_end is not None and self.log.last_status.get(self.name, 0) < 3
                and self._status(self.fmu.dll.fmi2GetBooleanStatus, c_int, _FMI2_TERMINATED)):
            end_s = self._status(self.fmu.dll.fmi2GetRealStatus, c_double, _FMI2_LAST_SUCCESSFUL_TIME)
            said = self._said(self.log.last(self.name))
            at = f" at t = {end_s:.6g} s" if isinstance(end_s, float) else ""
            self.on_end(f"{self.name} ended the simulation{at} (fmi2Terminated)" + (f": {said}" if said else ""))
            return
        self._failed("fmi2DoStep", status)

    def _status(self, fn: object, ctype: type, kind: int) -> object | None:
        """An fmi2Get<Type>Status value, or None when the FMU does not give it."""
        value = ctype()
        try:
            ok = fn(c_void_p(self._component), c_int(kind), byref(value)) == 0  # type: ignore[operator]
        except (AttributeError, OSError):
            return None
        return value.value if ok else None

    def _failed(self, call: str, status: int | None = None) -> None:
        self.fatal = self.fatal or status == 4
        label = f" (status {_STATUS[status]})" if status is not None and 0 <= status < len(_STATUS) else ""
        raise SlaveError(self.name, call + label, self.time_s, self._said(self.log.last(self.name)))

