"""Initial outputs that are valid in Initialization Mode, for any master's initial exchange.

FMI 2.0 (sections 2.1.6 and 4.2.4: the calls allowed in Initialization Mode) lets a master read a
slave's outputs in Initialization Mode, computed from the parameters and inputs set so far: that is
how a master solves the initial exchange of coupled slaves. pythonfmu offers only
``exit_initialization_mode`` to compute a start, so a slave that computes its initial state there
shows placeholder outputs (zeros) throughout Initialization Mode. A master that exchanges once
before leaving Initialization Mode and not again before the first step (fmpy's container runtime,
``fmpy/native/container-fmu``: ``updateConnections`` then ``exitInitializationMode``) then steps every
component on those placeholders: the flight control saw an aircraft of mass 0 and held its
commands, the airframe rolled without thrust, and the whole take-off came one step late (1.48 m
lower at 30 s). An iterative master (ours) read the same placeholders while it settled, so the
engine's steady start was computed at the placeholder flight condition (sea level) instead of the
airframe's (the runway's elevation).

:class:`InitialOutputs` (mixed in before :class:`openemss.fmus.signal_io.SignalIO`) computes the
slave's start (its :meth:`InitialOutputs.compute_start`) when an output is read in Initialization
Mode and something it depends on was set since the last computation (a parameter, or an input its
``START_INPUTS`` names; by default every input), and again when Initialization Mode ends if that
happened after it. A value set equal to the one held does not count, so an iterating master that has
settled causes no recomputation. The checks are instance attributes installed on entering
Initialization Mode and removed on leaving it: the per-step calls of a run go straight to
SignalIO's batched methods, with no check in between.

A start that fails while an output is read keeps the placeholders and is computed again when
Initialization Mode ends, where its error is reported as before (nothing is flown on the
placeholders: the slave does not leave Initialization Mode).
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pythonfmu import Fmi2Causality

_KINDS = ("real", "integer", "boolean", "string")


class InitialOutputs:
    """Mix-in of a SignalIO slave: the start computed in Initialization Mode when an output is read.

    The slave defines :meth:`compute_start`, which builds its model from the current parameters
    and inputs and publishes the initial outputs (it may be called more than once before the
    first step; each call replaces what the previous one built).
    """

    #: Names of the inputs the start reads (None: every input); a parameter always counts.
    START_INPUTS: tuple[str, ...] | None = None
    _out_vr: dict[int, Any]  # SignalIO's output value references
    vars: dict[int, Any]  # pythonfmu's variables by value reference

    def compute_start(self) -> None:
        """Build the initial state from the parameters and inputs set so far; publish the outputs."""
        raise NotImplementedError(f"{type(self).__name__} does not define compute_start")

    def enter_initialization_mode(self) -> None:
        super().enter_initialization_mode()  # type: ignore[misc]
        self._start_stale = True
        read = self.START_INPUTS
        self._start_vrs = frozenset(vr for vr, v in self.vars.items() if v.causality == Fmi2Causality.parameter
                                    or v.causality == Fmi2Causality.input and (read is None or v.name in read))
        # build-fmus sets ``fmi_guard`` on the slave class: what a function set on the instance for pythonfmu's C
        # layer must be wrapped in (orchestrator/fmu/lifecycle.py); absent when the slave runs outside an FMU
        guard = getattr(type(self), "fmi_guard", None) or (lambda fn, slave: fn)
        for kind in _KINDS:
            self.__dict__[f"get_{kind}"] = guard(self._checked_get(getattr(type(self), f"get_{kind}")), self)
            self.__dict__[f"set_{kind}"] = guard(self._checked_set(getattr(type(self), f"get_{kind}"),
                                                                   getattr(type(self), f"set_{kind}")), self)

    def exit_initialization_mode(self) -> None:
        super().exit_initialization_mode()  # type: ignore[misc]
        for kind in _KINDS:
            self.__dict__.pop(f"get_{kind}", None)
            self.__dict__.pop(f"set_{kind}", None)
        if getattr(self, "_start_stale", True):  # also when a master skipped enterInitializationMode
            self.compute_start()
        self._start_stale = False

    def _checked_get(self, get: Callable[[Any, list[int]], list[Any]]) -> Callable[[list[int]], list[Any]]:
        outputs = self._out_vr

        def checked(vrs: list[int]) -> list[Any]:
            if self._start_stale and any(vr in outputs for vr in vrs):
                try:
                    self.compute_start()
                    self._start_stale = False
                except Exception:  # noqa: BLE001 -- computed again, and its error reported, on leaving
                    pass
            return get(self, vrs)
        return checked

    def _checked_set(self, get: Callable[[Any, list[int]], list[Any]],
                     put: Callable[[Any, list[int], list[Any]], None]) -> Callable[[list[int], list[Any]], None]:
        read = self._start_vrs

        def checked(vrs: list[int], values: list[Any]) -> None:
            if self._start_stale:
                put(self, vrs, values)
                return
            mine = [(vr, x) for vr, x in zip(vrs, values, strict=True) if vr in read]
            held = get(self, [vr for vr, _ in mine]) if mine else []
            put(self, vrs, values)
            self._start_stale = held != [x for _, x in mine]
        return checked
