"""Great-circle geometry for guidance, and a local tangent plane for the runway.

Navigation (waypoints, orbits, legs of tens to hundreds of kilometres) uses a
sphere of radius :data:`R_EARTH_M`, the IUGG mean Earth radius R1 = (2a + b)/3
of WGS-84. On the ellipsoid, great-circle distances are in error by up to about
0.3 % (Veness); for guidance, where only relative positions to a moving target
matter, that is irrelevant. Where it matters -- the last kilometres of an
approach, where the runway's centre line and glide path must be met to a few
decimetres -- :func:`local_ne_m` maps latitude/longitude into a plane tangent to
the WGS-84 ellipsoid at a reference point (the runway threshold), using the
meridian and prime-vertical radii of curvature there. Its error grows with the
square of the distance: below 1 m at 20 km.

All angles are radians, all distances metres. Bearings and courses are true,
clockwise from north, in [0, 2 pi). Cross-track distances are positive when the
point lies to the **right** of the directed path.

References
----------
E. Williams, "Aviation Formulary V1.47", https://edwilliams.org/avform147.htm.
C. Veness, "Calculate distance, bearing and more between latitude/longitude
points", Movable Type Scripts, https://www.movable-type.co.uk/scripts/latlong.html.
H. Moritz, "Geodetic Reference System 1980", Bulletin Geodesique 54, 1980
(mean radius R1); NIMA TR8350.2, "World Geodetic System 1984", 3rd ed., 2000.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.jit import jitable
from ..infra.records import fast_init
from .errors import GeometryError

__all__ = [
    "R_EARTH_M", "WGS84_A_M", "WGS84_F", "LatLon",
    "wrap_pi", "wrap_2pi", "distance_m", "central_angle_rad", "initial_bearing_rad",
    "final_bearing_rad", "destination", "cross_track_m", "along_track_m", "midpoint",
    "local_ne_m", "from_local_ne", "MIN_LEG_M", "leg_problem",
]

#: Mean Earth radius R1 of WGS-84/GRS 80 [m].
R_EARTH_M: float = 6371008.8
#: WGS-84 semi-major axis [m] and flattening [-] (defining constants of the datum).
WGS84_A_M: float = 6378137.0
WGS84_F: float = 1.0 / 298.257223563

#: Shortest leg with a course, and the least distance from the antipode for one [m]: two fixes closer
#: than this coincide for guidance; two this close to opposite points of the Earth have no defined course.
MIN_LEG_M: float = 1.0

_TWO_PI = 2.0 * math.pi
_E2 = WGS84_F * (2.0 - WGS84_F)  # first eccentricity squared of WGS-84 [-]
_A_1_E2_M = WGS84_A_M * (1.0 - _E2)  # a (1 - e^2) [m]


@fast_init
@dataclass(frozen=True, slots=True)
class LatLon:
    """A point on the Earth.

    Attributes
    ----------
    lat_rad : float
        Geodetic latitude, north positive [rad].
    lon_rad : float
        Longitude, east positive [rad].
    """

    lat_rad: float
    lon_rad: float

    @classmethod
    def from_deg(cls, lat_deg: float, lon_deg: float) -> LatLon:
        """Point from degrees (north and east positive) [deg]."""
        return cls(math.radians(lat_deg), math.radians(lon_deg))

    @property
    def lat_deg(self) -> float:
        """Latitude [deg]."""
        return math.degrees(self.lat_rad)

    @property
    def lon_deg(self) -> float:
        """Longitude [deg]."""
        return math.degrees(self.lon_rad)


@jitable
def wrap_pi(angle_rad: float) -> float:
    """Angle wrapped to [-pi, pi) [rad]."""
    return (angle_rad + math.pi) % _TWO_PI - math.pi


def wrap_2pi(angle_rad: float) -> float:
    """Angle wrapped to [0, 2 pi) [rad]."""
    return angle_rad % _TWO_PI


def central_angle_rad(p1: LatLon, p2: LatLon) -> float:
    """Great-circle angle between two points (haversine formula) [rad]."""
    dlat = p2.lat_rad - p1.lat_rad
    dlon = p2.lon_rad - p1.lon_rad
    a = math.sin(dlat / 2) ** 2 + math.cos(p1.lat_rad) * math.cos(p2.lat_rad) * math.sin(dlon / 2) ** 2
    return 2.0 * math.atan2(math.sqrt(a), math.sqrt(max(0.0, 1.0 - a)))


def distance_m(p1: LatLon, p2: LatLon, radius_m: float = R_EARTH_M) -> float:
    """Great-circle distance on the sphere [m]."""
    return radius_m * central_angle_rad(p1, p2)


def initial_bearing_rad(p1: LatLon, p2: LatLon) -> float:
    """Initial true course of the great circle from ``p1`` to ``p2`` in [0, 2 pi) [rad].

    Raises
    ------
    GeometryError
        If the points coincide (no direction is defined).
    """
    dlon = p2.lon_rad - p1.lon_rad
    y = math.sin(dlon) * math.cos(p2.lat_rad)
    x = math.cos(p1.lat_rad) * math.sin(p2.lat_rad) - math.sin(p1.lat_rad) * math.cos(p2.lat_rad) * math.cos(dlon)
    if abs(x) < 1e-15 and abs(y) < 1e-15:
        what = ("are antipodal (opposite points of the Earth): every great circle through one passes through the "
                "other, so the course between them is undefined" if central_angle_rad(p1, p2) > math.pi / 2 else
                "coincide; a bearing needs two distinct points")
        raise GeometryError(f"initial bearing: points ({p1.lat_deg:.6f}, {p1.lon_deg:.6f}) and "
                            f"({p2.lat_deg:.6f}, {p2.lon_deg:.6f}) deg {what}")
    return wrap_2pi(math.atan2(y, x))


def leg_problem(p1: LatLon, p2: LatLon, radius_m: float = R_EARTH_M) -> str | None:
    """Why the leg from ``p1`` to ``p2`` has no great-circle course, or None when it has one.

    The points coincide (closer than :data:`MIN_LEG_M`), or are antipodal (within :data:`MIN_LEG_M` of
    opposite points of the Earth: every great circle through one passes through the other).
    """
    d_m = distance_m(p1, p2, radius_m)
    if d_m < MIN_LEG_M:
        return f"has no course: the points coincide ({d_m:.3g} m apart; a leg needs at least {MIN_LEG_M:g} m)"
    if math.pi * radius_m - d_m < MIN_LEG_M:
        return ("has no course: the points are antipodal (opposite points of the Earth, "
                f"{d_m / 1e3:.0f} km apart): every great circle through one passes through the other")
    return None


def final_bearing_rad(p1: LatLon, p2: LatLon) -> float:
    """True course on arrival at ``p2`` along the great circle from ``p1`` [rad]."""
    return wrap_2pi(initial_bearing_rad(p2, p1) + math.pi)


def destination(p: LatLon, bearing_rad: float, dist_m: float, radius_m: float = R_EARTH_M) -> LatLon:
    """Point reached from ``p`` after ``dist_m`` along the great circle of initial course ``bearing_rad``."""
    d = dist_m / radius_m
    lat2 = math.asin(math.sin(p.lat_rad) * math.cos(d) + math.cos(p.lat_rad) * math.sin(d) * math.cos(bearing_rad))
    lon2 = p.lon_rad + math.atan2(math.sin(bearing_rad) * math.sin(d) * math.cos(p.lat_rad),
                                  math.cos(d) - math.sin(p.lat_rad) * math.sin(lat2))
    return LatLon(lat2, wrap_pi(lon2))


def cross_track_m(start: LatLon, end: LatLon, p: LatLon, radius_m: float = R_EARTH_M) -> float:
    """Signed distance of ``p`` from the great circle ``start`` -> ``end`` [m], right positive."""
    d13 = central_angle_rad(start, p)
    if d13 == 0.0:
        return 0.0
    t13 = initial_bearing_rad(start, p)
    t12 = initial_bearing_rad(start, end)
    return radius_m * math.asin(max(-1.0, min(1.0, math.sin(d13) * math.sin(t13 - t12))))


def track_position_m(start: LatLon, end: LatLon, p: LatLon, radius_m: float = R_EARTH_M,
                     course_rad: float | None = None) -> tuple[float, float]:
    """(cross-track, along-track) of ``p`` on the great circle ``start`` -> ``end`` [m]: the values of
    :func:`cross_track_m` and :func:`along_track_m`, sharing their distance and bearings (one call per
    guidance step instead of two). ``course_rad``: ``initial_bearing_rad(start, end)`` when the caller
    has it (a leg flown for many steps) [rad]."""
    d13 = central_angle_rad(start, p)
    if d13 == 0.0:
        return 0.0, 0.0
    dt = initial_bearing_rad(start, p) - (initial_bearing_rad(start, end) if course_rad is None else course_rad)
    dxt = math.asin(max(-1.0, min(1.0, math.sin(d13) * math.sin(dt))))
    c = math.cos(dxt)
    dat = math.acos(max(-1.0, min(1.0, math.cos(d13) / c))) if c > 0 else 0.0
    return radius_m * dxt, (radius_m * dat if math.cos(dt) >= 0 else -radius_m * dat)


def along_track_m(start: LatLon, end: LatLon, p: LatLon, radius_m: float = R_EARTH_M) -> float:
    """Distance from ``start`` along the great circle towards ``end`` to the foot of ``p`` [m].

    Negative when the foot lies behind ``start``.
    """
    d13 = central_angle_rad(start, p)
    if d13 == 0.0:
        return 0.0
    dxt = math.asin(max(-1.0, min(1.0, math.sin(d13) * math.sin(initial_bearing_rad(start, p)
                                                                  - initial_bearing_rad(start, end)))))
    c = math.cos(dxt)
    dat = math.acos(max(-1.0, min(1.0, math.cos(d13) / c))) if c > 0 else 0.0
    sign = 1.0 if math.cos(initial_bearing_rad(start, p) - initial_bearing_rad(start, end)) >= 0 else -1.0
    return sign * radius_m * dat


def midpoint(p1: LatLon, p2: LatLon) -> LatLon:
    """Point half-way along the great circle from ``p1`` to ``p2``."""
    dlon = p2.lon_rad - p1.lon_rad
    bx = math.cos(p2.lat_rad) * math.cos(dlon)
    by = math.cos(p2.lat_rad) * math.sin(dlon)
    lat = math.atan2(math.sin(p1.lat_rad) + math.sin(p2.lat_rad),
                     math.hypot(math.cos(p1.lat_rad) + bx, by))
    lon = p1.lon_rad + math.atan2(by, math.cos(p1.lat_rad) + bx)
    return LatLon(lat, wrap_pi(lon))


def _radii_m(lat_rad: float) -> tuple[float, float]:
    """Meridian (M) and prime-vertical (N) radii of curvature of WGS-84 at ``lat_rad`` [m]."""
    s2 = math.sin(lat_rad) ** 2
    w = math.sqrt(1.0 - _E2 * s2)
    return _A_1_E2_M / w**3, WGS84_A_M / w


def local_ne_m(ref: LatLon, p: LatLon, alt_m: float = 0.0) -> tuple[float, float]:
    """North and east offsets of ``p`` from ``ref`` in the WGS-84 tangent plane at ``ref`` [m].

    Parameters
    ----------
    ref : LatLon
        Origin of the plane (e.g. a runway threshold).
    p : LatLon
        The point.
    alt_m : float
        Height of the plane above the ellipsoid [m] (scales the radii; 450 m changes
        distances by 7e-5).

    Returns
    -------
    tuple of float
        (north [m], east [m]).
    """
    m, n = _radii_m(ref.lat_rad)
    north = (m + alt_m) * (p.lat_rad - ref.lat_rad)
    east = (n + alt_m) * math.cos(ref.lat_rad) * wrap_pi(p.lon_rad - ref.lon_rad)
    return north, east


def from_local_ne(ref: LatLon, north_m: float, east_m: float, alt_m: float = 0.0) -> LatLon:
    """Inverse of :func:`local_ne_m`."""
    m, n = _radii_m(ref.lat_rad)
    return LatLon(ref.lat_rad + north_m / (m + alt_m),
                  wrap_pi(ref.lon_rad + east_m / ((n + alt_m) * math.cos(ref.lat_rad))))
