"""Vertical guidance of a waypoint section: the section's constraint flown with the plans of :mod:`.vnav`.

:class:`RouteDistance` gives the distance to go along the section's legs to its constraint point:
the distance to the active waypoint on its leg, then the legs up to the constraint's waypoint. Each
fly-by turn on the way is shortened by 2 R tan(|dpsi|/2) - R |dpsi|. It ends where the turn at the
constraint's waypoint begins, R tan(|dpsi|/2) before it, with R the turn radius at the planned speed
there (:class:`.guidance.WaypointSequencer`'s anticipation).

:class:`SectionVnav` decides at the section's start whether it climbs, descends or stays level, plans it,
and gives every step the vertical targets and the *vertical mode* (:data:`VNAV_MODES`):

=========  ==========================================================================
ALT        altitude held (level section; before the top of descent; after a capture)
CLIMB      open climb to the constraint at maximum thrust (TECS speed priority)
PATH       managed descent path: altitude and vertical speed of the path, thrust and
           airbrake fly the speed (TECS path priority)
DECEL      deceleration segment, level at the constraint altitude, to the target speed
           (pitch holds the altitude alone, thrust and airbrake fly the speed)
HOLD       planned hold at the constraint's waypoint: a spiral to the constraint altitude
DESCENT    open descent (a section without a plan, or a path left for the speed)
APPROACH   the landing section's approach and landing
=========  ==========================================================================

In flight the descent is checked every ``replan_period_s``. When the aircraft would reach the fix
more than ``unable_margin_m`` high even at the path's steepest gradient, a hold is planned then,
before the fix (flagged), instead of an unplanned loop after it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.records import fast_init
from ..mission.geo import LatLon, distance_m, final_bearing_rad, initial_bearing_rad, wrap_pi
from ..mission.speed import SpeedCommand, SpeedKind
from .atmosphere import G0_M_S2
from .guidance import FLY_BY_MAX_TURN_RAD, GuidanceParams
from .state import AircraftState
from .vnav import ClimbPlan, DescentPlan, Vnav

__all__ = ["VNAV_MODES", "RouteDistance", "SectionVnav", "VerticalTargets", "HoldRecord"]

#: Vertical modes, in the order of their codes (the FMU's Integer output ``vnav_mode``).
VNAV_MODES = ("", "ALT", "CLIMB", "PATH", "DECEL", "HOLD", "DESCENT", "APPROACH")


def turn_radius_m(v_m_s: float, gp: GuidanceParams) -> float:
    """Radius of the fly-by turns at ground speed ``v_m_s`` [m]: the sequencer's, at ``fly_by_bank_frac`` of the
    bank limit."""
    return v_m_s * v_m_s / (G0_M_S2 * math.tan(gp.fly_by_bank_frac * max(gp.phi_max_rad, 1e-3)))


def _turn(a: LatLon, b: LatLon, c: LatLon | None) -> float | None:
    """Course change at ``b`` from the leg a -> b to b -> c [rad] (None without a next point)."""
    if c is None or distance_m(b, c) < 1.0 or distance_m(a, b) < 1.0:
        return None
    return wrap_pi(initial_bearing_rad(b, c) - final_bearing_rad(a, b))


class RouteDistance:
    """Distance to go along a waypoint section's legs to its constraint point.

    Parameters
    ----------
    start : LatLon
        Start of the first leg (as the section's sequencer has it).
    waypoints : list of LatLon
        The section's waypoints.
    then : LatLon or None
        Where the aircraft goes after the last waypoint (for the anticipation of the last turn).
    constraint_index : int
        Index of the constraint's waypoint.
    gp : GuidanceParams
        Guidance parameters (fly-by, bank limit).
    v_turns_m_s, v_fix_m_s : float
        Ground speeds planned at the intermediate turns and at the constraint's waypoint [m/s].
    """

    def __init__(self, start: LatLon, waypoints: list[LatLon], then: LatLon | None, constraint_index: int,
                 gp: GuidanceParams, v_turns_m_s: float, v_fix_m_s: float) -> None:
        pts = [start] + list(waypoints)
        self.constraint_index = constraint_index
        fly_by = bool(gp.wp_fly_by)
        # remaining[i]: legs after waypoint i up to the constraint's waypoint, less the fly-by shortening
        rem = [0.0] * (len(waypoints) + 1)
        for i in range(constraint_index - 1, -1, -1):
            leg = distance_m(waypoints[i], waypoints[i + 1])
            cut = 0.0
            dpsi = _turn(pts[i], waypoints[i], waypoints[i + 1])
            if fly_by and dpsi is not None and abs(dpsi) <= FLY_BY_MAX_TURN_RAD:
                r = turn_radius_m(v_turns_m_s, gp)
                cut = 2.0 * r * math.tan(abs(dpsi) / 2.0) - r * abs(dpsi)
            rem[i] = rem[i + 1] + leg - cut
        self._remaining = rem
        nxt = waypoints[constraint_index + 1] if constraint_index + 1 < len(waypoints) else then
        dpsi = _turn(pts[constraint_index], waypoints[constraint_index], nxt)
        self.lead_m = 0.0
        if fly_by and dpsi is not None and abs(dpsi) <= FLY_BY_MAX_TURN_RAD:
            self.lead_m = turn_radius_m(v_fix_m_s, gp) * math.tan(abs(dpsi) / 2.0)

    def dtg(self, index: int, dist_to_go_m: float) -> float:
        """Distance to go [m] with waypoint ``index`` active at ``dist_to_go_m`` [m] along its leg (< 0 past the
        constraint point)."""
        if index > self.constraint_index:
            return -1.0
        return dist_to_go_m + self._remaining[index] - self.lead_m


@fast_init
@dataclass(frozen=True, slots=True)
class VerticalTargets:
    """What the vertical guidance asks of TECS in one step (see :class:`~.state.Targets`)."""

    alt_cmd_m: float
    hdot_ff_m_s: float
    speed: SpeedCommand
    airbrake: bool
    priority: str | None
    mode: str
    dtg_m: float


@dataclass
class HoldRecord:
    """A planned hold (flagged): where, why, and how it went.

    Attributes
    ----------
    section_index : int
        The section whose constraint needs it.
    planned_at_s : float
        Time the hold was planned [s].
    reason : str
        ``"planned"`` (at the section's start) or ``"unable"`` (found in flight).
    height_m : float
        Height to lose (> 0) or gain (< 0) at the fix when planned [m].
    turns_planned : float
        Turns of the spiral planned [-].
    start_s, end_s : float or None
        When the hold was flown [s].
    """

    section_index: int
    planned_at_s: float
    reason: str
    height_m: float
    turns_planned: float
    start_s: float | None = None
    end_s: float | None = None


class SectionVnav:
    """The vertical guidance of one waypoint section (see the module's docstring).

    Parameters
    ----------
    vnav : Vnav
        The planner.
    gp : GuidanceParams
        The section's guidance parameters (fly-by, bank limit).
    index : int
        The section's index.
    altitude_m : float
        The section's altitude constraint [m].
    speed : SpeedCommand
        The section's speed.
    entry_speed : SpeedCommand or None
        The speed flown when the section begins (the previous section's; None: the true airspeed).
    start : LatLon
        Start of the section's first leg.
    waypoints : list of LatLon
        The section's waypoints; ``constraint_index`` the one the altitude is due at.
    then : LatLon or None
        The next section's first fix (the last turn's anticipation).
    x : AircraftState
        The state at the section's start.
    t_s : float
        Time of the start [s].
    tecs : tuple of float
        TECS's (Vdot_max [m/s^2], k_V [1/s], gamma_max [rad]), for the plans.
    """

    def __init__(self, vnav: Vnav, gp: GuidanceParams, index: int, altitude_m: float, speed: SpeedCommand,
                 entry_speed: SpeedCommand | None, start: LatLon, waypoints: list[LatLon], constraint_index: int,
                 then: LatLon | None, x: AircraftState, t_s: float, tecs: tuple[float, float, float]) -> None:
        self.vnav, self.index, self.h_c, self.speed = vnav, index, altitude_m, speed
        p = vnav.parameters
        self._tecs = tecs
        self.entry = entry_speed if entry_speed is not None else SpeedCommand(x.tas_m_s, SpeedKind.TAS)
        dT = x.dT_isa_K
        dh = altitude_m - x.alt_m
        self.kind = "level" if abs(dh) <= p.level_band_m else ("climb" if dh > 0 else "descent")
        v_fix = speed.tas_m_s(altitude_m, dT)
        self.route = RouteDistance(start, waypoints, then, constraint_index, gp, max(x.tas_m_s, v_fix), v_fix)
        self.fix = waypoints[constraint_index]
        self.descent: DescentPlan | None = None
        self.climb: ClimbPlan | None = None
        self.hold: HoldRecord | None = None
        self._captured = self.kind == "level"
        self._next_check = t_s + p.replan_period_s
        s0 = self._dtg_from(x.pos, start, waypoints)
        self.s_start_m = s0
        if self.kind == "descent":
            self.descent = vnav.plan_descent(x.alt_m, altitude_m, max(s0, 0.0), self.entry, speed, x.mass_kg,
                                             tecs[0], tecs[1], dT)
            if self.descent.hold_height_m > p.hold_exit_m:
                self.hold = HoldRecord(index, t_s, "planned", self.descent.hold_height_m, self.descent.hold_turns)
        elif self.kind == "climb":
            self.climb = vnav.plan_climb(x.alt_m, altitude_m, max(s0, 0.0), speed, x.tas_m_s, x.mass_kg, tecs[2], dT)
            if not self.climb.feasible:
                self.hold = HoldRecord(index, t_s, "planned", -(altitude_m - x.alt_m), math.nan)

    def _dtg_from(self, pos: LatLon, start: LatLon, waypoints: list[LatLon]) -> float:
        """Distance to go from ``pos`` at the start: along the first leg to its waypoint, then the route."""
        from ..mission.geo import track_position_m

        if distance_m(start, waypoints[0]) < 1.0:
            return self.route.dtg(0, distance_m(pos, waypoints[0]))
        _, atk = track_position_m(start, waypoints[0], pos)
        return self.route.dtg(0, distance_m(start, waypoints[0]) - atk)

    @property
    def hold_pending(self) -> bool:
        """A hold at the fix is planned and not yet flown."""
        return self.hold is not None and self.hold.end_s is None

    def step(self, t_s: float, x: AircraftState, index: int, dist_to_go_m: float) -> VerticalTargets:
        """Vertical targets with waypoint ``index`` active, ``dist_to_go_m`` [m] along its leg."""
        s = self.route.dtg(index, dist_to_go_m)
        p = self.vnav.parameters
        if self.kind == "descent" and self.descent is not None:
            d = self.descent
            if s < 0.0:  # past the constraint point (an intermediate waypoint's): hold its altitude
                return VerticalTargets(self.h_c, 0.0, self.speed, False, "path", "ALT", s)
            # where the path levels off ahead (the bottom of descent), its vertical speed is taken
            # ``path_lead_s`` ahead: the level-off needs the thrust back from idle, and the engine's spool-up
            # lags; without the lead the aircraft sinks through the level-off by about its sink rate x the lag.
            # Not at the push-over at the top of descent, where idle comes at once (it would dive below the path)
            h, slope = d.profile.at(s)
            ahead = d.profile.at(s - p.path_lead_s * x.gs_m_s)[1]
            if abs(ahead) < abs(slope):
                slope = ahead
            speed = d.speed_target if s <= d.s_decel_m else d.speed_descent
            if t_s >= self._next_check:
                self._next_check = t_s + p.replan_period_s
                self._check_unable(t_s, x, s)
            if s > d.s_tod_m:
                mode = "ALT"
            elif s > d.s_decel_m or slope != 0.0:
                mode = "PATH"
            else:
                mode = "DECEL"
            prio = "path_only" if mode == "DECEL" else "path"
            if mode == "PATH" and x.tas_m_s > speed.tas_m_s(x.alt_m, x.dT_isa_K) + p.overspeed_m_s:
                prio = "speed"
            return VerticalTargets(h, -slope * x.gs_m_s, speed, mode != "ALT", prio, mode, s)
        if self.kind == "climb" and not self._captured:
            if abs(x.alt_m - self.h_c) < p.level_band_m:
                self._captured = True
            else:
                return VerticalTargets(self.h_c, 0.0, self.speed, False, None, "CLIMB", s)
        return VerticalTargets(self.h_c, 0.0, self.speed, False, "path", "ALT", s)

    def _check_unable(self, t_s: float, x: AircraftState, s: float) -> None:
        """Plan a hold when the fix would be reached more than ``unable_margin_m`` high at the steepest path."""
        p = self.vnav.parameters
        if self.hold is not None or s <= 0.0:
            return
        excess = x.alt_m - self.h_c - s * math.tan(p.gamma_path_max_rad)
        if excess > p.unable_margin_m:
            self.hold = HoldRecord(self.index, t_s, "unable", excess,
                                   self.vnav.hold_turns(excess, self.h_c, self.speed, x.mass_kg, x.dT_isa_K))

    def hold_step(self, t_s: float, x: AircraftState) -> tuple[VerticalTargets, bool]:
        """Vertical targets in the hold at the fix, and whether it is over (within ``hold_exit_m``)."""
        h = self.hold
        assert h is not None
        if h.start_s is None:
            h.start_s = t_s
        done = abs(x.alt_m - self.h_c) < self.vnav.parameters.hold_exit_m
        if done:
            h.end_s = t_s
        return VerticalTargets(self.h_c, 0.0, self.speed, self.kind == "descent", "speed", "HOLD", -1.0), done
