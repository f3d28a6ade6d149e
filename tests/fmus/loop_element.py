"""Test FMU: ``y = k*u + c + x`` with ``dx/dt = g*u`` (exact for an input held over the step).

With ``g = 0`` it is a static affine element; two of them in a ring are an algebraic loop with the
fixed point ``u1 = (k2*c1 + c2) / (1 - k1*k2)``. With ``g != 0`` one of them integrates, and the
ring is a dynamic loop with direct feedthrough. Its state (``x``) is a registered variable, so a
build with ``canGetAndSetFMUstate`` (tests/test_iterative.py) can save and restore it.
"""
from __future__ import annotations

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class LoopElement(Fmi2Slave):
    """An affine element with an integrator: the building block of the coupled-loop tests."""

    description = "y = k*u + c + x, dx/dt = g*u"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.k = 0.5
        self.c = 0.0
        self.g = 0.0
        self.u = 0.0
        self.x = 0.0
        tunable = Fmi2Variability.tunable
        self.register_variable(Real("k", causality=Fmi2Causality.parameter, variability=tunable,
                                    description="Feedthrough gain [-]"))
        self.register_variable(Real("c", causality=Fmi2Causality.parameter, variability=tunable,
                                    description="Offset [-]"))
        self.register_variable(Real("g", causality=Fmi2Causality.parameter, variability=tunable,
                                    description="Integrator gain [1/s]"))
        self.register_variable(Real("u", causality=Fmi2Causality.input, description="Input [-]"))
        self.register_variable(Real("x", causality=Fmi2Causality.output, description="Integrator state [-]"))
        self.register_variable(Real("y", causality=Fmi2Causality.output, description="k*u + c + x [-]",
                                    getter=lambda: self.k * self.u + self.c + self.x))

    def do_step(self, current_time: float, step_size: float) -> bool:
        self.x += self.g * self.u * step_size
        return True
