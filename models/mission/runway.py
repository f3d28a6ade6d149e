"""A runway direction of a mission: threshold, heading, elevation, size, and its frame.

Positions relative to a runway are taken in the WGS-84 tangent plane of its threshold
(:func:`.geo.local_ne_m`), exact to centimetres over an approach.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .geo import LatLon, from_local_ne, local_ne_m

__all__ = ["Runway"]


@dataclass(frozen=True, slots=True)
class Runway:
    """A runway direction.

    Attributes
    ----------
    name : str
        Designator, e.g. ``"EDDM 26R"``.
    threshold : LatLon
        Landing threshold on the centre line.
    heading_rad : float
        True heading of the runway direction [rad].
    elevation_m : float
        Threshold elevation above mean sea level [m].
    length_m, width_m : float
        Runway length and width [m].
    """

    name: str
    threshold: LatLon
    heading_rad: float
    elevation_m: float
    length_m: float = 3000.0
    width_m: float = 45.0

    def local(self, pos: LatLon) -> tuple[float, float]:
        """(along, cross) of ``pos`` in the runway frame [m]: along from the threshold in the
        landing direction (negative on the approach), cross right of the centre line positive."""
        n, e = local_ne_m(self.threshold, pos, self.elevation_m)
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return n * c + e * s, -n * s + e * c

    def point(self, along_m: float, cross_m: float = 0.0) -> LatLon:
        """Position at ``along_m`` and ``cross_m`` in the runway frame [m]."""
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return from_local_ne(self.threshold, along_m * c - cross_m * s, along_m * s + cross_m * c, self.elevation_m)
