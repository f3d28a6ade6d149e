"""The free stream (station 0): the standard atmosphere, the real-gas totals and the ram recovery.

:func:`free_stream` is the one implementation, on plain floats and arrays so that numba compiles it:
:func:`.atmosphere.free_stream` (the Python API, with its range checks and messages) calls it, as do
:class:`.jit_cycle.FastCycle` and :func:`.jit_solve.chord_solve`. The atmosphere is
:func:`openemss.models.common.atmosphere.isa_T_p` itself, compiled (one source), and the ram recovery
:func:`.inlet.ram_recovery`.

References
----------
ISO 2533:1975, "Standard Atmosphere" (:func:`openemss.models.common.atmosphere.isa_T_p`).
MIL-E-5008B, ram recovery (as :func:`.inlet.ram_recovery_mil_e_5008b`).
"""
from __future__ import annotations

import math

import numpy as np

from ..common import atmosphere as _atm
from . import jit_kernels as K
from .inlet import ram_recovery
from .jit_kernels import jit

__all__ = ["atm_array", "free_stream"]


def atm_array() -> np.ndarray:
    """The standard atmosphere's valid ranges as :func:`free_stream` checks them, from
    :mod:`openemss.models.common.atmosphere` (one source): altitude [m] and temperature [K], low and high."""
    return np.array([_atm.ALT_MIN_M, _atm.ALT_MAX_M, _atm.T_MIN_K, _atm.T_MAX_K], dtype=float)


#: The atmosphere's own source, compiled (not a second implementation).
_isa_T_p = jit(_atm.isa_T_p)


@jit
def free_stream(gc: np.ndarray, gs: np.ndarray, atm: np.ndarray, alt: float, Mach: float, dT: float,
                fs: np.ndarray) -> int:
    """Fill fs with (Tt0 [K], Pt0 [Pa], V0 [m/s], p_amb [Pa], Mach, ram recovery [-]) at altitude alt [m],
    Mach [-] and ISA deviation dT [K], as :func:`.atmosphere.free_stream` and
    :func:`.inlet.ram_recovery_mil_e_5008b`; returns 1 (fs untouched) where they would raise."""
    if not (0.0 <= Mach <= 3.0) or not (atm[0] <= alt <= atm[1]) or not (abs(dT) < 1e300):
        return 1
    T, P = _isa_T_p(alt, dT)
    if not (atm[2] <= T <= atm[3]):
        return 1
    err = np.zeros(1, np.int64)
    c = K.cp(gc, gs, T, 0.0, err)
    R_ = gs[10]
    V0 = Mach * math.sqrt(c / (c - R_) * R_ * T)
    ht = K.h(gc, gs, T, 0.0, err) + 0.5 * V0 * V0
    Tt = K.T_from_h(gc, gs, ht, 0.0, T, err)
    Pt = P * math.exp((K.phi(gc, gs, Tt, 0.0, err) - K.phi(gc, gs, T, 0.0, err)) / R_)
    if err[0]:
        return 1
    fs[0], fs[1], fs[2], fs[3], fs[4] = Tt, Pt, V0, P, Mach
    fs[5] = ram_recovery(Mach)
    return 0
