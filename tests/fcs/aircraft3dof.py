"""A 3-DoF point-mass aircraft with bank, pitch and roll dynamics, ground roll and a
first-order engine, to fly whole missions through the FlightControlSystem in tests.

Longitudinal as pointmass.py (2000 kg, 11.2 m^2, CL_alpha 5, CD0 0.025, k 0.06), with
the lift vector banked:

    Vdot     = (T cos a - D - F_ground) / m - g sin gamma
    gammadot = (L + T sin a) cos(phi) / (m V) - g cos(gamma) / V
    psidot   = (L + T sin a) sin(phi) / (m V cos gamma),   a = (theta - gamma) / cos(phi)

roll: pdot = -p / 0.3 s + 6 rad/s^2 aileron (qbar/1e4 Pa), phidot = p; pitch: as
pointmass.py. Ground: below the runway elevation the aircraft rolls (gamma = 0), the
wheels take W - L, rolling friction 0.02, brakes 0.4 g at full, a 3 m wheelbase bicycle
model steers (17 deg at full), the heading is tied to the ground track. Engine:
corrected fan speed N1c [%] follows 400 Wf / (delta sqrt(theta)) with 1 s lag, thrust
13 kN (rho/rho0)^0.7 (N1c/100)^2, Tt41 = 700 K + 7 K/% N1c, N1 = N1c sqrt(theta).
Airbrake: drag increment 0.028 x position, the position following ``airbrake_cmd`` at 1/1.5 s.
No wind unless given (constant, north/east [m/s]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.state import AircraftState, EngineState
from openemss.models.mission.geo import LatLon, destination, final_bearing_rad, initial_bearing_rad

G = 9.80665
S, CBAR, IYY = 11.2, 1.9, 2800.0
CL0, CLA, CD0, K_IND, CL_MAX = 0.1, 5.0, 0.025, 0.06, 1.4
CM0, CMA, CMQ, CMDE, DE_MAX = 0.02, -0.6, -15.0, -1.2, 0.35
TAU_ROLL, L_DA = 0.3, 6.0
MU_ROLL, BRAKE_G, WHEELBASE, STEER_MAX = 0.02, 0.4, 3.0, 0.3
CD_AIRBRAKE, AIRBRAKE_RATE = 0.028, 1.0 / 1.5  # airbrake: drag increment fully out [-], travel rate [1/s]


@dataclass
class Aircraft3Dof:
    pos: LatLon
    h: float
    V: float
    psi: float
    elev_ground: float
    gamma: float = 0.0
    theta: float = 0.0
    q: float = 0.0
    phi: float = 0.0
    p: float = 0.0
    mass: float = 2000.0
    N1c: float = 30.0
    on_ground: bool = True
    wind_n: float = 0.0
    wind_e: float = 0.0
    Vdot: float = 0.0
    psidot: float = 0.0
    fuel_burnt: float = 0.0
    touchdown: tuple[float, float, LatLon] | None = None  # (sink rate, time, position) of the first touchdown
    t: float = 0.0
    airbrake_cmd: float = 0.0
    airbrake: float = 0.0

    def atm(self):
        return isa(self.h)

    def thrust(self) -> float:
        return 13000.0 * (self.atm().rho_kg_m3 / 1.225) ** 0.7 * (max(self.N1c, 0.0) / 100.0) ** 2

    def engine(self) -> EngineState:
        a = self.atm()
        th = a.T_K / 288.15
        return EngineState(self.N1c * math.sqrt(th), self.N1c, 700.0 + 7.0 * self.N1c)

    def state(self) -> AircraftState:
        a = self.atm()
        vn = self.V * math.cos(self.gamma) * math.cos(self.psi) + (0.0 if self.on_ground else self.wind_n)
        ve = self.V * math.cos(self.gamma) * math.sin(self.psi) + (0.0 if self.on_ground else self.wind_e)
        qbar = 0.5 * a.rho_kg_m3 * self.V**2
        r = self.psidot * math.cos(self.phi)
        return AircraftState(self.pos, self.h, self.V, self.Vdot, self.gamma, vn, ve, self.psi, self.phi, self.theta,
                             self.p, self.q, r, 0.0, qbar, self.mass, self.on_ground)

    def step(self, dt: float, elevator: float, aileron: float, steer: float, brake: float, Wf: float) -> None:
        a = self.atm()
        V = max(self.V, 1.0)
        qbar = 0.5 * a.rho_kg_m3 * V * V
        # engine
        delta, th = a.p_Pa / 101325.0, a.T_K / 288.15
        n1_ss = min(400.0 * Wf / (delta * math.sqrt(th)), 115.0)
        self.N1c += (n1_ss - self.N1c) / 1.0 * dt
        T = self.thrust()
        self.mass -= Wf * dt
        self.fuel_burnt += Wf * dt
        # aerodynamics
        cphi = math.cos(self.phi)
        alpha = (self.theta - self.gamma) / max(cphi, 0.2)
        CL = min(CL0 + CLA * alpha, CL_MAX)
        L = qbar * S * CL
        cmd = min(max(self.airbrake_cmd, 0.0), 1.0)
        self.airbrake += min(max(cmd - self.airbrake, -AIRBRAKE_RATE * dt), AIRBRAKE_RATE * dt)
        D = qbar * S * (CD0 + K_IND * CL * CL + CD_AIRBRAKE * self.airbrake)
        de = max(-1.0, min(1.0, elevator)) * DE_MAX
        M = qbar * S * CBAR * (CM0 + CMA * alpha + CMQ * self.q * CBAR / (2 * V) + CMDE * de)
        W = self.mass * G
        if self.on_ground:
            N = max(W - L - T * math.sin(alpha), 0.0)
            F = MU_ROLL * N + brake * BRAKE_G * G * self.mass * min(1.0, N / W) * (1.0 if self.V > 0.1 else 0.0)
            self.Vdot = (T * math.cos(alpha) - D - F) / self.mass
            self.V = max(self.V + self.Vdot * dt, 0.0)
            self.psidot = self.V * math.tan(max(-1.0, min(1.0, steer)) * STEER_MAX) / WHEELBASE
            self.psi += self.psidot * dt
            # pitch: rotation about the main gear, nose gear stops it at theta = 0
            self.q += M / IYY * dt if (self.theta > 0.0 or M > 0.0) else 0.0
            self.q = self.q if (self.theta > 0.0 or self.q > 0.0) else 0.0
            self.theta = max(self.theta + self.q * dt, 0.0)
            self.phi, self.p, self.gamma = 0.0, 0.0, 0.0
            self.h = self.elev_ground
            if L + T * math.sin(alpha) > W * 1.0 and self.V > 30.0:
                self.on_ground = False
        else:
            Lt = L + T * math.sin(alpha)
            self.Vdot = (T * math.cos(alpha) - D) / self.mass - G * math.sin(self.gamma)
            gdot = Lt * cphi / (self.mass * V) - G * math.cos(self.gamma) / V
            self.psidot = Lt * math.sin(self.phi) / (self.mass * V * math.cos(self.gamma))
            self.p += (-self.p / TAU_ROLL + L_DA * aileron * min(qbar / 1e4, 3.0)) * dt
            self.phi += self.p * dt
            self.q += M / IYY * dt
            self.theta += self.q * dt
            self.V += self.Vdot * dt
            self.gamma += gdot * dt
            self.psi += self.psidot * dt
            self.h += self.V * math.sin(self.gamma) * dt
            if self.h <= self.elev_ground:
                if self.touchdown is None:
                    self.touchdown = (-self.V * math.sin(self.gamma), self.t, self.pos)
                self.on_ground, self.h, self.gamma, self.phi, self.p = True, self.elev_ground, 0.0, 0.0, 0.0
        st = self.state()
        vg = math.hypot(st.vn_m_s, st.ve_m_s)
        if vg * dt > 1e-6:
            new = destination(self.pos, math.atan2(st.ve_m_s, st.vn_m_s), vg * dt)
            self.psi += math.remainder(final_bearing_rad(self.pos, new) - initial_bearing_rad(self.pos, new),
                                       2 * math.pi)
            self.pos = new
        self.t += dt
