"""Test FMU: y = k*u for one variable of each exchanged type (Real, Integer, Boolean).

Trivial on purpose: the orchestrator benchmark uses it to measure the master's
own overhead per FMU-step, and the tests use it for typed connections and
algebraic loops in initialization (y depends directly on u).
"""
from __future__ import annotations

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class Gain(Fmi2Slave):
    """Real, Integer and Boolean pass-through with a gain on the Real."""

    description = "y_real = k * u_real, y_int = u_int + 1, y_bool = not u_bool"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.k = 1.0
        self.u_real = 0.0
        self.u_int = 0
        self.u_bool = False
        self.register_variable(Real("k", causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable,
                                    description="Gain [-]"))
        self.register_variable(Real("u_real", causality=Fmi2Causality.input, description="Input [-]"))
        discrete = Fmi2Variability.discrete
        self.register_variable(Integer("u_int", causality=Fmi2Causality.input, variability=discrete,
                                       description="Input [-]"))
        self.register_variable(Boolean("u_bool", causality=Fmi2Causality.input, variability=discrete,
                                       description="Input [-]"))
        self.register_variable(Real("y_real", causality=Fmi2Causality.output, description="k * u_real [-]",
                                    getter=lambda: self.k * self.u_real))
        self.register_variable(Integer("y_int", causality=Fmi2Causality.output, variability=discrete,
                                       description="u_int + 1 [-]",
                                       getter=lambda: self.u_int + 1))
        self.register_variable(Boolean("y_bool", causality=Fmi2Causality.output, variability=discrete,
                                       description="not u_bool [-]",
                                       getter=lambda: not self.u_bool))

    def do_step(self, current_time: float, step_size: float) -> bool:
        return True
