"""Great-circle geometry against published worked examples and identities.

Sources
-------
E. Williams, "Aviation Formulary V1.47" (worked examples, LAX -> JFK: d = 0.623585 rad
= 2144 nm, initial course 1.150035 rad = 66 deg; distances there in arc units,
1 nm = 1 arc minute).
C. Veness, Movable Type Scripts "latlong" page: 50 03 59N 005 42 53W -> 58 38 38N
003 04 12W: 968.9 km (R = 6371 km), initial bearing 009 07 11, final bearing
011 16 31, midpoint 54 21 44N 004 31 50W; destination from 53 19 14N 001 43 47W on
096 01 18 for 124.8 km: 53 11 18N 000 08 00E.
"""

from __future__ import annotations

import math

import pytest

from openemss.models.mission.errors import GeometryError
from openemss.models.mission.geo import (
    LatLon,
    along_track_m,
    central_angle_rad,
    cross_track_m,
    destination,
    distance_m,
    final_bearing_rad,
    from_local_ne,
    initial_bearing_rad,
    local_ne_m,
    midpoint,
    wrap_pi,
)

NM_ARC_RADIUS_M = 1852.0 * 180 * 60 / math.pi  # Williams' sphere: 1 nm per arc minute
ARCSEC = math.radians(1 / 3600)


def dms(d: float, m: float, s: float, sign: int = 1) -> float:
    return sign * (d + m / 60 + s / 3600)


LAX = LatLon.from_deg(dms(33, 57, 0), dms(118, 24, 0, -1))
JFK = LatLon.from_deg(dms(40, 38, 0), dms(73, 47, 0, -1))
P1 = LatLon.from_deg(dms(50, 3, 59), dms(5, 42, 53, -1))
P2 = LatLon.from_deg(dms(58, 38, 38), dms(3, 4, 12, -1))


def test_williams_lax_jfk_distance_and_course() -> None:
    # published to 6 decimals: tolerance is half the last digit
    assert central_angle_rad(LAX, JFK) == pytest.approx(0.623585, abs=5e-7)
    assert initial_bearing_rad(LAX, JFK) == pytest.approx(1.150035, abs=5e-7)
    assert distance_m(LAX, JFK, NM_ARC_RADIUS_M) / 1852 == pytest.approx(2144, abs=0.5)


def test_williams_destination_100nm_on_066_radial() -> None:
    # Williams' worked example, in his radian values: LAX (0.592539, 2.066470 W), radial 1.15 rad,
    # 100 nm -> lat 0.604180 rad = 34.6 N, lon 116.6 W (the longitude is given to 0.1 deg)
    lax = LatLon(0.592539, -2.066470)
    p = destination(lax, 1.15, 100 * 1852, NM_ARC_RADIUS_M)
    assert p.lat_rad == pytest.approx(0.604180, abs=1e-6)  # his inputs are rounded to 1e-6 rad
    assert p.lon_deg == pytest.approx(-116.6, abs=0.05)


def test_veness_distance_bearings_midpoint() -> None:
    assert distance_m(P1, P2, 6371e3) == pytest.approx(968.9e3, abs=0.05e3)  # 4 significant figures
    assert initial_bearing_rad(P1, P2) == pytest.approx(math.radians(dms(9, 7, 11)), abs=0.5 * ARCSEC)
    assert final_bearing_rad(P1, P2) == pytest.approx(math.radians(dms(11, 16, 31)), abs=0.5 * ARCSEC)
    m = midpoint(P1, P2)
    assert m.lat_deg == pytest.approx(dms(54, 21, 44), abs=0.5 / 3600)
    assert m.lon_deg == pytest.approx(dms(4, 31, 50, -1), abs=0.5 / 3600)


def test_veness_destination() -> None:
    start = LatLon.from_deg(dms(53, 19, 14), dms(1, 43, 47, -1))
    p = destination(start, math.radians(dms(96, 1, 18)), 124.8e3, 6371e3)
    # the published distance has 4 significant figures (+-50 m = 1.6 arc s): 2 arc s tolerance
    assert p.lat_deg == pytest.approx(dms(53, 11, 18), abs=2 / 3600)
    assert p.lon_deg == pytest.approx(dms(0, 8, 0), abs=2 / 3600)


@pytest.mark.parametrize("offset_m", [-5000.0, -120.0, 0.0, 37.0, 25000.0])
def test_cross_and_along_track_identities(offset_m: float) -> None:
    """A point built at a right angle off the path is exactly that far off it (spherical right triangle)."""
    a = LatLon.from_deg(48.35, 11.78)
    b = destination(a, math.radians(250), 150e3)
    along = 60e3
    foot = destination(a, initial_bearing_rad(a, b), along)
    course_at_foot = initial_bearing_rad(foot, b)
    p = destination(foot, course_at_foot + math.pi / 2, offset_m)
    assert cross_track_m(a, b, p) == pytest.approx(offset_m, abs=1e-6 * 6371e3 * 1e-6 + 1e-6)
    assert along_track_m(a, b, p) == pytest.approx(along, abs=1e-6)


def test_along_track_behind_start_is_negative() -> None:
    a = LatLon.from_deg(48.0, 11.0)
    b = destination(a, 0.3, 50e3)
    behind = destination(a, 0.3 + math.pi, 2e3)
    assert along_track_m(a, b, behind) == pytest.approx(-2e3, rel=1e-9)


def test_distance_bearing_destination_round_trip() -> None:
    for brg_deg in (0, 45, 135, 180, 262.3, 359):
        q = destination(JFK, math.radians(brg_deg), 3.7e5)
        assert distance_m(JFK, q) == pytest.approx(3.7e5, rel=1e-12)
        assert wrap_pi(initial_bearing_rad(JFK, q) - math.radians(brg_deg)) == pytest.approx(0.0, abs=1e-12)


def test_local_plane_agrees_with_sphere_near_origin_and_inverts() -> None:
    """Within 20 km the tangent plane and the sphere agree to the ellipsoid's radius ratio (<0.5 %)."""
    ref = LatLon.from_deg(48.3538, 11.7861)
    for brg_deg in (0, 82, 180, 262):
        q = destination(ref, math.radians(brg_deg), 20e3)
        n, e = local_ne_m(ref, q)
        assert math.hypot(n, e) == pytest.approx(20e3, rel=5e-3)
        back = from_local_ne(ref, n, e)
        assert back.lat_rad == pytest.approx(q.lat_rad, abs=1e-14)
        assert back.lon_rad == pytest.approx(q.lon_rad, abs=1e-14)


def test_coincident_points_have_no_bearing() -> None:
    with pytest.raises(GeometryError, match="coincide"):
        initial_bearing_rad(LAX, LAX)


def test_track_position_equals_cross_and_along_track() -> None:
    """The combined form used by the guidance gives the two separate functions' values (which the tests
    above check against published geometry), to round-off, on both sides and behind the start."""
    import random

    from openemss.models.mission.geo import LatLon, along_track_m, cross_track_m, track_position_m

    rng = random.Random(1)
    for _ in range(200):
        a = LatLon.from_deg(rng.uniform(40, 55), rng.uniform(0, 20))
        b = LatLon.from_deg(rng.uniform(40, 55), rng.uniform(0, 20))
        p = LatLon.from_deg(rng.uniform(40, 55), rng.uniform(0, 20))
        xtk, atk = track_position_m(a, b, p)
        assert xtk == cross_track_m(a, b, p)
        assert abs(atk - along_track_m(a, b, p)) <= 1e-9 * max(1.0, abs(atk))
