"""TECS and the pitch loop, closed loop on the point-mass longitudinal model (pointmass.py).

Independent references: the energy identity d/dt(h + V^2/2g) = V (sin gamma + Vdot/g)
(conservation of mechanical energy of a point mass), the first-order altitude capture
law of TECS (no overshoot by construction, bound stated per test), and the limits
given to the controller.
"""

from __future__ import annotations

import numpy as np
import pytest
from pointmass import G, PointMass, trimmed

from openemss.models.fcs.pitch import PitchController
from openemss.models.fcs.tecs import SpeedCommand, SpeedKind, Tecs, TecsInput, TecsParams, specific_energy_rate_m_s

DT_CTRL = 0.05
N_SUB = 5


def fly(ac: PointMass, tecs: Tecs, pitch: PitchController, t_end: float, speed: SpeedCommand,
        alt_cmd: float | None = None, gamma_cmd: float | None = None, elev0: float = 0.0) -> dict[str, np.ndarray]:
    log: dict[str, list] = {k: [] for k in ("t", "V", "h", "gamma", "theta", "T", "lever", "prio", "E", "Edot")}
    elevator, T_cmd = elev0, ac.T
    for k in range(int(round(t_end / DT_CTRL))):
        Vd = ac.Vdot(elevator, T_cmd)
        out = tecs.step(DT_CTRL, TecsInput(ac.h, ac.V, Vd, ac.gamma, ac.mass), speed, alt_cmd, gamma_cmd)
        elevator = pitch.step(DT_CTRL, out.theta_cmd_rad, ac.theta, ac.q, ac.qbar())
        T_cmd = out.thrust_cmd_N
        for _ in range(N_SUB):
            ac.step(DT_CTRL / N_SUB, elevator, T_cmd)
        for key, v in (("t", (k + 1) * DT_CTRL), ("V", ac.V), ("h", ac.h), ("gamma", ac.gamma),
                       ("theta", ac.theta), ("T", ac.T), ("lever", out.lever), ("prio", out.priority),
                       ("E", ac.h + ac.V**2 / (2 * G)),
                       ("Edot", specific_energy_rate_m_s(ac.V, ac.Vdot(elevator, T_cmd), ac.gamma))):
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


def test_speed_step_at_thrust_limit_is_flown_by_pitch() -> None:
    """With the lever capped at 2 % above what level flight at the new speed needs, a +20 m/s step
    saturates the thrust: pitch takes speed priority and the height pays (the energy of 20 m/s is
    285 m of height), the speed is reached within 1 m/s in 60 s and held."""
    ac, tecs, pitch, de = engaged(130.0, 3000.0)
    ac150, _ = trimmed(150.0, 3000.0)
    tecs.set_parameter("lever_max", ac150.T / tecs.available_thrust_N(3000.0) * 1.02)
    h = fly(ac, tecs, pitch, 120.0, SpeedCommand(150.0), alt_cmd=3000.0, elev0=de)
    assert "speed" in set(h["prio"])
    assert np.all(np.abs(h["V"][h["t"] > 60.0] - 150.0) < 1.0)
    assert h["h"].min() < 3000.0 - 100.0  # the height paid for the speed


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
