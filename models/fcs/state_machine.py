"""The mission state machine: runs the sections of a :class:`~openemss.models.mission.mission.Mission` in order.

Each section becomes an executor of its type's class (:mod:`.sections`, one class per type,
registered once) when it starts, so it can use the state at entry; the executor turns the
aircraft state into :class:`~.state.Targets` every step and says when it is complete (the
completion criteria are in :mod:`.sections`).

:attr:`MissionRunner.active_index` and :attr:`~MissionRunner.active_name` report the
active section at every instant; :attr:`~MissionRunner.history` lists the
transitions (time, index, name).

A waypoint section's altitude is a constraint at its last waypoint (or ``altitude_at``),
flown by the section's vertical guidance (:mod:`.vertical`, planned by :mod:`.vnav`):
top of descent, managed path, deceleration, and a planned, flagged hold at the fix where
the constraint cannot be met (:attr:`MissionRunner.holds`).
"""

from __future__ import annotations

from ..mission.geo import LatLon
from ..mission.mission import Mission
from ..mission.sections import REGISTRY, section_label
from ..mission.speed import SpeedCommand
from .approach import ApproachParams
from .errors import FcsError
from .guidance import L1Guidance
from .performance import Performance
from .runway_checks import check_departure
from .sections import LAWS, SectionType
from .state import AircraftState, Targets
from .tecs import TecsParams
from .vertical import HoldRecord
from .vnav import Vnav

__all__ = ["MissionRunner"]



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
        if unflown := [s for s in mission.sections if s.type not in LAWS]:
            raise FcsError(f"{mission.source}: {section_label(unflown[0])}: the flight control has no flight law for "
                           f"section type {unflown[0].type!r} (declared, not registered in models/fcs/sections.py); "
                           f"it flies {', '.join(LAWS)}")
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
        self._n_sections = len(mission.sections)
        self._exec: SectionType | None = None
        self.history: list[tuple[float, int, str]] = []
        #: time the held targets were computed [s] (a managed path's altitude moves on from there)
        self.targets_time_s = 0.0
        self._held: Targets | None = None  # targets of an outer-rate section, held until _next_s
        self._next_s = 0.0
        #: how long the targets last returned are held [s]: the outer period for an outer-rate section, else 0
        self.held_for_s = 0.0

    @property
    def finished(self) -> bool:
        """All sections completed."""
        return self.active_index >= self._n_sections

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
        return REGISTRY[nxt.type].entry_fix(nxt)

    def step(self, t_s: float, dt_s: float, x: AircraftState) -> Targets:
        """Targets of the active section at time ``t_s`` [s]; advances on completion.

        A section of an outer-rate type (:attr:`.sections.SectionType.outer_rate`) is stepped every
        ``guidance.outer_period_s``; in between its last targets are returned as they were
        (:attr:`targets_time_s` says when they were computed).
        """
        held = self._held
        if held is not None and t_s < self._next_s:
            return held
        self._held = None
        self.targets_time_s = t_s
        self.held_for_s = 0.0
        while not self.finished:
            sec = self.mission.sections[self.active_index]
            if self._exec is None:
                if not self.history and REGISTRY[sec.type].departs_from_runway:  # the mission's start
                    check_departure(sec["runway"], x, section_label(sec), self.mission.source)
                self._exec = LAWS[sec.type](sec, x, t_s, self)
                self.history.append((t_s, sec.index, sec.name))
            tg = self._exec.step(t_s, dt_s, x)
            if not self._exec.done:
                if self._exec.outer_rate:
                    period = self.guidance.parameters.outer_period_s
                    if period > dt_s:
                        # half a step early, so that t0 + k h meets it whatever the rounding of the sums
                        self._held, self._next_s = tg, t_s + period - 0.5 * dt_s
                        self.held_for_s = period
                return tg
            self.flown_by = self._exec.flown_by()
            field = self._exec.speed_field
            speed = sec.get(field) if field is not None else None
            self.last_speed = speed if isinstance(speed, SpeedCommand) else self.last_speed
            self.active_index += 1
            self._exec = None
        if not self.history or self.history[-1][1] != len(self.mission.sections):
            self.history.append((t_s, len(self.mission.sections), "finished"))
        return Targets(len(self.mission.sections), "finished", "finished", "STOPPED", theta_cmd_rad=0.0, lever=0.0,
                       phi_cmd_rad=0.0, brake=1.0, gear_down=True)
