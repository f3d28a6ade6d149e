"""Ground contact outside the landing envelope ends the flight with LossOfAircraftError.

Independent checks: the sink rate at contact of a descent on a straight path is V sin(gamma) (the
kinematics of the start condition), and the three criteria are the stated limits of
models/airframe/adapter.py (twice the CS 25.473 gear design sink rate; the fuselage's height; a
wingtip below the ground).
"""
from __future__ import annotations

import math

import pytest

pytest.importorskip("jsbsim")

from openemss.models.airframe.adapter import CRASH_SINK_M_S, Airframe  # noqa: E402
from openemss.models.airframe.errors import LossOfAircraftError  # noqa: E402
from openemss.models.airframe.trim import trim_level  # noqa: E402

GROUND_M = 450.0


def fly_down(gamma_deg: float, gear_down: bool, bank_deg: float = 0.0,
             t_max_s: float = 60.0) -> tuple[list[float], bool]:
    """Start 40 m above the ground trimmed on a straight descent at gamma_deg (1900 kg, 75 m/s) and hold
    that path (elevator on the path error around the trim) and the bank; returns the sink rates [m/s] and
    whether the wheels touched."""
    gamma = math.radians(gamma_deg)
    alt = GROUND_M + 40.0
    tr = trim_level(alt, 0.22, mass_kg=1900.0, gear_down=gear_down, flight_path_rad=gamma)
    af = Airframe()
    af.start_air(alt, tr.tas_m_s, 263.0, alpha_rad=tr.alpha_rad, elevator=tr.elevator, Fn_N=tr.Fn_N,
                 gear_down=gear_down, ground_elevation_m=GROUND_M, flight_path_rad=gamma, fuel_kg=400.0)
    sinks: list[float] = []
    t = 0.0
    while t < t_max_s:
        s = af.state()
        sinks.append(-s.vs_m_s)
        g = math.asin(s.vs_m_s / s.tas_m_s)
        af.set_surfaces(aileron=max(-1.0, min(1.0, 2.0 * (math.radians(bank_deg) - s.phi_rad) - 0.5 * s.p_rad_s)),
                        elevator=max(-1.0, min(1.0, tr.elevator - 2.0 * (gamma - g) + 0.5 * s.q_rad_s)))
        af.step(0.05)
        t += 0.05
    return sinks, af.state().on_ground


def test_steep_dive_into_the_ground_is_a_loss_naming_the_sink_rate() -> None:
    # 75 m/s at -8 deg sinks at 10.4 m/s, beyond the 6 m/s the gear holds
    assert 75.0 * math.sin(math.radians(8.0)) > CRASH_SINK_M_S
    with pytest.raises(LossOfAircraftError, match=r"touchdown sinking at (9|10|11)\.\d m/s"):
        fly_down(-8.0, gear_down=True)


def test_gear_up_contact_is_a_loss_of_the_fuselage() -> None:
    with pytest.raises(LossOfAircraftError, match="fuselage on the ground .*gear up"):
        fly_down(-2.0, gear_down=False)


def test_steep_bank_near_the_ground_is_a_wingtip_strike() -> None:
    with pytest.raises(LossOfAircraftError, match="wingtip strike"):
        fly_down(-2.0, gear_down=True, bank_deg=40.0)


def test_a_gentle_touchdown_is_no_loss() -> None:
    # 75 m/s at -2 deg sinks at 2.6 m/s: within the gear's limit
    sinks, touched = fly_down(-2.0, gear_down=True, t_max_s=20.0)
    assert touched
    assert max(sinks) == pytest.approx(75.0 * math.sin(math.radians(2.0)), abs=0.5)
