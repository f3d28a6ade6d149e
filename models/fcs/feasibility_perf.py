"""The aircraft and engine performance the mission feasibility check (:mod:`.feasibility`) needs.

:class:`Performance` is what the check asks of a performance model: trimmed level flight at a
condition (drag, lift) and the engine's thrust range there, as a :class:`PerfPoint`; the
gradients and turn drag derived from a point are written here once. :class:`Limits` are the
flight control's own limits the check applies. openEMSS's implementation on the shipped models is
``openemss.report.model_performance.ModelPerformance``; the tests use analytic ones.

References
----------
.. [1] Anderson, J. D., *Aircraft Performance and Design*, McGraw-Hill, 1999, sect. 5.3 (rate of
   climb: (T - D) / W is the sine of the climb angle at constant speed), 5.4 (gliding flight), 5.14
   (level turn: lift n W, drag due to lift n^2 times the level flight's).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from .atmosphere import G0_M_S2
from .errors import FcsError

__all__ = ["PerfPoint", "Performance", "PerformanceError", "Limits", "from_dotted"]


class PerformanceError(FcsError):
    """The performance model has no answer at a point (beyond the stall, no engine steady state)."""


@dataclass(frozen=True, slots=True)
class PerfPoint:
    """Steady level flight at one condition, and the engine's thrust range there.

    Attributes
    ----------
    alt_m, mach, tas_m_s, mass_kg : float
        Altitude MSL [m], Mach [-], true airspeed [m/s], mass [kg].
    drag_N : float
        Drag in trimmed level flight [N].
    CL, CL_max, k_induced : float
        Lift coefficient, its maximum, the drag-due-to-lift factor (CD_i = k CL^2) [-].
    qS_N : float
        Dynamic pressure times wing area [N].
    thrust_max_N, thrust_idle_N : float
        Net thrust at the lever's maximum and at flight idle [N].
    fuel_max_kg_s, fuel_idle_kg_s : float
        Fuel flow at those settings [kg/s].
    drag_airbrake_N : float
        Drag increment of the airbrake fully out there [N] (0 for an aircraft without one).
    """

    alt_m: float
    mach: float
    tas_m_s: float
    mass_kg: float
    drag_N: float
    CL: float
    CL_max: float
    k_induced: float
    qS_N: float
    thrust_max_N: float
    thrust_idle_N: float
    fuel_max_kg_s: float
    fuel_idle_kg_s: float
    drag_airbrake_N: float = 0.0

    @property
    def weight_N(self) -> float:
        return self.mass_kg * G0_M_S2

    def drag_in_turn_N(self, n: float) -> float:
        """Drag at load factor ``n`` [N]: D + q S k CL^2 (n^2 - 1)."""
        return self.drag_N + self.qS_N * self.k_induced * self.CL ** 2 * (n * n - 1.0)

    def climb_gradient(self, n: float = 1.0) -> float:
        """Energy gradient at maximum thrust, (T_max - D(n)) / W [-] (per air distance)."""
        return (self.thrust_max_N - self.drag_in_turn_N(n)) / self.weight_N

    def descent_gradient(self, n: float = 1.0, airbrake: float = 0.0) -> float:
        """Energy loss gradient at idle with the airbrake ``airbrake`` [0, 1] out,
        (D(n) + airbrake dD_airbrake - T_idle) / W [-] (per air distance)."""
        return (self.drag_in_turn_N(n) + airbrake * self.drag_airbrake_N - self.thrust_idle_N) / self.weight_N


class Performance(Protocol):
    """What the check needs from the aircraft and its engine."""

    rolling_friction: float

    def point(self, alt_m: float, mach: float, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        """Trimmed level flight and the thrust range (raises :class:`PerformanceError`)."""

    def thrust_max_N(self, alt_m: float, mach: float) -> float:
        """Maximum thrust [N] (also on the ground)."""

    def cruise_fuel_kg_s(self, alt_m: float, mach: float, Fn_N: float) -> float:
        """Fuel flow for a thrust [kg/s]."""


def from_dotted(cls: type[Any], get: Callable[[str], float], optional: tuple[str, ...] = ()) -> Any:
    """An instance of the dataclass ``cls`` whose fields are parameters of the system, named in its
    ``NAMES`` (field -> dotted parameter name) and read with ``get``; the ``optional`` fields keep their
    defaults where ``get`` raises KeyError."""
    vals: dict[str, float] = {}
    for k, v in cls.NAMES.items():
        try:
            vals[k] = float(get(v))
        except KeyError:
            if k not in optional:
                raise
    return cls(**vals)


@dataclass(frozen=True, slots=True)
class Limits:
    """The flight control's limits the check applies (its parameters, by their dotted names)."""

    phi_max_rad: float        #: guidance.phi_max_rad
    fly_by_bank_frac: float   #: guidance.fly_by_bank_frac
    gamma_max_rad: float      #: tecs.gamma_max_rad
    gamma_min_rad: float      #: tecs.gamma_min_rad
    mach_max: float           #: tecs.mach_max
    v_min_cas_m_s: float      #: tecs.V_min_cas_m_s
    gs_angle_rad: float       #: approach.gs_angle_rad
    tch_m: float              #: approach.tch_m
    hold_enter_m: float       #: approach.hold_enter_m
    airbrake_plan_max: float = 0.0  #: vnav.airbrake_plan_max (the most airbrake a descent is planned with)

    NAMES = {"phi_max_rad": "guidance.phi_max_rad", "fly_by_bank_frac": "guidance.fly_by_bank_frac",
             "gamma_max_rad": "tecs.gamma_max_rad", "gamma_min_rad": "tecs.gamma_min_rad",
             "mach_max": "tecs.mach_max", "v_min_cas_m_s": "tecs.V_min_cas_m_s",
             "gs_angle_rad": "approach.gs_angle_rad", "tch_m": "approach.tch_m",
             "hold_enter_m": "approach.hold_enter_m", "airbrake_plan_max": "vnav.airbrake_plan_max"}

    @classmethod
    def from_parameters(cls, get: Callable[[str], float]) -> Limits:
        """From the FCS's parameters, ``get("tecs.gamma_max_rad")`` etc.; an FCS without the airbrake
        parameter plans none."""
        return from_dotted(cls, get, optional=("airbrake_plan_max",))


