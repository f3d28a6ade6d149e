"""Lateral-directional derivatives of UPERA from its geometry.

Body-axis roll (Cl) and yaw (Cn) moments about the design CG and side force
(CY), per radian of sideslip, control deflection or non-dimensional rate
(p b/(2V), r b/(2V)). Control signs as in :mod:`.aero`: aileron positive rolls
right, rudder positive yaws the nose right.

References
----------
.. [1] Nelson, R. C., *Flight Stability and Automatic Control*, 2nd ed., McGraw-Hill,
   1998, sect. 2.6-2.7 and 3.8 (vertical-tail sidewash factor, eq. 2.73; tail terms).
.. [2] Etkin, B., Reid, L. D., *Dynamics of Flight*, 3rd ed., Wiley, 1996, sect. 5.7
   (strip theory: roll damping, Cn_p = -CL/8, Cl_r = CL/4).
.. [3] Raymer, D. P., *Aircraft Design*, 6th ed., AIAA, 2018, eq. 16.48 (fuselage Cn_beta).
.. [4] Finck, R. D., *USAF DATCOM*, 1978, sect. 5.2.1.1 (fuselage side force, K_i = 1 mid wing).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .aero import AeroModel

__all__ = ["Lateral", "lateral"]

ADVERSE_YAW_K = -0.15  # Nelson fig. 5.x empirical factor: Cn_da = 2 K CL Cl_da [1]


@dataclass(frozen=True)
class Lateral:
    """Lateral-directional derivatives (functions of Mach and lift coefficient)."""

    aero: AeroModel
    sidewash: float  # (1 + dsigma/dbeta) eta_v [-]
    cy_beta_fus: float
    cn_beta_fus: float

    def _g(self):  # noqa: ANN202
        return self.aero.geom

    def cy_beta_v(self, mach: ArrayLike) -> NDArray:
        """Vertical-tail side force per sideslip [1/rad]."""
        g = self._g()
        return -self.aero.a_v(mach) * self.sidewash * g.vtail.area_m2 / g.wing.area_m2

    def cy_beta(self, mach: ArrayLike) -> NDArray:
        return self.cy_beta_v(mach) + self.cy_beta_fus

    def cn_beta(self, mach: ArrayLike) -> NDArray:
        """Weathercock stability [1/rad]: tail (positive) + fuselage (negative)."""
        g = self._g()
        return -self.cy_beta_v(mach) * g.l_v_m / g.wing.span_m + self.cn_beta_fus

    def cl_beta(self, mach: ArrayLike, cl: ArrayLike) -> NDArray:
        """Dihedral effect [1/rad]: sweep (strip theory -CL tan L (1+2l)/(3(1+l))), geometric
        dihedral -a G (1+2l)/(6(1+l)), mid wing (no wing-body term), vertical tail CY_bv z_v/b."""
        g = self._g()
        w = g.wing
        lam = w.taper
        sweep = -np.asarray(cl, dtype=float) * math.tan(w.sweep_c4_rad) * (1 + 2 * lam) / (3 * (1 + lam))
        gamma = math.radians(g.raw["wing"]["dihedral_deg"])
        dihedral = -self.aero.a_wb(mach) * gamma * (1 + 2 * lam) / (6 * (1 + lam))
        return sweep + dihedral + self.cy_beta_v(mach) * g.z_v_m / w.span_m

    def cl_p(self, mach: ArrayLike) -> NDArray:
        """Roll damping, strip theory with the 3-D lift slope: -a (1+3l)/(12(1+l)) [1/rad]."""
        lam = self._g().wing.taper
        return -self.aero.a_wb(mach) * (1 + 3 * lam) / (12 * (1 + lam))

    def cn_p(self, cl: ArrayLike) -> NDArray:
        """Yaw due to roll rate, wing: -CL/8 (tail term vanishes at small alpha) [1/rad]."""
        return -np.asarray(cl, dtype=float) / 8.0

    def cl_r(self, mach: ArrayLike, cl: ArrayLike) -> NDArray:
        """Roll due to yaw rate: CL/4 (wing) - 2 (l_v z_v / b^2) CY_bv (tail) [1/rad]."""
        g = self._g()
        b = g.wing.span_m
        return np.asarray(cl, dtype=float) / 4.0 - 2 * g.l_v_m * g.z_v_m / b ** 2 * self.cy_beta_v(mach)

    def cn_r(self, mach: ArrayLike) -> NDArray:
        """Yaw damping: 2 (l_v/b)^2 CY_bv (tail), x1.1 for wing and fuselage [1/rad]."""
        g = self._g()
        return 1.1 * 2 * (g.l_v_m / g.wing.span_m) ** 2 * self.cy_beta_v(mach)

    def cy_p(self, mach: ArrayLike) -> NDArray:
        g = self._g()
        return 2 * g.z_v_m / g.wing.span_m * self.cy_beta_v(mach)

    def cy_r(self, mach: ArrayLike) -> NDArray:
        g = self._g()
        return -2 * g.l_v_m / g.wing.span_m * self.cy_beta_v(mach)

    def cl_da(self, mach: ArrayLike) -> NDArray:
        """Aileron power, strip theory: 2 a tau int(c y dy) / (S b) [1/rad]."""
        g = self._g()
        w = g.wing
        a = g.raw["aileron"]
        y1, y2 = a["inner_span_fraction"] * w.semi_span_m, a["outer_span_fraction"] * w.semi_span_m
        return 2 * self.aero.a_wb(mach) * self.aero.tau_a * w.chord_moment_m3(y1, y2) / (w.area_m2 * w.span_m)

    def cn_da(self, mach: ArrayLike, cl: ArrayLike) -> NDArray:
        """Adverse yaw 2 K CL Cl_da [1/rad]."""
        return 2 * ADVERSE_YAW_K * np.asarray(cl, dtype=float) * self.cl_da(mach)

    def cy_dr(self, mach: ArrayLike) -> NDArray:
        """Side force of the rudder (nose-right deflection pushes the tail left) [1/rad]."""
        g = self._g()
        return -self.aero.a_v(mach) * self.aero.tau_r * self.sidewash * g.vtail.area_m2 / g.wing.area_m2

    def cn_dr(self, mach: ArrayLike) -> NDArray:
        g = self._g()
        return -self.cy_dr(mach) * g.l_v_m / g.wing.span_m

    def cl_dr(self, mach: ArrayLike) -> NDArray:
        g = self._g()
        return self.cy_dr(mach) * g.z_v_m / g.wing.span_m


def lateral(aero: AeroModel) -> Lateral:
    """Lateral-directional derivatives of ``aero``'s geometry."""
    g = aero.geom
    w = g.wing
    # Nelson eq. 2.73 (from DATCOM): (1 + dsigma/dbeta) eta_v; z_w is the wing's distance
    # below the fuselage axis, d the fuselage depth.
    z_w = -g.raw["wing"]["z_m"]
    sidewash = 0.724 + 3.06 * (g.vtail.area_m2 / w.area_m2) / (1 + math.cos(w.sweep_c4_rad)) + \
        0.4 * z_w / g.fuselage_diameter_m + 0.009 * w.aspect_ratio
    fus = g.raw["fuselage"]
    d, length = g.fuselage_diameter_m, g.fuselage_length_m
    area = math.pi * d ** 2 / 4
    volume = area * (length - 2.0 / 3.0 * (fus["nose_length_m"] + fus["tailcone_length_m"]))  # cones at the ends
    cy_beta_fus = -2.0 * 1.0 * area / w.area_m2  # DATCOM 5.2.1.1, K_i = 1 (mid wing), S_0 = max section
    cn_beta_fus = -1.3 * volume / (w.area_m2 * w.span_m)  # Raymer eq. 16.48, D_f/W_f = 1 (round)
    return Lateral(aero=aero, sidewash=sidewash, cy_beta_fus=cy_beta_fus, cn_beta_fus=cn_beta_fus)
