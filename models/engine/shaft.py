"""Shafts: each spool's power balance over the contributions its components declare.

A spool carries turbines, compressors and power ports. A turbine delivers P_T;
the bearings and gearbox lose (1 - eta_mech) of it; the compressors absorb
sum P_C; a port exchanges P_X [W] with the outside, SIGNED: positive is power
taken from the spool (accessories, a generator), negative is power delivered
to it (a motor assist). The net power into the spool is

    P_net = sum (eta_mech P_T) - sum P_C - sum P_X.

At design P_net = 0 fixes the turbine power, P_T = (sum P_C + P_X) / eta_mech; off
design P_net = 0 is a matching equation (steady state) or drives the spool
acceleration, dN/dt = P_net / (I omega) * 30/pi. pyCycle's ``fracLoss`` is
1 - eta_mech and its ``HPX`` is P_X. The mechanical loss applies to the turbine
power only: a port's P_X is the power at the shaft (an electric machine's own
losses belong to the machine's model).

The topology of the shafts is data: :data:`TURBOFAN_SHAFTS` declares, once, which
component's power goes to which spool and how (:class:`ShaftTerm`);
:func:`spool_balance` forms the balances of any such declaration from a vector of
the terms' powers, the same function compiled (numba, :mod:`.gas_path`) and in
Python (:mod:`.offdesign`). Adding a machine on a shaft is one more term here and
its power in the vector (see ``models/engine/README.md``, "How to add a component").

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.15
and ch. 8 (shaft power balance, transient spool acceleration).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .errors import OutOfRangeError
from .jit_kernels import jit

__all__ = ["ShaftTerm", "SPOOLS", "TURBINE", "COMPRESSOR", "PORT", "TURBOFAN_SHAFTS", "TERM_INDEX", "term_arrays",
           "spool_balance", "turbine_power_required", "net_power", "spool_acceleration",
           "spool_acceleration_of"]

#: Spools of the two-spool turbofan, in the order of the balances (index 0 HP, 1 LP).
SPOOLS: tuple[str, ...] = ("hp", "lp")
#: Kinds of shaft terms: a turbine delivers its power less the mechanical loss; a compressor absorbs its
#: power; a port takes its signed power (+ out of the spool, - into it).
TURBINE, COMPRESSOR, PORT = 0, 1, 2
_KINDS = {"turbine": TURBINE, "compressor": COMPRESSOR, "port": PORT}


@dataclass(frozen=True)
class ShaftTerm:
    """One contribution to a spool's power balance.

    Attributes
    ----------
    name : str
        The power's name, as in the cycle's ``powers_W`` (``"hpt"``, ``"fan_outer"``, ``"port_lp"``...).
    spool : str
        The spool it sits on, one of :data:`SPOOLS`.
    kind : str
        ``"turbine"`` (delivers P, less (1 - eta_mech) P), ``"compressor"`` (absorbs P) or ``"port"``
        (signed P [W]: + taken from the spool, - delivered to it).
    """

    name: str
    spool: str
    kind: str

    def __post_init__(self) -> None:
        if self.spool not in SPOOLS or self.kind not in _KINDS:
            raise OutOfRangeError(f"ShaftTerm {self.name!r}: spool {self.spool!r} must be one of {SPOOLS}, kind "
                                  f"{self.kind!r} one of {tuple(_KINDS)}")


#: The turbofan's shafts, declared once: the order is the order of the power vector of :func:`spool_balance`.
TURBOFAN_SHAFTS: tuple[ShaftTerm, ...] = (
    ShaftTerm("hpt", "hp", "turbine"), ShaftTerm("hpc", "hp", "compressor"), ShaftTerm("port_hp", "hp", "port"),
    ShaftTerm("lpt", "lp", "turbine"), ShaftTerm("fan_outer", "lp", "compressor"),
    ShaftTerm("fan_inner", "lp", "compressor"), ShaftTerm("booster", "lp", "compressor"),
    ShaftTerm("port_lp", "lp", "port"))
#: Index of each term's power in the power vector.
TERM_INDEX: dict[str, int] = {t.name: i for i, t in enumerate(TURBOFAN_SHAFTS)}


def term_arrays(terms: tuple[ShaftTerm, ...] = TURBOFAN_SHAFTS,
                spools: tuple[str, ...] = SPOOLS) -> tuple[np.ndarray, np.ndarray]:
    """(spool index, kind code) of each term, the integer arrays :func:`spool_balance` reads."""
    return (np.array([spools.index(t.spool) for t in terms], dtype=np.int64),
            np.array([_KINDS[t.kind] for t in terms], dtype=np.int64))


@jit
def spool_balance(P_W: np.ndarray, spool: np.ndarray, kind: np.ndarray, eta_mech: np.ndarray,
                  net_W: np.ndarray, loss_W: np.ndarray) -> None:
    """Net power into each spool and its mechanical loss [W], from the declared terms' powers.

    Parameters
    ----------
    P_W : powers of the terms [W], in the order of the declaration (ports signed, + taken from the spool).
    spool, kind : each term's spool index and kind code (:func:`term_arrays`).
    eta_mech : mechanical efficiency of each spool [-].
    net_W, loss_W : outputs, per spool: sum eta_mech P_T - sum P_C - sum P_X, and sum (1 - eta_mech) P_T.
    """
    for s in range(net_W.shape[0]):
        net_W[s] = 0.0
        loss_W[s] = 0.0
    for k in range(P_W.shape[0]):
        s = spool[k]
        if kind[k] == TURBINE:
            net_W[s] += eta_mech[s] * P_W[k]
            loss_W[s] += (1.0 - eta_mech[s]) * P_W[k]
        else:                                   # a compressor absorbs, a port takes (signed)
            net_W[s] -= P_W[k]


_ONE_SPOOL = term_arrays((ShaftTerm("turbine", "hp", "turbine"), ShaftTerm("compressor", "hp", "compressor"),
                          ShaftTerm("port", "hp", "port")))


def _check(eta_mech: float, port_W: float) -> None:
    if not (0.0 < eta_mech <= 1.0):
        raise OutOfRangeError(f"shaft: eta_mech={eta_mech!r} is outside the valid range (0, 1]")
    if not math.isfinite(port_W):
        raise OutOfRangeError(f"shaft: port power {port_W!r} W must be finite (+ taken from the spool, "
                              "- delivered to it)")


def net_power(turbine_power_W: float, compressor_powers_W: Iterable[float], offtake_W: float = 0.0,
              eta_mech: float = 1.0) -> float:
    """Net power [W] into a spool with one turbine, its compressors and one port (:func:`spool_balance`):
    eta_mech P_T - sum P_C - P_X, `offtake_W` signed (+ taken, - a motor's assist); zero in steady state."""
    _check(eta_mech, offtake_W)
    P = np.array([turbine_power_W, sum(compressor_powers_W), offtake_W])
    net, loss = np.empty(1), np.empty(1)
    spool_balance(P, _ONE_SPOOL[0], _ONE_SPOOL[1], np.array([eta_mech]), net, loss)
    return float(net[0])


def turbine_power_required(compressor_powers_W: Iterable[float], offtake_W: float = 0.0,
                           eta_mech: float = 1.0) -> float:
    """Turbine power [W] that balances the spool: (sum P_C + P_X) / eta_mech, `offtake_W` signed.

    Raises
    ------
    OutOfRangeError
        If an assist (negative `offtake_W`) covers all the compressors' power: no turbine is needed.
    """
    _check(eta_mech, offtake_W)
    P_C = sum(compressor_powers_W)
    if not P_C + offtake_W > 0.0:
        raise OutOfRangeError(f"shaft: the compressors absorb {P_C:.6g} W and the port {offtake_W:.6g} W: an assist "
                              f"of more than the compressors' power leaves no power for the turbine")
    return (P_C + offtake_W) / eta_mech


@jit
def spool_acceleration_of(net_power_W: float, N_rpm: float, inertia_kg_m2: float) -> float:
    """:func:`spool_acceleration` without its check (N_rpm, inertia_kg_m2 > 0), for compiled callers."""
    omega = N_rpm * math.pi / 30.0
    return net_power_W / (inertia_kg_m2 * omega) * 30.0 / math.pi


def spool_acceleration(net_power_W: float, N_rpm: float, inertia_kg_m2: float) -> float:
    """Spool acceleration dN/dt [rpm/s] from the net power [W], speed [rpm] and polar inertia [kg m^2]:
    dN/dt = P_net / (I omega) * 30/pi, omega = N pi/30."""
    if not (N_rpm > 0.0 and inertia_kg_m2 > 0.0):
        raise OutOfRangeError(f"shaft.spool_acceleration: N_rpm={N_rpm!r} and inertia_kg_m2={inertia_kg_m2!r} "
                              f"must be > 0")
    return _accel(net_power_W, N_rpm, inertia_kg_m2)


# called from Python, the plain function (a compiled call would cost more than the arithmetic)
_accel = getattr(spool_acceleration_of, "py_func", spool_acceleration_of)
