"""FCS, UPERA airframe (JSBSim) and the engine model's transient (Larzac 04 preset) coupled
in Python at 20 Hz: the whole propulsion-control chain TECS lever -> fuel controller ->
spool dynamics -> net thrust -> airframe.

Stated bounds: from a trimmed start at 5000 m, Mach 0.5, the hold is bumpless (altitude
within 2 m, Mach within 0.002); the combined step to 5300 m and Mach 0.55 never dips
below 5000 m - 5 m (no height traded for speed while a climb is commanded), captures the
altitude within 5 m and the Mach number within 0.002, and Tt41 stays below its limit.
"""

from __future__ import annotations

import math

import pytest

pytest.importorskip("jsbsim")
adapter = pytest.importorskip("openemss.models.airframe.adapter")
transient = pytest.importorskip("openemss.models.engine.transient")

from openemss.models.airframe.trim import trim_level  # noqa: E402
from openemss.models.engine.cycle_design import design  # noqa: E402
from openemss.models.engine.design_params import load_params, preset_path  # noqa: E402
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps  # noqa: E402
from openemss.models.fcs.fcs import FlightControlSystem  # noqa: E402
from openemss.models.fcs.state import AircraftState, EngineState  # noqa: E402
from openemss.models.mission.geo import LatLon, local_ne_m  # noqa: E402
from openemss.models.mission.mission import parse_mission  # noqa: E402

MISSION = """
mission: {name: coupled steps}
sections:
  - {type: Levelling, altitude_m: 5000, speed: {mach: 0.5}, tolerance_m: 5, hold_s: 10}
  - {type: Levelling, altitude_m: 5300, speed: {mach: 0.55}, tolerance_m: 5, hold_s: 20}
"""
DT = 0.05


def test_fcs_engine_airframe_coupled() -> None:
    dp = design(load_params(preset_path("larzac04_sls")))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    tr = transient.TurbofanTransient(od)
    trm = trim_level(5000.0, 0.5)
    pt = od.solve(5000.0, 0.5, Fn_N=trm.Fn_N)
    af = adapter.Airframe()
    s = af.start_air(5000.0, trm.tas_m_s, 0.0, alpha_rad=trm.alpha_rad, elevator=trm.elevator,
                     Fn_N=trm.Fn_N)
    fcs = FlightControlSystem(parse_mission(MISSION), Wf0_kg_s=pt.Wf_kg_s, elevator0=trm.elevator)
    fcs.set_parameter("fuel_control.Wf_min_kg_s", 0.03)  # idle within the engine maps at altitude
    N1, N2 = pt.N1_rpm, pt.N2_rpm
    es = tr.state(0.0, N1, N2, pt.Wf_kg_s, 5000.0, 0.5, guess=pt)
    prev = None
    log: list[tuple[int, float, float, float]] = []
    k = 0
    while not fcs.finished and k * DT < 300.0:
        pos = LatLon.from_deg(s.lat_deg, s.lon_deg)
        if prev is None:
            vn, ve = s.gs_m_s * math.cos(s.psi_rad), s.gs_m_s * math.sin(s.psi_rad)
        else:
            n, e = local_ne_m(prev, pos)
            vn, ve = n / DT, e / DT
        prev = pos
        x = AircraftState(pos, s.alt_m, s.tas_m_s, math.nan, math.asin(s.vs_m_s / s.tas_m_s), vn, ve,
                          s.psi_rad, s.phi_rad, s.theta_rad, s.p_rad_s, s.q_rad_s, s.r_rad_s, s.beta_rad,
                          0.5 * s.rho_amb_kg_m3 * s.tas_m_s**2, s.mass_kg, s.on_ground)
        P = es.point
        out = fcs.step(k * DT, DT, x, EngineState(P.N1_pct, P.N1c_pct, P.T41_K))
        wf = out.Wf_cmd_kg_s
        s0 = tr.state(k * DT, N1, N2, wf, s.alt_m, s.mach, guess=es)
        p = tr.state((k + 1) * DT, N1 + DT * s0.dN1_dt_rpm_s, N2 + DT * s0.dN2_dt_rpm_s, wf, s.alt_m, s.mach,
                     guess=s0)
        N1 += 0.5 * DT * (s0.dN1_dt_rpm_s + p.dN1_dt_rpm_s)
        N2 += 0.5 * DT * (s0.dN2_dt_rpm_s + p.dN2_dt_rpm_s)
        es = tr.state((k + 1) * DT, N1, N2, wf, s.alt_m, s.mach, guess=p)
        af.set_surfaces(aileron=out.aileron_norm, elevator=out.elevator_norm, rudder=out.rudder_norm)
        af.set_thrust(es.point.Fn_N)
        af.set_fuel_flow(wf)
        af.step(DT)
        s = af.state()
        log.append((out.targets.section_index, s.alt_m, s.mach, es.point.T41_K))
        k += 1
    assert fcs.finished
    first = [r for r in log if r[0] == 0]
    second = [r for r in log if r[0] == 1]
    assert max(abs(r[1] - 5000.0) for r in first) < 2.0
    assert max(abs(r[2] - 0.5) for r in first) < 0.002
    assert min(r[1] for r in second) > 5000.0 - 5.0
    assert abs(second[-1][1] - 5300.0) < 5.0 and abs(second[-1][2] - 0.55) < 0.002
    assert max(r[3] for r in log) < fcs.get_parameter("fuel_control.Tt41_max_K")
