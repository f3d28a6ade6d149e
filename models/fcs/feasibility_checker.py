"""What the mission feasibility check (:mod:`.feasibility`) gives every section type's check: the findings, the
state carried from section to section, and the physics shared by the checks (:class:`Checker`).

A section type carries its own check (:attr:`.sections.SectionType.feasibility`, the shipped ones in
:mod:`.feasibility_sections`): a function ``check(ck, sec, st, out) -> float`` that reads the section, adds its
findings with ``ck.flag`` or ``ck.note``, fills ``out`` (the :class:`~.feasibility.SectionCheck` figures), moves
``st`` to the section's end and returns the section's target altitude [m]. The methods of :class:`Checker` are
the physics the check may use: the achievable climb or descent over a distance (specific excess power, [1]_),
level flight and turns at a load factor, turn radii at the bank limit, the fuel burned.

References
----------
.. [1] Anderson, J. D., *Aircraft Performance and Design*, McGraw-Hill, 1999, sect. 5.3 (rate of
   climb, specific excess power) and 5.8 (energy height); sect. 5.4 (gliding flight).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..common.airspeed import cas_from_tas, mach_from_tas
from ..mission.geo import LatLon
from ..mission.speed import SpeedCommand
from ..mission.weather import WindProfile
from .atmosphere import G0_M_S2, isa
from .feasibility_perf import Limits, Performance, PerfPoint

if TYPE_CHECKING:
    from ..mission.mission import Mission, Section

__all__ = ["VERDICTS", "NOTE", "Finding", "CheckState", "Checker", "FeasibilityCheck", "pct"]

VERDICTS = ("ok", "marginal", "infeasible")  #: a section's verdict, by severity
NOTE = "note"  #: a finding that informs and judges nothing


@dataclass(frozen=True, slots=True)
class Finding:
    """One finding of a section: ``verdict`` (``marginal``, ``infeasible`` or ``note``) and what, with the numbers."""

    verdict: str
    text: str


@dataclass
class CheckState:
    """Where the checked flight is at a section's end: position, altitude MSL [m], true airspeed [m/s], estimated
    mass [kg], ground track on arrival [rad] (None: not known), and the time [s] and fuel [kg] estimated so far."""

    pos: LatLon
    alt_m: float
    tas_m_s: float
    mass_kg: float
    course_rad: float | None   # ground track on arrival
    time_s: float = 0.0
    fuel_kg: float = 0.0


#: A section type's feasibility check: (checker, section, state at its start, figures to fill) -> the altitude the
#: section ends at [m]; it moves the state to the section's end (:mod:`.feasibility_checker`).
FeasibilityCheck = Callable[["Checker", "Section", CheckState, dict[str, "float | None"]], float]


def pct(x: float) -> str:
    return f"{100.0 * x:.1f} % ({math.degrees(math.atan(x)):.1f} deg)"


class Checker:
    """The physics the section types' checks share, and the findings of the section being checked.

    Attributes
    ----------
    m : Mission
        The mission checked (its waypoints name the points in messages).
    perf : Performance
        The trimmed aircraft and its engine.
    lim : Limits
        The flight control's limits.
    wind : WindProfile or None
        Winds aloft (None: still air).
    dT : float
        ISA temperature deviation [K].
    margin : float
        Relative margin below which a feasible section is marginal [-].
    findings : list of Finding
        The findings of the section being checked.
    next_fix : LatLon or None
        Where the section after the one being checked begins (its type's ``entry_fix``), for the turn
        anticipation at the last fly-by waypoint, as the flight control plans it; None when there is none.
    """

    def __init__(self, mission: Mission, perf: Performance, limits: Limits, wind: WindProfile | None,
                 dT_isa_K: float, margin: float) -> None:
        self.m, self.perf, self.lim, self.wind, self.dT, self.margin = mission, perf, limits, wind, dT_isa_K, margin
        self.findings: list[Finding] = []
        self.next_fix: LatLon | None = None

    def note(self, text: str) -> None:
        """A finding that informs and judges nothing."""
        self.findings.append(Finding(NOTE, text))

    # -- helpers ------------------------------------------------------------------------------
    def flag(self, need: float, can: float, text: Callable[[str], str]) -> None:
        """A finding when ``can`` falls short of ``need`` (infeasible) or of ``need (1 + margin)``."""
        if can < need:
            self.findings.append(Finding("infeasible", text("infeasible")))
        elif can < need * (1.0 + self.margin):
            self.findings.append(Finding("marginal", text(f"marginal (margin {100.0 * (can / need - 1.0):.0f} %, "
                                                          f"less than {100.0 * self.margin:.0f} %)")))

    def speed(self, spd: SpeedCommand, alt_m: float) -> tuple[float, float]:
        """(TAS [m/s], Mach [-]) of a speed command at an altitude, Mach clipped as the TECS does."""
        atm = isa(alt_m, self.dT)
        tas = spd.tas_m_s(alt_m, self.dT)
        mach = mach_from_tas(tas, atm)
        if mach > self.lim.mach_max:
            mach = self.lim.mach_max
            tas = mach * atm.a_m_s
        return tas, mach

    def ground_speed(self, tas: float, alt_m: float, course_rad: float | None) -> float:
        """Ground speed along ``course_rad`` [m/s] (TAS when still air or no course)."""
        if self.wind is None or course_rad is None:
            return tas
        n, e = self.wind.ne_m_s(alt_m)
        along = n * math.cos(course_rad) + e * math.sin(course_rad)
        cross = -n * math.sin(course_rad) + e * math.cos(course_rad)
        return along + math.sqrt(max(tas * tas - cross * cross, 1.0))

    def max_ground_speed(self, tas: float, alt_m: float) -> float:
        if self.wind is None:
            return tas
        return tas + math.hypot(*self.wind.ne_m_s(alt_m))

    def point(self, alt_m: float, spd: SpeedCommand, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        return self.perf.point(alt_m, self.speed(spd, alt_m)[1], mass_kg, gear_down)

    # -- vertical -----------------------------------------------------------------------------
    def vertical(self, h0: float, h1: float, v0: float, spd: SpeedCommand, mass: float, dist: float | None,
                 course: float | None, n: float = 1.0, gear_down: bool = False, what: str = "") \
            -> tuple[float | None, float | None, float | None]:
        """(required, achievable gradient, needed distance) of an altitude and speed change."""
        v1 = self.speed(spd, h1)[0]
        dE = (h1 - h0) + (v1 * v1 - v0 * v0) / (2.0 * G0_M_S2)
        dh = h1 - h0
        if abs(dh) < 1.0:  # a speed change at one altitude: the level-flight thrust check covers it
            return None, None, None
        climb = dE > 0.0
        inv, inv_ab = [], []
        for h in (h0, 0.5 * (h0 + h1), h1):
            p = self.point(h, spd, mass, gear_down)
            g = p.climb_gradient(n) if climb else p.descent_gradient(n)
            g_ab = g if climb else p.descent_gradient(n, self.lim.airbrake_plan_max)
            if g <= 0.0:
                why = (f"drag {p.drag_in_turn_N(n) / 1e3:.2f} kN exceeds the maximum thrust "
                       f"{p.thrust_max_N / 1e3:.2f} kN" if climb else
                       f"idle thrust {p.thrust_idle_N / 1e3:.2f} kN exceeds the drag "
                       f"{p.drag_in_turn_N(n) / 1e3:.2f} kN")
                self.findings.append(Finding("infeasible", f"{what}{'climb' if climb else 'descent'} "
                                             f"{h0:.0f} -> {h1:.0f} m: at {h:.0f} m and M {p.mach:.2f} the {why}"))
                return (None if dist is None else abs(dh) / dist), 0.0, math.inf
            gs_ratio = self.ground_speed(p.tas_m_s, h, course) / p.tas_m_s
            inv.append(gs_ratio / g)
            inv_ab.append(gs_ratio / g_ab)
        d_energy = abs(dE) * (inv[0] + 4.0 * inv[1] + inv[2]) / 6.0
        # A descent that idle cannot make in the distance is planned with the airbrake, up to
        # vnav.airbrake_plan_max of its travel (the rest is the flight management's margin).
        d_energy_ab = abs(dE) * (inv_ab[0] + 4.0 * inv_ab[1] + inv_ab[2]) / 6.0
        airbrake = (not climb and dist is not None and self.lim.airbrake_plan_max > 0.0
                    and d_energy > dist and d_energy_ab < d_energy)
        if airbrake:
            d_energy_idle, d_energy = d_energy, d_energy_ab
        gamma_lim = self.lim.gamma_max_rad if dh > 0 else -self.lim.gamma_min_rad
        gs_air = self.ground_speed(v1, h1, course) / v1
        d_gamma = abs(dh) / math.tan(max(gamma_lim, 1e-3)) * gs_air
        needed = max(d_energy, d_gamma)
        can = abs(dh) / needed if needed > 0 else math.inf
        if dist is None:
            return None, math.copysign(can, dh), needed
        need = abs(dh) / max(dist, 1.0)
        by = "thrust" if d_energy >= d_gamma else \
            f"the flight-path limit {math.degrees(gamma_lim):.1f} deg (tecs.gamma_{'max' if dh > 0 else 'min'}_rad)"
        setting = "at full thrust" if climb else (
            f"at idle with the airbrake planned up to {100.0 * self.lim.airbrake_plan_max:.0f} %" if airbrake
            else "at idle")
        spdtxt = f"M {self.speed(spd, h1)[1]:.2f}"
        self.flag(need, can, lambda v: (
            f"{what}{'climb' if dh > 0 else 'descent'} {h0:.0f} -> {h1:.0f} m over {dist / 1e3:.1f} km needs "
            f"{pct(need)}; {setting} at {spdtxt} the aircraft makes {pct(can)} (limited by {by}), i.e. "
            f"{needed / 1e3:.1f} km: {v}"))
        if airbrake and can >= need:
            self.findings.append(Finding("note", f"{what}descent {h0:.0f} -> {h1:.0f} m over {dist / 1e3:.1f} km: idle "
                                         f"alone needs {d_energy_idle / 1e3:.1f} km; planned with the airbrake"))
        return math.copysign(need, dh), math.copysign(can, dh), needed

    def level(self, p: PerfPoint, n: float, what: str) -> float:
        """Maximum thrust over drag at load factor ``n``; findings for thrust and lift."""
        d = p.drag_in_turn_N(n)
        ratio = p.thrust_max_N / d if d > 0 else math.inf
        turn = f" in a {math.degrees(math.acos(1.0 / n)):.0f}-deg banked turn" if n > 1.0001 else ""
        self.flag(1.0, ratio, lambda v: f"{what}level flight at {p.alt_m:.0f} m, M {p.mach:.2f}{turn} needs "
                  f"{d / 1e3:.2f} kN, the engine gives at most {p.thrust_max_N / 1e3:.2f} kN: {v}")
        if n > 1.0001:
            self.flag(n * p.CL, 0.95 * p.CL_max, lambda v: f"{what}the turn at {n:.2f} g needs CL = {n * p.CL:.2f}, "
                      f"95 % of CL_max = {0.95 * p.CL_max:.2f}: {v}")
        cas = cas_from_tas(p.tas_m_s, isa(p.alt_m, self.dT))
        if cas < self.lim.v_min_cas_m_s:
            self.findings.append(Finding("marginal", f"{what}{cas:.0f} m/s CAS is below the underspeed protection "
                                         f"{self.lim.v_min_cas_m_s:.0f} m/s (tecs.V_min_cas_m_s): the TECS flies "
                                         "faster"))
        return ratio

    def turn_radius(self, gs: float, bank_frac: float = 1.0) -> float:
        return gs * gs / (G0_M_S2 * math.tan(max(bank_frac * self.lim.phi_max_rad, 1e-3)))

    def fuel(self, st: CheckState, p: PerfPoint, dist_m: float, gs: float) -> None:
        t = dist_m / max(gs, 1.0)
        wf = self.perf.cruise_fuel_kg_s(p.alt_m, p.mach, p.drag_N)
        st.time_s += t
        st.fuel_kg += wf * t
        st.mass_kg -= wf * t


    def name(self, p: LatLon) -> str:
        for n, w in self.m.waypoints:
            if w == p:
                return n
        return f"({p.lat_deg:.3f}, {p.lon_deg:.3f})"

