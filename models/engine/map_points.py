"""Results of a map evaluation: immutable named tuples of floats.

Named tuples rather than frozen dataclasses because a map is evaluated
millions of times in a mission and building a named tuple costs a fraction
of a frozen dataclass's ``__init__`` (measured 0.3 us against 0.55 us); they are
just as immutable and their fields are named and typed.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["CompressorPoint", "CompressorPointD", "TurbinePoint", "TurbinePointD"]


class CompressorPoint(NamedTuple):
    """Compressor map output: corrected flow [kg/s], pressure ratio [-], isentropic efficiency [-]."""

    Wc_kg_s: float
    PR: float
    eff: float


class CompressorPointD(NamedTuple):
    """Compressor map output with partial derivatives with respect to speed and beta.

    ``d*_dnc`` are per unit of the speed argument (``nc_rel`` for a
    :class:`CompressorMap`, ``Nc`` for a :class:`ScaledCompressorMap`);
    ``d*_dbeta`` per unit beta. Flow derivatives in kg/s per unit.
    """

    Wc_kg_s: float
    PR: float
    eff: float
    dWc_dnc: float
    dWc_dbeta: float
    dPR_dnc: float
    dPR_dbeta: float
    deff_dnc: float
    deff_dbeta: float


class TurbinePoint(NamedTuple):
    """Turbine map output: corrected flow [kg/s], isentropic efficiency [-]."""

    Wc_kg_s: float
    eff: float


class TurbinePointD(NamedTuple):
    """Turbine map output with partial derivatives with respect to speed and pressure ratio."""

    Wc_kg_s: float
    eff: float
    dWc_dnc: float
    dWc_dpr: float
    deff_dnc: float
    deff_dpr: float
