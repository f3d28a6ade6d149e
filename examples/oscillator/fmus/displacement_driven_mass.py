"""Mass 2 of the two-mass oscillator with the coupling spring and damper: driven by
the displacement [m] and velocity [m/s] of mass 1; outputs the coupling force [N]
that acts on mass 1."""
from __future__ import annotations

from linear_step import ExactLinearStep
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real

REQUIREMENTS = ["numpy>=1.24", "scipy>=1.10"]


class DisplacementDrivenMass(Fmi2Slave):
    """Displacement and velocity in, coupling force out."""

    description = "Mass-spring-damper tied to the wall and, through a coupling spring, to mass 1"
    author = "openEMSS"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.m2_kg = 1.0
        self.k2_N_m = 10.0
        self.d2_N_s_m = 0.1
        self.kc_N_m = 100.0
        self.dc_N_s_m = 1.0
        self.x2_start_m = 0.0
        self.v2_start_m_s = 0.0
        self.x1_m = 0.0
        self.v1_m_s = 0.0
        self._x_m: float | None = None  # state, None until initialization ends
        self._v_m_s = 0.0
        self._stepper: ExactLinearStep | None = None
        for name, desc in (
            ("m2_kg", "Mass [kg]"),
            ("k2_N_m", "Wall spring stiffness [N/m]"),
            ("d2_N_s_m", "Wall damper coefficient [N.s/m]"),
            ("kc_N_m", "Coupling spring stiffness [N/m]"),
            ("dc_N_s_m", "Coupling damper coefficient [N.s/m]"),
            ("x2_start_m", "Initial displacement [m]"),
            ("v2_start_m_s", "Initial velocity [m/s]"),
        ):
            self.register_variable(
                Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable,
                     description=desc)
            )
        self.register_variable(Real("x1_m", causality=Fmi2Causality.input, description="Displacement of mass 1 [m]"))
        self.register_variable(Real("v1_m_s", causality=Fmi2Causality.input, description="Velocity of mass 1 [m/s]"))
        self.register_variable(Real("x2_m", causality=Fmi2Causality.output, description="Displacement [m]",
                                    getter=lambda: self._position()))
        self.register_variable(Real("f_c_N", causality=Fmi2Causality.output,
                                    description="Coupling force acting on mass 1 [N]", getter=self._coupling_force))

    def _position(self) -> float:
        return self.x2_start_m if self._x_m is None else self._x_m

    def _coupling_force(self) -> float:
        """Force of the coupling spring and damper on mass 1 [N] (direct feedthrough of x1, v1)."""
        v2 = self.v2_start_m_s if self._x_m is None else self._v_m_s
        return self.kc_N_m * (self._position() - self.x1_m) + self.dc_N_s_m * (v2 - self.v1_m_s)

    def exit_initialization_mode(self) -> None:
        self._x_m = self.x2_start_m
        self._v_m_s = self.v2_start_m_s
        # With x1 and v1 held over a step, mass 2 sees stiffness k2 + kc, damping d2 + dc
        # and a constant force kc*x1 + dc*v1.
        self._stepper = ExactLinearStep(self.m2_kg, self.k2_N_m + self.kc_N_m, self.d2_N_s_m + self.dc_N_s_m)

    def do_step(self, current_time: float, step_size: float) -> bool:
        force = self.kc_N_m * self.x1_m + self.dc_N_s_m * self.v1_m_s
        self._x_m, self._v_m_s = self._stepper.step(self._x_m, self._v_m_s, force, step_size)
        return True
