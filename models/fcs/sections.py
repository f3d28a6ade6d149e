"""The flight laws of the mission section types: each type's step and completion, registered once.

A section type is declared by the mission (:mod:`openemss.models.mission.sections`: its fields, completion,
conformance kind, the one registry the mission reader and the report read); here each type's class derives from
its declaration and adds how the FCS flies it: the state machine (:mod:`.state_machine`) makes an executor of the
class when a section starts, and the mission check judges the section with the class's
:attr:`SectionType.feasibility` (the shipped checks in :mod:`.feasibility_sections`).

A new section type is one subclass of :class:`SectionType` (its fields, step and completion) with
``@register``: the declaration is registered in the mission's registry and the flight law in :data:`LAWS` by the
same call, and nothing else names it. The navigation types (waypoints, orbits, turns, levelling) set
:attr:`SectionType.outer_rate`: the state machine steps them every ``guidance.outer_period_s`` and holds their
targets in between.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any, ClassVar

from ..common.airspeed import cas_from_tas
from ..mission import sections as decl
from ..mission.geo import LatLon, wrap_pi
from ..mission.sections import REGISTRY, SectionSpec, section_label
from ..mission.speed import SpeedCommand, SpeedKind
from . import feasibility_sections as checks
from .approach import AutoLand, centreline_steer
from .atmosphere import isa
from .guidance import L1Guidance, OrbitTracker, WaypointSequencer
from .runway_checks import check_on_runway
from .state import AircraftState, Targets
from .vertical import SectionVnav

if TYPE_CHECKING:
    from ..mission.mission import Section
    from .feasibility_checker import FeasibilityCheck
    from .state_machine import MissionRunner

__all__ = ["SectionType", "LAWS", "register", "unregister"]


class SectionType(SectionSpec):
    """A mission section type the FCS flies: its declaration (:class:`~openemss.models.mission.sections.SectionSpec`:
    fields, completion, conformance) and, as an instance, the executor of one section of that type.

    An executor is made when its section starts (so it can use the state at entry); every step it
    turns the aircraft state into :class:`~.state.Targets` and sets :attr:`done` when complete.

    Class attributes
    ----------------
    outer_rate : bool
        The section is navigation at the outer loops' rate: its step may be run every
        ``guidance.outer_period_s`` only, its targets held in between (its step must not integrate
        ``dt_s``). False (the default) for the sections that fly the aircraft near the ground
        (take-off, landing) or by the clock (custom commands): they run every step.
    feasibility : FeasibilityCheck or None
        The section's check before the flight (:mod:`.feasibility`): a function ``(checker, section, state,
        figures) -> end altitude [m]`` (:mod:`.feasibility_checker`); None (the default): not checked, the
        section's verdict is ``n/a`` and a note says ``<type> sections <not_checked>: not checked``.
    not_checked : str
        Why a type without a feasibility check has none (in that note).
    """

    outer_rate: ClassVar[bool] = False
    feasibility: ClassVar[FeasibilityCheck | None] = None
    not_checked: ClassVar[str] = "have no feasibility check"

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        self.sec, self.t0, self.ctx = sec, t_s, ctx
        self.done = False

    def flown_by(self) -> LatLon | None:
        """The last waypoint of the completed section when it was flown by (the next leg starts there)."""
        return None

    @property
    def label(self) -> str:
        """The section as messages name it (:func:`~openemss.models.mission.sections.section_label`)."""
        return section_label(self.sec)

    def targets(self, **kw: Any) -> Targets:
        return Targets.make(self.sec.index, self.sec.name, self.sec.type, **kw)

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:  # pragma: no cover - abstract
        raise NotImplementedError


#: The flight law of each section type the FCS flies, by its ``type`` name (the state machine and the mission
#: check read it); the declarations are the mission's registry.
LAWS: dict[str, type[SectionType]] = {}


def register(cls: type[SectionType]) -> type[SectionType]:
    """Class decorator: register a section type's flight law under its ``type_name`` (once), and its declaration
    in the mission's registry unless the class derives from the declaration registered there under that name.

    Raises
    ------
    ValueError
        When the name is empty or taken (a flight law registered, or another declaration of that name), or the
        declaration's conformance kind is not one the report judges or its fields lack those the kind needs.
    """
    declared = REGISTRY.get(cls.type_name)
    if cls.type_name in LAWS or (declared is not None and not issubclass(cls, declared)):
        raise ValueError(f"section type {cls.__name__}: type_name {cls.type_name!r} is empty or taken")
    if declared is None:
        decl.register(cls)
    LAWS[cls.type_name] = cls
    return cls


def unregister(type_name: str) -> None:
    """Remove a section type registered by :func:`register`: its flight law, and its declaration when the law was
    registered as it (a type declared by the mission keeps its declaration)."""
    law = LAWS.pop(type_name, None)
    if law is not None and REGISTRY.get(type_name) is law:
        del REGISTRY[type_name]


@register
class Rolling(decl.Rolling, SectionType):
    """The flight law of a Rolling section (:class:`openemss.models.mission.sections.Rolling`)."""

    feasibility = staticmethod(checks.rolling)

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
class TakeOff(decl.TakeOff, SectionType):
    """The flight law of a TakeOff section (:class:`openemss.models.mission.sections.TakeOff`)."""

    feasibility = staticmethod(checks.takeoff)

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
class WaypointFollowing(decl.WaypointFollowing, SectionType):
    """The flight law of a WaypointFollowing section (:class:`openemss.models.mission.sections.WaypointFollowing`)."""

    feasibility = staticmethod(checks.waypoint_following)
    outer_rate = True

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
class Orbiting(decl.Orbiting, SectionType):
    """The flight law of a Orbiting section (:class:`openemss.models.mission.sections.Orbiting`)."""

    feasibility = staticmethod(checks.orbiting)
    outer_rate = True

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
class GTurns(decl.GTurns, SectionType):
    """The flight law of a GTurns section (:class:`openemss.models.mission.sections.GTurns`)."""

    feasibility = staticmethod(checks.gturns)
    outer_rate = True

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
class Levelling(decl.Levelling, SectionType):
    """The flight law of a Levelling section (:class:`openemss.models.mission.sections.Levelling`)."""

    feasibility = staticmethod(checks.levelling)
    outer_rate = True

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
class Landing(decl.Landing, SectionType):
    """The flight law of a Landing section (:class:`openemss.models.mission.sections.Landing`)."""

    feasibility = staticmethod(checks.landing)

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
class Custom(decl.Custom, SectionType):
    """The flight law of a Custom section (:class:`openemss.models.mission.sections.Custom`)."""

    not_checked = "fly open-loop commands"

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
