"""The mission section types: each one class with its fields, its step and its completion, registered once.

:data:`REGISTRY` maps a section's ``type`` to its class. The mission reader (:mod:`.mission`) takes the
fields and their checks from it, the state machine (:mod:`.state_machine`) makes an executor of the
class when a section starts, and the documentation lists :attr:`SectionType.completion`:

=================  ==============================================================
type               complete when
=================  ==============================================================
Rolling            calibrated airspeed >= ``rotate_cas_m_s``
TakeOff            height above the runway >= ``until_height_agl_m`` (after lift-off)
WaypointFollowing  every waypoint passed (fly-over within ``wp_accept_m`` or abeam;
                   fly-by at the turn anticipation distance), and a planned hold at
                   the constraint's waypoint flown
Orbiting           ``turns`` full turns swept around the centre after capture
GTurns             ``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed
Levelling          ``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``
Landing            stopped on the runway (ground speed < ``v_stop_m_s``)
Custom             ``duration_s`` elapsed
=================  ==============================================================

A new section type is a subclass of :class:`SectionType` with ``@register``: nothing else names it. Its class
also says how the mission check judges it before the flight (:attr:`SectionType.feasibility`, the shipped
checks in :mod:`.feasibility_sections`) and what the report compares after it (:attr:`SectionType.conformance`).
The navigation types (waypoints, orbits, turns, levelling) set :attr:`SectionType.outer_rate`: the state
machine steps them every ``guidance.outer_period_s`` and holds their targets in between.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any, ClassVar

from ..mission.geo import LatLon, wrap_pi
from . import feasibility_sections as checks
from .approach import AutoLand, centreline_steer
from .atmosphere import cas_from_tas, isa
from .guidance import L1Guidance, OrbitTracker, WaypointSequencer
from .runway_checks import check_on_runway
from .state import AircraftState, Targets
from .tecs import SpeedCommand, SpeedKind
from .vertical import SectionVnav

if TYPE_CHECKING:
    from .feasibility_checker import FeasibilityCheck
    from .mission import Section
    from .state_machine import MissionRunner

__all__ = ["Field", "SectionType", "REGISTRY", "register", "CONFORMANCE", "TARGETS", "APPROACH"]

#: A field of a section type: (kind, required, default, (min, max) or choices, unit and help).
Field = tuple[str, bool, Any, Any, str]

#: :attr:`SectionType.conformance` of a section flown to an altitude (and a speed): the report compares them with
#: the flown altitude and speed (``openemss.report.conformance.section_conformance``).
TARGETS = "targets"
#: :attr:`SectionType.conformance` of an ILS approach to a runway: its phases are the approach's
#: (:data:`.approach.APPROACH_PHASES`, the FCS's ``ils_phase``) and the report measures the localizer and glide
#: slope captures (``openemss.report.conformance.ils_conformance``).
APPROACH = "approach"
#: Each conformance kind and the fields a section type of that kind must have.
CONFORMANCE: dict[str, tuple[str, ...]] = {TARGETS: ("altitude_m",), APPROACH: ("runway", "approach_altitude_m")}


class SectionType:
    """A mission section type: its fields (:attr:`fields`), its completion (:attr:`completion`) and,
    as an instance, the executor of one section of that type.

    An executor is made when its section starts (so it can use the state at entry); every step it
    turns the aircraft state into :class:`~.state.Targets` and sets :attr:`done` when complete.

    Class attributes
    ----------------
    type_name : str
        The ``type`` of the mission file.
    fields : dict
        Field name -> (kind, required, default, (min, max) or choices, unit and help), read by
        :func:`.mission.parse_mission`.
    completion : str
        When a section of this type is complete (the documentation and ``emss`` read it).
    speed_field : str or None
        The field holding the speed the section leaves the aircraft at (the next section's
        descent holds it until its deceleration).
    outer_rate : bool
        The section is navigation at the outer loops' rate: its step may be run every
        ``guidance.outer_period_s`` only, its targets held in between (its step must not integrate
        ``dt_s``). False (the default) for the sections that fly the aircraft near the ground
        (take-off, landing) or by the clock (custom commands): they run every step.
    departs_from_runway : bool
        A ground run on the section's ``runway``: a mission that begins with it starts there, on the ground
        (:func:`.runway_checks.check_departure`), and the aircraft must not leave the runway on the ground
        (:func:`.runway_checks.check_on_runway`); the mission check starts there too.
    feasibility : FeasibilityCheck or None
        The section's check before the flight (:mod:`.feasibility`): a function ``(checker, section, state,
        figures) -> end altitude [m]`` (:mod:`.feasibility_checker`); None (the default): not checked, the
        section's verdict is ``n/a`` and a note says ``<type> sections <not_checked>: not checked``.
    not_checked : str
        Why a type without a feasibility check has none (in that note).
    conformance : str or None
        What the report compares after the flight: :data:`TARGETS` (altitude and speed targets),
        :data:`APPROACH` (the ILS captures), or None (nothing); :data:`CONFORMANCE` lists the fields each needs.
    """

    type_name: ClassVar[str] = ""
    fields: ClassVar[dict[str, Field]] = {}
    completion: ClassVar[str] = ""
    speed_field: ClassVar[str | None] = "speed"
    outer_rate: ClassVar[bool] = False
    departs_from_runway: ClassVar[bool] = False
    feasibility: ClassVar[FeasibilityCheck | None] = None
    not_checked: ClassVar[str] = "have no feasibility check"
    conformance: ClassVar[str | None] = None

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        self.sec, self.t0, self.ctx = sec, t_s, ctx
        self.done = False

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        """A problem among the validated field ``values`` that no single field shows, as (field or
        None, what is wrong), or None; ``raw`` is the section as the file gives it."""
        return None

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        """Where a section of this type begins, for the turn anticipation of the fly-by waypoint before it."""
        return None

    def flown_by(self) -> LatLon | None:
        """The last waypoint of the completed section when it was flown by (the next leg starts there)."""
        return None

    @property
    def label(self) -> str:
        """The section as messages name it (:func:`section_label`)."""
        return section_label(self.sec)

    def targets(self, **kw: Any) -> Targets:
        return Targets.make(self.sec.index, self.sec.name, self.sec.type, **kw)

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:  # pragma: no cover - abstract
        raise NotImplementedError


def section_label(sec: Section) -> str:
    """A section as messages name it: ``section 0 (Rolling 'take-off roll')``."""
    return f"section {sec.index} ({sec.type} '{sec.name}')"


#: The section types by their ``type`` name, in the order of the documentation: the one registry
#: that the mission reader, the state machine and the documentation read.
REGISTRY: dict[str, type[SectionType]] = {}


def register(cls: type[SectionType]) -> type[SectionType]:
    """Class decorator: register a section type under its :attr:`~SectionType.type_name` (once).

    Raises
    ------
    ValueError
        When the name is empty or taken, or the type's :attr:`~SectionType.conformance` is not a kind of
        :data:`CONFORMANCE` or its fields lack those the kind needs.
    """
    if not cls.type_name or cls.type_name in REGISTRY:
        raise ValueError(f"section type {cls.__name__}: type_name {cls.type_name!r} is empty or taken")
    if cls.conformance is not None:
        needs = CONFORMANCE.get(cls.conformance)
        if needs is None:
            raise ValueError(f"section type {cls.__name__}: conformance {cls.conformance!r} is not one of "
                             f"{', '.join(CONFORMANCE)} (or None)")
        if missing := [f for f in needs if f not in cls.fields]:
            raise ValueError(f"section type {cls.__name__}: conformance {cls.conformance!r} needs the field(s) "
                             f"{', '.join(missing)}")
    REGISTRY[cls.type_name] = cls
    return cls


@register
class Rolling(SectionType):
    """Rolling section; completes when calibrated airspeed >= ``rotate_cas_m_s``."""

    type_name = "Rolling"
    feasibility = staticmethod(checks.rolling)
    speed_field = None
    departs_from_runway = True
    completion = "calibrated airspeed >= ``rotate_cas_m_s``"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "runway of the take-off roll"),
        "lever": ("number", False, 1.0, (0.0, 1.0), "thrust lever [-]"),
        "rotate_cas_m_s": ("number", True, None, (20.0, 150.0), "ends at this calibrated airspeed [m/s]"),
    }

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        s, rwy = self.sec, self.sec["runway"]
        cas = cas_from_tas(x.tas_m_s, isa(x.alt_m, x.dT_isa_K))
        self.done = cas >= s["rotate_cas_m_s"]
        check_on_runway(rwy, x, t_s, self.label, cas, f"rotation at {s['rotate_cas_m_s']:g} m/s")
        steer = centreline_steer(rwy, self.ctx.approach_params, x.pos, x.psi_rad)
        return self.targets(phase="ROLL", theta_cmd_rad=self.ctx.approach_params.theta_ground_rad, lever=s["lever"],
                            phi_cmd_rad=0.0, align_heading_rad=rwy.heading_rad, track_cmd_rad=rwy.heading_rad,
                            xtk_m=rwy.local(x.pos)[1], steer=steer)


@register
class TakeOff(SectionType):
    """TakeOff section; completes when height above the runway >= ``until_height_agl_m`` (after lift-off)."""

    type_name = "TakeOff"
    feasibility = staticmethod(checks.takeoff)
    speed_field = "climb_speed"
    departs_from_runway = True
    completion = "height above the runway >= ``until_height_agl_m`` (after lift-off)"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "runway (centre line and elevation)"),
        "lever": ("number", False, 1.0, (0.0, 1.0), "thrust lever [-]"),
        "pitch_deg": ("number", False, 10.0, (2.0, 20.0), "rotation pitch attitude [deg]"),
        "rotation_rate_deg_s": ("number", False, 3.0, (0.5, 10.0), "rotation rate [deg/s]"),
        "climb_speed": ("speed", True, None, None, "initial climb speed"),
        "until_height_agl_m": ("number", False, 300.0, (20.0, 3000.0), "ends at this height above the runway [m]"),
    }

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        self.theta_cmd = x.theta_rad
        self.climbing = False
        self.gear_down = True

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        s, rwy = self.sec, self.sec["runway"]
        h_agl = x.alt_m - rwy.elevation_m
        ap = self.ctx.approach_params
        if h_agl > ap.gear_up_agl_m and not x.on_ground:
            self.gear_down = False
        common = dict(lever=s["lever"], track_cmd_rad=rwy.heading_rad, xtk_m=rwy.local(x.pos)[1],
                      gear_down=self.gear_down)
        if not self.climbing and not x.on_ground and h_agl > ap.climb_engage_agl_m:
            self.climbing = True
        if x.on_ground:
            check_on_runway(rwy, x, t_s, self.label, cas_from_tas(x.tas_m_s, isa(x.alt_m, x.dT_isa_K)),
                            f"rotating to {s['pitch_deg']:g} deg of pitch")
        if not self.climbing:
            self.theta_cmd = min(self.theta_cmd + math.radians(s["rotation_rate_deg_s"]) * dt_s,
                                 math.radians(s["pitch_deg"]))
            steer = centreline_steer(rwy, self.ctx.approach_params, x.pos, x.psi_rad) if x.on_ground else 0.0
            return self.targets(phase="ROTATE" if x.on_ground else "LIFTOFF", theta_cmd_rad=self.theta_cmd,
                                phi_cmd_rad=0.0, align_heading_rad=rwy.heading_rad, steer=steer, **common)
        self.done = h_agl >= s["until_height_agl_m"]
        lat = self.ctx.guidance.line(rwy.heading_rad, rwy.local(x.pos)[1], x.vn_m_s, x.ve_m_s, x.psi_rad)
        return self.targets(phase="CLIMB", alt_cmd_m=rwy.elevation_m + s["until_height_agl_m"] + 200.0,
                            speed=s["climb_speed"], phi_cmd_rad=lat.phi_cmd_rad, vnav_mode="CLIMB", **common)


@register
class WaypointFollowing(SectionType):
    """WaypointFollowing section; completes when every waypoint passed (fly-over within ``wp_accept_m`` or abeam; fly-by at the turn anticipation distance), and a planned hold at the constraint's waypoint flown."""

    type_name = "WaypointFollowing"
    feasibility = staticmethod(checks.waypoint_following)
    conformance = TARGETS
    outer_rate = True
    completion = "every waypoint passed (fly-over within ``wp_accept_m`` or abeam; fly-by at the turn anticipation distance), and a planned hold at the constraint's waypoint flown"
    fields: ClassVar[dict[str, Field]] = {
        "waypoints": ("waypoints", True, None, None, "names of waypoints, in order"),
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude [m]"),
        "speed": ("speed", True, None, None, "speed"),
        "fly_by": ("bool", False, False, None, "fly-by (true) or fly-over (false) waypoints"),
        "altitude_at": ("waypoint", False, None, None, "the waypoint of the section the altitude is due at "
                        "(default: the last); descents are planned to it, the altitude held after it"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        at = values["altitude_at"]
        if "altitude_at" in raw and at not in values["waypoints"]:
            return "altitude_at", (f"{raw['altitude_at']!r} is not one of the section's waypoints "
                                   f"({', '.join(map(str, raw['waypoints']))})")
        return None

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        return sec["waypoints"][0]

    def flown_by(self) -> LatLon | None:
        return self.seq.leg[1] if self.sec["fly_by"] else None

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        g = L1Guidance(dataclasses.replace(ctx.guidance.parameters, wp_fly_by=bool(sec["fly_by"])))
        self._g = g
        # flown by from the previous section's last waypoint: the first leg starts there, not where the
        # turn into it began
        start = ctx.flown_by if sec["fly_by"] and ctx.flown_by is not None else x.pos
        then = ctx.next_fix() if sec["fly_by"] else None
        wps = list(sec["waypoints"])
        self.seq = WaypointSequencer(g, wps, start, then)
        at = sec.get("altitude_at")
        jc = len(wps) - 1 if at is None else max(i for i, w in enumerate(wps) if w == at)
        tp = ctx.tecs_params
        self.vert = SectionVnav(ctx.vnav, g.parameters, sec.index, sec["altitude_m"], sec["speed"], ctx.last_speed,
                                start, wps, jc, then, x, t_s, (tp.Vdot_max_m_s2, tp.k_V_1_s, tp.gamma_max_rad))
        if self.vert.hold is not None:
            ctx.holds.append(self.vert.hold)
        self._in_hold = False

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        vert = self.vert
        had_hold = vert.hold is not None
        if not self._in_hold:
            cmd = self.seq.step(x.pos, x.vn_m_s, x.ve_m_s, x.psi_rad)
        if self.seq.done and vert.hold_pending:
            self._in_hold = True
            p = self.ctx.vnav.parameters
            cmd = self._g.orbit(x.pos, x.vn_m_s, x.ve_m_s, vert.fix, p.hold_radius_m, 1, x.psi_rad)
            v, over = vert.hold_step(t_s, x)
            self.done = over
            phase = "HOLD"
        else:
            v = vert.step(t_s, x, self.seq.index, cmd.dist_to_go_m)
            self.done = self.seq.done and not vert.hold_pending
            phase = f"TO_WP{min(self.seq.index, len(self.sec['waypoints']) - 1)}"
        if not had_hold and vert.hold is not None:
            self.ctx.holds.append(vert.hold)  # planned in flight (unable)
        return self.targets(phase=phase, alt_cmd_m=v.alt_cmd_m, hdot_ff_m_s=v.hdot_ff_m_s, speed=v.speed,
                            priority=v.priority, airbrake=v.airbrake, vnav_mode=v.mode, phi_cmd_rad=cmd.phi_cmd_rad,
                            track_cmd_rad=cmd.track_cmd_rad, xtk_m=cmd.xtk_m, gear_down=False)


def _mode(alt_cmd_m: float, x: AircraftState, band_m: float) -> str:
    """ALT within ``band_m`` of the commanded altitude, else CLIMB or DESCENT (open)."""
    dh = alt_cmd_m - x.alt_m
    return "ALT" if abs(dh) <= band_m else ("CLIMB" if dh > 0 else "DESCENT")


@register
class Orbiting(SectionType):
    """Orbiting section; completes when ``turns`` full turns swept around the centre after capture."""

    type_name = "Orbiting"
    feasibility = staticmethod(checks.orbiting)
    conformance = TARGETS
    outer_rate = True
    completion = "``turns`` full turns swept around the centre after capture"
    fields: ClassVar[dict[str, Field]] = {
        "center": ("waypoint", True, None, None, "waypoint at the centre"),
        "radius_m": ("number", True, None, (200.0, 100000.0), "radius [m]"),
        "direction": ("choice", False, "clockwise", ("clockwise", "counterclockwise"), "direction"),
        "turns": ("number", True, None, (0.1, 100.0), "turns after capture [-]"),
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude [m]"),
        "speed": ("speed", True, None, None, "speed"),
    }

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        d = 1 if sec["direction"] == "clockwise" else -1
        self.orb = OrbitTracker(ctx.guidance, sec["center"], sec["radius_m"], d, sec["turns"])
        self._alt_m, self._speed = sec["altitude_m"], sec["speed"]  # read at every step: looked up once

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        cmd = self.orb.step(x.pos, x.vn_m_s, x.ve_m_s, x.psi_rad)
        self.done = self.orb.done
        phase = f"ORBIT {self.orb.turns_flown:.2f}" if self.orb.captured else "ORBIT_ENTRY"
        return self.targets(phase=phase, alt_cmd_m=self._alt_m, speed=self._speed,
                            phi_cmd_rad=cmd.phi_cmd_rad, track_cmd_rad=cmd.track_cmd_rad, xtk_m=cmd.xtk_m,
                            gear_down=False, vnav_mode=_mode(self._alt_m, x, self.ctx.level_band_m))


@register
class GTurns(SectionType):
    """GTurns section; completes when ``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed."""

    type_name = "GTurns"
    feasibility = staticmethod(checks.gturns)
    conformance = TARGETS
    outer_rate = True
    completion = "``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed"
    fields: ClassVar[dict[str, Field]] = {
        "load_factor": ("number", True, None, (1.02, 6.0), "load factor of the level turn [g]"),
        "direction": ("choice", False, "right", ("right", "left"), "turn direction"),
        "heading_change_deg": ("number", False, None, (1.0, 3600.0), "ends after this heading change [deg]"),
        "duration_s": ("number", False, None, (1.0, 36000.0), "or after this time [s]"),
        "altitude_m": ("number", False, None, (-400.0, 15000.0), "altitude [m] (default: at entry)"),
        "speed": ("speed", False, None, None, "speed (default: at entry)"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        if ("heading_change_deg" in raw) == ("duration_s" in raw):
            return None, "give exactly one of 'heading_change_deg' or 'duration_s'"
        return None

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        self.alt = sec["altitude_m"] if sec["altitude_m"] is not None else x.alt_m
        self.speed = sec["speed"] if sec["speed"] is not None else SpeedCommand(x.tas_m_s, SpeedKind.TAS)
        self.turned = 0.0
        self.psi_prev = x.psi_rad
        self.sign = 1.0 if sec["direction"] == "right" else -1.0

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        self.turned += wrap_pi(x.psi_rad - self.psi_prev)
        self.psi_prev = x.psi_rad
        s = self.sec
        if s["heading_change_deg"] is not None:
            self.done = abs(self.turned) >= math.radians(s["heading_change_deg"])
        else:
            self.done = t_s - self.t0 >= s["duration_s"]
        phi = self.sign * math.acos(1.0 / s["load_factor"])
        return self.targets(phase="TURN", alt_cmd_m=self.alt, speed=self.speed, phi_cmd_rad=phi, gear_down=False,
                            vnav_mode=_mode(self.alt, x, self.ctx.level_band_m))


@register
class Levelling(SectionType):
    """Levelling section; completes when ``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``."""

    type_name = "Levelling"
    feasibility = staticmethod(checks.levelling)
    conformance = TARGETS
    outer_rate = True
    completion = "``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``"
    fields: ClassVar[dict[str, Field]] = {
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude to capture [m]"),
        "speed": ("speed", True, None, None, "speed"),
        "heading_deg": ("number", False, None, (0.0, 360.0), "true heading to hold [deg] (default: at entry)"),
        "tolerance_m": ("number", False, 10.0, (0.1, 500.0), "altitude band counted as captured [m]"),
        "hold_s": ("number", False, 20.0, (0.0, 3600.0), "time to stay in the band [s]"),
    }

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        hd = sec["heading_deg"]
        self.heading = math.radians(hd) if hd is not None else x.psi_rad
        self.t_in: float | None = None

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        s = self.sec
        if abs(x.alt_m - s["altitude_m"]) < s["tolerance_m"]:
            self.t_in = t_s if self.t_in is None else self.t_in
            self.done = t_s - self.t_in >= s["hold_s"]
        else:
            self.t_in = None
        return self.targets(phase="CAPTURE" if self.t_in is None else "HOLD", alt_cmd_m=s["altitude_m"],
                            speed=s["speed"], heading_cmd_rad=self.heading, track_cmd_rad=self.heading,
                            gear_down=False, vnav_mode=_mode(s["altitude_m"], x, self.ctx.level_band_m))


@register
class Landing(SectionType):
    """Landing section; completes when stopped on the runway (ground speed < ``v_stop_m_s``)."""

    type_name = "Landing"
    feasibility = staticmethod(checks.landing)
    conformance = APPROACH
    speed_field = None
    completion = "stopped on the runway (ground speed < ``v_stop_m_s``)"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "landing runway"),
        "approach_altitude_m": ("number", True, None, (0.0, 6000.0), "altitude held until glide slope capture [m]"),
        "approach_speed": ("speed", True, None, None, "final approach speed"),
    }

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        return sec["runway"].threshold  # the turn onto the localizer: towards the threshold along the centre line

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        self.land = AutoLand(sec["runway"], sec["approach_altitude_m"], ctx.guidance, ctx.approach_params)
        # the fields read at every step, looked up once (a Section's field look-up is a search of its fields)
        self._speed, self._track_rad = sec["approach_speed"], sec["runway"].heading_rad

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        c = self.land.step(dt_s, x.pos, x.alt_m, x.vn_m_s, x.ve_m_s, x.psi_rad, x.tas_m_s, x.theta_rad, x.on_ground)
        self.done = self.land.done
        ground = c.theta_cmd_rad is not None
        return self.targets(phase=c.phase, alt_cmd_m=c.alt_cmd_m, gamma_cmd_rad=c.gamma_cmd_rad,
                            theta_cmd_rad=c.theta_cmd_rad, speed=self._speed,
                            lever=0.0 if c.idle else None, phi_cmd_rad=c.phi_cmd_rad,
                            align_heading_rad=c.align_heading_rad, track_cmd_rad=self._track_rad,
                            xtk_m=c.ils.loc_m, steer=c.steer, brake=c.brake,
                            gear_down=ground or c.phase not in ("LOC_ARMED",), vnav_mode="APPROACH",
                            priority="path" if c.phase in ("LOC_ARMED", "LOC", "GS") else None)


@register
class Custom(SectionType):
    """Custom section; completes when ``duration_s`` elapsed."""

    type_name = "Custom"
    not_checked = "fly open-loop commands"
    speed_field = None
    completion = "``duration_s`` elapsed"
    fields: ClassVar[dict[str, Field]] = {
        "duration_s": ("number", True, None, (0.1, 36000.0), "duration [s]"),
        "commands": ("commands", True, None, None, "time points {t_s, lever, pitch_deg, bank_deg}, held between"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        if values["commands"][0][0] != 0.0:
            return "commands", "the first command must be at t_s = 0"
        return None

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        tau = t_s - self.t0
        cmds = self.sec["commands"]
        cur = cmds[0]
        for c in cmds:
            if c[0] <= tau:
                cur = c
        self.done = tau >= self.sec["duration_s"]
        _, lever, pitch_deg, bank_deg = cur
        return self.targets(phase="CUSTOM", theta_cmd_rad=math.radians(pitch_deg), lever=lever,
                            phi_cmd_rad=math.radians(bank_deg), gear_down=x.on_ground)
