"""The mission state machine: runs the sections of a :class:`~.mission.Mission` in order.

Each section becomes an *executor* when it starts (so it can use the state at entry),
turns the aircraft state into :class:`~.state.Targets` every step, and says when it
is complete. Completion criteria (explicit, per type):

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

:attr:`MissionRunner.active_index` and :attr:`~MissionRunner.active_name` report the
active section at every instant; :attr:`~MissionRunner.history` lists the
transitions (time, index, name).

A waypoint section's altitude is a constraint at its last waypoint (or ``altitude_at``),
flown by the section's vertical guidance (:mod:`.vertical`, planned by :mod:`.vnav`):
top of descent, managed path, deceleration, and a planned, flagged hold at the fix where
the constraint cannot be met (:attr:`MissionRunner.holds`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from .approach import ApproachParams, AutoLand, centreline_steer
from .atmosphere import cas_from_tas, isa
from .geo import LatLon, wrap_pi
from .guidance import L1Guidance, OrbitTracker, WaypointSequencer
from .mission import Mission, Section
from .performance import Performance
from .state import AircraftState, Targets
from .tecs import SpeedCommand, SpeedKind, TecsParams
from .vertical import HoldRecord, SectionVnav
from .vnav import Vnav

__all__ = ["MissionRunner"]



class _Exec:
    """Base executor: holds the section and its start time."""

    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        self.sec, self.t0, self.ctx = sec, t_s, ctx
        self.done = False

    def targets(self, **kw: Any) -> Targets:
        return Targets(self.sec.index, self.sec.name, self.sec.type, **kw)

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:  # pragma: no cover - abstract
        raise NotImplementedError


class _Rolling(_Exec):
    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        s, rwy = self.sec, self.sec["runway"]
        cas = cas_from_tas(x.tas_m_s, isa(x.alt_m, x.dT_isa_K))
        self.done = cas >= s["rotate_cas_m_s"]
        steer = centreline_steer(rwy, self.ctx.approach_params, x.pos, x.psi_rad)
        return self.targets(phase="ROLL", theta_cmd_rad=self.ctx.approach_params.theta_ground_rad, lever=s["lever"],
                            phi_cmd_rad=0.0, align_heading_rad=rwy.heading_rad, track_cmd_rad=rwy.heading_rad,
                            xtk_m=rwy.local(x.pos)[1], steer=steer)


class _TakeOff(_Exec):
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


class _Waypoints(_Exec):
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


class _Orbit(_Exec):
    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        d = 1 if sec["direction"] == "clockwise" else -1
        self.orb = OrbitTracker(ctx.guidance, sec["center"], sec["radius_m"], d, sec["turns"])

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        cmd = self.orb.step(x.pos, x.vn_m_s, x.ve_m_s, x.psi_rad)
        self.done = self.orb.done
        phase = f"ORBIT {self.orb.turns_flown:.2f}" if self.orb.captured else "ORBIT_ENTRY"
        return self.targets(phase=phase, alt_cmd_m=self.sec["altitude_m"], speed=self.sec["speed"],
                            phi_cmd_rad=cmd.phi_cmd_rad, track_cmd_rad=cmd.track_cmd_rad, xtk_m=cmd.xtk_m,
                            gear_down=False, vnav_mode=_mode(self.sec["altitude_m"], x, self.ctx.level_band_m))


class _GTurn(_Exec):
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


class _Level(_Exec):
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


class _Landing(_Exec):
    def __init__(self, sec: Section, x: AircraftState, t_s: float, ctx: MissionRunner) -> None:
        super().__init__(sec, x, t_s, ctx)
        self.land = AutoLand(sec["runway"], sec["approach_altitude_m"], ctx.guidance, ctx.approach_params)

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        c = self.land.step(dt_s, x.pos, x.alt_m, x.vn_m_s, x.ve_m_s, x.psi_rad, x.tas_m_s, x.theta_rad, x.on_ground)
        self.done = self.land.done
        ground = c.theta_cmd_rad is not None
        return self.targets(phase=c.phase, alt_cmd_m=c.alt_cmd_m, gamma_cmd_rad=c.gamma_cmd_rad,
                            theta_cmd_rad=c.theta_cmd_rad, speed=self.sec["approach_speed"],
                            lever=0.0 if c.idle else None, phi_cmd_rad=c.phi_cmd_rad,
                            align_heading_rad=c.align_heading_rad, track_cmd_rad=self.sec["runway"].heading_rad,
                            xtk_m=c.ils.loc_m, steer=c.steer, brake=c.brake,
                            gear_down=ground or c.phase not in ("LOC_ARMED",), vnav_mode="APPROACH",
                            priority="path" if c.phase in ("LOC_ARMED", "LOC", "GS") else None)


class _Custom(_Exec):
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


_EXECUTORS: dict[str, type[_Exec]] = {"Rolling": _Rolling, "TakeOff": _TakeOff, "WaypointFollowing": _Waypoints,
                                      "Orbiting": _Orbit, "GTurns": _GTurn, "Levelling": _Level,
                                      "Landing": _Landing, "Custom": _Custom}


class MissionRunner:
    """Runs the sections of ``mission`` in order and reports the active one.

    Parameters
    ----------
    mission : Mission
        A validated mission.
    guidance : L1Guidance, optional
        Path follower shared by the sections (its parameters are the tunable ones).
    approach_params : ApproachParams, optional
        Approach, landing and ground-steering parameters.
    """

    def __init__(self, mission: Mission, guidance: L1Guidance | None = None,
                 approach_params: ApproachParams | None = None, vnav: Vnav | None = None,
                 tecs_params: TecsParams | None = None) -> None:
        self.mission = mission
        self.guidance = guidance if guidance is not None else L1Guidance()
        #: the vertical planner (its parameters and the performance model are tunable through the FCS)
        self.vnav = vnav if vnav is not None else Vnav(Performance())
        #: TECS's parameters as the plans use them (the FCS keeps them current)
        self.tecs_params = tecs_params if tecs_params is not None else TecsParams.from_file()
        #: speed of the last section completed (a descent holds it until its deceleration)
        self.last_speed: SpeedCommand | None = None
        #: planned holds, in the order planned (flagged: summary and plots report them)
        self.holds: list[HoldRecord] = []
        #: last waypoint of the section just completed, when it was a fly-by waypoint section
        self.flown_by: LatLon | None = None
        self.approach_params = approach_params if approach_params is not None else ApproachParams.from_file()
        self.active_index = 0
        self._exec: _Exec | None = None
        self.history: list[tuple[float, int, str]] = []

    @property
    def finished(self) -> bool:
        """All sections completed."""
        return self.active_index >= len(self.mission.sections)

    @property
    def active_name(self) -> str:
        """Name of the active section (``"finished"`` after the last)."""
        return "finished" if self.finished else self.mission.sections[self.active_index].name

    @property
    def level_band_m(self) -> float:
        """Band about the commanded altitude reported as ALT by the sections without a plan [m]."""
        return self.vnav.parameters.level_band_m

    def next_fix(self) -> LatLon | None:
        """The first waypoint of the section after the active one, if that is a waypoint section, or the
        threshold of a landing's runway (for the turn anticipation of fly-by waypoints across sections)."""
        secs = self.mission.sections
        if self.active_index + 1 >= len(secs):
            return None
        nxt = secs[self.active_index + 1]
        if nxt.type == "WaypointFollowing":
            return nxt["waypoints"][0]
        if nxt.type == "Landing":  # the turn onto the localizer: towards the threshold along the centre line
            return nxt["runway"].threshold
        return None

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        """Targets of the active section at time ``t_s`` [s]; advances on completion."""
        while not self.finished:
            sec = self.mission.sections[self.active_index]
            if self._exec is None:
                self._exec = _EXECUTORS[sec.type](sec, x, t_s, self)
                self.history.append((t_s, sec.index, sec.name))
            tg = self._exec.step(t_s, dt_s, x)
            if not self._exec.done:
                return tg
            self.flown_by = self._exec.seq.leg[1] if isinstance(self._exec, _Waypoints) and sec["fly_by"] else None
            speed = sec.get("speed") if sec.type != "TakeOff" else sec.get("climb_speed")
            self.last_speed = speed if isinstance(speed, SpeedCommand) else self.last_speed
            self.active_index += 1
            self._exec = None
        if not self.history or self.history[-1][1] != len(self.mission.sections):
            self.history.append((t_s, len(self.mission.sections), "finished"))
        return Targets(len(self.mission.sections), "finished", "finished", "STOPPED", theta_cmd_rad=0.0, lever=0.0,
                       phi_cmd_rad=0.0, brake=1.0, gear_down=True)
