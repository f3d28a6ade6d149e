"""Electrical power system FMU: HP starter-generator, LP motor-generator, battery pack, DC bus, energy management.

A thin pythonfmu slave over :class:`openemss.models.electric.system.ElectricSystem`. Inputs: the spool
speeds (the engine's ``N1_rpm``, ``N2_rpm``), the thrust lever (the flight control's ``lever_norm``),
``vs_m_s`` and ``on_ground`` (the airframe's) and ``pulse_load_W`` (an event-driven pulse load, set by a scenario).
Outputs: the signed shaft powers ``offtake_hp_W`` and ``offtake_lp_W`` under the engine FMU's input names
(> 0 taken from the spool, < 0 delivered to it), the bus, battery and ledger figures, the limit flags,
``ems_mode`` and ``mass_kg`` (the airframe's ``added_mass_kg``).

Parameters: every entry of ``openemss.models.electric``'s ``data/electric.yaml`` under its dotted name
(``ems.boost_W``, ``battery.n_parallel``, ...), tunable during the run; the battery's layout and initial
state of charge take effect at initialisation.

Each ``doStep(t, h)`` holds the inputs sampled at ``t`` over the step (zero-order hold) and outputs the
powers of that step, so the engine flies the offtake the energy ledger counts.
"""
from __future__ import annotations

import math

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Status

from openemss.models.electric.errors import ElectricError
from openemss.models.electric.params import entries
from openemss.models.electric.system import FLAGS, INPUTS, OUTPUTS, ElectricSystem

REQUIREMENTS = ["pyyaml>=6.0"]


def _desc(text: str, unit: str) -> str:
    return f"{text} [{unit}]"


class Electric(Fmi2Slave):
    """Hybrid-electric power system on the two spools of a turbofan."""

    author = "openEMSS"
    description = ("Electrical power system: spool speeds [rpm], lever and pulse load [W] in; signed shaft "
                   "offtakes [W], battery state and energy ledger out")

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        tunable, discrete = Fmi2Variability.tunable, Fmi2Variability.discrete
        par, inp, out = Fmi2Causality.parameter, Fmi2Causality.input, Fmi2Causality.output
        self._sys = ElectricSystem()
        for e in entries():
            rng = f"; {e.lo:g} to {e.hi:g}" if math.isfinite(e.lo) or math.isfinite(e.hi) else ""
            desc = _desc(f"{e.note}{rng} (data/electric.yaml)", "-" if e.unit in ("1", "") else e.unit)
            kind = Boolean if isinstance(e.value, bool) else Integer if isinstance(e.value, int) else Real
            self.register_variable(kind(e.name, causality=par, variability=tunable, description=desc,
                                        getter=lambda n=e.name: self._sys.get_parameter(n),
                                        setter=lambda x, n=e.name: self._set(n, x)), nested=False)
        self._u = [0.0] * len(INPUTS)
        for j, (name, unit, text) in enumerate(INPUTS):
            self.register_variable(Real(name, causality=inp, description=_desc(text, unit),
                                        getter=lambda j=j: self._u[j],
                                        setter=lambda x, j=j: self._u.__setitem__(j, float(x))))
        self.on_ground = True
        self.register_variable(Boolean("on_ground", causality=inp, variability=discrete,
                                       description="A wheel carries weight [-]"))
        self._out0 = len(self.vars)
        for i, (name, unit, text) in enumerate(OUTPUTS):
            self.register_variable(Real(name, causality=out, description=_desc(text, unit),
                                        getter=lambda i=i: self._sys.values[i]))
        for i, (name, text) in enumerate(FLAGS):
            self.register_variable(Boolean(name, causality=out, variability=discrete, description=f"{text} [-]",
                                           getter=lambda i=i: self._sys.flags[i]))
        self.register_variable(Integer("ems_mode", causality=out, variability=discrete,
                                       description="Energy management mode: 0 generate, 1 boost, 2 charge, "
                                                   "3 pulse [-]", getter=lambda: self._sys.mode))

    def _set(self, name: str, value: float | int | bool) -> None:
        try:
            self._sys.set_parameter(name, value)
        except ElectricError as exc:
            self.log(str(exc), Fmi2Status.error, "logStatusError")
            raise

    def get_real(self, vrs: list[int]) -> list[float]:
        """The outputs straight from the model's list; pythonfmu's own calls one getter per variable."""
        vals, base, n = self._sys.values, self._out0, len(OUTPUTS)
        return [vals[vr - base] if 0 <= vr - base < n else Fmi2Slave.get_real(self, [vr])[0] for vr in vrs]

    def exit_initialization_mode(self) -> None:
        self._sys.reset()

    def do_step(self, current_time: float, step_size: float) -> bool:
        """One step; inputs that are not finite fail it with the cause logged."""
        bad = [f"{name}={self._u[j]}" for j, (name, _, _) in enumerate(INPUTS) if not math.isfinite(self._u[j])]
        if bad:
            self.log(f"electric: t={current_time:.6g} s: input(s) not finite: {', '.join(bad)}",
                     Fmi2Status.error, "logStatusError")
            return False
        n1, n2, lever, vs, pulse = self._u
        self._sys.step(current_time, step_size, n1, n2, lever, bool(self.on_ground), vs, pulse)
        return True
