"""International Standard Atmosphere with a temperature deviation, and the free stream.

The ISA (ISO 2533:1975, identical to the U.S. Standard Atmosphere 1976 up to
32 km) is defined by its sea-level state (288.15 K, 101325 Pa), g0 =
9.80665 m/s^2, R = 287.05287 J/(kg K) and three layers of linear temperature
in geopotential altitude: -6.5 K/km to 11 km, isothermal to 20 km, +1.0 K/km to
32 km. These few defining constants of the standard are written here, not
in a data file, because they *are* the standard.

An ISA deviation dT_isa adds to the temperature at every altitude while the
pressure stays that of the standard at the same (pressure) altitude, the usual
convention of engine performance work (hot and cold days).

References
----------
ISO 2533:1975, "Standard Atmosphere".
NOAA/NASA/USAF, "U.S. Standard Atmosphere, 1976", NOAA-S/T 76-1562, 1976.
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import OutOfRangeError
from .flow import FlowStation, flow_TP, total_from_static
from .gas import DEFAULT_GAS, GasModel

__all__ = ["ALT_MIN_M", "ALT_MAX_M", "Ambient", "FreeStream", "isa", "free_stream"]

_T0_K = 288.15
_P0_PA = 101325.0
_G0 = 9.80665
_R_AIR = 287.05287
#: (base geopotential altitude [m], base temperature [K], lapse rate [K/m]) of the ISA layers.
_LAYERS = ((0.0, 288.15, -0.0065), (11000.0, 216.65, 0.0), (20000.0, 216.65, 0.001))
#: Valid geopotential altitude range [m].
ALT_MIN_M: float = -1000.0
ALT_MAX_M: float = 32000.0


def _base_pressures() -> tuple[float, ...]:
    p = [_P0_PA]
    for (H0, T0, L), (H1, _, _) in zip(_LAYERS[:-1], _LAYERS[1:], strict=True):
        p.append(_p_in_layer(p[-1], H1 - H0, T0, L))
    return tuple(p)


def _p_in_layer(p_base: float, dH: float, T_base: float, L: float) -> float:
    if L == 0.0:
        return p_base * math.exp(-_G0 * dH / (_R_AIR * T_base))
    return p_base * (1.0 + L * dH / T_base) ** (-_G0 / (_R_AIR * L))


_P_BASE = _base_pressures()


@dataclass(frozen=True, slots=True)
class Ambient:
    """Static ambient state.

    Attributes
    ----------
    alt_m : float
        Geopotential (pressure) altitude [m].
    dT_isa_K : float
        Deviation from ISA temperature [K].
    T_K : float
        Static temperature [K].
    P_Pa : float
        Static pressure [Pa].
    rho_kg_m3 : float
        Density [kg/m^3] (ideal gas, R of dry air).
    a_m_s : float
        Speed of sound [m/s] with gamma = 1.4 (the standard's value; the
        engine uses real-gas sound speeds from :mod:`.gas`).
    """

    alt_m: float
    dT_isa_K: float
    T_K: float
    P_Pa: float
    rho_kg_m3: float
    a_m_s: float


def isa(alt_m: float, dT_isa_K: float = 0.0) -> Ambient:
    """ISA static state at geopotential altitude `alt_m` [m] with deviation `dT_isa_K` [K].

    Raises
    ------
    OutOfRangeError
        If the altitude lies outside -1000 m to 32000 m or the temperature
        would leave 150 K to 350 K.
    """
    if not (ALT_MIN_M <= alt_m <= ALT_MAX_M):
        raise OutOfRangeError(f"atmosphere.isa: alt_m={alt_m!r} m is outside the valid range "
                              f"{ALT_MIN_M} m to {ALT_MAX_M} m")
    i = 0 if alt_m < _LAYERS[1][0] else (1 if alt_m < _LAYERS[2][0] else 2)
    H0, T0, L = _LAYERS[i]
    T_std = T0 + L * (alt_m - H0)
    P = _p_in_layer(_P_BASE[i], alt_m - H0, T0, L)
    T = T_std + dT_isa_K
    if not (150.0 <= T <= 350.0):
        raise OutOfRangeError(f"atmosphere.isa: dT_isa_K={dT_isa_K!r} K gives T={T:.2f} K, outside "
                              f"the valid range 150 K to 350 K")
    return Ambient(alt_m, dT_isa_K, T, P, P / (_R_AIR * T), math.sqrt(1.4 * _R_AIR * T))


@dataclass(frozen=True, slots=True)
class FreeStream:
    """Free stream (station 0) of a flight condition.

    Attributes
    ----------
    amb : Ambient
        Static ambient state.
    Mach : float
        Flight Mach number [-].
    V0_m_s : float
        Flight speed [m/s] (real-gas speed of sound of dry air at T_K).
    Tt0_K, Pt0_Pa : float
        Free-stream total temperature [K] and pressure [Pa].
    """

    amb: Ambient
    Mach: float
    V0_m_s: float
    Tt0_K: float
    Pt0_Pa: float

    def station(self, W_kg_s: float, gas: GasModel = DEFAULT_GAS) -> FlowStation:
        """Station 0 carrying `W_kg_s` [kg/s] of dry air."""
        return flow_TP(W_kg_s, self.Tt0_K, self.Pt0_Pa, 0.0, gas)


def free_stream(alt_m: float, Mach: float, dT_isa_K: float = 0.0,
                gas: GasModel = DEFAULT_GAS) -> FreeStream:
    """Free-stream state at altitude `alt_m` [m], flight Mach `Mach` [-] and ISA deviation [K].

    The totals are real-gas: V0 = Mach sqrt(gamma(T) R T), h(Tt0) = h(T) + V0^2/2,
    Pt0 = P exp((phi(Tt0) - phi(T))/R).
    """
    if not (0.0 <= Mach <= 3.0):
        raise OutOfRangeError(f"atmosphere.free_stream: Mach={Mach!r} is outside the valid range 0 to 3")
    amb = isa(alt_m, dT_isa_K)
    V0 = Mach * math.sqrt(gas.gamma(amb.T_K) * gas.R() * amb.T_K)
    Tt0, Pt0 = total_from_static(amb.T_K, amb.P_Pa, V0, 0.0, gas)
    return FreeStream(amb, Mach, V0, Tt0, Pt0)
