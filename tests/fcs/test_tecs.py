"""TECS and the pitch loop, closed loop on the point-mass longitudinal model (pointmass.py).

Independent references: the energy identity d/dt(h + V^2/2g) = V (sin gamma + Vdot/g)
(conservation of mechanical energy of a point mass), the first-order altitude capture
law of TECS (no overshoot by construction, bound stated per test), the limits
given to the controller, and for the speed steps at the thrust limit (issue 14) the
point mass's own equation of level flight at constant thrust, m dV/dt = T - D(V),
integrated by quadrature (t = integral of m dV / (T - D(V))), and its force balance
on a steady descent path (W sin gamma = D + D_airbrake - T).
"""

from __future__ import annotations

import math

import numpy as np
import pointmass
import pytest
from perf_models import pointmass as pointmass_perf
from pointmass import G, PointMass, drag_N, trimmed
from scipy.integrate import quad

from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.performance import Performance
from openemss.models.fcs.pitch import PitchController
from openemss.models.fcs.tecs import Tecs, TecsInput, TecsParams, specific_energy_rate_m_s
from openemss.models.mission.speed import SpeedCommand, SpeedKind

DT_CTRL = 0.05
N_SUB = 5


def fly(ac: PointMass, tecs: Tecs, pitch: PitchController, t_end: float, speed: SpeedCommand,
        alt_cmd: float | None = None, gamma_cmd: float | None = None, elev0: float = 0.0,
        perf: Performance | None = None, path: tuple[float, float] | None = None,
        airbrake: bool = False) -> dict[str, np.ndarray]:
    """Fly TECS on the point mass. With ``perf`` the energy-rate limits come from it (as the FCS gives them);
    ``path = (h0, gamma)`` flies a straight path from h0 at angle gamma in altitude mode with its vertical speed
    fed forward (as a managed descent); ``airbrake`` lets TECS use the airbrake, its drag applied at once."""
    keys = ("t", "V", "h", "gamma", "theta", "T", "lever", "prio", "E", "Edot", "ab", "hc")
    log: dict[str, list] = {k: [] for k in keys}
    elevator, T_cmd, D_ab, x_run = elev0, ac.T, 0.0, 0.0
    for k in range(int(round(t_end / DT_CTRL))):
        Vd = ac.Vdot(elevator, T_cmd, D_ab)
        e_min = e_max = math.nan
        ab_max = 0.0
        if perf is not None:
            look = perf.lookup(ac.h, ac.V / isa(ac.h).a_m_s)
            e_min, e_max, ab_max = perf.energy_rates(look, ac.qbar(), ac.mass, airbrake=airbrake)
        hdot_ff = 0.0
        if path is not None:
            alt_cmd = path[0] + math.tan(path[1]) * x_run
            hdot_ff = ac.V * math.cos(ac.gamma) * math.tan(path[1])
        out = tecs.step(DT_CTRL, TecsInput(ac.h, ac.V, Vd, ac.gamma, ac.mass, 0.0, e_min, e_max), speed, alt_cmd,
                        gamma_cmd, hdot_ff_m_s=hdot_ff, airbrake_max_N=ab_max,
                        priority="path" if path is not None else None)
        elevator = pitch.step(DT_CTRL, out.theta_cmd_rad, ac.theta, ac.q, ac.qbar())
        T_cmd, D_ab = out.thrust_cmd_N, out.airbrake_drag_N
        x0 = ac.x
        for _ in range(N_SUB):
            ac.step(DT_CTRL / N_SUB, elevator, T_cmd, D_ab)
        x_run += ac.x - x0
        for key, v in (("t", (k + 1) * DT_CTRL), ("V", ac.V), ("h", ac.h), ("gamma", ac.gamma),
                       ("theta", ac.theta), ("T", ac.T), ("lever", out.lever), ("prio", out.priority),
                       ("E", ac.h + ac.V**2 / (2 * G)),
                       ("Edot", specific_energy_rate_m_s(ac.V, ac.Vdot(elevator, T_cmd, D_ab), ac.gamma)),
                       ("ab", D_ab), ("hc", math.nan if alt_cmd is None else alt_cmd)):
            log[key].append(v)
    return {k: np.array(v) for k, v in log.items()}


def engaged(V: float, h: float, **kw: float) -> tuple[PointMass, Tecs, PitchController, float]:
    ac, de = trimmed(V, h)
    tecs = Tecs(TecsParams.from_file(**kw))
    tecs.reset(ac.T, ac.mass * G, ac.theta)
    pitch = PitchController()
    pitch.reset(de)
    return ac, tecs, pitch, de


def test_trim_is_held() -> None:
    ac, tecs, pitch, de = engaged(150.0, 3000.0)
    h = fly(ac, tecs, pitch, 30.0, SpeedCommand(150.0), alt_cmd=3000.0, elev0=de)
    assert np.max(np.abs(h["h"] - 3000.0)) < 0.5
    assert np.max(np.abs(h["V"] - 150.0)) < 0.1


def test_altitude_step_captured_without_overshoot() -> None:
    """+300 m at 150 m/s: overshoot under 3 m (1 %), speed held within 3 m/s, settled to 1 m in 90 s."""
    ac, tecs, pitch, de = engaged(150.0, 3000.0)
    h = fly(ac, tecs, pitch, 120.0, SpeedCommand(150.0), alt_cmd=3300.0, elev0=de)
    overshoot = h["h"].max() - 3300.0
    assert overshoot < 3.0
    assert np.max(np.abs(h["V"] - 150.0)) < 3.0
    assert np.all(np.abs(h["h"][h["t"] > 90.0] - 3300.0) < 1.0)
    assert h["gamma"].max() <= tecs.parameters.gamma_max_rad + 0.01


def test_large_climb_respects_flight_path_limit_and_levels_off() -> None:
    ac, tecs, pitch, de = engaged(140.0, 1000.0)
    h = fly(ac, tecs, pitch, 300.0, SpeedCommand(140.0), alt_cmd=5000.0, elev0=de)
    assert h["gamma"].max() <= tecs.parameters.gamma_max_rad + 0.01
    assert h["h"].max() - 5000.0 < 5.0
    assert abs(h["h"][-1] - 5000.0) < 2.0
    assert np.max(np.abs(h["V"] - 140.0)) < 6.0


def test_speed_step_captured_without_overshoot() -> None:
    """+20 m/s at 3000 m: speed overshoot under 1 m/s, altitude within 15 m, settled to 0.5 m/s in 60 s."""
    ac, tecs, pitch, de = engaged(130.0, 3000.0)
    h = fly(ac, tecs, pitch, 90.0, SpeedCommand(150.0), alt_cmd=3000.0, elev0=de)
    assert h["V"].max() - 150.0 < 1.0
    assert np.max(np.abs(h["h"] - 3000.0)) < 15.0
    assert np.all(np.abs(h["V"][h["t"] > 60.0] - 150.0) < 0.5)


def _time_to_speed(T_N: float, h: float, v0: float, v1: float) -> float:
    """Time from v0 to v1 [s] in level flight at constant thrust T: the integral of m dV / (T - D(V))."""
    return quad(lambda v: pointmass.M_KG / (T_N - drag_N(v, h)), v0, v1)[0]


def test_speed_step_at_thrust_limit_holds_altitude() -> None:
    """Issue 14: with the lever capped at 2 % above what level flight at the new speed needs, a +20 m/s step
    at 3000 m saturates the thrust; TECS cuts the acceleration to what the thrust gives (energy-rate limits
    of a matching performance model) and holds the height within 30 m (the issue's bound; measured: 1 m).
    The speed reaches 149 m/s no later than 1.15 times the time at constant maximum thrust by quadrature
    (engine lag 1 s, the jerk limit; measured 1.02), and settles within 1 m/s."""
    ac, tecs, pitch, de = engaged(130.0, 3000.0)
    ac150, _ = trimmed(150.0, 3000.0)
    cap = ac150.T / tecs.available_thrust_N(3000.0) * 1.02
    tecs.set_parameter("lever_max", cap)
    perf = Performance(pointmass_perf(thrust_max_factor=cap))
    h = fly(ac, tecs, pitch, 200.0, SpeedCommand(150.0), alt_cmd=3000.0, elev0=de, perf=perf)
    assert np.max(np.abs(h["h"] - 3000.0)) < 30.0
    t_ref = _time_to_speed(cap * tecs.available_thrust_N(3000.0), 3000.0, 130.0, 149.0)
    t_149 = h["t"][np.argmax(h["V"] >= 149.0)]
    assert h["V"].max() >= 149.0 and t_149 < 1.15 * t_ref
    assert np.all(np.abs(h["V"][h["t"] > t_149 + 60.0] - 150.0) < 1.0)


def test_mach_step_at_7500_m_near_the_thrust_limit_holds_altitude() -> None:
    """Issue 14: the Mach 0.7 -> 0.8 step at 7500 m with the maximum thrust 10 % above the drag at Mach 0.8:
    height within 30 m (measured 8 m); Mach 0.795 no later than 1.15 times the constant-thrust quadrature's
    time (measured 1.05)."""
    a = isa(7500.0).a_m_s
    ac, tecs, pitch, de = engaged(0.7 * a, 7500.0)
    cap = 1.10 * drag_N(0.8 * a, 7500.0) / tecs.available_thrust_N(7500.0)
    tecs.set_parameter("lever_max", cap)
    perf = Performance(pointmass_perf(thrust_max_factor=cap))
    h = fly(ac, tecs, pitch, 300.0, SpeedCommand(0.8, SpeedKind.MACH), alt_cmd=7500.0, elev0=de, perf=perf)
    assert np.max(np.abs(h["h"] - 7500.0)) < 30.0
    t_ref = _time_to_speed(cap * tecs.available_thrust_N(7500.0), 7500.0, 0.7 * a, 0.795 * a)
    t_hit = h["t"][np.argmax(h["V"] >= 0.795 * a)]
    assert h["V"].max() >= 0.795 * a and t_hit < 1.15 * t_ref
    assert abs(h["V"][-1] / a - 0.8) < 0.003


def test_level_deceleration_at_idle_holds_altitude() -> None:
    """150 -> 110 m/s at 3000 m, idle thrust (none on this model): height within 30 m; 112 m/s no later than
    1.3 times the quadrature of m dV/dt = -D(V)."""
    ac, tecs, pitch, de = engaged(150.0, 3000.0)
    perf = Performance(pointmass_perf())
    h = fly(ac, tecs, pitch, 200.0, SpeedCommand(110.0), alt_cmd=3000.0, elev0=de, perf=perf)
    assert np.max(np.abs(h["h"] - 3000.0)) < 30.0
    t_ref = _time_to_speed(0.0, 3000.0, 150.0, 112.0)
    t_hit = h["t"][np.argmax(h["V"] <= 112.0)]
    assert h["V"].min() <= 112.0 and t_hit < 1.3 * t_ref
    assert np.all(np.abs(h["V"][h["t"] > 150.0] - 110.0) < 1.0)


def test_open_climb_that_must_accelerate_does_not_descend() -> None:
    """1000 -> 4000 m and 120 -> 160 m/s with the thrust capped at 1.3 times the drag at 160 m/s: the height
    never falls below the start (within 2 m), and both targets are reached."""
    ac, tecs, pitch, de = engaged(120.0, 1000.0)
    cap = 1.3 * drag_N(160.0, 1000.0) / tecs.available_thrust_N(1000.0)
    tecs.set_parameter("lever_max", cap)
    perf = Performance(pointmass_perf(thrust_max_factor=cap))
    h = fly(ac, tecs, pitch, 900.0, SpeedCommand(160.0), alt_cmd=4000.0, elev0=de, perf=perf)
    assert h["h"].min() > 1000.0 - 2.0
    assert abs(h["h"][-1] - 4000.0) < 5.0 and abs(h["V"][-1] - 160.0) < 1.0


def test_energy_rate_limits_cut_the_channel_without_priority() -> None:
    """The limiting by hand: a demand beyond E_max is cut in the acceleration (path priority) to
    g (E_max - margin - sin gamma_c), or in the flight path (speed priority) to asin(E_max - margin - Vdot_c/g)
    (margin 0.005 here, below a quarter of the headroom 0.05)."""
    tecs = Tecs(TecsParams.from_file(jerk_max_m_s3=0.0, energy_margin=0.005))
    p = tecs.parameters
    x = TecsInput(3000.0, 150.0, 0.0, 0.0, 2000.0, 0.0, -0.1, 0.05)
    tecs.reset(3000.0, 2000.0 * G, 0.05)
    out = tecs.step(0.05, x, SpeedCommand(170.0), alt_cmd_m=3000.0)  # level: gamma_c 0, Vdot_c 1.5 m/s^2
    assert out.limited and out.gamma_cmd_rad == 0.0
    assert out.Vdot_cmd_m_s2 == pytest.approx(G * (0.05 - p.energy_margin), rel=1e-12)
    # open climb (gamma_c at its limit: speed priority), Vdot_c 1.5 m/s^2: the flight path is cut to
    # asin(E_max - margin - Vdot_c/g) ...
    x2 = TecsInput(3000.0, 150.0, 0.0, 0.0, 2000.0, 0.0, -0.1, 0.20)
    tecs.reset(3000.0, 2000.0 * G, 0.05)
    out = tecs.step(0.05, x2, SpeedCommand(170.0), alt_cmd_m=4000.0)
    assert out.limited and out.Vdot_cmd_m_s2 == pytest.approx(1.5)
    assert math.sin(out.gamma_cmd_rad) == pytest.approx(0.20 - p.energy_margin - 1.5 / G, rel=1e-12)
    # ... but not below level: with E_max 0.05 the climb is level and the acceleration is cut instead (no
    # margin: E_max is below sin(gamma_max), no headroom over the climb asked for)
    tecs.reset(3000.0, 2000.0 * G, 0.05)
    out = tecs.step(0.05, x, SpeedCommand(170.0), alt_cmd_m=4000.0)
    assert out.limited and out.gamma_cmd_rad == 0.0
    assert out.Vdot_cmd_m_s2 == pytest.approx(G * 0.05, rel=1e-12)


def test_descent_path_steeper_than_idle_is_held_with_the_airbrake(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 6-deg path from 5000 m at 150 m/s on a clean point mass (CD0 0.012: idle descends at 4 deg): TECS
    asks the airbrake for the drag the path needs; steady, it is the force balance W sin(gamma) - D(V) (T = 0
    at idle here) within 5 %, the path within 10 m, the speed within 1.5 m/s."""
    monkeypatch.setattr(pointmass, "CD0", 0.012)
    ac, tecs, pitch, de = engaged(150.0, 5000.0)
    perf = Performance(pointmass_perf(cd0=0.012, cd_airbrake=0.03))
    gam = -math.radians(6.0)
    h = fly(ac, tecs, pitch, 120.0, SpeedCommand(150.0), alt_cmd=5000.0, elev0=de, perf=perf, path=(5000.0, gam),
            airbrake=True)
    late = h["t"] > 60.0
    assert np.max(np.abs(h["h"][late] - h["hc"][late])) < 10.0
    assert np.max(np.abs(h["V"][late] - 150.0)) < 1.5
    h_mid = float(np.mean(h["h"][late]))
    ref = pointmass.M_KG * G * math.sin(-gam) - drag_N(150.0, h_mid, gam)
    assert ref > 300.0  # the airbrake is needed
    assert float(np.mean(h["ab"][late])) == pytest.approx(ref, rel=0.05)


def test_speed_as_mach_and_cas() -> None:
    ac, tecs, pitch, de = engaged(150.0, 5000.0)
    h = fly(ac, tecs, pitch, 120.0, SpeedCommand(0.5, SpeedKind.MACH), alt_cmd=5000.0, elev0=de)
    assert h["V"][-1] / 320.529 == pytest.approx(0.5, abs=0.002)  # a(5000 m) = 320.529 m/s (ISA table)


def test_underspeed_protection() -> None:
    """A speed command below V_min (62 m/s CAS) is not followed below V_min."""
    ac, tecs, pitch, de = engaged(90.0, 500.0)
    h = fly(ac, tecs, pitch, 120.0, SpeedCommand(40.0, SpeedKind.CAS), alt_cmd=500.0, elev0=de)
    assert h["V"].min() > 62.0 * 0.97


def test_energy_rate_identity() -> None:
    """d/dt(h + V^2/2g) along a trajectory equals V (sin gamma + Vdot/g), the controller's energy rate.

    A phugoid excited by an elevator and thrust step, sampled at 0.01 s: the central difference of
    the energy height has the truncation error dt^2/6 |d3E/dt3| (d3E/dt3 estimated from the
    second difference of the energy rate); allowed: 1.5 times that, plus 1e-9 m/s.
    """
    ac, de = trimmed(150.0, 3000.0)
    dt, elevator, T_cmd = 0.01, de - 0.05, ac.T * 1.3
    t, E, Edot = [], [], []
    for k in range(3000):
        t.append(k * dt)
        E.append(ac.h + ac.V**2 / (2 * G))
        Edot.append(specific_energy_rate_m_s(ac.V, ac.Vdot(elevator, T_cmd), ac.gamma))
        ac.step(dt, elevator, T_cmd)
    dEdt = np.gradient(np.array(E), np.array(t))
    err = np.abs(dEdt[1:-1] - np.array(Edot)[1:-1])
    assert np.max(np.abs(Edot)) > 5.0  # the trajectory does exchange and gain energy
    Edd = np.abs(np.gradient(np.gradient(np.array(Edot), dt), dt))[1:-1]
    assert np.all(err < 1.5 * dt**2 / 6 * np.maximum(Edd, np.roll(Edd, 1)) + 1e-9)
    assert np.max(err) < 3e-4 * np.max(np.abs(Edot))


@pytest.mark.parametrize("V, h", [(80.0, 500.0), (150.0, 3000.0), (230.0, 7500.0)])
def test_pitch_loop_step_across_the_envelope(V: float, h: float) -> None:
    """Inner loop alone (thrust held): a 2-deg pitch step, with the qbar gain schedule, reaches
    90 % within 2 s with less than 25 % overshoot (short period damped by k_q; the phugoid is left
    to TECS) and is within 5 % after 10 s, from 80 m/s at 500 m to 230 m/s at 7500 m."""
    import math

    ac, de = trimmed(V, h)
    pc = PitchController()
    pc.reset(de)
    th0, T = ac.theta, ac.T
    cmd = th0 + math.radians(2.0)
    r = []
    for _ in range(int(10.0 / DT_CTRL)):
        el = pc.step(DT_CTRL, cmd, ac.theta, ac.q, ac.qbar())
        for _ in range(N_SUB):
            ac.step(DT_CTRL / N_SUB, el, T)
        r.append((ac.theta - th0) / math.radians(2.0))
    resp = np.array(r)
    t = np.arange(1, resp.size + 1) * DT_CTRL
    assert resp.max() - 1.0 < 0.25
    assert t[np.argmax(resp > 0.9)] < 2.0
    assert abs(resp[-1] - 1.0) < 0.05


def test_turn_pitch_rate_and_compensation() -> None:
    """Steady level turn: body pitch rate q = g sin(phi) tan(phi) / V (Etkin & Reid sect. 4.7); at 60 deg
    and 100 m/s, 9.80665 x 0.866025 x 1.732051 / 100 = 0.147100 rad/s. The pitch loop's damping acts on
    q less that rate: in the steady turn, on attitude, it gives the same elevator as in straight flight."""
    import math

    from openemss.models.fcs.pitch import PitchController, turn_pitch_rate

    assert turn_pitch_rate(math.radians(60.0), 100.0) == pytest.approx(0.147100, abs=2e-6)
    assert turn_pitch_rate(0.0, 100.0) == 0.0
    assert turn_pitch_rate(math.radians(-60.0), 100.0) == turn_pitch_rate(math.radians(60.0), 100.0)
    q = turn_pitch_rate(math.radians(60.0), 150.0)
    straight, turning = PitchController(), PitchController()
    assert turning.step(0.05, 0.05, 0.05, q, 10000.0, q_turn_rad_s=q) == straight.step(0.05, 0.05, 0.05, 0.0, 10000.0)


def test_pitch_ground_gains_on_weight_on_wheels() -> None:
    """With weight on wheels the ground gains act: the proportional elevator is k_ground x error."""
    from openemss.models.fcs.pitch import PitchController, PitchParams

    p = PitchParams.from_file(k_theta_1_rad=2.0, k_theta_ground_1_rad=0.5, k_q_s_rad=0.0, k_q_ground_s_rad=0.0,
                              k_theta_i_1_rad_s=0.0, k_theta_i_ground_1_rad_s=0.0)
    air, ground = PitchController(p), PitchController(p)
    # qbar = qbar_ref: gain schedule 1; the elevator is minus the nose-up command
    assert air.step(0.05, 0.1, 0.0, 0.0, p.qbar_ref_Pa) == pytest.approx(-0.2)
    assert ground.step(0.05, 0.1, 0.0, 0.0, p.qbar_ref_Pa, on_ground=True) == pytest.approx(-0.05)
