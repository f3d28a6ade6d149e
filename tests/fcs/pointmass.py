"""Point-mass longitudinal aircraft with pitch dynamics, for closed-loop tests of the FCS.

UPERA-class numbers from the brief: mass 2000 kg, wing 11.2 m^2, CL_alpha 5 /rad,
CD0 0.025, k 0.06, thrust up to 13 kN at sea level (lapse (rho/rho0)^0.7), engine
thrust lag 1 s. Pitch: Iyy 2800 kg m^2, chord 1.9 m, Cm_alpha -0.6, Cm_q -15,
Cm_de -1.2 /rad with +-0.35 rad surface travel (elevator > 0 nose down).
Equations (flat Earth, no wind, thrust along the body axis):

    Vdot     = (T cos a - D) / m - g sin gamma
    gammadot = (L + T sin a) / (m V) - g cos gamma / V
    hdot = V sin gamma,  xdot = V cos gamma,  thetadot = q,
    qdot = qbar S c Cm / Iyy,  a = theta - gamma.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from openemss.models.fcs.atmosphere import isa

G = 9.80665
M_KG = 2000.0
S_M2 = 11.2
C_M = 1.9
IYY = 2800.0
CL0, CLA = 0.1, 5.0
CD0, K_IND = 0.025, 0.06
CM0, CMA, CMQ, CMDE = 0.02, -0.6, -15.0, -1.2
DE_MAX_RAD = 0.35
T_SLS_N = 13000.0
TAU_ENGINE_S = 1.0


@dataclass
class PointMass:
    V: float
    gamma: float
    h: float
    theta: float
    q: float = 0.0
    x: float = 0.0
    T: float = 0.0
    mass: float = M_KG

    def t_avail(self) -> float:
        return T_SLS_N * (isa(self.h).rho_kg_m3 / 1.225) ** 0.7

    def deriv(self, s: np.ndarray, elevator: float, T_cmd: float,
              drag_extra_N: float = 0.0) -> tuple[np.ndarray, float]:
        V, gam, h, th, q, x, T = s
        rho = isa(h).rho_kg_m3
        qbar = 0.5 * rho * V * V
        a = th - gam
        CL = CL0 + CLA * a
        L = qbar * S_M2 * CL
        D = qbar * S_M2 * (CD0 + K_IND * CL * CL) + drag_extra_N
        de = max(-1.0, min(1.0, elevator)) * DE_MAX_RAD
        Cm = CM0 + CMA * a + CMQ * q * C_M / (2 * V) + CMDE * de
        Vd = (T * math.cos(a) - D) / self.mass - G * math.sin(gam)
        return np.array([Vd, (L + T * math.sin(a)) / (self.mass * V) - G * math.cos(gam) / V,
                         V * math.sin(gam), q, qbar * S_M2 * C_M * Cm / IYY, V * math.cos(gam),
                         (T_cmd - T) / TAU_ENGINE_S]), Vd

    def state(self) -> np.ndarray:
        return np.array([self.V, self.gamma, self.h, self.theta, self.q, self.x, self.T])

    def set(self, s: np.ndarray) -> None:
        self.V, self.gamma, self.h, self.theta, self.q, self.x, self.T = (float(v) for v in s)

    def Vdot(self, elevator: float, T_cmd: float, drag_extra_N: float = 0.0) -> float:
        return self.deriv(self.state(), elevator, T_cmd, drag_extra_N)[1]

    def qbar(self) -> float:
        return 0.5 * isa(self.h).rho_kg_m3 * self.V**2

    def step(self, dt: float, elevator: float, T_cmd: float, drag_extra_N: float = 0.0) -> None:
        """Classical RK4 with the commands held (``drag_extra_N``: an airbrake's drag, at once)."""
        s = self.state()
        k1 = self.deriv(s, elevator, T_cmd, drag_extra_N)[0]
        k2 = self.deriv(s + 0.5 * dt * k1, elevator, T_cmd, drag_extra_N)[0]
        k3 = self.deriv(s + 0.5 * dt * k2, elevator, T_cmd, drag_extra_N)[0]
        k4 = self.deriv(s + dt * k3, elevator, T_cmd, drag_extra_N)[0]
        self.set(s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))


def drag_N(V: float, h: float, gamma: float = 0.0, mass: float = M_KG) -> float:
    """Drag in steady straight flight at flight-path angle gamma (lift W cos gamma, thrust along the path) [N]."""
    qbar = 0.5 * isa(h).rho_kg_m3 * V * V
    CL = mass * G * math.cos(gamma) / (qbar * S_M2)
    return qbar * S_M2 * (CD0 + K_IND * CL * CL)


def trimmed(V: float, h: float) -> tuple[PointMass, float]:
    """Level flight trim: returns the aircraft and the trim elevator [-]."""
    rho = isa(h).rho_kg_m3
    qbar = 0.5 * rho * V * V
    T = 0.0
    a = 0.0
    for _ in range(50):
        CL = (M_KG * G - T * math.sin(a)) / (qbar * S_M2)
        a = (CL - CL0) / CLA
        T = qbar * S_M2 * (CD0 + K_IND * CL * CL) / math.cos(a)
    de = -(CM0 + CMA * a) / CMDE
    return PointMass(V, 0.0, h, a, T=T), de / DE_MAX_RAD
