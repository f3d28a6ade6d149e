"""UPERA's airbrake (issue 14): drag increment, rate limit and blow-back in JSBSim.

Independent references: the flat-plate drag of the panels' frontal area worked by hand from the
geometry's stated inputs (two panels 0.45 m x 0.40 m hinged at their leading edges, 60 deg, plate
CD 1.18 on the frontal area from Hoerner 1965 ch. 3, installation factor 0.85): dCD = 0.85 x 1.18 x
2 x 0.45 x 0.40 x sin 60 deg / 11.2 m^2 = 0.02792; the difference of two JSBSim trims (same
altitude, Mach and mass, with and without the airbrake) must give it within 1 % (the JSBSim table
interpolates sin(delta) linearly over 11 points: at most 0.14 %; the trim with the airbrake flies at a
slightly smaller CL, see the test). Rate limit: full travel in 1.5 s,
a constant rate. Blow-back: above 16 kPa the panels' hinge moment, ~ qbar sin(delta), is held, so
their drag force stays that of full deflection at 16 kPa, 0.02792 x 16000 Pa x 11.2 m^2 = 5003 N.
"""
from __future__ import annotations

import math

import pytest

pytest.importorskip("jsbsim")

from openemss.models.airframe.adapter import Airframe  # noqa: E402
from openemss.models.airframe.geometry import load_geometry  # noqa: E402
from openemss.models.airframe.trim import trim_level  # noqa: E402

S_M2 = 11.2


def _dcd_by_hand(position: float) -> float:
    ab = load_geometry().section("airbrake")
    assert (ab["panels"], ab["panel_length_m"], ab["panel_height_m"], ab["max_deg"]) == (2, 0.45, 0.40, 60.0)
    return 0.85 * 1.18 * 2 * 0.45 * 0.40 * math.sin(math.radians(60.0 * position)) / S_M2


def test_hand_figure() -> None:
    assert _dcd_by_hand(1.0) == pytest.approx(0.02792, abs=5e-6)


@pytest.mark.parametrize(("alt_m", "mach", "position"), [(5000.0, 0.5, 1.0), (5000.0, 0.5, 0.45),
                                                         (1200.0, 0.3, 1.0)])
def test_trimmed_drag_increment_is_the_flat_plate_figure(alt_m: float, mach: float, position: float) -> None:
    clean = trim_level(alt_m, mach, 1900.0)
    braked = trim_level(alt_m, mach, 1900.0, airbrake=position)
    assert clean.qbar_Pa < 16000.0  # below the blow-back dynamic pressure: the position is the command
    # within 1 %: the table's interpolation (0.14 %) and the induced drag of the trim's slightly smaller CL
    # (the larger thrust carries T sin(alpha) of the weight: -0.5 % of dCD at CL 0.37)
    assert braked.CD - clean.CD == pytest.approx(_dcd_by_hand(position), rel=1e-2)
    # no lift of its own: CL within 1 % (the trim's larger thrust carries T sin(alpha) of the weight: 0.4 %)
    assert braked.CL == pytest.approx(clean.CL, rel=1e-2)


def test_blow_back_holds_the_drag_force() -> None:
    """At Mach 0.75 and 2500 m (qbar 29 kPa) full airbrake gives the drag force of full deflection at
    16 kPa (within 0.5 %), not the 2.0 times more that 0.02792 qbar S would be."""
    clean = trim_level(2500.0, 0.75, 1900.0)
    braked = trim_level(2500.0, 0.75, 1900.0, airbrake=1.0)
    assert clean.qbar_Pa > 16000.0 * 1.5
    d_force = (braked.CD - clean.CD) * clean.qbar_Pa * S_M2
    assert d_force == pytest.approx(_dcd_by_hand(1.0) * 16000.0 * S_M2, rel=5e-3)


def test_rate_limit_full_travel_in_one_and_a_half_seconds() -> None:
    af = Airframe()
    tr = trim_level(3000.0, 0.4, 1900.0, airframe=af)
    af.start_air(3000.0, tr.tas_m_s, 0.0, alpha_rad=tr.alpha_rad, elevator=tr.elevator, Fn_N=tr.Fn_N,
                 fuel_kg=400.0)
    assert af.state().airbrake_pos_norm == 0.0
    af.set_airbrake(1.0)
    pos = []
    for _ in range(40):  # 2 s in steps of 0.05 s
        af.step(0.05)
        pos.append(af.state().airbrake_pos_norm)
    dt_int = 1.0 / af.rate_hz
    assert pos[14] == pytest.approx(0.75 / 1.5, abs=dt_int / 1.5 + 1e-9)  # t = 0.75 s: half way
    assert pos[29] == pytest.approx(1.0)  # t = 1.5 s: fully out
    af.set_airbrake(0.0)
    af.step(0.5)
    assert af.state().airbrake_pos_norm == pytest.approx(1.0 - 0.5 / 1.5, abs=dt_int / 1.5 + 1e-9)
