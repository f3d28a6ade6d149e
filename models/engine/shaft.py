"""Shafts: power balance with mechanical efficiency and power offtake.

A spool's turbine delivers P_T; the bearings and gearbox lose (1 - eta_mech)
of it; the compressors on the spool absorb sum P_C; the accessories and
generators take the offtake P_X [W]:

    eta_mech P_T = sum P_C + P_X.

At design this fixes the turbine power; off-design the imbalance drives the
spool acceleration, dN/dt = (eta_mech P_T - sum P_C - P_X) / (I omega (2 pi/60)).
pyCycle's ``fracLoss`` is 1 - eta_mech and its ``HPX`` is P_X.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.15
and ch. 8 (shaft power balance, transient spool acceleration).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from .errors import OutOfRangeError

__all__ = ["turbine_power_required", "net_power", "spool_acceleration"]


def _check(eta_mech: float, offtake_W: float) -> None:
    if not (0.0 < eta_mech <= 1.0):
        raise OutOfRangeError(f"shaft: eta_mech={eta_mech!r} is outside the valid range (0, 1]")
    if not (offtake_W >= 0.0):
        raise OutOfRangeError(f"shaft: offtake_W={offtake_W!r} must be >= 0")


def turbine_power_required(compressor_powers_W: Iterable[float], offtake_W: float = 0.0,
                           eta_mech: float = 1.0) -> float:
    """Turbine power [W] that balances the spool: (sum P_C + P_X) / eta_mech."""
    _check(eta_mech, offtake_W)
    return (sum(compressor_powers_W) + offtake_W) / eta_mech


def net_power(turbine_power_W: float, compressor_powers_W: Iterable[float], offtake_W: float = 0.0,
              eta_mech: float = 1.0) -> float:
    """Net spool power [W]: eta_mech P_T - sum P_C - P_X (zero in steady state)."""
    _check(eta_mech, offtake_W)
    return eta_mech * turbine_power_W - sum(compressor_powers_W) - offtake_W


def spool_acceleration(net_power_W: float, N_rpm: float, inertia_kg_m2: float) -> float:
    """Spool acceleration dN/dt [rpm/s] from the net power [W], speed [rpm] and polar inertia [kg m^2]."""
    if not (N_rpm > 0.0 and inertia_kg_m2 > 0.0):
        raise OutOfRangeError(f"shaft.spool_acceleration: N_rpm={N_rpm!r} and inertia_kg_m2={inertia_kg_m2!r} "
                              f"must be > 0")
    omega = N_rpm * math.pi / 30.0
    return net_power_W / (inertia_kg_m2 * omega) * 30.0 / math.pi
