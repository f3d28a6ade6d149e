"""Lateral guidance on real coordinates: L1 path following of great-circle legs,
waypoint sequencing and orbits, producing bank-angle commands.

L1 guidance (Park, Deyst & How 2004): a reference point is taken on the path at
the distance L1 ahead of the aircraft; with eta the angle from the ground
velocity to the line of sight to that point, the lateral acceleration command is

    a_cmd = 2 Vg^2 sin(eta) / L1,        phi_cmd = atan(a_cmd / g),

which for small errors is a PD law on the cross-track error with natural period
T and damping zeta when L1 = zeta T Vg / pi. Legs are great circles (the cross
track distance and the path direction at the foot of the aircraft come from
:mod:`openemss.models.mission.geo`); in the aircraft's neighbourhood the path is treated as the straight
line tangent to the great circle, which is exact to far below a metre within L1
(a few kilometres). Orbits use the line tangent to the circle at the aircraft's
radial plus the centripetal feed-forward dir Vg^2 / R; the equilibrium is then
exactly on the circle (no steady radius error).

Cross-track distances are positive to the right of the path; orbit direction
+1 is clockwise seen from above (right turns), -1 counter-clockwise.

References
----------
S. Park, J. Deyst, J. P. How, "A new nonlinear guidance logic for trajectory
tracking", AIAA Guidance, Navigation and Control Conference, AIAA 2004-4900.
S. Park, J. Deyst, J. P. How, "Performance and Lyapunov stability of a nonlinear
path-following guidance method", J. Guidance, Control, and Dynamics 30(6), 2007.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.records import fast_init
from ..mission.geo import (
    LatLon,
    central_angle_rad,
    destination,
    distance_m,
    final_bearing_rad,
    initial_bearing_rad,
    track_position_m,
    wrap_pi,
)
from .atmosphere import G0_M_S2
from .clip import clip
from .errors import FcsError
from .tunable import Tunable, load_params

__all__ = ["GuidanceParams", "PathCommand", "L1Guidance", "WaypointSequencer", "OrbitTracker"]


@dataclass(frozen=True, slots=True)
class GuidanceParams:
    """L1 guidance parameters (data/lateral.yaml, section ``guidance``)."""

    L1_period_s: float
    L1_damping: float
    L1_min_turn_radii: float
    L1_orbit_max_radii: float
    L1_min_m: float
    phi_max_rad: float
    wp_accept_m: float
    wp_fly_by: bool
    fly_by_bank_frac: float
    orbit_capture_frac: float
    orbit_capture_track_rad: float
    outer_period_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> GuidanceParams:
        """Parameter set of ``data/lateral.yaml``, section ``guidance``."""
        return load_params(cls, "lateral.yaml", "guidance", **overrides)


@fast_init
@dataclass(frozen=True, slots=True)
class PathCommand:
    """Guidance result.

    Attributes
    ----------
    phi_cmd_rad : float
        Bank-angle command [rad].
    track_cmd_rad : float
        Direction of the path at the aircraft [rad] (for display and plots).
    xtk_m : float
        Cross-track error, right of the path positive [m] (orbit: dir (R - r)).
    dist_to_go_m : float
        Distance to the end of the leg [m] (orbit: distance to the circle).
    eta_rad : float
        L1 angle from the ground velocity to the reference point [rad].
    """

    phi_cmd_rad: float
    track_cmd_rad: float
    xtk_m: float
    dist_to_go_m: float
    eta_rad: float


class L1Guidance(Tunable[GuidanceParams]):
    """L1 path following of great-circle legs and circles."""

    tunable_name = "guidance"

    def __init__(self, params: GuidanceParams | None = None) -> None:
        self._params = params if params is not None else GuidanceParams.from_file()
        #: the last leg flown: (start, end, length [m], initial course [rad])
        self._leg: tuple[LatLon | None, LatLon | None, float, float] = (None, None, 0.0, 0.0)
        self._tan_phi: tuple[GuidanceParams | None, float] = (None, 0.0)  # (parameters, tan of the bank limit)

    def turn_radius_m(self, vg_m_s: float) -> float:
        """Radius of a level turn at the bank limit, Vg^2 / (g tan phi_max) [m]."""
        cached = self._tan_phi
        if cached[0] is not self._params:  # once per parameter set (a new set replaces the old one)
            cached = self._tan_phi = (self._params, math.tan(max(self._params.phi_max_rad, 1e-3)))
        return vg_m_s * vg_m_s / (G0_M_S2 * cached[1])

    def l1_m(self, vg_m_s: float) -> float:
        """L1 distance for ground speed ``vg_m_s`` [m].

        zeta T Vg / pi, but at least ``L1_min_turn_radii`` turn radii at the bank limit:
        the 2 Vg^2/L1 law asks for more than the bank limit allows when L1 is shorter than
        about one turn radius, and then overshoots a large-offset capture. At 50 m/s
        the first term governs; at jet speeds (150-250 m/s, turn radii 4-11 km) the second.
        """
        p = self._params
        # max of the three written out (the builtin costs ~0.1 us a call; the same value: the first largest)
        L1 = p.L1_damping * p.L1_period_s * vg_m_s / math.pi
        b = p.L1_min_turn_radii * self.turn_radius_m(vg_m_s)
        L1 = b if b > L1 else L1
        return p.L1_min_m if p.L1_min_m > L1 else L1

    def _command(self, path_brg: float, xtk: float, vn: float, ve: float, ff_m_s2: float,
                 dist_to_go: float, L1_max_m: float = math.inf, psi_rad: float | None = None,
                 damping: float | None = None) -> PathCommand:
        vg = math.hypot(vn, ve)
        L1 = self.l1_m(vg)  # min(L1, L1_max_m) and max(cos, 0.5) below written out (as in l1_m)
        L1 = L1_max_m if L1_max_m < L1 else L1
        chi = math.atan2(ve, vn) if vg > 1.0 else path_brg
        if abs(xtk) < L1:
            brg_l1 = path_brg - math.asin(xtk / L1)
        else:
            brg_l1 = path_brg - math.copysign(math.pi / 2, xtk)
        eta = wrap_pi(brg_l1 - chi)
        s = math.sin(eta) if abs(eta) <= math.pi / 2 else math.copysign(1.0, eta)
        a = 2.0 * vg * vg * s / L1 + ff_m_s2
        if damping is not None and damping > _L1_DAMPING and abs(xtk) < L1:
            # near the line L1 is the PD law y'' = -(2 Vg/L1) y' - 2 (Vg/L1)^2 y: damping 1/sqrt(2); the
            # cross-track rate's extra term raises it to ``damping``: (2 sqrt(2) damping - 2) Vg/L1
            a -= (2.0 * math.sqrt(2.0) * damping - 2.0) * vg / L1 * vg * math.sin(wrap_pi(chi - path_brg))
        if psi_rad is not None:
            # the air-relative velocity turns; its part normal to the ground track is cos(crab) of it
            c = math.cos(wrap_pi(psi_rad - chi))
            a /= 0.5 if 0.5 > c else c
        lim = self._params.phi_max_rad
        phi = clip(math.atan(a / G0_M_S2), -lim, lim)
        return PathCommand.make(phi, path_brg, xtk, dist_to_go, eta)

    def line(self, path_brg_rad: float, xtk_m: float, vn_m_s: float, ve_m_s: float,
             psi_rad: float | None = None, dist_to_go_m: float = math.inf, damping: float | None = None) -> PathCommand:
        """Follow a straight line given by its direction [rad] and the cross-track error [m] (right +).

        For paths whose geometry is computed elsewhere, e.g. a runway centre line in the
        WGS-84 tangent plane of its threshold (:mod:`.approach`). ``damping`` [-], when above L1's own
        1/sqrt(2), adds cross-track rate feedback near the line for that damping ratio (a localizer
        captured without overshoot).
        """
        return self._command(path_brg_rad, xtk_m, vn_m_s, ve_m_s, 0.0, dist_to_go_m, psi_rad=psi_rad,
                             damping=damping)

    def leg(self, pos: LatLon, vn_m_s: float, ve_m_s: float, start: LatLon, end: LatLon,
            psi_rad: float | None = None) -> PathCommand:
        """Follow the great circle ``start`` -> ``end``.

        Parameters
        ----------
        pos : LatLon
            Aircraft position.
        vn_m_s, ve_m_s : float
            Ground velocity north and east [m/s].
        start, end : LatLon
            The leg.
        psi_rad : float, optional
            True heading [rad]; with it the command allows for the wind's crab angle
            (the acceleration normal to the track is cos(crab) of the air-relative one).
        """
        leg = self._leg
        if leg[0] is not start or leg[1] is not end:  # the leg's length and course, once per leg
            leg_len = distance_m(start, end)
            if leg_len == 0.0:
                raise FcsError(f"guidance: leg from ({start.lat_deg:.6f}, {start.lon_deg:.6f}) deg to itself; "
                               "a leg needs two distinct points")
            leg = self._leg = (start, end, leg_len, initial_bearing_rad(start, end))
        leg_len, course = leg[2], leg[3]
        xtk, atk = track_position_m(start, end, pos, course_rad=course)
        foot = destination(start, course, atk)
        path_brg = (initial_bearing_rad(foot, end) if leg_len - atk > 1.0 else final_bearing_rad(start, end))
        return self._command(path_brg, xtk, vn_m_s, ve_m_s, 0.0, leg_len - atk, psi_rad=psi_rad)

    def orbit(self, pos: LatLon, vn_m_s: float, ve_m_s: float, center: LatLon, radius_m: float,
              direction: int, psi_rad: float | None = None) -> PathCommand:
        """Follow the circle of ``radius_m`` around ``center``; ``direction`` +1 clockwise, -1 counter-clockwise.

        ``psi_rad`` (true heading [rad], optional) lets the command allow for the crab angle.
        """
        if direction not in (1, -1):
            raise FcsError(f"guidance.orbit: direction {direction!r}; allowed: +1 (clockwise), -1 (counter-clockwise)")
        r = distance_m(center, pos)
        brg_c = initial_bearing_rad(center, pos) if r > 1e-3 else math.atan2(ve_m_s, vn_m_s)
        path_brg = brg_c + direction * math.pi / 2
        xtk = direction * (radius_m - r)
        vg2 = vn_m_s * vn_m_s + ve_m_s * ve_m_s
        return self._command(path_brg, xtk, vn_m_s, ve_m_s, direction * vg2 / radius_m, abs(r - radius_m),
                             self._params.L1_orbit_max_radii * radius_m, psi_rad)


#: Damping ratio of the L1 law near its path (Park, Deyst & How 2004: the linearised law) [-].
_L1_DAMPING = 1.0 / math.sqrt(2.0)

#: Sharpest course change flown by (turn anticipated) with ``wp_fly_by``; sharper ones are flown over [rad].
FLY_BY_MAX_TURN_RAD = math.radians(120.0)


class WaypointSequencer:
    """Steps through a list of waypoints, following the great-circle leg to the next one.

    A waypoint counts as passed when the aircraft is within ``wp_accept_m`` of it, or
    when the along-track distance of its leg is flown (the aircraft is abeam or beyond),
    or -- with ``wp_fly_by`` set: fly-by waypoints, as in ARINC 424 -- when the distance to go is below the
    turn anticipation R tan(|dpsi|/2), with dpsi the course change to the next leg and R
    the turn radius at ``fly_by_bank_frac`` (80 %) of the bank limit, for course changes up to
    FLY_BY_MAX_TURN_RAD (120 deg; sharper ones are flown over). Fly-by turns stay close to the legs but
    pass the waypoint at a distance of the order of R (1/cos(dpsi/2) - 1) or more;
    fly-over (the default) passes within ``wp_accept_m`` and overshoots the next leg.

    Parameters
    ----------
    guidance : L1Guidance
        The path follower (its parameters give the acceptance distance).
    waypoints : sequence of LatLon
        Waypoints in order.
    start : LatLon
        Start of the first leg (the aircraft position when the section begins).
    then : LatLon, optional
        Where the aircraft goes after the last waypoint (e.g. the first waypoint of the next
        section): with fly-by, the turn at the last waypoint is anticipated towards it too.
    """

    def __init__(self, guidance: L1Guidance, waypoints: list[LatLon], start: LatLon,
                 then: LatLon | None = None) -> None:
        if not waypoints:
            raise FcsError("waypoint following needs at least one waypoint")
        self._g = guidance
        self._wps = list(waypoints)
        self._then = then
        self._dpsi: tuple[int, float | None] = (-1, None)  # course change at the active waypoint, by index
        self._tan_fly_by: tuple[GuidanceParams | None, float] = (None, 0.0)  # tan of the fly-by bank, by parameters
        self._prev = start
        self.index = 0
        if central_angle_rad(start, self._wps[0]) == 0.0:  # starting on the first waypoint
            self._prev, self.index = self._wps[0], 1

    @property
    def done(self) -> bool:
        """All waypoints passed."""
        return self.index >= len(self._wps)

    @property
    def leg(self) -> tuple[LatLon, LatLon]:
        """Current leg (from, to); after the last waypoint, the last leg."""
        i = min(self.index, len(self._wps) - 1)
        return self._prev, self._wps[i]

    def _course_change(self, a: LatLon, b: LatLon) -> float | None:
        """Course change at the active waypoint ``b`` (leg a -> b, then on) [rad]; None after the last
        waypoint with nothing to turn to. Computed once per waypoint."""
        if self._dpsi[0] != self.index:
            nxt = self._wps[self.index + 1] if self.index + 1 < len(self._wps) else \
                (self._then if self.index + 1 == len(self._wps) else None)
            dpsi = None if nxt is None else wrap_pi(initial_bearing_rad(b, nxt) - final_bearing_rad(a, b))
            self._dpsi = (self.index, dpsi)
        return self._dpsi[1]

    def step(self, pos: LatLon, vn_m_s: float, ve_m_s: float, psi_rad: float | None = None) -> PathCommand:
        """Guidance along the current leg; advances to the next waypoint when this one is passed."""
        a, b = self.leg
        cmd = self._g.leg(pos, vn_m_s, ve_m_s, a, b, psi_rad)
        lead = 0.0
        dpsi = self._course_change(a, b) if self._g.parameters.wp_fly_by else None
        if dpsi is not None:
            vg = math.hypot(vn_m_s, ve_m_s)
            gp = self._g.parameters
            if self._tan_fly_by[0] is not gp:  # once per parameter set
                self._tan_fly_by = (gp, math.tan(gp.fly_by_bank_frac * max(gp.phi_max_rad, 1e-3)))
            r = vg * vg / (G0_M_S2 * self._tan_fly_by[1])
            # a turn sharper than FLY_BY_MAX_TURN_RAD is flown over, as FMSs do: its anticipation would
            # exceed several turn radii and cut the waypoint off altogether
            lead = r * math.tan(abs(dpsi) / 2) if abs(dpsi) <= FLY_BY_MAX_TURN_RAD else 0.0
        if not self.done and (cmd.dist_to_go_m <= lead or distance_m(pos, b) < self._g.parameters.wp_accept_m):
            self._prev = b
            self.index += 1
            if not self.done:
                cmd = self._g.leg(pos, vn_m_s, ve_m_s, *self.leg, psi_rad)
        return cmd


class OrbitTracker:
    """Orbits a point and counts completed turns once the circle is captured.

    Parameters
    ----------
    guidance : L1Guidance
        The path follower.
    center : LatLon
        Centre of the orbit.
    radius_m : float
        Radius [m].
    direction : int
        +1 clockwise, -1 counter-clockwise.
    turns : float
        Number of turns to fly after capture.
    """

    def __init__(self, guidance: L1Guidance, center: LatLon, radius_m: float, direction: int, turns: float) -> None:
        self._g = guidance
        self.center, self.radius_m, self.direction, self.turns = center, radius_m, direction, turns
        self.captured = False
        self.swept_rad = 0.0
        self._brg_prev: float | None = None

    @property
    def turns_flown(self) -> float:
        """Turns completed since capture [-]."""
        return self.swept_rad / (2.0 * math.pi)

    @property
    def done(self) -> bool:
        """The requested number of turns has been flown."""
        return self.turns_flown >= self.turns

    def step(self, pos: LatLon, vn_m_s: float, ve_m_s: float, psi_rad: float | None = None) -> PathCommand:
        """Guidance on the circle; updates capture and the swept angle."""
        cmd = self._g.orbit(pos, vn_m_s, ve_m_s, self.center, self.radius_m, self.direction, psi_rad)
        brg = initial_bearing_rad(self.center, pos) if distance_m(self.center, pos) > 1.0 else 0.0
        chi = math.atan2(ve_m_s, vn_m_s)
        if (not self.captured and abs(cmd.xtk_m) < self._g.parameters.orbit_capture_frac * self.radius_m
                and abs(wrap_pi(chi - cmd.track_cmd_rad)) < self._g.parameters.orbit_capture_track_rad):
            self.captured = True
        elif self.captured and self._brg_prev is not None:
            self.swept_rad += max(0.0, self.direction * wrap_pi(brg - self._brg_prev))
        self._brg_prev = brg
        return cmd
