"""The ISA atmosphere for the guidance laws: the FCS's range and error type.

The atmosphere is :mod:`openemss.models.common.atmosphere` (ISO 2533:1975), the one shared by the
engine, the airframe and the FCS (``build-fmus`` vendors it into each FMU); this module limits it to
the FCS's altitudes, keeps the last answer (the FCS asks several times per step for the same altitude)
and raises the FCS's own error type outside the range. The airspeed conversions (Mach, CAS, TAS) are
:mod:`openemss.models.common.airspeed`.

References
----------
ISO 2533:1975, "Standard Atmosphere". NOAA-S/T 76-1562, "U.S. Standard Atmosphere, 1976".
"""

from __future__ import annotations

import math

from ..common import atmosphere as _atm
from ..common.atmosphere import T_MAX_K, T_MIN_K, Atmosphere, isa_T_p, rho_a
from ..infra.jit import jitable
from .errors import FcsError

__all__ = ["Atmosphere", "isa", "isa_values", "G0_M_S2", "ALT_MAX_M"]

G0_M_S2: float = _atm.G0_M_S2
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
