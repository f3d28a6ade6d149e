"""ISA atmosphere and airspeed conversions (Mach, CAS, TAS) for the guidance laws.

The atmosphere is :mod:`openemss.models.common.atmosphere` (ISO 2533:1975), the one shared by the
engine, the airframe and the FCS (``build-fmus`` vendors it into each FMU); this module adds the
airspeed conversions and raises the FCS's own error type for an altitude outside the range.

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

from ..common import atmosphere as _atm
from ..common.atmosphere import T_MAX_K, T_MIN_K, Atmosphere, isa_T_p, rho_a
from ..infra.jit import jitable
from .errors import FcsError

__all__ = ["Atmosphere", "isa", "isa_values", "tas_from_mach", "mach_from_tas", "tas_from_cas", "cas_from_tas",
           "tas_from_cas_values", "cas_from_tas_values", "G0_M_S2", "ALT_MAX_M"]

G0_M_S2: float = _atm.G0_M_S2
_P0_PA = _atm.P0_PA
_A0_M_S = _atm.A0_M_S
#: Valid geopotential altitude range [m] of the FCS's laws.
ALT_MIN_M: float = _atm.ALT_MIN_M
ALT_MAX_M: float = 20000.0


def isa(alt_m: float, dT_isa_K: float = 0.0) -> Atmosphere:
    """ISA at geopotential (pressure) altitude ``alt_m`` [m] with deviation ``dT_isa_K`` [K].

    Raises
    ------
    FcsError
        If the altitude is outside [-1000, 20000] m or the deviation leaves the standard's temperatures.
    """
    last = _LAST
    if alt_m == last[0] and dT_isa_K == last[1]:  # the FCS asks several times per step for the same altitude
        return last[2]
    if not (ALT_MIN_M <= alt_m <= ALT_MAX_M):
        raise FcsError(f"isa: altitude {alt_m:.1f} m outside the valid range [{ALT_MIN_M}, {ALT_MAX_M}] m")
    try:
        atm = _atm.isa(alt_m, dT_isa_K)
    except _atm.AtmosphereRangeError as exc:
        raise FcsError(str(exc)) from None
    last[:] = (alt_m, dT_isa_K, atm)
    return atm


@jitable
def isa_values(alt_m: float, dT_isa_K: float) -> tuple[float, float, float, float, bool]:
    """:func:`isa` on plain floats for the compiled laws: (T [K], p [Pa], rho [kg/m^3], a [m/s], in range); out
    of :func:`isa`'s range the last is False (the caller raises :func:`isa`'s error) and the values are finite."""
    ok = ALT_MIN_M <= alt_m <= ALT_MAX_M
    T, p = isa_T_p(alt_m if ok else 0.0, dT_isa_K)
    if not (T_MIN_K <= T <= T_MAX_K):           # also a NaN deviation
        ok, T = False, _atm.T0_K
    rho, a = rho_a(T, p)
    return T, p, rho, a, ok


#: The last (altitude, deviation, atmosphere) of :func:`isa` (an Atmosphere is frozen: it may be shared).
_LAST: list = [math.nan, math.nan, None]


def tas_from_mach(mach: float, atm: Atmosphere) -> float:
    """True airspeed for Mach number ``mach`` [m/s]."""
    return mach * atm.a_m_s


def mach_from_tas(tas_m_s: float, atm: Atmosphere) -> float:
    """Mach number for true airspeed ``tas_m_s`` [-]."""
    return tas_m_s / atm.a_m_s


@jitable
def _qc_from_mach(mach: float, p_Pa: float) -> float:
    return p_Pa * ((1.0 + 0.2 * mach * mach) ** 3.5 - 1.0)


@jitable
def _mach_from_qc(qc_Pa: float, p_Pa: float) -> float:
    return math.sqrt(5.0 * ((qc_Pa / p_Pa + 1.0) ** (2.0 / 7.0) - 1.0))


def tas_from_cas(cas_m_s: float, atm: Atmosphere) -> float:
    """True airspeed for calibrated airspeed ``cas_m_s`` (subsonic) [m/s]."""
    return tas_from_cas_values(cas_m_s, atm.p_Pa, atm.a_m_s)


def cas_from_tas(tas_m_s: float, atm: Atmosphere) -> float:
    """Calibrated airspeed for true airspeed ``tas_m_s`` (subsonic) [m/s]."""
    return cas_from_tas_values(tas_m_s, atm.p_Pa, atm.a_m_s)


@jitable
def tas_from_cas_values(cas_m_s: float, p_Pa: float, a_m_s: float) -> float:
    """:func:`tas_from_cas` at static pressure ``p_Pa`` [Pa] and speed of sound ``a_m_s`` [m/s]."""
    qc = _qc_from_mach(cas_m_s / _A0_M_S, _P0_PA)
    return _mach_from_qc(qc, p_Pa) * a_m_s


@jitable
def cas_from_tas_values(tas_m_s: float, p_Pa: float, a_m_s: float) -> float:
    """:func:`cas_from_tas` at static pressure ``p_Pa`` [Pa] and speed of sound ``a_m_s`` [m/s]."""
    qc = _qc_from_mach(tas_m_s / a_m_s, p_Pa)
    return _mach_from_qc(qc, _P0_PA) * _A0_M_S
