"""Flow stations: the state carried from component to component.

A :class:`FlowStation` holds what 0-D cycle analysis needs of a stream: mass
flow W [kg/s], total temperature Tt [K], total pressure Pt [Pa], fuel-air ratio
FAR [-] (kg of fuel burned per kg of dry air, :mod:`.gas`) and, for speed and
exact energy book-keeping, the sensible total enthalpy ht [J/kg] that belongs
to (Tt, FAR). Components are functions from stations to stations; the energy
flow of a station is W ht, and sums of W ht close the energy balance of every
component exactly because the enthalpy of a mixture is linear in its species.

Static quantities follow from real-gas relations of :mod:`.gas`: the static
temperature T from ht = h(T) + V^2/2, the static pressure from constant
entropy, p/pt = exp((phi(T) - phi(Tt))/R).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 3
(total and static properties, corrected flow and speed).
E. S. Hendricks, J. S. Gray, "pyCycle: A Tool for Efficient Optimization of Gas
Turbine Engine Cycles", Aerospace 6(87), 2019 (flow-station concept).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..common.atmosphere import P0_PA, T0_K
from . import jit_kernels as K
from .errors import OutOfRangeError
from .gas import DEFAULT_GAS, GasModel
from .jit_kernels import jit

__all__ = ["T_STD_K", "P_STD_PA", "FlowStation", "check_flow", "flow_TP", "flow_hP", "mix", "mix_state", "split",
           "StaticState", "static_at_mach", "static_at_pressure", "total_from_static"]

#: Reference temperature of corrected quantities [K] (ISA sea level, the one atmosphere's).
T_STD_K: float = T0_K
#: Reference pressure of corrected quantities [Pa] (ISA sea level, the one atmosphere's).
P_STD_PA: float = P0_PA


@dataclass(frozen=True, slots=True)
class FlowStation:
    """Total state and mass flow of a stream at one station.

    Attributes
    ----------
    W_kg_s : float
        Mass flow [kg/s] (air plus burned fuel).
    Tt_K : float
        Total temperature [K].
    Pt_Pa : float
        Total pressure [Pa].
    FAR : float
        Fuel-air ratio [-], kg of fuel burned per kg of dry air.
    ht_J_kg : float
        Sensible total enthalpy [J/kg], h(Tt_K, FAR) of :mod:`.gas`.

    Notes
    -----
    Build stations with :func:`flow_TP` or :func:`flow_hP`, which keep Tt and
    ht consistent.
    """

    W_kg_s: float
    Tt_K: float
    Pt_Pa: float
    FAR: float
    ht_J_kg: float

    @property
    def W_air_kg_s(self) -> float:
        """Dry-air mass flow [kg/s]."""
        return self.W_kg_s / (1.0 + self.FAR)

    @property
    def W_fuel_kg_s(self) -> float:
        """Burned-fuel mass flow contained in the stream [kg/s]."""
        return self.W_kg_s * self.FAR / (1.0 + self.FAR)

    @property
    def H_W(self) -> float:
        """Sensible total enthalpy flow W ht [W]."""
        return self.W_kg_s * self.ht_J_kg

    @property
    def Wc_kg_s(self) -> float:
        """Corrected flow W sqrt(Tt/288.15 K)/(Pt/101325 Pa) [kg/s]."""
        return self.W_kg_s * math.sqrt(self.Tt_K / T_STD_K) / (self.Pt_Pa / P_STD_PA)

    def with_W(self, W_kg_s: float) -> FlowStation:
        """The same total state with another mass flow [kg/s]."""
        return FlowStation(W_kg_s, self.Tt_K, self.Pt_Pa, self.FAR, self.ht_J_kg)

    def with_Pt(self, Pt_Pa: float) -> FlowStation:
        """The same flow and temperature at another total pressure [Pa]."""
        return FlowStation(self.W_kg_s, self.Tt_K, Pt_Pa, self.FAR, self.ht_J_kg)


def check_flow(where: str, W_kg_s: float, Pt_Pa: float) -> None:
    """Raise :class:`~.errors.OutOfRangeError` (naming `where`) unless W >= 0 and Pt > 0 are finite."""
    if not (W_kg_s >= 0.0 and math.isfinite(W_kg_s)):
        raise OutOfRangeError(f"{where}: W_kg_s={W_kg_s!r} must be finite and >= 0")
    if not (Pt_Pa > 0.0 and math.isfinite(Pt_Pa)):
        raise OutOfRangeError(f"{where}: Pt_Pa={Pt_Pa!r} must be finite and > 0")


def flow_TP(W_kg_s: float, Tt_K: float, Pt_Pa: float, FAR: float = 0.0,
            gas: GasModel = DEFAULT_GAS) -> FlowStation:
    """Flow station from mass flow [kg/s], total temperature [K], total pressure [Pa], FAR [-]."""
    check_flow("flow_TP", W_kg_s, Pt_Pa)
    return FlowStation(W_kg_s, Tt_K, Pt_Pa, FAR, gas.h(Tt_K, FAR))


def flow_hP(W_kg_s: float, ht_J_kg: float, Pt_Pa: float, FAR: float = 0.0,
            gas: GasModel = DEFAULT_GAS, T_guess_K: float | None = None) -> FlowStation:
    """Flow station from mass flow [kg/s], total enthalpy [J/kg], total pressure [Pa], FAR [-]."""
    check_flow("flow_hP", W_kg_s, Pt_Pa)
    return FlowStation(W_kg_s, gas.T_from_h(ht_J_kg, FAR, T_guess_K), Pt_Pa, FAR, ht_J_kg)


def mix(streams: Iterable[FlowStation], Pt_Pa: float | None = None,
        gas: GasModel = DEFAULT_GAS) -> FlowStation:
    """Adiabatic mixing of streams: mass, air, fuel and enthalpy conserved.

    Parameters
    ----------
    streams : iterable of FlowStation
        The entering streams; the first is the primary stream.
    Pt_Pa : float, optional
        Total pressure of the mixed stream [Pa]; default the primary stream's
        (a bleed injected into a main stream takes its pressure; the momentum
        balance of a mixer is not modelled).
    gas : GasModel
        Gas model.

    Returns
    -------
    FlowStation
        W = sum W_i, FAR = sum fuel / sum air, ht = sum W_i ht_i / W.
    """
    s = list(streams)
    W = sum(x.W_kg_s for x in s)
    if not W > 0.0:
        raise OutOfRangeError(f"flow.mix: total mass flow {W!r} kg/s must be > 0")
    P = s[0].Pt_Pa if Pt_Pa is None else Pt_Pa
    check_flow("flow.mix", W, P)
    a = np.array([(x.W_kg_s, x.Tt_K, x.FAR, x.ht_J_kg) for x in s]).T.copy()
    gc, gs = gas.kernel_arrays()
    err = np.zeros(1, np.int64)
    Wm, Tm, FAR, hm = mix_state(gc, gs, a[0], a[1], a[2], a[3], len(s), err)
    if err[0]:
        raise OutOfRangeError(f"flow.mix: the mixed stream (W={W!r} kg/s, ht={hm!r} J/kg, FAR={FAR!r}) is outside "
                              f"the gas tables")
    return FlowStation(float(Wm), float(Tm), P, float(FAR), float(hm))


@jit
def mix_state(gc: np.ndarray, gs: np.ndarray, W: np.ndarray, T: np.ndarray, f: np.ndarray, ht: np.ndarray, n: int,
              err: np.ndarray) -> tuple[float, float, float, float]:
    """(W [kg/s], Tt [K], FAR [-], ht [J/kg]) of the adiabatic mixture of the first n streams (mass, air, fuel
    and enthalpy conserved): the one implementation, compiled (:mod:`.gas_path`) and called by :func:`mix`."""
    Ws = air = fuel = H = WT = 0.0
    for i in range(n):
        Ws += W[i]
    if not Ws > 0.0:
        err[0] = 1
        return 1.0, 300.0, 0.0, 0.0
    for i in range(n):
        air += W[i] / (1.0 + f[i])
    for i in range(n):
        fuel += W[i] * f[i] / (1.0 + f[i])
    for i in range(n):
        H += W[i] * ht[i]
    for i in range(n):
        WT += W[i] * T[i]
    F = fuel / air
    return Ws, K.T_from_h(gc, gs, H / Ws, F, WT / Ws, err), F, H / Ws


def split(fs: FlowStation, fraction: float) -> tuple[FlowStation, FlowStation]:
    """Split a stream into (fraction, 1 - fraction) of its mass flow, same total state."""
    if not (0.0 <= fraction <= 1.0):
        raise OutOfRangeError(f"flow.split: fraction={fraction!r} must lie in [0, 1]")
    return fs.with_W(fs.W_kg_s * fraction), fs.with_W(fs.W_kg_s * (1.0 - fraction))


@dataclass(frozen=True, slots=True)
class StaticState:
    """Static state of a stream.

    Attributes
    ----------
    Ts_K : float
        Static temperature [K].
    Ps_Pa : float
        Static pressure [Pa].
    V_m_s : float
        Velocity [m/s].
    Mach : float
        Mach number [-].
    rho_kg_m3 : float
        Static density [kg/m^3].
    A_m2 : float
        Flow area W/(rho V) [m^2] (inf for V = 0).
    """

    Ts_K: float
    Ps_Pa: float
    V_m_s: float
    Mach: float
    rho_kg_m3: float
    A_m2: float


def _static(fs: FlowStation, Ts_K: float, Ps_Pa: float, gas: GasModel) -> StaticState:
    V = math.sqrt(max(2.0 * (fs.ht_J_kg - gas.h(Ts_K, fs.FAR)), 0.0))
    R_ = gas.R(fs.FAR)
    a = math.sqrt(gas.gamma(Ts_K, fs.FAR) * R_ * Ts_K)
    rho = Ps_Pa / (R_ * Ts_K)
    A = fs.W_kg_s / (rho * V) if V > 0.0 else math.inf
    return StaticState(Ts_K, Ps_Pa, V, V / a, rho, A)


def static_at_mach(fs: FlowStation, Mach: float, gas: GasModel = DEFAULT_GAS) -> StaticState:
    """Static state of a stream at a given Mach number [-] (real gas, isentropic)."""
    Ts, p_pt = gas.static_from_total(fs.Tt_K, Mach, fs.FAR)
    return _static(fs, Ts, fs.Pt_Pa * p_pt, gas)


def static_at_pressure(fs: FlowStation, Ps_Pa: float, gas: GasModel = DEFAULT_GAS) -> StaticState:
    """Static state of a stream expanded isentropically to static pressure `Ps_Pa` [Pa] <= Pt."""
    if not (0.0 < Ps_Pa <= fs.Pt_Pa):
        raise OutOfRangeError(f"flow.static_at_pressure: Ps_Pa={Ps_Pa!r} must lie in (0, Pt={fs.Pt_Pa!r}] Pa")
    Ts = gas.T_isentropic(fs.Tt_K, Ps_Pa / fs.Pt_Pa, fs.FAR, fs.Tt_K)
    return _static(fs, Ts, Ps_Pa, gas)


def total_from_static(Ts_K: float, Ps_Pa: float, V_m_s: float, FAR: float = 0.0,
                      gas: GasModel = DEFAULT_GAS) -> tuple[float, float]:
    """Total temperature [K] and pressure [Pa] of a stream of static state (Ts, Ps) and speed V.

    ht = h(Ts) + V^2/2 (adiabatic), Pt = Ps exp((phi(Tt) - phi(Ts))/R) (isentropic).
    """
    ht = gas.h(Ts_K, FAR) + 0.5 * V_m_s * V_m_s
    Tt = gas.T_from_h(ht, FAR, Ts_K)
    return Tt, Ps_Pa * math.exp((gas.phi(Tt, FAR) - gas.phi(Ts_K, FAR)) / gas.R(FAR))
