"""The aircraft's performance for the mission feasibility check, from the shipped models.

:class:`ModelPerformance` implements :class:`openemss.models.fcs.feasibility.Performance` with

* the drag of UPERA trimmed in level flight: :func:`openemss.models.airframe.trim.trim_level`
  on the JSBSim model (still air; the check applies the wind to the ground speeds), and the
  maximum lift and drag-due-to-lift factor of :func:`openemss.models.airframe.aero.aero_model`;
* the engine of the system's parameter set (:class:`openemss.models.engine.engine_model.EngineModel`,
  the maps extended below idle, as the engine FMU flies them), matched in steady state at the
  thrust range the fuel controller gives: maximum = the lever's maximum times ``k_delta`` as the
  corrected fan speed demand, reduced until Tt41 and N1 are within ``Tt41_max_K`` and
  ``N1_max_pct`` (the limiters of :mod:`openemss.models.fcs.fuel_control`), the fuel flow within
  ``Wf_max_kg_s``; idle = the larger of ``N1c_idle_pct`` and ``lever_min`` times ``k_delta`` as the
  demand, or the fuel flow's stops if they give more: ``Wf_min_kg_s`` and the engine's minimum
  flows (a fraction of the design flow, and the minimum-flow stop on Pt3).

Every point is matched once and kept (a mission check needs a few dozen: about 3 ms for a trim,
1 to 3 ms for an engine point once the engine's compiled kernels are cached; the first run
compiles them, about 10 s).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from openemss.models.airframe.adapter import Airframe
from openemss.models.airframe.aero import aero_model
from openemss.models.airframe.errors import AirframeError
from openemss.models.airframe.trim import trim_level
from openemss.models.engine.design_params import TurbofanParams
from openemss.models.engine.engine_model import EngineLimits, EngineModel
from openemss.models.engine.errors import ModelError
from openemss.models.engine.offdesign import OffDesignPoint
from openemss.models.fcs.feasibility_perf import PerformanceError, PerfPoint

__all__ = ["FuelControlLimits", "ModelPerformance"]


@dataclass(frozen=True, slots=True)
class FuelControlLimits:
    """The thrust range the flight control allows (its parameters by their dotted names)."""

    k_delta_pct: float       #: fuel_control.k_delta_pct
    N1c_idle_pct: float      #: fuel_control.N1c_idle_pct
    Tt41_max_K: float        #: fuel_control.Tt41_max_K
    N1_max_pct: float        #: fuel_control.N1_max_pct
    Wf_min_kg_s: float       #: fuel_control.Wf_min_kg_s
    Wf_max_kg_s: float       #: fuel_control.Wf_max_kg_s
    lever_min: float         #: tecs.lever_min
    lever_max: float         #: tecs.lever_max

    NAMES = {"k_delta_pct": "fuel_control.k_delta_pct", "N1c_idle_pct": "fuel_control.N1c_idle_pct",
             "Tt41_max_K": "fuel_control.Tt41_max_K", "N1_max_pct": "fuel_control.N1_max_pct",
             "Wf_min_kg_s": "fuel_control.Wf_min_kg_s", "Wf_max_kg_s": "fuel_control.Wf_max_kg_s",
             "lever_min": "tecs.lever_min", "lever_max": "tecs.lever_max"}


def _key(*v: float) -> tuple[float, ...]:
    return tuple(round(x, 6) for x in v)


class ModelPerformance:
    """Trimmed UPERA and the system's engine within the fuel controller's limits.

    Parameters
    ----------
    engine : TurbofanParams
        The engine's design parameters (a preset, or the engine FMU's design override).
    fuel : FuelControlLimits
        Lever, N1c, Tt41, N1 and fuel-flow limits of the flight control.
    engine_limits : EngineLimits, optional
        The engine's fuel-system stops (its FMU parameters).
    dT_isa_K : float
        ISA temperature deviation [K].
    flaps : float
        Flap setting the flight control commands [0, 1].
    """

    def __init__(self, engine: TurbofanParams, fuel: FuelControlLimits, engine_limits: EngineLimits | None = None,
                 dT_isa_K: float = 0.0, flaps: float = 0.0) -> None:
        self.fuel, self.dT, self.flaps = fuel, float(dT_isa_K), float(flaps)
        self._af = Airframe(dT_isa_K=dT_isa_K)
        self._aero = aero_model()
        self.rolling_friction = float(self._af.geometry.section("gear")["rolling_friction"])
        try:
            self._em = EngineModel(engine, limits=engine_limits)  # None: data/engine.json's
        except ModelError as e:
            raise PerformanceError(f"engine '{engine.name}': {e}") from None
        self._points: dict[tuple[float, ...], PerfPoint] = {}
        self._engine: dict[tuple[float, ...], OffDesignPoint] = {}

    # -- engine ---------------------------------------------------------------------------------
    def _solve(self, alt_m: float, mach: float, guess: OffDesignPoint | None = None, **setting: float) \
            -> OffDesignPoint:
        key = _key(alt_m, mach, *setting.values()) + tuple(setting)  # type: ignore[operator]
        hit = self._engine.get(key)
        if hit is not None:
            return hit
        try:
            try:
                pt = self._em.od.solve(alt_m, mach, self.dT, guess=guess, **setting)
            except ModelError:
                if guess is None:
                    raise
                pt = self._em.od.solve(alt_m, mach, self.dT, **setting)  # from the design's point instead
        except ModelError as e:
            what = ", ".join(f"{k} = {v:.4g}" for k, v in setting.items())
            raise PerformanceError(f"engine: no steady state at {alt_m:.0f} m, M {mach:.2f} with {what}: {e}") from None
        self._engine[key] = pt
        return pt

    def _over(self, pt: OffDesignPoint) -> bool:
        f = self.fuel
        return pt.T41_K > f.Tt41_max_K or pt.N1_pct > f.N1_max_pct or pt.Wf_kg_s > f.Wf_max_kg_s

    def max_point(self, alt_m: float, mach: float) -> OffDesignPoint:
        """Steady maximum: the lever's N1c demand, lowered to the first limit reached (bisection)."""
        demand = self.fuel.k_delta_pct * self.fuel.lever_max
        pt = self._solve(alt_m, mach, N1c_pct=demand)
        if not self._over(pt):
            return pt
        lo, hi = self.idle_point(alt_m, mach).N1c_pct, demand
        best = self._solve(alt_m, mach, N1c_pct=lo)
        for _ in range(12):  # 0.02 % of N1c
            mid = 0.5 * (lo + hi)
            p = self._solve(alt_m, mach, N1c_pct=mid)
            lo, hi, best = (mid, hi, p) if not self._over(p) else (lo, mid, best)
        return best

    def idle_point(self, alt_m: float, mach: float) -> OffDesignPoint:
        """Steady flight idle: the idle N1c demand, or the fuel flow's lower stops if they give more (with no
        idle demand, ``N1c_idle_pct`` 0 and ``lever_min`` 0, idle is the stops: the fuel controller's Wf_min).

        Below the demand the stops are approached from it in steps of corrected fan speed, each matched
        from the last; where the engine has no steady state that low (sub-idle near sea level) the lowest
        one found is taken, which overstates the idle thrust: the descent gradient is then conservative."""
        f, em = self.fuel, self._em
        demand = max(f.N1c_idle_pct, f.k_delta_pct * f.lever_min)
        pt = self._solve(alt_m, mach, N1c_pct=demand if demand > 0.0 else 40.0)  # 40 %: a point that converges

        def stop(p: OffDesignPoint) -> float:
            return max(f.Wf_min_kg_s, em.limits.Wf_min_frac * em.dp.Wf_kg_s,
                       em.Wf_Pt3_min_kg_s_Pa * p.stations["3"].Pt_Pa)

        if demand > 0.0 and pt.Wf_kg_s >= stop(pt) * (1.0 - 1e-6):
            return pt
        n1c = pt.N1c_pct
        while pt.Wf_kg_s < stop(pt) * (1.0 - 1e-6) or (demand <= 0.0 and pt.Wf_kg_s > stop(pt) * (1.0 + 1e-6)):
            going_up = pt.Wf_kg_s < stop(pt)
            try:
                nxt = self._solve(alt_m, mach, guess=pt, N1c_pct=n1c + (2.0 if going_up else -2.0))
            except PerformanceError:
                return pt
            if (nxt.Wf_kg_s >= stop(nxt)) != (pt.Wf_kg_s >= stop(pt)):  # bracketed: finish on the stop
                try:
                    return self._solve(alt_m, mach, guess=nxt, Wf_kg_s=stop(nxt))
                except PerformanceError:
                    return nxt if going_up else pt
            pt, n1c = nxt, nxt.N1c_pct
            if not 5.0 < n1c < 110.0:
                return pt
        return pt

    def thrust_max_N(self, alt_m: float, mach: float) -> float:
        """Steady maximum net thrust [N]."""
        return self.max_point(alt_m, mach).Fn_N

    def cruise_fuel_kg_s(self, alt_m: float, mach: float, Fn_N: float) -> float:
        """Fuel flow for a net thrust [kg/s], clipped to the idle..maximum range."""
        lo, hi = self.idle_point(alt_m, mach), self.max_point(alt_m, mach)
        if Fn_N <= lo.Fn_N:
            return lo.Wf_kg_s
        if Fn_N >= hi.Fn_N:
            return hi.Wf_kg_s
        return self._solve(alt_m, mach, Fn_N=float(Fn_N)).Wf_kg_s

    # -- aircraft -------------------------------------------------------------------------------
    def _airbrake_drag_N(self, qbar_Pa: float) -> float:
        """Drag of the airbrake fully out at ``qbar_Pa`` [N]: its drag increment (:meth:`.AeroModel.cd_airbrake`)
        on the wing area, the dynamic pressure held at the panels' blow-back pressure (the JSBSim file's
        channel); 0 for a geometry without an airbrake."""
        g = self._aero.geom
        if "airbrake" not in g.raw:
            return 0.0
        q = min(qbar_Pa, float(g.raw["airbrake"].get("blowback_qbar_Pa", math.inf)))
        return float(self._aero.cd_airbrake(1.0)) * q * g.wing.area_m2

    def point(self, alt_m: float, mach: float, mass_kg: float, gear_down: bool = False) -> PerfPoint:
        """Trimmed level flight at ``alt_m`` [m], ``mach`` [-], ``mass_kg`` [kg], and the thrust range there."""
        key = _key(alt_m, mach, mass_kg, float(gear_down))
        hit = self._points.get(key)
        if hit is not None:
            return hit
        g = self._af.geometry
        mass = min(max(mass_kg, g.oem_kg), g.mtom_kg)
        try:
            r = trim_level(alt_m, mach, mass, airframe=self._af, flaps=self.flaps, gear_down=gear_down)
        except AirframeError as e:
            raise PerformanceError(f"level flight at {alt_m:.0f} m, M {mach:.2f}, {mass:.0f} kg"
                                   f"{' with the gear down' if gear_down else ''}: {e}") from None
        hi, lo = self.max_point(alt_m, mach), self.idle_point(alt_m, mach)
        p = PerfPoint(alt_m=alt_m, mach=mach, tas_m_s=r.tas_m_s, mass_kg=mass, drag_N=r.drag_N, CL=r.CL,
                      CL_max=float(self._aero.clmax(self.flaps)), k_induced=float(self._aero.k_induced()),
                      qS_N=r.qbar_Pa * g.wing.area_m2, thrust_max_N=hi.Fn_N, thrust_idle_N=lo.Fn_N,
                      fuel_max_kg_s=hi.Wf_kg_s, fuel_idle_kg_s=lo.Wf_kg_s,
                      drag_airbrake_N=self._airbrake_drag_N(r.qbar_Pa))
        if not all(math.isfinite(v) for v in (p.drag_N, p.thrust_max_N, p.thrust_idle_N)):
            raise PerformanceError(f"level flight at {alt_m:.0f} m, M {mach:.2f}: no finite drag or thrust")
        self._points[key] = p
        return p
