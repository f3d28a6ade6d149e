"""Airspeed conversions (Mach, calibrated and true airspeed) in the ISO 2533 atmosphere.

Calibrated airspeed uses the subsonic compressible (Saint-Venant) relation for the impact pressure qc,
the definition of CAS:

    qc = p0 [(1 + 0.2 (CAS/a0)^2)^3.5 - 1] = p [(1 + 0.2 M^2)^3.5 - 1]

with p0 and a0 the standard sea-level pressure and speed of sound (:mod:`.atmosphere`).

References
----------
ISO 2533:1975, "Standard Atmosphere". NOAA-S/T 76-1562, "U.S. Standard Atmosphere, 1976".
E. Williams, "Aviation Formulary V1.47", section "Mach numbers, true vs calibrated airspeeds".
"""

from __future__ import annotations

import math

from ..infra.jit import jitable
from .atmosphere import A0_M_S as _A0_M_S
from .atmosphere import P0_PA as _P0_PA
from .atmosphere import Atmosphere

__all__ = ["tas_from_mach", "mach_from_tas", "tas_from_cas", "cas_from_tas", "tas_from_cas_values",
           "cas_from_tas_values"]


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
