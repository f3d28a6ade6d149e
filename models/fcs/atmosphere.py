"""ISA atmosphere and airspeed conversions (Mach, CAS, TAS) for the guidance laws.

The FCS package cannot import the engine's atmosphere (packages are vendored
into separate FMUs and use relative imports only), so it carries this small
one: the two lowest layers of the ISA (ISO 2533:1975 = U.S. Standard Atmosphere
1976 below 20 km, geopotential altitude), with an ISA temperature deviation
that changes temperature (hence speed of sound) but not pressure. The constants
*are* the standard, so they are written here.

Calibrated airspeed uses the subsonic compressible (Saint-Venant) relation for
the impact pressure qc, the definition of CAS:

    qc = p0 [(1 + 0.2 (CAS/a0)^2)^3.5 - 1] = p [(1 + 0.2 M^2)^3.5 - 1]

References
----------
ISO 2533:1975, "Standard Atmosphere". NOAA-S/T 76-1562, "U.S. Standard Atmosphere, 1976".
E. Williams, "Aviation Formulary V1.47", section "Mach numbers, true vs calibrated airspeeds".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import FcsError

__all__ = ["Atmosphere", "isa", "tas_from_mach", "mach_from_tas", "tas_from_cas", "cas_from_tas",
           "G0_M_S2", "ALT_MAX_M"]

G0_M_S2: float = 9.80665
_R = 287.05287
_GAMMA = 1.4
_T0_K = 288.15
_P0_PA = 101325.0
_A0_M_S = math.sqrt(_GAMMA * _R * _T0_K)
_L_K_M = -0.0065
_H_TROP_M = 11000.0
_T_TROP_K = 216.65
_P_TROP_PA = _P0_PA * (_T_TROP_K / _T0_K) ** (-G0_M_S2 / (_R * _L_K_M))
#: Valid geopotential altitude range [m].
ALT_MIN_M: float = -1000.0
ALT_MAX_M: float = 20000.0


@dataclass(frozen=True, slots=True)
class Atmosphere:
    """Static ambient state.

    Attributes
    ----------
    T_K : float
        Temperature [K].
    p_Pa : float
        Pressure [Pa].
    rho_kg_m3 : float
        Density [kg/m^3].
    a_m_s : float
        Speed of sound [m/s].
    """

    T_K: float
    p_Pa: float
    rho_kg_m3: float
    a_m_s: float


def isa(alt_m: float, dT_isa_K: float = 0.0) -> Atmosphere:
    """ISA at geopotential (pressure) altitude ``alt_m`` [m] with deviation ``dT_isa_K`` [K].

    Raises
    ------
    FcsError
        If the altitude is outside [-1000, 20000] m.
    """
    if not (ALT_MIN_M <= alt_m <= ALT_MAX_M):
        raise FcsError(f"isa: altitude {alt_m:.1f} m outside the valid range [{ALT_MIN_M}, {ALT_MAX_M}] m")
    if alt_m <= _H_TROP_M:
        T_std = _T0_K + _L_K_M * alt_m
        p = _P0_PA * (T_std / _T0_K) ** (-G0_M_S2 / (_R * _L_K_M))
    else:
        T_std = _T_TROP_K
        p = _P_TROP_PA * math.exp(-G0_M_S2 * (alt_m - _H_TROP_M) / (_R * _T_TROP_K))
    T = T_std + dT_isa_K
    return Atmosphere(T, p, p / (_R * T), math.sqrt(_GAMMA * _R * T))


def tas_from_mach(mach: float, atm: Atmosphere) -> float:
    """True airspeed for Mach number ``mach`` [m/s]."""
    return mach * atm.a_m_s


def mach_from_tas(tas_m_s: float, atm: Atmosphere) -> float:
    """Mach number for true airspeed ``tas_m_s`` [-]."""
    return tas_m_s / atm.a_m_s


def _qc_from_mach(mach: float, p_Pa: float) -> float:
    return p_Pa * ((1.0 + 0.2 * mach * mach) ** 3.5 - 1.0)


def _mach_from_qc(qc_Pa: float, p_Pa: float) -> float:
    return math.sqrt(5.0 * ((qc_Pa / p_Pa + 1.0) ** (2.0 / 7.0) - 1.0))


def tas_from_cas(cas_m_s: float, atm: Atmosphere) -> float:
    """True airspeed for calibrated airspeed ``cas_m_s`` (subsonic) [m/s]."""
    qc = _qc_from_mach(cas_m_s / _A0_M_S, _P0_PA)
    return _mach_from_qc(qc, atm.p_Pa) * atm.a_m_s


def cas_from_tas(tas_m_s: float, atm: Atmosphere) -> float:
    """Calibrated airspeed for true airspeed ``tas_m_s`` (subsonic) [m/s]."""
    qc = _qc_from_mach(tas_m_s / atm.a_m_s, atm.p_Pa)
    return _mach_from_qc(qc, _P0_PA) * _A0_M_S
