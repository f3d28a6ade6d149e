"""Bleeds: air taken from a compressor, at a stage or at its exit, and where it goes.

A bleed is described as in pyCycle and NPSS, by fractions of the compressor:

* ``frac_W``    bleed mass flow / compressor inlet mass flow [-];
* ``frac_P``    (Pt_bleed - Pt_in) / (Pt_out - Pt_in) [-];
* ``frac_work`` (ht_bleed - ht_in) / (ht_out - ht_in) [-]: the share of the
  compressor's specific work the bleed air has received.

An exit bleed has frac_P = frac_work = 1. For an interstage bleed behind
stage k of n stages of equal work and equal pressure ratio,
frac_work = k/n and frac_P = (PR^(k/n) - 1)/(PR - 1) (:func:`stage_fractions`).

Where the air goes (``sink``):

* ``"overboard"``: leaves the engine (customer bleed, anti-ice, handling
  bleed dumped overboard);
* ``"bypass"``: returned to the bypass duct ahead of the bypass nozzle (the
  handling bleed of the turbofan of SPEC.md);
* ``"hpt"`` / ``"lpt"``: turbine cooling air, re-entering the turbine at
  ``sink_frac_P`` of its pressure drop (1: at the inlet, so it does work in
  the whole turbine; 0: at the exit, no work), as in pyCycle.

References
----------
E. S. Hendricks, J. S. Gray, "pyCycle: A Tool for Efficient Optimization of Gas
Turbine Engine Cycles", Aerospace 6(87), 2019 (bleed fractions frac_W, frac_P, frac_work).
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.13 (bleeds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import jit_kernels as K
from .errors import OutOfRangeError
from .flow import FlowStation, check_flow
from .gas import DEFAULT_GAS, GasModel
from .jit_kernels import jit

__all__ = ["SINKS", "BleedSpec", "stage_fractions", "bleed_state", "bleed_station"]

#: Allowed destinations of a bleed.
SINKS: tuple[str, ...] = ("overboard", "bypass", "hpt", "lpt")


@dataclass(frozen=True, slots=True)
class BleedSpec:
    """One bleed of a compressor.

    Attributes
    ----------
    name : str
        Name, used in results (``"handling"``, ``"customer"``, ``"cool_hpt"``...).
    frac_W : float
        Bleed flow / compressor inlet flow [-], in [0, 1).
    frac_P : float
        Pressure fraction [-], in [0, 1]; 1 at the compressor exit.
    frac_work : float
        Work fraction [-], in [0, 1]; 1 at the compressor exit.
    sink : str
        Destination, one of :data:`SINKS`.
    sink_frac_P : float
        For turbine cooling: where in the turbine's pressure drop it re-enters
        [-], 1 at the turbine inlet, 0 at its exit.
    """

    name: str
    frac_W: float
    frac_P: float = 1.0
    frac_work: float = 1.0
    sink: str = "overboard"
    sink_frac_P: float = 1.0

    def __post_init__(self) -> None:
        if not (0.0 <= self.frac_W < 1.0):
            raise OutOfRangeError(f"bleed {self.name!r}: frac_W={self.frac_W!r} is outside [0, 1)")
        for attr in ("frac_P", "frac_work", "sink_frac_P"):
            v = getattr(self, attr)
            if not (0.0 <= v <= 1.0):
                raise OutOfRangeError(f"bleed {self.name!r}: {attr}={v!r} is outside [0, 1]")
        if self.sink not in SINKS:
            raise OutOfRangeError(f"bleed {self.name!r}: sink={self.sink!r} is not one of {SINKS}")

    @property
    def at_exit(self) -> bool:
        """True for a bleed from the compressor exit (frac_P = frac_work = 1)."""
        return self.frac_P == 1.0 and self.frac_work == 1.0


def stage_fractions(stage: int, n_stages: int, PR: float) -> tuple[float, float]:
    """(frac_P, frac_work) [-] behind stage `stage` of `n_stages` of equal work and pressure ratio.

    frac_work = stage/n_stages; frac_P = (PR^(stage/n_stages) - 1)/(PR - 1).
    """
    if not (1 <= stage <= n_stages):
        raise OutOfRangeError(f"bleed.stage_fractions: stage={stage!r} must lie in 1..{n_stages}")
    if not PR > 1.0:
        raise OutOfRangeError(f"bleed.stage_fractions: PR={PR!r} must exceed 1")
    x = stage / n_stages
    return (PR ** x - 1.0) / (PR - 1.0), x


@jit
def bleed_state(gc: np.ndarray, gs: np.ndarray, T_in: float, P_in: float, FAR: float, h_in: float, T_out: float,
                P_out: float, h_out: float, frac_P: float, frac_work: float,
                err: np.ndarray) -> tuple[float, float, float]:
    """(Tt [K], Pt [Pa], ht [J/kg]) of a bleed from a compressor with inlet (T_in, P_in, h_in) and unbled exit
    (T_out, P_out, h_out): the exit state for an exit bleed, else ht = h_in + frac_work (h_out - h_in),
    Pt = P_in + frac_P (P_out - P_in) and Tt from ht. The one implementation (:func:`bleed_station` and the gas
    path, :mod:`.gas_path`); ``err[0]`` 8 for a pressure not finite or not positive, 1 where the gas tables end."""
    if frac_P == 1.0 and frac_work == 1.0:
        return T_out, P_out, h_out
    h = h_in + frac_work * (h_out - h_in)
    P = P_in + frac_P * (P_out - P_in)
    if not (P > 0.0 and math.isfinite(P)):
        err[0] = err[0] or 8
    return K.T_from_h(gc, gs, h, FAR, T_in, err), P, h


def bleed_station(spec: BleedSpec, fs_in: FlowStation, fs_out: FlowStation,
                  gas: GasModel = DEFAULT_GAS) -> FlowStation:
    """The bleed stream of a compressor with inlet `fs_in` and (unbled) exit state `fs_out`.

    W = frac_W W_in, ht = ht_in + frac_work (ht_out - ht_in),
    Pt = Pt_in + frac_P (Pt_out - Pt_in), FAR of the inlet.
    """
    W = spec.frac_W * fs_in.W_kg_s
    if spec.at_exit:
        return FlowStation(W, fs_out.Tt_K, fs_out.Pt_Pa, fs_out.FAR, fs_out.ht_J_kg)
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    T, P, h = bleed_state(gc, gs, fs_in.Tt_K, fs_in.Pt_Pa, fs_in.FAR, fs_in.ht_J_kg, fs_out.Tt_K, fs_out.Pt_Pa,
                          fs_out.ht_J_kg, spec.frac_P, spec.frac_work, err)
    check_flow(f"bleed {spec.name!r}", W, float(P))
    if err[0]:
        raise OutOfRangeError(f"bleed {spec.name!r}: its enthalpy {float(h)!r} J/kg is outside the gas tables")
    return FlowStation(W, float(T), float(P), fs_in.FAR, float(h))
