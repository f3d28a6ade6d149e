"""Kinematic point-mass lateral model on the sphere, for guidance tests.

Bank follows its command with a first-order lag (the closed roll loop, time
constant 0.5 s, rate limit 15 deg/s); coordinated turn psidot = g tan(phi) / V;
ground velocity = air velocity + wind; position moved along the great circle of
the ground track (geo.destination), the heading carried along the geodesic
(zero bank flies a great circle). Optional vertical channel: the flight-path
angle follows its command with a 1 s lag.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from openemss.models.mission.geo import LatLon, destination, final_bearing_rad, initial_bearing_rad

G = 9.80665
TAU_PHI_S = 0.5
P_MAX_RAD_S = math.radians(15.0)
TAU_GAMMA_S = 1.0


@dataclass
class Kinematic:
    pos: LatLon
    psi: float
    V: float
    phi: float = 0.0
    wind_n: float = 0.0
    wind_e: float = 0.0
    h: float = 0.0
    gamma: float = 0.0

    @property
    def vn(self) -> float:
        return self.V * math.cos(self.gamma) * math.cos(self.psi) + self.wind_n

    @property
    def ve(self) -> float:
        return self.V * math.cos(self.gamma) * math.sin(self.psi) + self.wind_e

    @property
    def chi(self) -> float:
        return math.atan2(self.ve, self.vn)

    def step(self, dt: float, phi_cmd: float, gamma_cmd: float | None = None) -> None:
        dphi = (phi_cmd - self.phi) / TAU_PHI_S
        self.phi += max(-P_MAX_RAD_S, min(P_MAX_RAD_S, dphi)) * dt
        self.psi += G * math.tan(self.phi) / self.V * dt
        vg = math.hypot(self.vn, self.ve)
        new = destination(self.pos, self.chi, vg * dt)
        if vg * dt > 1e-6:  # a geodesic step turns the bearing (meridians converge): carry the heading along
            self.psi += math.remainder(final_bearing_rad(self.pos, new) - initial_bearing_rad(self.pos, new),
                                       2 * math.pi)
        self.pos = new
        if gamma_cmd is not None:
            self.gamma += (gamma_cmd - self.gamma) / TAU_GAMMA_S * dt
        self.h += self.V * math.sin(self.gamma) * dt
