"""Can the aircraft fly a mission as planned? Per section: required against achievable gradients and turns.

Before a mission is flown, each section's altitude change is compared with what the aircraft
can do there, and its turns with the bank limit of the guidance:

* **Climb and descent.** A section's altitude is reached by its constraint point: the waypoint
  ``altitude_at`` of a WaypointFollowing section, by default its last (as the flight control's
  vertical planner takes it; the distance runs along the legs), the end of its turns for an
  Orbiting section (approach to the circle plus ``turns`` x 2 pi R), the glide slope intercept
  for a Landing. The required gradient is the altitude change over the ground distance from the
  previous section's end. The achievable one follows from the
  specific excess power [1]_: the total energy height ``E = h + V^2 / 2g`` changes along the air
  path at ``dE/ds = (T - D) / W``, with T the maximum thrust (climb) or the idle thrust (descent)
  and D the level-flight drag of the trimmed aircraft at the section's speed, altitude and
  estimated mass; over the ground ``dE/dx = (T - D)/W * TAS/GS`` in the wind. The distance needed
  is the larger of ``|dE| * mean(1/|dE/dx|)`` (thrust, averaged over the altitude band with
  Simpson's rule) and ``|dh| / tan(gamma_limit)`` (the TECS flight-path-angle limits). A speed
  change is part of ``dE``.
* **Turns.** Radius at the bank limit ``R = GS^2 / (g tan phi_max)`` with the largest ground speed
  (TAS plus the wind speed) against the orbit radius; the turn anticipation of fly-by waypoints
  ``R tan(dpsi/2)`` (at ``fly_by_bank_frac`` of the limit, as the sequencer plans it; at the last
  waypoint towards where the next section begins, as the flight control flies it) against the leg
  lengths; the thrust for the turn's load factor ``n = 1/cos(phi)``: ``D(n) = D + q S k CL^2
  (n^2 - 1)`` (drag due to lift grows with n^2) against the maximum thrust, and ``n CL`` against
  the maximum lift coefficient.
* **Level flight.** Maximum thrust against the drag at each section's speed and altitude; the
  speed within the trim envelope (no stall) and the TECS Mach limit; the glide slope of a
  Landing against the idle descent gradient with the gear down (the approach speed is held on
  the glide path only if idle thrust lets the aircraft descend that steeply).

A section is *infeasible* when the achievable falls short of the required, *marginal* when it
is within ``margin`` (default 20 %) of it. The mass falls along the mission by an estimate of
the fuel burned (cruise at the engine's fuel flow for the drag, climbs at maximum thrust).

Each section type carries its check (:attr:`.sections.SectionType.feasibility`, the shipped ones in
:mod:`.feasibility_sections`, sharing the physics of :class:`~.feasibility_checker.Checker`); a type without
one (``Custom``, or a registered type that brings none) is not checked: its verdict is ``n/a``.

The physics of the aircraft and engine come in through :class:`Performance` (in openEMSS:
``openemss.report.model_performance``, the trimmed JSBSim airframe and the engine model of the
system's parameter set), so this module depends on neither.

References
----------
.. [1] Anderson, J. D., *Aircraft Performance and Design*, McGraw-Hill, 1999, sect. 5.3 (rate of
   climb, specific excess power) and 5.8 (energy height); sect. 5.4 (gliding flight).
.. [2] Raymer, D. P., *Aircraft Design: A Conceptual Approach*, 6th ed., AIAA, 2018, sect. 17.8
   (ground roll with the mean acceleration at V/sqrt(2)).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..mission.geo import LatLon
from ..mission.mission import Mission, Section
from ..mission.sections import REGISTRY
from ..mission.weather import WindProfile
from .errors import FcsError
from .feasibility_checker import NOTE, VERDICTS, Checker, CheckState, Finding
from .feasibility_perf import Limits, Performance, PerformanceError, PerfPoint
from .sections import LAWS

__all__ = ["PerfPoint", "Performance", "PerformanceError", "Limits", "Finding", "SectionCheck", "MissionCheck",
           "check_mission", "VERDICTS"]


@dataclass(frozen=True, slots=True)
class SectionCheck:
    """The check of one section. Gradients are dimensionless (0.05 = 5 %), positive up.

    Attributes
    ----------
    index, type, name : the section.
    verdict : str
        ``ok``, ``marginal`` or ``infeasible`` (the worst of ``findings``), or ``n/a``.
    alt_from_m, alt_to_m : float
        Altitude at the start and the section's target altitude [m].
    tas_m_s, mach, mass_kg : float
        Target true airspeed [m/s] and Mach [-] at the target altitude, estimated mass at entry [kg].
    distance_m : float or None
        Ground distance available for the altitude change [m] (None: no constraint).
    required_gradient, achievable_gradient : float or None
        Altitude change over ``distance_m``, and over the distance needed at full thrust (climb)
        or idle (descent) within the flight-path-angle limits [-].
    needed_distance_m : float or None
        Distance the altitude (and speed) change takes [m].
    turn_radius_m, geometry_radius_m : float or None
        Radius at the bank limit and at the largest ground speed [m]; the radius or leg length the
        section offers [m].
    thrust_ratio : float or None
        Maximum thrust over drag at the target (in the turn for orbits and G-turns) [-].
    findings : tuple of Finding
    """

    index: int
    type: str
    name: str
    verdict: str
    alt_from_m: float
    alt_to_m: float
    tas_m_s: float | None
    mach: float | None
    mass_kg: float
    distance_m: float | None
    required_gradient: float | None
    achievable_gradient: float | None
    needed_distance_m: float | None
    turn_radius_m: float | None
    geometry_radius_m: float | None
    thrust_ratio: float | None
    findings: tuple[Finding, ...]


@dataclass(frozen=True, slots=True)
class MissionCheck:
    """The check of a whole mission."""

    mission: str
    source: str
    margin: float
    mass_kg: float
    sections: tuple[SectionCheck, ...]
    fuel_estimate_kg: float
    time_estimate_s: float
    #: findings of the whole mission (e.g. more fuel needed than on board)
    notes: tuple[Finding, ...] = ()

    @property
    def findings(self) -> list[tuple[SectionCheck, Finding]]:
        """Every finding with its section, in mission order."""
        return [(s, f) for s in self.sections for f in s.findings]

    def count(self, verdict: str) -> int:
        """Number of sections with this verdict."""
        return sum(1 for s in self.sections if s.verdict == verdict)


def _check_section(ck: Checker, sec: Section, st: CheckState, nxt: Section | None) -> SectionCheck:
    """The check of one section by its type's :attr:`~.sections.SectionType.feasibility` (``n/a`` without one)."""
    kind = LAWS.get(sec.type)  # None: a type the flight control does not fly (declared by the mission only)
    ck.findings = []
    ck.next_fix = REGISTRY[nxt.type].entry_fix(nxt) if nxt is not None else None
    h0, mass0 = st.alt_m, st.mass_kg
    out: dict[str, float | None] = dict(tas_m_s=None, mach=None, distance_m=None, required_gradient=None,
                                        achievable_gradient=None, needed_distance_m=None, turn_radius_m=None,
                                        geometry_radius_m=None, thrust_ratio=None)
    h1 = h0
    if kind is None or kind.feasibility is None:
        why = "have no flight law in the flight control" if kind is None else kind.not_checked
        ck.note(f"{sec.type} sections {why}: not checked")
        verdict = "n/a"
    else:
        try:
            h1 = kind.feasibility(ck, sec, st, out)
        except PerformanceError as e:
            ck.findings.append(Finding("infeasible", str(e)))
        verdict = max((f.verdict for f in ck.findings if f.verdict != NOTE), key=VERDICTS.index, default="ok")
    return SectionCheck(sec.index, sec.type, sec.name, verdict, h0, h1, mass_kg=mass0,
                        findings=tuple(ck.findings), **out)  # type: ignore[arg-type]


def check_mission(mission: Mission, perf: Performance, limits: Limits, mass_kg: float, *,
                  start: tuple[LatLon, float, float] | None = None, wind: WindProfile | None = None,
                  dT_isa_K: float = 0.0, margin: float = 0.2, fuel_kg: float | None = None) -> MissionCheck:
    """Check every section of ``mission`` (see the module docstring).

    Parameters
    ----------
    mission : Mission
        The validated mission.
    perf : Performance
        Trimmed aircraft and engine.
    limits : Limits
        The flight control's limits.
    mass_kg : float
        Mass at the start [kg]; reduced along the mission by the fuel estimate.
    start : (LatLon, alt_m, tas_m_s), optional
        Where the mission starts; default the first section's runway threshold at rest.
    wind : WindProfile, optional
        Winds aloft (ground speeds, turn radii).
    dT_isa_K : float
        ISA temperature deviation [K].
    margin : float
        Relative margin below which a feasible section is marginal [-].
    fuel_kg : float, optional
        Fuel on board at the start [kg], against the estimate of the fuel the mission burns.
    """
    if not 0.0 <= margin <= 10.0:
        raise FcsError(f"feasibility: margin {margin} outside the allowed range 0 to 10")
    if start is None:
        rwy = next((s["runway"] for s in mission.sections if REGISTRY[s.type].departs_from_runway), None)
        if rwy is None:
            ground = " or ".join(n for n, c in REGISTRY.items() if c.departs_from_runway)
            raise FcsError(f"{mission.source}: the mission starts with no {ground} section; give the "
                           "start position, altitude and speed")
        start = (rwy.threshold, rwy.elevation_m, 0.0)
    pos, alt, tas = start
    st = CheckState(pos, alt, tas, mass_kg, None)
    ck = Checker(mission, perf, limits, wind, dT_isa_K, margin)
    secs = mission.sections
    results = tuple(_check_section(ck, s, st, secs[i + 1] if i + 1 < len(secs) else None) for i, s in enumerate(secs))
    notes = []
    if fuel_kg is not None:
        ck.findings = []
        ck.flag(st.fuel_kg, fuel_kg, lambda v: f"the mission burns about {st.fuel_kg:.0f} kg of fuel (a rough "
                f"estimate), {fuel_kg:.0f} kg are on board: {v}")
        notes = ck.findings
    return MissionCheck(mission.name, mission.source, margin, mass_kg, results, st.fuel_kg, st.time_s, tuple(notes))
