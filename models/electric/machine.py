"""An electric machine on a spool: starter-generator (HP) or motor-generator (LP), with limits and losses.

Sign convention (the engine's): the shaft power ``P_shaft_W`` is the power the machine takes from its
spool: > 0 generating, < 0 motoring (power delivered to the spool). The electrical power ``P_elec_W`` is
the power it delivers to the DC bus: > 0 generating, < 0 drawn from the bus. Losses are always >= 0 and

    P_shaft_W = P_elec_W + P_loss_W                                               (energy balance)

holds exactly in every operating point, generating or motoring.

Losses (Larminie & Lowry, 2012, sec. 6.5)::

    P_loss = k_c T^2 + k_i w + k_w w^3 + C      (copper, iron, windage, constant; C only under torque)

with the torque ``T = P_shaft / w`` [N m] and the speed ``w`` [rad/s]. A spinning machine without
torque loses ``k_i w + k_w w^3`` (drag on the spool, shaft side, P_elec = 0).

Limits: ``|T| <= T_max``, ``|P_shaft| <= P_max`` (so the envelope is torque-limited below the corner
speed ``P_max / T_max`` and power-limited above), and no torque outside ``[n_min, n_max]``.

References
----------
J. Larminie, J. Lowry, "Electric Vehicle Technology Explained", 2nd ed., Wiley, 2012, sec. 6.5
(efficiency maps, the loss model above).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .params import MachineParams

__all__ = ["MachinePoint", "ElectricMachine", "RPM"]

RPM = math.pi / 30.0  #: rad/s per rpm


@dataclass(frozen=True)
class MachinePoint:
    """One operating point.

    Attributes
    ----------
    P_shaft_W : float
        Power taken from the spool [W] (< 0: delivered to it).
    P_elec_W : float
        Power delivered to the bus [W] (< 0: drawn from it).
    P_loss_W : float
        Losses [W], >= 0.
    T_Nm : float
        Torque on the machine, > 0 generating [N m].
    limited : bool
        The request was cut by the torque, power or speed limits.
    """

    P_shaft_W: float
    P_elec_W: float
    P_loss_W: float
    T_Nm: float
    limited: bool


class ElectricMachine:
    """A machine directly on a spool (no gearbox), with the loss model and limits of the module text.

    Parameters
    ----------
    p : MachineParams
        Limits and loss coefficients.
    """

    def __init__(self, p: MachineParams) -> None:
        self.p = p

    @property
    def mass_kg(self) -> float:
        """Machine and converter mass from the specific power [kg]."""
        return self.p.P_max_W / self.p.power_density_W_kg

    def on(self, n_rpm: float) -> bool:
        """Whether the machine can carry torque at ``n_rpm``."""
        return self.p.n_min_rpm <= n_rpm <= self.p.n_max_rpm and n_rpm > 0.0

    def shaft_limit_W(self, n_rpm: float) -> float:
        """Largest ``|P_shaft|`` at ``n_rpm`` [W]: min(P_max, T_max w); 0 where the machine is off."""
        return min(self.p.P_max_W, self.p.T_max_Nm * n_rpm * RPM) if self.on(n_rpm) else 0.0

    def spin_loss_W(self, n_rpm: float) -> float:
        """Iron and windage losses without torque [W]."""
        w = max(n_rpm, 0.0) * RPM
        return self.p.k_i_W_s * w + self.p.k_w_W_s3 * w ** 3

    def loss_W(self, P_shaft_W: float, n_rpm: float) -> float:
        """Losses at shaft power ``P_shaft_W`` and speed ``n_rpm`` [W]."""
        w = max(n_rpm, 0.0) * RPM
        if P_shaft_W == 0.0 or w == 0.0:
            return self.spin_loss_W(n_rpm)
        T = P_shaft_W / w
        return self.p.k_c_W_Nm2 * T * T + self.spin_loss_W(n_rpm) + self.p.C_W

    def at_shaft(self, P_shaft_W: float, n_rpm: float) -> MachinePoint:
        """The operating point for a requested shaft power, cut to the limits."""
        lim = self.shaft_limit_W(n_rpm)
        P = max(-lim, min(lim, P_shaft_W))
        limited = P != P_shaft_W
        loss = self.loss_W(P, n_rpm)
        P_s = P if P != 0.0 else loss  # no torque: the spin losses are drawn from the spool
        w = max(n_rpm, 0.0) * RPM
        return MachinePoint(P_s, P_s - loss, loss, P / w if w > 0.0 else 0.0, limited)

    def at_elec(self, P_elec_W: float, n_rpm: float) -> MachinePoint:
        """The operating point delivering ``P_elec_W`` to the bus (< 0: drawing it), cut to the limits.

        Solves ``P_elec = P_s - k_c (P_s/w)^2 - k_i w - k_w w^3 - C`` for the shaft power ``P_s`` on the
        branch of the smaller ``|P_s|`` (the efficient one); a request beyond the machine's largest
        output gives the limit's point.
        """
        if P_elec_W == 0.0 or not self.on(n_rpm):
            pt = self.at_shaft(0.0, n_rpm)
            return MachinePoint(pt.P_shaft_W, pt.P_elec_W, pt.P_loss_W, pt.T_Nm, pt.limited or P_elec_W != 0.0)
        w = n_rpm * RPM
        a = self.p.k_c_W_Nm2 / (w * w)
        c0 = self.spin_loss_W(n_rpm) + self.p.C_W
        # a P_s^2 - P_s + (P_elec + c0) = 0; for P_elec < 0 (motoring) the root is negative
        disc = 1.0 - 4.0 * a * (P_elec_W + c0)
        if a == 0.0:
            P_s = P_elec_W + c0
        elif disc < 0.0:  # beyond the largest generated power: the limit's point
            return self.at_shaft(math.copysign(math.inf, P_elec_W), n_rpm)
        else:
            P_s = (1.0 - math.sqrt(disc)) / (2.0 * a)
        pt = self.at_shaft(P_s, n_rpm)
        return pt
