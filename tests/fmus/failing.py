"""Test FMU: integrates time and raises a Python exception once t >= fail_time_s."""
from __future__ import annotations

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class FailingClock(Fmi2Slave):
    """Outputs the time it has integrated [s]; fails in doStep at fail_time_s [s]."""

    description = "A clock that raises at a given time"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.fail_time_s = 3.0
        self.clock_s = 0.0
        self.register_variable(Real("fail_time_s", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable, description="Time of failure [s]"))
        self.register_variable(Real("clock_s", causality=Fmi2Causality.output, description="Integrated time [s]"))

    def do_step(self, current_time: float, step_size: float) -> bool:
        if current_time >= self.fail_time_s - 1e-9:
            raise RuntimeError(f"deliberate failure of the test FMU at t = {current_time:g} s")
        self.clock_s += step_size
        return True
