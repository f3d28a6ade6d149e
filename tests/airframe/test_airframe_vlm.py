"""Cross-check of the handbook aerodynamics with an independent vortex-lattice solution (vlm.py).

The lattice solves potential flow on the flat planform. It shares no formula with
Helmbold/DATCOM, Nita-Scholz or the DATCOM downwash chart. The tolerances are what
a lattice of 160 x 4 panels resolves (it converges slowly from above: the UPERA
wing's CL_alpha is 3.319, 3.292, 3.278 and 3.271 /rad with 40, 80, 160 and 320
strips), plus the stated accuracy of the handbook methods.
"""
from __future__ import annotations

import math

import pytest

from openemss.models.airframe.aero import aero_model, helmbold_slope, planform_efficiency_nita_scholz
from openemss.models.airframe.geometry import Planform
from openemss.models.airframe.vlm import vlm_downwash_gradient, vlm_wing

A = aero_model()
G = A.geom
W = G.wing


def test_high_aspect_ratio_limit() -> None:
    """A = 30, rectangular: lifting-line theory gives 2 pi A/(A + 2) for elliptic loading with a 2 pi
    section slope, and Prandtl-Glauert gives 1/beta at Mach 0.6. 5 %: the rectangular load lowers the
    slope by Glauert's factor 1/(1 + tau 2/A) (2 to 3 % here), and the lattice converges from 160 strips on."""
    p = Planform(30.0, 30.0, 1.0, 0.0, 0.1, 0.4)
    r0 = vlm_wing(p, 0.0)
    assert r0.cl_alpha == pytest.approx(2 * math.pi * 30 / 32, rel=0.05)
    assert r0.cl_alpha < 2 * math.pi * 30 / 32
    assert vlm_wing(p, 0.6).cl_alpha / r0.cl_alpha == pytest.approx(1 / 0.8, rel=0.03)


def test_upera_wing_lift_slope_matches_helmbold() -> None:
    """Wing alone (no fuselage factor): VLM vs Helmbold/DATCOM at Mach 0 and 0.7 within 2 %."""
    for mach in (0.0, 0.7):
        vlm = vlm_wing(W, mach).cl_alpha
        helm = float(helmbold_slope(W.aspect_ratio, W.tan_sweep(W.x_t_c), mach))
        print(f"UPERA wing CL_alpha at M {mach}: VLM {vlm:.3f} /rad, Helmbold {helm:.3f} /rad")
        assert vlm == pytest.approx(helm, rel=0.02)


def test_upera_span_efficiency_matches_nita_scholz() -> None:
    """Planform span efficiency (inviscid, no fuselage): VLM Trefftz plane vs Nita & Scholz's e_theo
    (their e_theo, the planform's part of the Oswald factor). 3 %: lattice convergence."""
    e_vlm = vlm_wing(W).span_efficiency
    e_theo = planform_efficiency_nita_scholz(W.aspect_ratio, W.taper, math.degrees(W.sweep_c4_rad))
    print(f"span efficiency: VLM {e_vlm:.4f}, Nita-Scholz e_theo {e_theo:.4f}")
    assert e_vlm == pytest.approx(e_theo, rel=0.03)


def test_downwash_at_the_tail() -> None:
    """d(epsilon)/d(alpha) at the tail (averaged over its span, 0.30 m above the wing plane, flat
    wake) vs DATCOM 4.4.1 as used in aero.py. 15 %: DATCOM's chart accuracy, and the lattice's flat,
    non-rolled-up wake. The DATCOM value is the higher one: the model's tail (and its static margin)
    errs on the weak side."""
    x = G.raw["htail"]["ac_x_m"] - G.raw["wing"]["root_le_x_m"]
    z = G.raw["htail"]["z_m"] - G.raw["wing"]["z_m"]
    vlm = vlm_downwash_gradient(W, x, z, G.htail.semi_span_m)
    print(f"downwash gradient at the tail: VLM {vlm:.3f}, DATCOM {A.deps_dalpha0:.3f}")
    assert vlm == pytest.approx(A.deps_dalpha0, rel=0.15)
    assert vlm < A.deps_dalpha0
