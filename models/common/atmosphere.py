"""The International Standard Atmosphere (ISO 2533:1975), one source for engine, airframe and FCS.

ISO 2533:1975 (identical to the U.S. Standard Atmosphere 1976 up to 32 km) is defined by its
sea-level state (288.15 K, 101325 Pa), g0 = 9.80665 m/s^2, R = 287.05287 J/(kg K) and layers of
linear temperature in geopotential altitude: -6.5 K/km to 11 km, isothermal to 20 km, +1.0 K/km
to 32 km. These defining constants *are* the standard, so they are written here, not in a data
file; every other figure (the layers' base pressures) is computed from them.

An ISA deviation ``dT_isa_K`` adds to the temperature at every altitude while the pressure stays
that of the standard at the same (pressure) altitude, the convention of engine performance work
(hot and cold days).

:func:`isa_T_p` is written on plain floats with no exception, so that the engine's compiled path
compiles this same source with numba (``jit(isa_T_p)``), and the FCS's compiled laws call it
(``jitable``); the range checks are :func:`check`'s.

References
----------
ISO 2533:1975, "Standard Atmosphere".
NOAA/NASA/USAF, "U.S. Standard Atmosphere, 1976", NOAA-S/T 76-1562, 1976 (Table I, geopotential
altitude; the test values).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.jit import jitable
from ..infra.records import fast_init

__all__ = ["G0_M_S2", "R_AIR_J_KG_K", "GAMMA_AIR", "T0_K", "P0_PA", "RHO0_KG_M3", "A0_M_S", "ALT_MIN_M",
           "ALT_MAX_M", "T_MIN_K", "T_MAX_K", "Atmosphere", "AtmosphereRangeError", "isa_T_p", "rho_a", "check", "isa",
           "sutherland_viscosity"]

G0_M_S2: float = 9.80665
R_AIR_J_KG_K: float = 287.05287
GAMMA_AIR: float = 1.4
T0_K: float = 288.15
P0_PA: float = 101325.0
#: Base geopotential altitude [m], base temperature [K] and lapse rate [K/m] of the layers.
LAYER_H_M: tuple[float, float, float] = (0.0, 11000.0, 20000.0)
LAYER_T_K: tuple[float, float, float] = (288.15, 216.65, 216.65)
LAYER_L_K_M: tuple[float, float, float] = (-0.0065, 0.0, 0.001)
#: Valid geopotential altitude range [m] and temperature range [K] (with a deviation).
ALT_MIN_M: float = -1000.0
ALT_MAX_M: float = 32000.0
T_MIN_K: float = 150.0
T_MAX_K: float = 350.0


def _p_in_layer(p_base: float, dH: float, T_base: float, L: float) -> float:
    """Hydrostatic pressure ``dH`` [m] above a layer's base at ``p_base`` [Pa] (barometric formula)."""
    if L == 0.0:
        return p_base * math.exp(-G0_M_S2 * dH / (R_AIR_J_KG_K * T_base))
    return p_base * (1.0 + L * dH / T_base) ** (-G0_M_S2 / (R_AIR_J_KG_K * L))


def _base_pressures() -> tuple[float, float, float]:
    p1 = _p_in_layer(P0_PA, LAYER_H_M[1] - LAYER_H_M[0], LAYER_T_K[0], LAYER_L_K_M[0])
    p2 = _p_in_layer(p1, LAYER_H_M[2] - LAYER_H_M[1], LAYER_T_K[1], LAYER_L_K_M[1])
    return (P0_PA, p1, p2)


#: Pressure at the base of each layer [Pa] (22632.06 Pa at 11 km, 5474.89 Pa at 20 km).
LAYER_P_PA: tuple[float, float, float] = _base_pressures()
RHO0_KG_M3: float = P0_PA / (R_AIR_J_KG_K * T0_K)
A0_M_S: float = math.sqrt(GAMMA_AIR * R_AIR_J_KG_K * T0_K)


@jitable
def isa_T_p(alt_m: float, dT_isa_K: float) -> tuple[float, float]:
    """Static temperature [K] and pressure [Pa] at geopotential altitude ``alt_m`` [m] with the ISA
    deviation ``dT_isa_K`` [K]. No range check (see :func:`check`); plain floats, so numba compiles it."""
    i = 0 if alt_m < LAYER_H_M[1] else (1 if alt_m < LAYER_H_M[2] else 2)
    H0, T0, L = LAYER_H_M[i], LAYER_T_K[i], LAYER_L_K_M[i]
    dH = alt_m - H0
    if L == 0.0:
        p = LAYER_P_PA[i] * math.exp(-G0_M_S2 * dH / (R_AIR_J_KG_K * T0))
    else:
        p = LAYER_P_PA[i] * (1.0 + L * dH / T0) ** (-G0_M_S2 / (R_AIR_J_KG_K * L))
    return T0 + L * dH + dT_isa_K, p


class AtmosphereRangeError(ValueError):
    """An altitude or temperature deviation outside the standard's range (the message names it)."""


def check(alt_m: float, dT_isa_K: float = 0.0) -> str | None:
    """``None`` if ``alt_m`` [m] and ``dT_isa_K`` [K] lie in the valid range, else what is wrong."""
    if not (ALT_MIN_M <= alt_m <= ALT_MAX_M):
        return f"altitude {alt_m!r} m is outside the valid range {ALT_MIN_M:g} to {ALT_MAX_M:g} m"
    if not math.isfinite(dT_isa_K):
        return f"ISA deviation {dT_isa_K!r} K is not a finite number"
    T = isa_T_p(alt_m, dT_isa_K)[0]
    if not (T_MIN_K <= T <= T_MAX_K):
        return (f"ISA deviation {dT_isa_K!r} K gives {T:.2f} K at {alt_m:g} m, outside the valid range "
                f"{T_MIN_K:g} to {T_MAX_K:g} K")
    return None


@fast_init  # built once per step by the FCS: see records.py
@dataclass(frozen=True, slots=True)
class Atmosphere:
    """Static ambient state: temperature [K], pressure [Pa], density [kg/m^3] (ideal gas, R of dry
    air) and speed of sound [m/s] (gamma 1.4, the standard's value)."""

    T_K: float
    p_Pa: float
    rho_kg_m3: float
    a_m_s: float


def isa(alt_m: float, dT_isa_K: float = 0.0) -> Atmosphere:
    """The ISA at geopotential (pressure) altitude ``alt_m`` [m] with deviation ``dT_isa_K`` [K].

    Raises
    ------
    AtmosphereRangeError
        If the altitude lies outside -1000 to 32000 m or the temperature outside 150 to 350 K.
    """
    if not (ALT_MIN_M <= alt_m <= ALT_MAX_M):
        raise AtmosphereRangeError(f"isa: {check(alt_m, dT_isa_K)}")
    T, p = isa_T_p(alt_m, dT_isa_K)
    if not (T_MIN_K <= T <= T_MAX_K):           # also a NaN deviation
        raise AtmosphereRangeError(f"isa: {check(alt_m, dT_isa_K)}")
    return Atmosphere.make(T, p, *rho_a(T, p))


@jitable
def rho_a(T_K: float, p_Pa: float) -> tuple[float, float]:
    """Density [kg/m^3] (ideal gas, R of dry air) and speed of sound [m/s] (gamma 1.4) at ``T_K`` [K], ``p_Pa``
    [Pa]: the standard's, for :func:`isa` and the FCS's compiled laws."""
    return p_Pa / (R_AIR_J_KG_K * T_K), math.sqrt(GAMMA_AIR * R_AIR_J_KG_K * T_K)


def sutherland_viscosity(T_K: float) -> float:
    """Dynamic viscosity of air by Sutherland's law [Pa s]: ``1.458e-6 T^1.5 / (T + 110.4)`` (ISO 2533,
    the standard's own constants)."""
    return 1.458e-6 * T_K ** 1.5 / (T_K + 110.4)
