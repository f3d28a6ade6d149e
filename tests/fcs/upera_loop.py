"""Closed loop of the FlightControlSystem with the UPERA JSBSim airframe (models/airframe).

The engine is the first-order stand-in of aircraft3dof.py (corrected fan speed with a
1 s lag, thrust 13 kN (rho/rho0)^0.7 (N1c/100)^2), so these runs test the control laws
on the 6-DoF airframe independently of the engine model; the FCS's performance model
(perf_models.upera_standin) has the shipped UPERA polar and airbrake with that thrust. The FCS measures what an FMU
would receive: the airframe's state; ground velocity from successive positions (it
carries the wind); the airspeed rate is left to the FCS, as an FMU leaves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.fcs import FlightControlSystem
from openemss.models.fcs.state import AircraftState, EngineState
from openemss.models.mission.geo import LatLon, local_ne_m


@dataclass
class Run:
    t: list[float] = field(default_factory=list)
    sec: list[int] = field(default_factory=list)
    phase: list[str] = field(default_factory=list)
    alt: list[float] = field(default_factory=list)
    alt_cmd: list[float] = field(default_factory=list)
    mach: list[float] = field(default_factory=list)
    mach_cmd: list[float] = field(default_factory=list)
    pos: list[LatLon] = field(default_factory=list)
    on_ground: list[bool] = field(default_factory=list)
    vs: list[float] = field(default_factory=list)
    wf: list[float] = field(default_factory=list)
    nz: list[float] = field(default_factory=list)
    mode: list[str] = field(default_factory=list)
    airbrake: list[float] = field(default_factory=list)
    xtk: list[float] = field(default_factory=list)


def fly_upera(af, s, fcs: FlightControlSystem, t_end: float, N1c0: float, dt: float = 0.05) -> Run:
    """Fly ``fcs`` on airframe ``af`` (started, state ``s``) until the mission ends or ``t_end`` [s]."""
    from openemss.models.fcs.vertical import VNAV_MODES
    from openemss.models.mission.speed import SpeedKind

    N1c = N1c0
    th_engine = s.T_amb_K / 288.15  # the temperature the engine last stepped in: its N1 output's correction
    prev_pos = None
    run = Run()
    k = 0
    while not fcs.finished and k * dt < t_end:
        # times and step sizes as a master with integer ticks has them: t_k = k dt, steps t_(k+1) - t_k
        # (equal to dt but in the last bits, which the FCS's ground acceleration, a difference of
        # position differences, sees)
        t = k * dt
        h = (k + 1) * dt - t
        pos = LatLon.from_deg(s.lat_deg, s.lon_deg)
        if prev_pos is None:
            vn, ve = s.gs_m_s * math.cos(s.psi_rad), s.gs_m_s * math.sin(s.psi_rad)
        else:
            n, e = local_ne_m(prev_pos, pos)
            vn, ve = n / (t - (k - 1) * dt), e / (t - (k - 1) * dt)
        gamma = math.asin(max(-1.0, min(1.0, s.vs_m_s / max(s.tas_m_s, 1.0))))
        Vdot = math.nan  # as the FCS FMU gets it: the FCS derives it from successive airspeeds (filtered)
        prev_pos = pos
        qbar = 0.5 * s.rho_amb_kg_m3 * s.tas_m_s * s.tas_m_s
        x = AircraftState(pos, s.alt_m, s.tas_m_s, Vdot, gamma, vn, ve, s.psi_rad, s.phi_rad, s.theta_rad,
                          s.p_rad_s, s.q_rad_s, s.r_rad_s, s.beta_rad, qbar, s.mass_kg, s.on_ground)
        th = s.T_amb_K / 288.15
        out = fcs.step(t, h, x, EngineState(N1c * math.sqrt(th_engine), N1c, 700.0 + 7.0 * N1c))
        th_engine = th
        delta = s.p_amb_Pa / 101325.0
        N1c += (min(400.0 * out.Wf_cmd_kg_s / (delta * math.sqrt(th)), 115.0) - N1c) * h
        thrust = 13000.0 * (s.rho_amb_kg_m3 / 1.225) ** 0.7 * (N1c / 100.0) ** 2
        af.set_surfaces(aileron=out.aileron_norm, elevator=out.elevator_norm, rudder=out.rudder_norm)
        af.set_thrust(thrust)
        af.set_fuel_flow(out.Wf_cmd_kg_s)
        af.set_gear(out.gear_down)
        af.set_brakes(out.brakes_norm)
        af.set_steering(out.steering_norm)
        af.set_airbrake(out.airbrake_norm)
        af.step(dt)
        s = af.state()
        tg = out.targets
        sp = tg.speed
        run.t.append(t + dt)
        run.sec.append(tg.section_index)
        run.phase.append(tg.phase)
        run.alt.append(s.alt_m)
        run.alt_cmd.append(tg.alt_cmd_m if tg.alt_cmd_m is not None else math.nan)
        run.mach.append(s.mach)
        run.mach_cmd.append(sp.value if sp is not None and sp.kind is SpeedKind.MACH else math.nan)
        run.pos.append(LatLon.from_deg(s.lat_deg, s.lon_deg))
        run.on_ground.append(s.on_ground)
        run.vs.append(s.vs_m_s)
        run.wf.append(out.Wf_cmd_kg_s)
        run.nz.append(s.load_factor)
        run.mode.append(VNAV_MODES[out.vnav_mode])
        run.airbrake.append(s.airbrake_pos_norm)
        run.xtk.append(tg.xtk_m)
        k += 1
    _ = isa  # the ISA of the FCS is what the laws use; the airframe has its own
    return run
