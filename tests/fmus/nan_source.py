"""Test FMU: an output that is NaN until the first step (a "no target yet" value), and an input."""
from __future__ import annotations

import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Real


class NanSource(Fmi2Slave):
    """target = NaN before the first step, then 1.0 [-]; echo = u [-]."""

    description = "NaN before the first step"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.u = 0.0
        self._stepped = False
        self.register_variable(Real("u", causality=Fmi2Causality.input, description="Input [-]"))
        self.register_variable(Real("target", causality=Fmi2Causality.output, description="Target [-]",
                                    getter=lambda: 1.0 if self._stepped else math.nan))
        self.register_variable(Real("echo", causality=Fmi2Causality.output, description="Echo of u [-]",
                                    getter=lambda: self.u))

    def do_step(self, current_time: float, step_size: float) -> bool:
        self._stepped = True
        return True
