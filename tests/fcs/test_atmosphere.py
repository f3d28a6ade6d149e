"""ISA and airspeed conversions of the FCS against the standard's tables and physical limits.

Tables: U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), Table I by geopotential
altitude (identical to ISO 2533 / ICAO Doc 7488 below 20 km), five significant figures.
"""

from __future__ import annotations

import math

import pytest

from openemss.models.common.airspeed import cas_from_tas, mach_from_tas, tas_from_cas, tas_from_mach
from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.errors import FcsError


@pytest.mark.parametrize("alt_m, T_K, p_Pa, rho", [
    (0.0, 288.15, 101325.0, 1.2250),
    (5000.0, 255.65, 54020.0, 0.73612),
    (11000.0, 216.65, 22632.0, 0.36392),
    (15000.0, 216.65, 12045.0, 0.19367),
])
def test_isa_table(alt_m: float, T_K: float, p_Pa: float, rho: float) -> None:
    a = isa(alt_m)
    assert a.T_K == pytest.approx(T_K, abs=0.005)
    assert a.p_Pa == pytest.approx(p_Pa, rel=1e-4)  # 5 significant figures in the table
    assert a.rho_kg_m3 == pytest.approx(rho, rel=1e-4)


def test_cas_equals_tas_at_sea_level_and_round_trips() -> None:
    sl = isa(0.0)
    for v in (30.0, 100.0, 250.0):
        assert cas_from_tas(v, sl) == pytest.approx(v, rel=1e-12)
    a = isa(7500.0, dT_isa_K=10.0)
    for v in (60.0, 150.0, 240.0):
        assert cas_from_tas(tas_from_cas(v, a), a) == pytest.approx(v, rel=1e-12)
    assert mach_from_tas(tas_from_mach(0.77, a), a) == pytest.approx(0.77, rel=1e-15)


def test_low_speed_cas_follows_the_series_of_the_impact_pressure() -> None:
    """qc = q (1 + M^2/4 + O(M^4)), so CAS = EAS (1 + (M^2 - M0^2)/8 + O(M^4)), M0 = CAS/a0.

    At 30 m/s and 5000 m the correction is 5e-4 and the neglected terms ~1e-6.
    """
    a = isa(5000.0)
    tas = 30.0
    eas = tas * math.sqrt(a.rho_kg_m3 / 1.225)
    M, M0 = tas / a.a_m_s, eas / 340.294
    assert cas_from_tas(tas, a) == pytest.approx(eas * (1 + (M**2 - M0**2) / 8), rel=1e-5)


def test_cas_above_eas_at_altitude() -> None:
    """Impact pressure exceeds the dynamic pressure, more so at lower static pressure: CAS > EAS."""
    a = isa(7500.0)
    tas = 0.75 * a.a_m_s
    assert cas_from_tas(tas, a) > tas * math.sqrt(a.rho_kg_m3 / 1.225)


def test_out_of_range_altitude() -> None:
    with pytest.raises(FcsError, match=r"valid range \[-1000.0, 20000.0\] m"):
        isa(25000.0)
