"""Test FMU: reports what the master set before and during initialization.

An input with a non-zero start value and a parameter: the outputs tell which
values the FMU had when it left initialization mode, and what the input held at
the first doStep, so a test can prove that start values and parameter bindings
reached it (fmpy's SSP runner overwrites inputs with 0.0 and ignores bindings).
"""
from __future__ import annotations

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class StartProbe(Fmi2Slave):
    """Echoes its input and parameters as seen at initialization and at the first step."""

    description = "Probe of start values and parameters"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.u_in = 3.5
        self.gain = 1.0
        self.count = 7
        self.u_at_init = -1.0
        self.u_at_first_step = -1.0
        self.gain_at_init = -1.0
        self.count_at_init = -1
        self._stepped = False
        self.register_variable(Real("u_in", causality=Fmi2Causality.input, description="Input, start 3.5 [-]"))
        self.register_variable(Real("gain", causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                                    description="Parameter, start 1.0 [-]"))
        self.register_variable(Integer("count", causality=Fmi2Causality.parameter,
                                       variability=Fmi2Variability.fixed, description="Parameter, start 7 [-]"))
        for name in ("u_at_init", "u_at_first_step", "gain_at_init"):
            self.register_variable(Real(name, causality=Fmi2Causality.output, description=f"{name} [-]"))
        self.register_variable(Integer("count_at_init", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete,
                                       description="count at initialization [-]"))

    def exit_initialization_mode(self) -> None:
        self.u_at_init = self.u_in
        self.gain_at_init = self.gain
        self.count_at_init = self.count

    def do_step(self, current_time: float, step_size: float) -> bool:
        if not self._stepped:
            self.u_at_first_step = self.u_in
            self._stepped = True
        return True
