"""ILS approach, flare, touchdown and roll-out on the kinematic model (kinematic.py),
with runway geometry checked against the ICAO glide-path definition.

Bounds (stated): localizer within 5 m of the centre line over the last 5 km; glide path
within 3 m from 20 s after capture to the flare; touchdown between 150 m and 900 m past
the threshold (the touchdown zone), within 5 m of the centre line, sink rate below
2 m/s (issue: 2 m/s); the aircraft stops on the runway. With and without a 10 kt
crosswind. The kinematic model has no sideslip, so it touches down crabbed (the de-crab
by rudder, `align_heading_rad`, needs the 6-DoF airframe) and the wheels then align it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from kinematic import Kinematic

from openemss.models.fcs.approach import ApproachParams, AutoLand, ils_deviation
from openemss.models.mission.geo import LatLon, distance_m
from openemss.models.mission.runway import Runway

DT = 0.05
KT = 0.514444
# a runway of the Munich type: 4000 m x 60 m, true heading 262.5 deg, elevation 448 m
RWY = Runway("TEST 26R", LatLon.from_deg(48.3665, 11.8109), math.radians(262.5), 448.0, 4000.0, 60.0)


def test_glide_path_geometry() -> None:
    p = ApproachParams.from_file()
    # at the threshold the path is tch above it; 10 km out tch + 10 km tan(3 deg)
    d0 = ils_deviation(RWY, p, RWY.point(0.0), RWY.elevation_m + p.tch_m)
    assert d0.gs_m == pytest.approx(0.0, abs=1e-6) and d0.along_m == pytest.approx(0.0, abs=1e-6)
    d10 = ils_deviation(RWY, p, RWY.point(-10e3, 35.0), RWY.elevation_m + p.tch_m + 10e3 * math.tan(p.gs_angle_rad))
    assert d10.gs_m == pytest.approx(0.0, abs=1e-6)
    assert d10.gs_rad == pytest.approx(0.0, abs=1e-9)
    assert d10.along_m == pytest.approx(-10e3, abs=1e-6)
    assert d10.loc_m == pytest.approx(35.0, abs=1e-6)
    assert distance_m(RWY.threshold, RWY.point(4000.0)) == pytest.approx(4000.0, rel=3e-3)  # sphere vs ellipsoid


@pytest.mark.parametrize("xwind_kt, above_m", [(0.0, 0.0), (10.0, 0.0), (-10.0, 0.0), (10.0, 1500.0)])
def test_ils_approach_to_full_stop(xwind_kt: float, above_m: float) -> None:
    """From 10 NM, intercepting at 30 deg; with above_m > 0 the approach starts that high above the
    approach altitude on an aircraft that descends at 1.7 deg at most in clean configuration (as with a
    high idle thrust; the path modes, gear down, may fly steeper): it first descends in the hold, then flies
    the same approach."""
    land = AutoLand(RWY, approach_alt_m=RWY.elevation_m + 760.0)
    gamma_min = -0.03 if above_m > 0.0 else -0.1
    # 10 NM out, 2 km right of the centre line, intercepting at 30 deg, 65 m/s
    start = RWY.point(-18520.0, 2000.0)
    hdg = RWY.heading_rad - math.radians(30.0)
    xw = xwind_kt * KT  # wind from the left of the runway (blowing to the right) for > 0
    wn, we = -xw * math.sin(RWY.heading_rad), xw * math.cos(RWY.heading_rad)
    ac = Kinematic(start, hdg, 65.0, wind_n=wn, wind_e=we, h=RWY.elevation_m + 760.0 + above_m)
    log: dict[str, list] = {k: [] for k in ("phase", "loc", "gs", "along", "h")}
    on_ground = False
    touchdown = None
    theta = 0.07  # airborne: gamma + 4 deg of angle of attack; on the ground it follows the pitch command
    t = 0.0
    while not land.done and t < 900.0 + 2.0 * above_m / (65.0 * -gamma_min):
        cmd = land.step(DT, ac.pos, ac.h, ac.vn, ac.ve, ac.psi, ac.V, theta, on_ground)
        for k, v in (("phase", cmd.phase), ("loc", cmd.ils.loc_m), ("gs", cmd.ils.gs_m), ("along", cmd.ils.along_m),
                     ("h", cmd.ils.h_agl_m)):
            log[k].append(v)
        if not on_ground:
            gamma_cmd = max(-0.1, cmd.gamma_cmd_rad) if cmd.gamma_cmd_rad is not None else \
                max(gamma_min, min(0.1, 0.1 * (cmd.alt_cmd_m - ac.h) / ac.V))
            ac.step(DT, cmd.phi_cmd_rad, gamma_cmd)
            theta = ac.gamma + 0.07
            if ac.h <= RWY.elevation_m:
                on_ground = True
                along, cross = RWY.local(ac.pos)
                touchdown = (along, cross, -ac.V * math.sin(ac.gamma))
                ac.h, ac.gamma, ac.phi = RWY.elevation_m, 0.0, 0.0
                ac.wind_n = ac.wind_e = 0.0  # the wheels hold the aircraft: ground track = heading
        else:  # ground roll: bicycle model, 3 m wheelbase, 17 deg steering, brakes 4 m/s^2 at full
            ac.psi += ac.V * math.tan(cmd.steer * 0.3) / 3.0 * DT
            ac.V = max(ac.V - (cmd.brake * 4.0 + 0.3) * DT, 0.0)
            ac.step(DT, 0.0, 0.0)
            ac.phi = 0.0
            if cmd.theta_cmd_rad is not None:
                theta += (cmd.theta_cmd_rad - theta) / 0.5 * DT
        t += DT
    assert land.done, log["phase"][-1]
    ph = np.array(log["phase"])
    for name in ("LOC", "GS", "FLARE", "DEROTATION", "ROLLOUT"):
        assert name in ph
    assert ("HOLD" in ph) == (above_m > 0.0) and (above_m == 0.0 or ph[0] == "HOLD")
    if above_m > 0.0:  # the hold stays near its circle and ends at the approach altitude
        held = ph == "HOLD"
        assert log["h"][int(np.argmin(held))] < 760.0 + 30.0 + 1.0
    along = np.array(log["along"])
    loc = np.array(log["loc"])
    gs = np.array(log["gs"])
    final = (along > -5000.0) & (along < 0.0)
    assert np.max(np.abs(loc[final])) < 5.0
    i_gs = int(np.argmax(ph == "GS"))
    tracking = (np.arange(len(ph)) > i_gs + int(20 / DT)) & (ph == "GS")
    assert np.max(np.abs(gs[tracking])) < 3.0
    assert touchdown is not None
    td_along, td_cross, td_sink = touchdown
    assert 150.0 < td_along < 900.0
    assert abs(td_cross) < 5.0
    assert td_sink < 2.0
    end_along, end_cross = RWY.local(ac.pos)
    assert end_along < RWY.length_m and abs(end_cross) < RWY.width_m / 2


def test_derotation_ends_when_the_pitch_settles_above_its_tolerance() -> None:
    """On three wheels the pitch is the gear's: after a bounce it may settle a little above theta_ground +
    nose_down_tol and stay there. De-rotation then ends derot_settle_s after its command reached theta_ground
    (and not before), so the brakes come on; with the pitch inside the tolerance it ends at once."""
    p = ApproachParams.from_file()
    for theta_stuck, expect_settle in ((p.theta_ground_rad + 1.2 * p.nose_down_tol_rad, True),
                                       (p.theta_ground_rad + 0.5 * p.nose_down_tol_rad, False)):
        land = AutoLand(RWY, approach_alt_m=RWY.elevation_m + 760.0)
        land.phase = "FLARE"
        pos = RWY.point(500.0)
        theta0 = 0.06
        cmd = land.step(DT, pos, RWY.elevation_m, 0.0, -40.0, RWY.heading_rad, 40.0, theta0, True)
        assert cmd.phase == "DEROTATION" or not expect_settle
        t_cmd_down = theta0 / p.theta_derot_rad_s       # when the lowered command reaches theta_ground
        t, t_end = DT, None
        while t < t_cmd_down + p.derot_settle_s + 2.0:
            cmd = land.step(DT, pos, RWY.elevation_m, 0.0, -40.0, RWY.heading_rad, 40.0, theta_stuck, True)
            t += DT
            if cmd.phase == "ROLLOUT":
                t_end = t
                assert cmd.brake > 0.0
                break
        assert t_end is not None
        if expect_settle:
            assert t_cmd_down + p.derot_settle_s - 2 * DT <= t_end <= t_cmd_down + p.derot_settle_s + 2 * DT
        else:
            assert t_end <= 2 * DT
