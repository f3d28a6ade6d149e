"""Performance databases (models/fcs/performance.py) written from the test aircraft's own equations.

The FCS plans and limits its commands with a performance database. For the test aircraft
(pointmass.py, aircraft3dof.py, the engine stand-in of upera_loop.py) the database is filled here
from their stated constants, so a test flies the FCS with a model that is right for its aircraft,
or wrong by a stated amount. ``synthetic`` builds one from functions of altitude and Mach.
"""

from __future__ import annotations

from collections.abc import Callable

from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.performance import PerformanceData, load_performance_data

ALT = tuple(float(h) for h in range(0, 9001, 1000))
MACH = tuple(round(0.1 + 0.05 * i, 2) for i in range(16))
N1C = (0.0, 100.0)


def synthetic(cd0: float, k: float, Fn_N: Callable[[float, float, float], float],
              thrust_max_N: Callable[[float, float], float], S_m2: float = 11.2, cd_airbrake: float = 0.0,
              cd_gear: float = 0.0, blowback_qbar_Pa: float = 1e9,
              base: PerformanceData | None = None) -> PerformanceData:
    """A database with a constant polar (or ``base``'s polar, when given) and the thrust functions
    ``Fn_N(h, M, N1c)`` and ``thrust_max_N(h, M)`` [N]."""
    def grid(f: Callable[[float, float], float]) -> tuple[tuple[float, ...], ...]:
        return tuple(tuple(float(f(h, m)) for m in MACH) for h in ALT)

    if base is not None:
        from openemss.models.fcs.performance import Performance

        p = Performance(base)
        cd0_t = grid(lambda h, m: p.polar(h, m)[0])
        k_t = grid(lambda h, m: p.polar(h, m)[1])
        S_m2, cd_airbrake, cd_gear = base.S_m2, base.cd_airbrake, base.cd_gear
        blowback_qbar_Pa = base.airbrake_blowback_qbar_Pa
    else:
        cd0_t, k_t = grid(lambda h, m: cd0), grid(lambda h, m: k)
    return PerformanceData(S_m2, ALT, MACH, cd0_t, k_t, cd_gear, cd_airbrake, 1.0471975511965976, blowback_qbar_Pa,
                           1.0 / 1.5, N1C, tuple(grid(lambda h, m, n=n: Fn_N(h, m, n)) for n in N1C),
                           grid(thrust_max_N), "tests/fcs/perf_models.py")


def lapse_thrust(h: float, sls_N: float = 13000.0, n: float = 0.7) -> float:
    """sls_N (rho/rho0)^n [N], the test aircraft's available thrust."""
    return sls_N * (isa(h).rho_kg_m3 / 1.225) ** n


def pointmass(thrust_max_factor: float = 1.0, cd_airbrake: float = 0.0, cd0: float = 0.025) -> PerformanceData:
    """pointmass.py and aircraft3dof.py: CD0 0.025, k 0.06, thrust 13 kN (rho/rho0)^0.7 (N1c/100)^2, so idle
    (N1c ~ 0) gives none; maximum thrust at N1c 100 % times ``thrust_max_factor``."""
    return synthetic(cd0, 0.06, lambda h, m, n1c: lapse_thrust(h) * (n1c / 100.0) ** 2,
                     lambda h, m: thrust_max_factor * lapse_thrust(h), cd_airbrake=cd_airbrake)


def upera_standin() -> PerformanceData:
    """The shipped UPERA polar and airbrake with the thrust of upera_loop.py's engine stand-in."""
    return synthetic(0.0, 0.0, lambda h, m, n1c: lapse_thrust(h) * (n1c / 100.0) ** 2,
                     lambda h, m: lapse_thrust(h), base=load_performance_data())
