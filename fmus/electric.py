"""Electrical power system FMU: HP starter-generator, LP motor-generator, battery pack, DC bus, energy management.

A thin pythonfmu slave over :class:`openemss.models.electric.system.ElectricSystem`. Inputs: the spool
speeds (the engine's ``N1_rpm``, ``N2_rpm``), the thrust lever (the flight control's ``lever_norm``),
``vs_m_s`` and ``on_ground`` (the airframe's) and ``pulse_load_W`` (an event-driven pulse load, set by a scenario).
Outputs: the signed shaft powers ``offtake_hp_W`` and ``offtake_lp_W`` under the engine FMU's input names
(> 0 taken from the spool, < 0 delivered to it), the bus, battery and ledger figures, the limit flags,
``ems_mode`` and ``added_mass_kg`` (the system's mass, fed to the airframe's input of that name).

Parameters: every entry of ``openemss.models.electric``'s ``data/electric.yaml`` under its dotted name
(``ems.boost_W``, ``battery.n_parallel``, ...), tunable during the run; the battery's layout and initial
state of charge take effect at initialisation.

Each ``doStep(t, h)`` holds the inputs sampled at ``t`` over the step (zero-order hold) and outputs the
powers of that step, so the engine flies the offtake the energy ledger counts.
"""
from __future__ import annotations

import math

from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from openemss.fmus.fmu_state import FmuState
from openemss.fmus.initial_outputs import InitialOutputs
from openemss.fmus.signal_io import SignalIO
from openemss.models.electric.electric_signals import PARAMETERS, SIGNALS
from openemss.models.electric.errors import ElectricError
from openemss.models.electric.system import INPUTS, ElectricSystem

REQUIREMENTS = ["pyyaml>=6.0"]
_INPUT_NAMES = tuple(name for name, _, _ in INPUTS)


class Electric(FmuState, InitialOutputs, SignalIO, Fmi2Slave):
    """Hybrid-electric power system on the two spools of a turbofan."""

    author = "openEMSS"
    description = ("Electrical power system: spool speeds [rpm], lever and pulse load [W] in; signed shaft "
                   "offtakes [W], battery state and energy ledger out")
    START_INPUTS = ()  # the start (battery layout, state of charge) reads parameters only

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        self._sys = ElectricSystem()
        for row in PARAMETERS:  # held by the model (validated there), not as attributes of the slave
            self.register_signal(row, getter=lambda n=row.name: self._sys.get_parameter(n),
                                 setter=lambda x, n=row.name: self._set(n, x), nested=False)
        self.register_signals(SIGNALS)
        self._outputs()

    def _outputs(self) -> None:
        self._y, self._yb, self._yi = self._sys.values, self._sys.flags, (self._sys.mode,)

    def _set(self, name: str, value: float | int | bool) -> None:
        try:
            self._sys.set_parameter(name, value)
        except ElectricError as exc:
            self.log(str(exc), Fmi2Status.error, "logStatusError")
            raise

    def compute_start(self) -> None:
        self._sys.reset()
        self._outputs()

    def do_step(self, current_time: float, step_size: float) -> bool:
        """One step; inputs that are not finite fail it with the cause logged."""
        u = {name: float(getattr(self, name)) for name in _INPUT_NAMES}
        bad = [f"{name}={v}" for name, v in u.items() if not math.isfinite(v)]
        if bad:
            self.log(f"electric: t={current_time:.6g} s: input(s) not finite: {', '.join(bad)}",
                     Fmi2Status.error, "logStatusError")
            return False
        self._sys.step(current_time, step_size, u["N1_rpm"], u["N2_rpm"], u["lever_norm"], bool(self.on_ground),
                       u["vs_m_s"], u["pulse_load_W"])
        self._outputs()
        return True
