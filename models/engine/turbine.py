"""Turbine at a given pressure ratio or for a given power, with cooling flows.

The primary flow expands from Pt_in to Pt_out = Pt_in/PR with isentropic
efficiency eta_is (real gas, entropy function phi of :mod:`.gas`):

    phi(Tt_is) = phi(Tt_in) - R ln PR,
    ht_out = ht_in - eta_is (ht_in - h(Tt_is)),   P = W (ht_in - ht_out).

Cooling air (:mod:`.bleed`, sink ``"hpt"``/``"lpt"``) re-enters at the pressure
Pt_c = Pt_out + frac_P (Pt_in - Pt_out): air entering at the inlet (frac_P = 1)
expands through the whole turbine and does work, air entering at the exit
(frac_P = 0) does none. Each cooling stream expands from Pt_c to Pt_out with
the same efficiency, and all streams mix at the exit, conserving mass, air,
fuel and enthalpy (the pyCycle/NPSS convention). Station 41 (rotor inlet) is
reported as the burner exit mixed with the inlet cooling air (frac_P = 1).

For a given power (design point) the PR follows in closed form without
cooling, and by a secant iteration on ln PR with it.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.3
(turbine efficiency, real-gas expansion) and 5.13 (cooling flows).
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (cooling flows
entering at a fraction of the turbine pressure drop).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from . import jit_kernels as K
from .errors import ConvergenceError, OutOfRangeError
from .flow import FlowStation, mix_state
from .gas import DEFAULT_GAS, T_MIN_K, GasModel
from .jit_kernels import jit

__all__ = ["Cooling", "TurbineResult", "turbine", "turbine_for_power", "expand_h"]


@dataclass(frozen=True, slots=True)
class Cooling:
    """A cooling stream entering a turbine.

    Attributes
    ----------
    flow : FlowStation
        The cooling air as delivered by its bleed port.
    frac_P : float
        Where it enters, as a fraction of the turbine pressure drop [-]; 1 inlet, 0 exit.
    """

    flow: FlowStation
    frac_P: float


@dataclass(frozen=True, slots=True)
class TurbineResult:
    """Result of a turbine calculation.

    Attributes
    ----------
    rotor_in : FlowStation
        Inlet flow mixed with the inlet cooling (frac_P = 1) air: station 41.
    out : FlowStation
        Exit flow with all cooling air mixed in.
    power_W : float
        Shaft power delivered [W].
    PR : float
        Total pressure ratio Pt_in/Pt_out [-], >= 1.
    eta_is : float
        Isentropic efficiency [-].
    Wp_in : float
        Flow parameter W sqrt(Tt)/Pt at the inlet [kg/s sqrt(K)/Pa], primary flow.
    """

    rotor_in: FlowStation
    out: FlowStation
    power_W: float
    PR: float
    eta_is: float
    Wp_in: float


@jit
def expand_h(gc: np.ndarray, gs: np.ndarray, Tt_K: float, FAR: float, ht_J_kg: float, Pt_from: float, Pt_to: float,
             eta: float, err: np.ndarray) -> float:
    """Exit enthalpy [J/kg] of a stream expanded from Pt_from to Pt_to [Pa] with isentropic efficiency `eta`
    [-]: ht - eta (ht - h(T_is)); the one implementation, compiled (:mod:`.gas_path`) and called by
    :func:`turbine`. ``err[0]`` is set where a temperature leaves the gas tables."""
    T_is = K.T_isentropic(gc, gs, Tt_K, Pt_to / Pt_from, FAR, Tt_K * (Pt_to / Pt_from) ** 0.25, err)
    return ht_J_kg - eta * (ht_J_kg - K.h(gc, gs, T_is, FAR, err))


@jit
def turbine_stream(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, PR: float,
             eta: float, cw: np.ndarray, cT: np.ndarray, cP: np.ndarray, cf: np.ndarray, ch: np.ndarray,
             cfp: np.ndarray, nc: int, err: np.ndarray) -> tuple[float, float, float, float, float, float, float,
                                                                 float, float, float]:
    """The turbine on floats, the one implementation (:func:`turbine` and the gas path, :mod:`.gas_path`, call it):
    the primary flow (W [kg/s], Tt [K], Pt [Pa], FAR [-], ht [J/kg]) expands by PR [-] at efficiency eta [-]; nc
    cooling streams (cw, cT, cP, cf, ch: W, Tt, Pt, FAR, ht; cfp: where they enter, frac_P) each enter at
    Pt_out + frac_P (Pt_in - Pt_out), expand to Pt_out with the same efficiency, and all mix at the exit.

    Returns (power [W], exit W, Tt, Pt, FAR, ht, rotor inlet W, Tt, FAR, ht): the rotor inlet (station 41) is the
    inlet mixed with the cooling air entering at the inlet (frac_P = 1). ``err[0]``: 2 for PR < 1 or eta outside
    (0, 1], 7 for a cooling stream below its entry pressure, 8 for a flow or pressure not finite or not positive,
    1 where the gas tables end (:mod:`.jit_kernels`)."""
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        err[0] = err[0] or 2
        return 0.0, W, T, P, f, ht, W, T, f, ht
    Pin, Pout = P, P / PR
    ho = expand_h(gc, gs, T, f, ht, Pin, Pout, eta, err) if PR > 1.0 else ht
    power = W * (ht - ho)
    Tg = T - (ht - ho) / K.cp(gc, gs, T, f, err)
    if not (W >= 0.0 and math.isfinite(W)) or not (Pout > 0.0 and math.isfinite(Pout)):
        err[0] = err[0] or 8
    To = K.T_from_h(gc, gs, ho, f, Tg, err)
    ex = np.empty((4, nc + 1))                  # the streams to mix: one allocation, not four
    eW, eT, ef, eh = ex[0], ex[1], ex[2], ex[3]
    eW[0], eT[0], ef[0], eh[0] = W, To, f, ho
    for i in range(nc):
        Pc = Pout + cfp[i] * (Pin - Pout)
        if cw[i] > 0.0 and cP[i] < Pc * (1.0 - 1e-12):     # a closed (zero) cooling flow has no pressure to lack
            err[0] = err[0] or 7
        hc = expand_h(gc, gs, cT[i], cf[i], ch[i], Pc, Pout, eta, err) if Pc > Pout else ch[i]
        power += cw[i] * (ch[i] - hc)
        eW[i + 1], eT[i + 1], ef[i + 1], eh[i + 1] = cw[i], cT[i], cf[i], hc
    if nc > 0:
        Wo, To, fo, ho = mix_state(gc, gs, eW, eT, ef, eh, nc + 1, err)
    else:
        Wo, fo = W, f
    W41, T41, f41, h41 = W, T, f, ht
    m = 0
    for i in range(nc):
        if cfp[i] == 1.0:
            m += 1
    if m > 0:
        eW[0], eT[0], ef[0], eh[0] = W, T, f, ht
        m = 1
        for i in range(nc):
            if cfp[i] == 1.0:
                eW[m], eT[m], ef[m], eh[m] = cw[i], cT[i], cf[i], ch[i]
                m += 1
        W41, T41, f41, h41 = mix_state(gc, gs, eW, eT, ef, eh, m, err)
    return power, Wo, To, Pout, fo, ho, W41, T41, f41, h41


def _expand(fs: FlowStation, Pt_from: float, Pt_to: float, eta: float, gas: GasModel) -> float:
    """Exit enthalpy [J/kg] of `fs` expanded from Pt_from to Pt_to with efficiency eta (:func:`expand_h`)."""
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    h_out = float(expand_h(gc, gs, fs.Tt_K, fs.FAR, fs.ht_J_kg, Pt_from, Pt_to, eta, err))
    if err[0]:
        raise OutOfRangeError(f"turbine: expanding Tt={fs.Tt_K!r} K, FAR={fs.FAR!r} from {Pt_from!r} Pa to "
                              f"{Pt_to!r} Pa leaves the gas tables ({K.T_MIN} K to {K.T_MAX} K)")
    return h_out


def _check(PR: float, eta_is: float) -> None:
    if not (PR >= 1.0):
        raise OutOfRangeError(f"turbine: PR={PR!r} must be >= 1")
    if not (0.0 < eta_is <= 1.0):
        raise OutOfRangeError(f"turbine: eta_is={eta_is!r} is outside the valid range (0, 1]")


def turbine(fs_in: FlowStation, PR: float, eta_is: float, cooling: Sequence[Cooling] = (),
            gas: GasModel = DEFAULT_GAS) -> TurbineResult:
    """Expand `fs_in` by `PR` [-] with isentropic efficiency `eta_is` [-], mixing in `cooling`
    (:func:`turbine_stream`, with its checks raised as messages).

    Raises
    ------
    OutOfRangeError
        For PR < 1, eta_is outside (0, 1], or a cooling stream whose pressure
        is below that of its entry point (it could not flow in).
    """
    _check(PR, eta_is)
    n = len(cooling)
    c = np.array([(k.flow.W_kg_s, k.flow.Tt_K, k.flow.Pt_Pa, k.flow.FAR, k.flow.ht_J_kg, k.frac_P) for k in cooling],
                 dtype=float).reshape(n, 6).T.copy()
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    P, Wo, To, Po, fo, ho, W41, T41, f41, h41 = turbine_stream(
        gc, gs, fs_in.W_kg_s, fs_in.Tt_K, fs_in.Pt_Pa, fs_in.FAR, fs_in.ht_J_kg, float(PR), float(eta_is), c[0], c[1],
        c[2], c[3], c[4], c[5], n, err)
    if err[0] == 7:
        Pt_out = fs_in.Pt_Pa / PR
        bad = [(k.flow.Pt_Pa, Pt_out + k.frac_P * (fs_in.Pt_Pa - Pt_out), k.frac_P) for k in cooling
               if k.flow.Pt_Pa < (Pt_out + k.frac_P * (fs_in.Pt_Pa - Pt_out)) * (1.0 - 1e-12)][0]
        raise OutOfRangeError(f"turbine: cooling air at Pt={bad[0]:.6g} Pa cannot enter at {bad[1]:.6g} Pa "
                              f"(frac_P={bad[2]})")
    if err[0] == 8:
        raise OutOfRangeError(f"turbine: W_kg_s={fs_in.W_kg_s!r} and Pt_out={fs_in.Pt_Pa / PR!r} Pa must be finite, "
                              "W >= 0 and Pt > 0")
    if err[0]:
        raise OutOfRangeError(f"turbine: expanding Tt={fs_in.Tt_K!r} K, FAR={fs_in.FAR!r} by PR={PR!r} leaves the gas "
                              f"tables ({K.T_MIN} K to {K.T_MAX} K)")
    out = FlowStation(float(Wo), float(To), float(Po), float(fo), float(ho))
    rotor_in = FlowStation(float(W41), float(T41), fs_in.Pt_Pa, float(f41), float(h41)) if \
        any(k.frac_P == 1.0 for k in cooling) else fs_in
    return TurbineResult(rotor_in, out, float(P), PR, eta_is, fs_in.W_kg_s * math.sqrt(fs_in.Tt_K) / fs_in.Pt_Pa)


def _power(fs_in: FlowStation, PR: float, eta: float, cooling: Sequence[Cooling], gas: GasModel) -> float:
    """Shaft power [W] of :func:`turbine` (:func:`turbine_stream`)."""
    return turbine(fs_in, PR, eta, cooling, gas).power_W


def turbine_for_power(fs_in: FlowStation, power_W: float, eta_is: float, cooling: Sequence[Cooling] = (),
                      gas: GasModel = DEFAULT_GAS, tol_rel: float = 1e-12) -> TurbineResult:
    """Turbine that delivers `power_W` [W] at isentropic efficiency `eta_is` [-]; PR is the unknown.

    Without cooling: ht_is = ht_in - P/(W eta_is), PR = exp((phi(Tt_in) - phi(T_is))/R).
    With cooling: secant iteration on ln PR until |P(PR) - P| < tol_rel P.

    Raises
    ------
    OutOfRangeError
        If the power cannot be delivered (the required expansion leaves the gas tables).
    ConvergenceError
        If the secant iteration does not converge in 30 steps.
    """
    if not (power_W >= 0.0):
        raise OutOfRangeError(f"turbine_for_power: power_W={power_W!r} must be >= 0")
    _check(1.0, eta_is)
    f, W = fs_in.FAR, fs_in.W_kg_s
    h_is = fs_in.ht_J_kg - power_W / (W * eta_is)
    if h_is <= gas.h(T_MIN_K, f):
        raise OutOfRangeError(f"turbine_for_power: delivering power_W={power_W:.6g} W from {W:.6g} kg/s at "
                              f"Tt={fs_in.Tt_K:.6g} K needs an expansion below {T_MIN_K} K: the turbine "
                              f"cannot drive its load")
    T_is = gas.T_from_h(h_is, f, fs_in.Tt_K * 0.8)
    PR0 = math.exp((gas.phi(fs_in.Tt_K, f) - gas.phi(T_is, f)) / gas.R(f))
    if not cooling or power_W == 0.0:
        return turbine(fs_in, PR0, eta_is, cooling, gas)
    x0 = math.log(PR0)
    r0 = _power(fs_in, PR0, eta_is, cooling, gas) - power_W
    x1 = x0 * power_W / (r0 + power_W)           # power ~ proportional to ln PR
    for _ in range(30):
        r1 = _power(fs_in, math.exp(x1), eta_is, cooling, gas) - power_W
        if abs(r1) <= tol_rel * power_W:
            return turbine(fs_in, math.exp(x1), eta_is, cooling, gas)
        x0, x1, r0 = x1, max(x1 - r1 * (x1 - x0) / (r1 - r0), 1e-9), r1
    raise ConvergenceError(f"turbine_for_power: no convergence for power_W={power_W!r} W; "
                           f"last power residual {r1!r} W")
