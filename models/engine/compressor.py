"""Compressor (fan, booster, HPC) at a given pressure ratio and isentropic efficiency.

With the entropy function phi of :mod:`.gas` (real gas, cp(T, FAR)):

    Tt_is:  phi(Tt_is) = phi(Tt_in) + R ln PR        (isentropic exit),
    ht_out = ht_in + (h(Tt_is) - ht_in) / eta_is,
    eta_poly = R ln PR / (phi(Tt_out) - phi(Tt_in)),

and the shaft power absorbed, with bleeds (:mod:`.bleed`) taken after they
have received the work fraction frac_work,

    P = W_in (ht_out - ht_in) - sum_b W_b (ht_out - ht_b).

Exit flow W_out = W_in - sum of interstage bleeds (exit bleeds, frac_P =
frac_work = 1, are returned separately and removed by the caller at
station 3 -> 31, so that station 3 is the full HPC delivery).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.2
(compressor efficiency definitions, real-gas calculation with the entropy function).
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (bleed work fractions).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from . import jit_kernels as K
from .bleed import BleedSpec, bleed_station
from .errors import OutOfRangeError
from .flow import FlowStation, check_flow
from .gas import DEFAULT_GAS, GasModel
from .jit_kernels import jit

__all__ = ["CompressorResult", "compressor", "compress_exit", "bled_power", "efficiency_poly_to_isentropic"]


@jit
def compress_exit(gc: np.ndarray, gs: np.ndarray, Tt_K: float, FAR: float, ht_J_kg: float, PR: float, eta_is: float,
                  err: np.ndarray) -> tuple[float, float]:
    """Exit (Tt [K], ht [J/kg]) of a compression by `PR` [-] at isentropic efficiency `eta_is` [-]: the one
    implementation, compiled (:mod:`.gas_path`) and called by :func:`compressor`.

    ht_out = ht_in + (h(T_is) - ht_in) / eta_is, T_is the isentropic exit temperature; ``err[0]`` is set where a
    temperature leaves the gas tables (:mod:`.jit_kernels`).
    """
    T_is = K.T_isentropic(gc, gs, Tt_K, PR, FAR, Tt_K * PR ** 0.2857, err)
    ht_out = ht_J_kg + (K.h(gc, gs, T_is, FAR, err) - ht_J_kg) / eta_is
    return K.T_from_h(gc, gs, ht_out, FAR, Tt_K + (T_is - Tt_K) / eta_is, err), ht_out


@jit
def bled_power(W_in: float, h_in: float, h_out: float, bW: np.ndarray, bh: np.ndarray, n: int) -> float:
    """Shaft power [W] absorbed by a compressor of inlet flow W_in [kg/s] from h_in to h_out [J/kg] whose n bleeds
    (flows bW [kg/s], enthalpies bh [J/kg]) leave with part of the work: W_in (h_out - h_in) - sum bW (h_out - bh).
    The one implementation (:func:`compressor` and the gas path, :mod:`.gas_path`)."""
    P_b = 0.0
    for i in range(n):
        P_b += bW[i] * (h_out - bh[i])
    return W_in * (h_out - h_in) - P_b


@dataclass(frozen=True, slots=True)
class CompressorResult:
    """Result of :func:`compressor`.

    Attributes
    ----------
    out : FlowStation
        Exit flow after the interstage bleeds (exit bleeds still included).
    bleeds : tuple of FlowStation
        One stream per bleed spec, in the order given.
    power_W : float
        Shaft power absorbed [W].
    PR : float
        Total pressure ratio Pt_out/Pt_in [-].
    eta_is, eta_poly : float
        Isentropic and polytropic efficiencies [-].
    Wc_in_kg_s : float
        Inlet corrected flow [kg/s].
    """

    out: FlowStation
    bleeds: tuple[FlowStation, ...]
    power_W: float
    PR: float
    eta_is: float
    eta_poly: float
    Wc_in_kg_s: float


def compressor(fs_in: FlowStation, PR: float, eta_is: float, bleeds: Sequence[BleedSpec] = (),
               gas: GasModel = DEFAULT_GAS) -> CompressorResult:
    """Compress `fs_in` by `PR` [-] at isentropic efficiency `eta_is` [-].

    Parameters
    ----------
    fs_in : FlowStation
        Inlet flow.
    PR : float
        Total pressure ratio [-], >= 1.
    eta_is : float
        Isentropic efficiency [-], in (0, 1].
    bleeds : sequence of BleedSpec
        Bleeds, frac_W relative to the inlet flow.
    gas : GasModel
        Gas model.

    Raises
    ------
    OutOfRangeError
        For PR < 1, eta_is outside (0, 1], or bleeds of 100 % or more.
    """
    if not (PR >= 1.0):
        raise OutOfRangeError(f"compressor: PR={PR!r} must be >= 1")
    if not (0.0 < eta_is <= 1.0):
        raise OutOfRangeError(f"compressor: eta_is={eta_is!r} is outside the valid range (0, 1]")
    f = fs_in.FAR
    check_flow("compressor", fs_in.W_kg_s, fs_in.Pt_Pa * PR)
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    Tt_out, ht_out = compress_exit(gc, gs, fs_in.Tt_K, f, fs_in.ht_J_kg, PR, eta_is, err)
    if err[0]:
        raise OutOfRangeError(f"compressor: compressing Tt={fs_in.Tt_K!r} K, FAR={f!r} by PR={PR!r} at eta_is="
                              f"{eta_is!r} leaves the gas tables ({K.T_MIN} K to {K.T_MAX} K)")
    full = FlowStation(fs_in.W_kg_s, float(Tt_out), fs_in.Pt_Pa * PR, f, float(ht_out))
    streams = tuple(bleed_station(b, fs_in, full, gas) for b in bleeds)
    W_inter = sum(s.W_kg_s for b, s in zip(bleeds, streams, strict=True) if not b.at_exit)
    W_all = sum(s.W_kg_s for s in streams)
    if W_all >= fs_in.W_kg_s:
        raise OutOfRangeError(f"compressor: bleeds take {W_all!r} kg/s of {fs_in.W_kg_s!r} kg/s")
    power = float(bled_power(fs_in.W_kg_s, fs_in.ht_J_kg, float(ht_out), np.array([b.W_kg_s for b in streams]),
                             np.array([b.ht_J_kg for b in streams]), len(streams)))
    dphi = gas.phi(full.Tt_K, f) - gas.phi(fs_in.Tt_K, f)
    eta_p = gas.R(f) * math.log(PR) / dphi if dphi > 0.0 else 1.0
    return CompressorResult(full.with_W(fs_in.W_kg_s - W_inter), streams, power, PR, eta_is, eta_p,
                            fs_in.Wc_kg_s)


def efficiency_poly_to_isentropic(eta_poly: float, PR: float, Tt_in_K: float, FAR: float = 0.0,
                                  gas: GasModel = DEFAULT_GAS) -> float:
    """Isentropic efficiency [-] of a compression of ratio `PR` with polytropic efficiency `eta_poly`.

    Real gas: the exit satisfies phi(Tt_out) = phi(Tt_in) + R ln(PR)/eta_poly.
    """
    if not (0.0 < eta_poly <= 1.0 and PR > 1.0):
        raise OutOfRangeError(f"efficiency_poly_to_isentropic: eta_poly={eta_poly!r} must lie in (0, 1] "
                              f"and PR={PR!r} exceed 1")
    p_in, R_ = gas.phi(Tt_in_K, FAR), gas.R(FAR)
    T_out = gas.T_from_phi(p_in + R_ * math.log(PR) / eta_poly, FAR)
    T_is = gas.T_from_phi(p_in + R_ * math.log(PR), FAR)
    h_in = gas.h(Tt_in_K, FAR)
    return (gas.h(T_is, FAR) - h_in) / (gas.h(T_out, FAR) - h_in)
