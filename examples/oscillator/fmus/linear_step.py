"""Exact step of a linear mass-spring-damper under a constant force (shared by both oscillator FMUs)."""
from __future__ import annotations

import numpy as np
from scipy.linalg import expm


class ExactLinearStep:
    """Advance ``m x'' + d x' + k x = f`` exactly over a step with ``f`` held constant.

    The state ``(x [m], v [m/s], f [N])`` is propagated with the matrix exponential of
    the augmented system, so the only error left in a co-simulation of these FMUs is
    the coupling error of the master algorithm.
    """

    def __init__(self, mass_kg: float, stiffness_N_m: float, damping_N_s_m: float) -> None:
        self._a = np.array(
            [
                [0.0, 1.0, 0.0],
                [-stiffness_N_m / mass_kg, -damping_N_s_m / mass_kg, 1.0 / mass_kg],
                [0.0, 0.0, 0.0],
            ]
        )
        self._cache: dict[float, np.ndarray] = {}

    def step(self, x_m: float, v_m_s: float, force_N: float, dt_s: float) -> tuple[float, float]:
        """Return ``(x [m], v [m/s])`` after ``dt_s`` [s]."""
        key = round(dt_s, 12)  # steps t[k+1] - t[k] differ in the last bits; one matrix per step size
        phi = self._cache.get(key)
        if phi is None:
            phi = expm(self._a * dt_s)
            self._cache[key] = phi
        x_new = phi[0, 0] * x_m + phi[0, 1] * v_m_s + phi[0, 2] * force_N
        v_new = phi[1, 0] * x_m + phi[1, 1] * v_m_s + phi[1, 2] * force_N
        return float(x_new), float(v_new)
