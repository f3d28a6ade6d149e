"""Mass 1 of the two-mass oscillator: tied to the wall by a spring and a damper,
driven by the coupling force [N]; outputs its displacement [m] and velocity [m/s]."""
from __future__ import annotations

from linear_step import ExactLinearStep
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real

REQUIREMENTS = ["numpy>=1.24", "scipy>=1.10"]


class ForceDrivenMass(Fmi2Slave):
    """Force in, displacement and velocity out."""

    description = "Mass-spring-damper tied to the wall, driven by a coupling force"
    author = "openEMSS"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.m1_kg = 1.0
        self.k1_N_m = 10.0
        self.d1_N_s_m = 0.1
        self.x1_start_m = 1.0
        self.v1_start_m_s = 0.0
        self.f_c_N = 0.0
        self._x_m: float | None = None  # state, None until initialization ends
        self._v_m_s = 0.0
        self._stepper: ExactLinearStep | None = None
        for name, desc in (
            ("m1_kg", "Mass [kg]"),
            ("k1_N_m", "Wall spring stiffness [N/m]"),
            ("d1_N_s_m", "Wall damper coefficient [N.s/m]"),
            ("x1_start_m", "Initial displacement [m]"),
            ("v1_start_m_s", "Initial velocity [m/s]"),
        ):
            self.register_variable(
                Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable,
                     description=desc)
            )
        self.register_variable(Real("f_c_N", causality=Fmi2Causality.input,
                                    description="Coupling force on the mass [N]"))
        # Before initialization ends the outputs follow the start parameters, so a
        # master reading outputs in initialization mode sees the initial state.
        self.register_variable(Real("x1_m", causality=Fmi2Causality.output, description="Displacement [m]",
                                    getter=lambda: self.x1_start_m if self._x_m is None else self._x_m))
        self.register_variable(Real("v1_m_s", causality=Fmi2Causality.output, description="Velocity [m/s]",
                                    getter=lambda: self.v1_start_m_s if self._x_m is None else self._v_m_s))

    def exit_initialization_mode(self) -> None:
        self._x_m = self.x1_start_m
        self._v_m_s = self.v1_start_m_s
        self._stepper = ExactLinearStep(self.m1_kg, self.k1_N_m, self.d1_N_s_m)

    def do_step(self, current_time: float, step_size: float) -> bool:
        self._x_m, self._v_m_s = self._stepper.step(self._x_m, self._v_m_s, self.f_c_N, step_size)
        return True
