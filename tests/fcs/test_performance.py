"""The FCS's performance database (models/fcs/performance.py, data/performance.json) against the models.

* The database is the models' (not a reference, a freshness check, as for UPERA.xml): sampled grid
  points are re-computed by the generator (models/performance/generate.py) and must equal the file.
  Regenerate with ``python -m openemss.models.performance.generate``.
* Independent reference for the gradient the planner descends at: the steady idle descent of the
  6-DoF airframe. The JSBSim model is trimmed (trim_level) in a straight descent at flight-path angle
  gamma, which gives the thrust that descent needs. gamma is then searched (secant) until that thrust
  equals the engine model's net thrust at the flight idle (N1c 40 %, the shipped system's idle). The
  points are off the database's grid (altitude, Mach and mass in between its nodes). The planner's sin
  gamma = (T_idle - D)/W must agree within 0.1 deg. That allows for the linear interpolation of the
  tables and the drag taken at the lift of level flight (0.6 % at 6 deg). Measured: within 0.02 deg
  at -2.5 to -8.9 deg.
* The airbrake's drag and its inverse, and the blow-back cap, by hand.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

pytest.importorskip("jsbsim")

from openemss.models.fcs.atmosphere import isa  # noqa: E402
from openemss.models.fcs.performance import Performance, load_performance_data  # noqa: E402
from openemss.models.performance import generate as gen  # noqa: E402

N1C_IDLE = 40.0


@pytest.fixture(scope="module")
def od():  # noqa: ANN201
    from openemss.models.engine.cycle_design import design
    from openemss.models.engine.design_params import load_params, preset_path
    from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps

    dp = design(load_params(preset_path("larzac04_sls")))
    return TurbofanOffDesign(dp, scaled_maps(dp))


def test_database_is_what_the_models_give(od) -> None:  # noqa: ANN001
    doc = json.loads((Path(__file__).resolve().parents[2] / "models" / "fcs" / "data" / "performance.json").read_text())
    for i, j in ((2, 5), (5, 9), (7, 12)):  # (altitude, Mach) indices of the grid
        h, m = gen.ALT_AXIS_M[i], gen.MACH_AXIS[j]
        cd0, k = gen.polar_point(h, m)
        assert doc["cd0"][i][j] == pytest.approx(cd0, abs=1e-7), (h, m)
        assert doc["k"][i][j] == pytest.approx(k, abs=1e-7), (h, m)
        col = gen.thrust_column(od, h, m)
        for jn, t in enumerate(col):
            if t is not None:
                assert doc["Fn_N"][jn][i][j] == pytest.approx(t, abs=1e-3), (h, m, gen.N1C_AXIS_PCT[jn])
        assert doc["thrust_max_N"][i][j] == pytest.approx(gen.max_thrust(od, h, m), abs=1e-3), (h, m)


def _trimmed_idle_descent(alt_m: float, mach: float, mass_kg: float, Fn_N: float, airbrake: float) -> float:
    """Flight-path angle [rad] of the steady descent whose trimmed thrust is ``Fn_N``, by secant."""
    from openemss.models.airframe.trim import trim_level

    def f(g: float) -> float:
        return trim_level(alt_m, mach, mass_kg, flight_path_rad=g, airbrake=airbrake).Fn_N - Fn_N

    g0, g1 = -0.05, -0.10
    f0, f1 = f(g0), f(g1)
    for _ in range(30):
        g2 = g1 - f1 * (g1 - g0) / (f1 - f0)
        g0, f0, g1, f1 = g1, f1, g2, f(g2)
        if abs(f1) < 1e-3:
            break
    return g1


@pytest.mark.parametrize(("alt_m", "mach", "mass_kg", "airbrake"),
                         [(3300.0, 0.57, 1850.0, 0.0), (6400.0, 0.72, 2000.0, 0.0), (1700.0, 0.33, 1700.0, 0.0),
                          (4500.0, 0.47, 1900.0, 0.5)])
def test_idle_descent_gradient_against_the_trimmed_airframe_and_the_engine(od, alt_m: float, mach: float,  # noqa: ANN001
                                                                        mass_kg: float, airbrake: float) -> None:
    t_idle = od.solve(alt_m, mach, N1c_pct=N1C_IDLE).Fn_N
    gamma_ref = _trimmed_idle_descent(alt_m, mach, mass_kg, t_idle, airbrake)
    perf = Performance(n1c_idle=lambda: N1C_IDLE)
    v = mach * isa(alt_m).a_m_s
    g = perf.energy_gradient(alt_m, v, mass_kg, "idle", airbrake=airbrake)
    assert -0.25 < gamma_ref < -0.01
    assert math.degrees(math.asin(g)) == pytest.approx(math.degrees(gamma_ref), abs=0.1)


def test_airbrake_drag_and_position_by_hand() -> None:
    data = load_performance_data()
    perf = Performance(data)
    S, cd = data.S_m2, data.cd_airbrake
    q = 10000.0  # below the blow-back
    assert perf.airbrake_drag_N(q, 1.0) == pytest.approx(cd * q * S, rel=1e-12)
    half = cd * q * S * math.sin(0.5 * data.airbrake_max_rad) / math.sin(data.airbrake_max_rad)
    assert perf.airbrake_drag_N(q, 0.5) == pytest.approx(half, rel=1e-12)
    assert perf.airbrake_position(half, q) == pytest.approx(0.5, rel=1e-12)
    q_hi = 2.0 * data.airbrake_blowback_qbar_Pa  # above it the force is that at the blow-back pressure
    assert perf.airbrake_drag_N(q_hi, 1.0) == pytest.approx(cd * data.airbrake_blowback_qbar_Pa * S, rel=1e-12)
    assert perf.airbrake_position(10.0 * cd * q * S, q) == 1.0
