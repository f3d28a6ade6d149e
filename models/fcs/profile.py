"""A planned vertical path: altitude over the distance to go, with rounded corners.

The path is a polyline through nodes (s_i, h_i), s the distance to go to the constraint point
[m] (the aircraft flies towards s = 0; beyond the last node the height is held). Each corner
is rounded by a parabola over [s_i - w_i, s_i + w_i] on which the slope changes linearly from
the one side's to the other's: flown at ground speed Vg, the vertical acceleration there is
Vg^2 (b - a) / (2 w), so w_i = Vg^2 |b - a| / (2 n_z g) gives a pull-up (or push-over) of n_z g.
Outside the roundings the path is the polyline. A rounding keeps the heights of both lines
where it joins them: h(s_i -+ w) are on the lines, and at the corner the path passes
(b - a) w / 4 inside it.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

from ..common.atmosphere import G0_M_S2

__all__ = ["VerticalProfile"]


@dataclass(frozen=True, slots=True)
class VerticalProfile:
    """Altitude [m] over distance to go [m], the nodes in increasing s, each corner rounded.

    Attributes
    ----------
    s_m : tuple of float
        Distance to go of the nodes, increasing [m].
    h_m : tuple of float
        Altitude of the nodes [m].
    w_m : tuple of float
        Half-width of each node's rounding [m] (0 at the ends).
    """

    s_m: tuple[float, ...]
    h_m: tuple[float, ...]
    w_m: tuple[float, ...]

    @classmethod
    def rounded(cls, s_m: list[float], h_m: list[float], vg_m_s: list[float], nz_g: float,
                g_m_s2: float = G0_M_S2) -> VerticalProfile:
        """The polyline through (s, h) with each inner corner rounded for a vertical acceleration of
        ``nz_g`` at ground speed ``vg_m_s`` [m/s] (one per node), two roundings shrunk in proportion where
        they would overlap on a segment."""
        n = len(s_m)
        if n < 2 or len(h_m) != n or any(b <= a for a, b in zip(s_m, s_m[1:], strict=False)):
            raise ValueError("a vertical profile needs at least two nodes with increasing distance to go")
        slopes = [(h_m[i + 1] - h_m[i]) / (s_m[i + 1] - s_m[i]) for i in range(n - 1)]
        w = [0.0] * n
        for i in range(1, n - 1):
            w[i] = vg_m_s[i] ** 2 * abs(slopes[i] - slopes[i - 1]) / (2.0 * nz_g * g_m_s2)
        for i in range(n - 1):  # no overlap: two roundings that would share a segment shrink in proportion
            room = s_m[i + 1] - s_m[i]
            if w[i] + w[i + 1] > room:
                f = room / (w[i] + w[i + 1])
                w[i], w[i + 1] = w[i] * f, w[i + 1] * f
        return cls(tuple(s_m), tuple(h_m), tuple(w))

    def _slope(self, i: int) -> float:
        s, h = self.s_m, self.h_m
        if i < 0 or i >= len(s) - 1:
            return 0.0
        return (h[i + 1] - h[i]) / (s[i + 1] - s[i])

    def at(self, s: float) -> tuple[float, float]:
        """(h [m], dh/ds [-]) at distance to go ``s`` [m]; flown towards s = 0, the vertical speed is
        -dh/ds times the ground speed."""
        S, H, W = self.s_m, self.h_m, self.w_m
        if s <= S[0]:
            return H[0], 0.0
        if s >= S[-1]:
            return H[-1], 0.0
        i = bisect.bisect_right(S, s) - 1  # S[i] <= s < S[i + 1]
        for j in (i, i + 1):  # inside the rounding of the node below or above?
            if 0 < j < len(S) - 1 and W[j] > 0.0 and abs(s - S[j]) < W[j]:
                a, b = self._slope(j - 1), self._slope(j)
                u = s - S[j] + W[j]
                return H[j] + a * (s - S[j]) + (b - a) * u * u / (4.0 * W[j]), a + (b - a) * u / (2.0 * W[j])
        a = self._slope(i)
        return H[i] + a * (s - S[i]), a
