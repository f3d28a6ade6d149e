"""Nozzles: convergent (choked or unchoked) and ideally expanded convergent-divergent.

Convergent nozzle, inlet totals (Pt, Tt, FAR) and ambient static pressure p_amb:

* the critical state follows from real-gas relations at Mach 1 (:mod:`.gas`,
  ``static_from_total``): T*, p* = pt (p/pt)*;
* choked if p_amb <= p*: the throat static pressure is p*, V = a(T*), and
  the jet leaves with pressure thrust (p* - p_amb) A;
* unchoked otherwise: the throat static pressure is p_amb, T from isentropic
  expansion, V = sqrt(2 (ht - h(T))).

Gross thrust with the velocity coefficient Cv (losses of jet momentum):

    F_G = Cv W V_throat + (p_throat - p_amb) A_eff,   A_eff = W/(rho V)

(the pyCycle convention, ``lossCoef='Cv'``). The geometric throat area is
A_geom = A_eff / Cd, with the discharge coefficient Cd; A_eff is what the
off-design matching keeps fixed.

Ideally expanded (CD) nozzle: F_G = Cv W V_ideal with V_ideal the velocity of
isentropic expansion to p_amb.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.14
(convergent nozzle, choking, gross thrust, Cd and Cv).
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (Cv convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import jit_kernels as K
from .errors import OutOfRangeError
from .flow import FlowStation, StaticState, static_at_mach, static_at_pressure
from .gas import DEFAULT_GAS, GasModel
from .jit_kernels import jit

__all__ = ["NozzleResult", "convergent_nozzle", "convergent_throat", "ideal_nozzle"]


@jit
def convergent_throat(gc: np.ndarray, gs: np.ndarray, W: float, Tt: float, Pt: float, FAR: float, ht: float,
                      P_amb: float, Cv: float, err: np.ndarray) -> tuple[float, float, float, float, bool, float]:
    """Throat of a convergent nozzle, ideal flow: (Ts [K], Ps [Pa], V [m/s], A_eff [m2], choked, Fg [N]).

    Choked (p_amb at or below the Mach-1 static pressure): Mach 1 at the throat and a pressure thrust
    (Ps - p_amb) A; else expanded to p_amb. Fg = Cv W V + pressure thrust. The one implementation, compiled
    (:mod:`.gas_path`) and called by :func:`convergent_nozzle`; ``err[0]`` set where the gas tables end.
    """
    Ts, p_pt = K.static_from_total(gc, gs, Tt, 1.0, FAR, err)
    Ps = Pt * p_pt
    choked = P_amb <= Ps
    if not choked:
        Ts = K.T_isentropic(gc, gs, Tt, P_amb / Pt, FAR, Tt, err)
        Ps = P_amb
    V = math.sqrt(max(2.0 * (ht - K.h(gc, gs, Ts, FAR, err)), 0.0))
    R_ = K.R(gs, FAR)
    A = W / (Ps / (R_ * Ts) * V) if V > 0.0 else math.inf
    return Ts, Ps, V, A, choked, Cv * W * V + ((Ps - P_amb) * A if choked else 0.0)


@dataclass(frozen=True, slots=True)
class NozzleResult:
    """Result of a nozzle calculation.

    Attributes
    ----------
    throat : StaticState
        Static state at the throat (exit plane of a convergent nozzle), ideal flow.
    choked : bool
        True if the throat is at Mach 1 with p_amb below the critical pressure.
    Fg_N : float
        Gross thrust [N].
    V_ideal_m_s : float
        Velocity of ideal full expansion to p_amb [m/s].
    A_eff_m2 : float
        Effective throat area [m^2], W/(rho V) of the ideal flow.
    A_geom_m2 : float
        Geometric throat area [m^2], A_eff / Cd.
    PR : float
        Nozzle pressure ratio Pt/p_amb [-].
    """

    throat: StaticState
    choked: bool
    Fg_N: float
    V_ideal_m_s: float
    A_eff_m2: float
    A_geom_m2: float
    PR: float


def _check(fs: FlowStation, P_amb_Pa: float, Cv: float, Cd: float) -> None:
    if not (0.0 < Cv <= 1.0 and 0.0 < Cd <= 1.0):
        raise OutOfRangeError(f"nozzle: Cv={Cv!r} and Cd={Cd!r} must lie in (0, 1]")
    if not (0.0 < P_amb_Pa):
        raise OutOfRangeError(f"nozzle: P_amb_Pa={P_amb_Pa!r} must be > 0")
    if fs.Pt_Pa < P_amb_Pa:
        raise OutOfRangeError(f"nozzle: inlet Pt={fs.Pt_Pa:.6g} Pa is below the ambient {P_amb_Pa:.6g} Pa "
                              "(reverse flow)")


def convergent_nozzle(fs: FlowStation, P_amb_Pa: float, Cv: float = 1.0, Cd: float = 1.0,
                      gas: GasModel = DEFAULT_GAS, with_ideal: bool = True) -> NozzleResult:
    """Convergent nozzle fed by `fs` exhausting to static pressure `P_amb_Pa` [Pa].

    Parameters
    ----------
    fs : FlowStation
        Nozzle inlet (station 7 or 17).
    P_amb_Pa : float
        Ambient static pressure [Pa].
    Cv : float
        Velocity (thrust) coefficient [-], (0, 1].
    Cd : float
        Discharge coefficient [-], (0, 1].
    gas : GasModel
        Gas model.
    with_ideal : bool
        Compute the fully expanded velocity V_ideal of a choked nozzle (one
        more isentropic expansion); if False it is NaN when choked.
    """
    _check(fs, P_amb_Pa, Cv, Cd)
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    Ts, Ps, V, A, choked, Fg = convergent_throat(gc, gs, fs.W_kg_s, fs.Tt_K, fs.Pt_Pa, fs.FAR, fs.ht_J_kg,
                                                 P_amb_Pa, Cv, err)
    if err[0]:
        raise OutOfRangeError(f"nozzle: the throat of a flow at Tt={fs.Tt_K!r} K, Pt={fs.Pt_Pa!r} Pa, FAR={fs.FAR!r} "
                              f"exhausting to {P_amb_Pa!r} Pa leaves the gas tables ({K.T_MIN} K to {K.T_MAX} K)")
    Ts, Ps, V, A, Fg = float(Ts), float(Ps), float(V), float(A), float(Fg)
    R_ = gas.R(fs.FAR)
    th = StaticState(Ts, Ps, V, V / math.sqrt(gas.gamma(Ts, fs.FAR) * R_ * Ts), Ps / (R_ * Ts), A)
    if choked:
        V_ideal = static_at_pressure(fs, P_amb_Pa, gas).V_m_s if with_ideal else math.nan
    else:
        V_ideal = V
    return NozzleResult(th, bool(choked), Fg, V_ideal, A, A / Cd, fs.Pt_Pa / P_amb_Pa)


def ideal_nozzle(fs: FlowStation, P_amb_Pa: float, Cv: float = 1.0,
                 gas: GasModel = DEFAULT_GAS) -> NozzleResult:
    """Convergent-divergent nozzle ideally expanded to `P_amb_Pa` [Pa]: F_G = Cv W V_ideal.

    The throat is reported at Mach 1 if the pressure ratio exceeds the
    critical one (its area is the sizing area), else at the exit.
    """
    _check(fs, P_amb_Pa, Cv, 1.0)
    ex = static_at_pressure(fs, P_amb_Pa, gas)
    star = static_at_mach(fs, 1.0, gas)
    choked = P_amb_Pa <= star.Ps_Pa
    th = star if choked else ex
    return NozzleResult(th, choked, Cv * fs.W_kg_s * ex.V_m_s, ex.V_m_s, th.A_m2, th.A_m2,
                        fs.Pt_Pa / P_amb_Pa)
