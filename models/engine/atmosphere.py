"""International Standard Atmosphere with a temperature deviation, and the free stream.

The ISA (ISO 2533:1975) is :mod:`openemss.models.common.atmosphere`, the one atmosphere of
engine, airframe and FCS; this module gives the engine's view of it (:class:`Ambient`, with the
altitude and deviation it was made for) and the free stream.

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

from dataclasses import dataclass

import numpy as np

from ..common import atmosphere as _atm
from .errors import OutOfRangeError
from .flow import FlowStation, flow_TP
from .gas import DEFAULT_GAS, GasModel
from .jit_freestream import atm_array
from .jit_freestream import free_stream as _free_stream

__all__ = ["ALT_MIN_M", "ALT_MAX_M", "Ambient", "FreeStream", "isa", "free_stream"]

#: Valid geopotential altitude range [m] (ISO 2533 to 32 km).
ALT_MIN_M: float = _atm.ALT_MIN_M
ALT_MAX_M: float = _atm.ALT_MAX_M


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
    try:
        a = _atm.isa(alt_m, dT_isa_K)
    except _atm.AtmosphereRangeError as exc:
        raise OutOfRangeError(f"atmosphere.{exc}") from None
    return Ambient(alt_m, dT_isa_K, a.T_K, a.p_Pa, a.rho_kg_m3, a.a_m_s)


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
    amb = isa(alt_m, dT_isa_K)                      # raises with the atmosphere's message
    gc, gs = gas.kernel_arrays()
    fs = np.empty(6)
    if _free_stream(gc, gs, atm_array(), float(alt_m), float(Mach), float(dT_isa_K), fs) != 0:
        raise OutOfRangeError(f"atmosphere.free_stream: the totals at {amb.T_K!r} K and Mach {Mach!r} leave the "
                              "gas tables")
    return FreeStream(amb, Mach, float(fs[2]), float(fs[0]), float(fs[1]))
