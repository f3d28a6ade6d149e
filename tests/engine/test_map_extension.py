"""Tests of the sub-idle map extension (models/engine/map_extension.py).

References, each independent of the code under test:
- the original map data and the unextended interpolating maps (the extension must
  reproduce every original node exactly and join the original surface's value and slope);
- the laws themselves, evaluated here from their closed forms: Stodola's ellipse (cone)
  law of turbine flow, the parabolic efficiency law over the blade-speed ratio u/c_is,
  the similarity (affinity) laws of compressors along beta lines (Gaudet & Gauthier,
  ASME GT2007-27193);
- NumPy's ``polyfit`` for the least-squares parabola.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.engine.map_extension import (
    EXTENSIONS,
    K_TURBINE,
    ellipse_flow,
    extend_map_data,
    fit_ellipse,
    fit_velocity_ratio_parabola,
    smooth_floor,
)
from openemss.models.engine.map_loading import load_map
from openemss.models.engine.maps import load_map_data

TURBINES = ("hpt1269", "lpt2269")
COMPRESSORS = ("lpc_hbtf", "axi5")


@pytest.mark.parametrize("name", TURBINES + COMPRESSORS)
def test_original_nodes_are_reproduced_exactly(name: str) -> None:
    """Every original node is in the extended data unchanged, and the extended map evaluates to it."""
    d, e = load_map_data(name), extend_map_data(load_map_data(name))
    i0 = e.speed_values.index(d.speed_values[0])
    j0 = e.line_values.index(d.line_values[0])
    m = load_map(name, extended=True)
    for key, rows in d.tables.items():
        ext = np.array(e.tables[key])[i0:i0 + len(d.speed_values), j0:j0 + len(d.line_values)]
        assert np.array_equal(ext, np.array(rows)), key
    plain = load_map(name)
    for n in plain.nc_rel:
        for y in (plain.pr if d.kind == "turbine" else plain.beta):
            assert m.evaluate(n, y) == pytest.approx(plain.evaluate(n, y), rel=1e-13, abs=1e-13)


def test_ellipse_law_limits() -> None:
    """x* = 0 is Stodola's cone law sqrt(1 - 1/PR^2); the law is 0 at PR = 1 and Wc* at and above PR*."""
    pr = np.array([1.0, 1.1, 1.5, 2.0, 4.0])
    assert np.allclose(ellipse_flow(pr, 1.0, 0.0), np.sqrt(1.0 - pr ** -2.0), rtol=0, atol=1e-15)
    assert ellipse_flow(1.0, 3.0, 0.4) == 0.0
    assert np.all(ellipse_flow(np.array([2.5, 3.0, 5.0]), 3.0, 0.4) == 3.0)


@pytest.mark.parametrize("name", TURBINES)
def test_turbine_flow_below_the_map_follows_the_ellipse_law(name: str) -> None:
    """On every original speed line, the new low-PR nodes equal the ellipse law fitted (here, by a root
    search) to the unextended map's value and slope dWc/dPR at its lowest PR."""
    from scipy.optimize import brentq
    d = load_map_data(name)
    e = extend_map_data(d)
    plain = load_map(name)
    pr_j = d.line_values[0]
    new_pr = np.array([p for p in e.line_values if p < pr_j])
    for i, sv in enumerate(d.speed_values):
        n = sv / d.speed_design
        p = plain.evaluate_with_derivatives(n, pr_j)
        w_j, s_j = p.Wc_kg_s, max(p.dWc_dpr, 0.0)                 # kg/s (corrected), per unit PR
        x_j = 1.0 / pr_j
        # slope of the law at x_j as a function of x*: W_j u/((1-x*)(1-u^2)) with u = (x_j-x*)/(1-x*)
        m = s_j * pr_j ** 2

        def g(xs: float, w_j: float = w_j, m: float = m, x_j: float = x_j) -> float:
            u = (x_j - xs) / (1.0 - xs)
            return w_j * u / ((1.0 - xs) * (1.0 - u * u)) - m
        xs = x_j if m == 0.0 else brentq(g, -50.0, x_j, xtol=1e-15)
        u_j = (x_j - xs) / (1.0 - xs)
        w_star = w_j / math.sqrt(1.0 - u_j ** 2)
        u = (1.0 / new_pr - xs) / (1.0 - xs)
        law = w_star * np.sqrt(1.0 - u ** 2)
        i_e = e.speed_values.index(sv)
        got = np.array(e.tables["WpMap"][i_e][:new_pr.size]) * (plain.evaluate(n, pr_j).Wc_kg_s /
                                                                d.tables["WpMap"][i][0])
        assert got == pytest.approx(law, rel=1e-9)
    assert fit_ellipse(2.0, 1.0, 0.0) == (1.0, 0.5)              # a choked line: vertex at its last point


@pytest.mark.parametrize("name", TURBINES)
def test_extended_turbine_map_is_c1_at_the_join_and_flow_rises_with_pr(name: str) -> None:
    m = load_map(name, extended=True)
    pr_j = load_map_data(name).line_values[0]
    h = 1e-7
    for n in (0.6, 0.8, 1.0):
        lo, hi = m.evaluate_with_derivatives(n, pr_j - h), m.evaluate_with_derivatives(n, pr_j + h)
        assert hi.Wc_kg_s - lo.Wc_kg_s == pytest.approx(0.0, abs=1e-5)
        assert hi.dWc_dpr == pytest.approx(lo.dWc_dpr, rel=1e-4, abs=1e-6)
        assert hi.deff_dpr == pytest.approx(lo.deff_dpr, rel=1e-4, abs=1e-6)
        w = [m.evaluate(n, p).Wc_kg_s for p in np.linspace(1.06, pr_j, 60)]
        assert all(b >= a for a, b in zip(w, w[1:], strict=False))      # flow never falls toward choke


@pytest.mark.parametrize("name", TURBINES)
def test_turbine_efficiency_follows_the_velocity_ratio_parabola(name: str) -> None:
    """New nodes: eta = eta_j P(nu)/P(nu_j) (before the smooth floor), P the parabola fitted by least
    squares to the map's efficiencies over nu = nc/sqrt(1 - PR^-k) (here with numpy.polyfit)."""
    d, e = load_map_data(name), extend_map_data(load_map_data(name))
    nc0 = np.array(d.speed_values) / d.speed_design
    pr0 = np.array(d.line_values)
    nu0 = nc0[:, None] / np.sqrt(1.0 - pr0[None, :] ** -0.25)
    c2, c1, c0 = np.polyfit(nu0.ravel(), np.array(d.tables["effMap"]).ravel(), 2)
    eta_pk, nu_opt, C = fit_velocity_ratio_parabola(nu0, np.array(d.tables["effMap"]))
    assert nu_opt == pytest.approx(-c1 / (2 * c2), rel=1e-9) and eta_pk == pytest.approx(c0 - c1 ** 2 / (4 * c2))
    assert K_TURBINE == pytest.approx(0.25)

    def P(nu: np.ndarray) -> np.ndarray:
        return c0 + c1 * nu + c2 * nu * nu

    j_new = [j for j, p in enumerate(e.line_values) if p < pr0[0]]
    pr_new = np.array([e.line_values[j] for j in j_new])
    for i, sv in enumerate(d.speed_values):
        n = sv / d.speed_design
        eta_j = d.tables["effMap"][i][0]
        expect = eta_j * P(n / np.sqrt(1.0 - pr_new ** -0.25)) / P(n / np.sqrt(1.0 - pr0[0] ** -0.25))
        got = np.array(e.tables["effMap"][e.speed_values.index(sv)])[j_new]
        assert got == pytest.approx(smooth_floor(expect), rel=1e-9)
    # efficiency never reaches 1 and never drops below the floor anywhere on the extended grid
    eff = np.array(e.tables["effMap"])
    assert eff.max() < 0.99 and eff.min() >= 0.2


@pytest.mark.parametrize("name", COMPRESSORS)
def test_compressor_low_speeds_follow_similarity_laws(name: str) -> None:
    """Below the lowest speed line: Wc ~ n^a, (PR^k - 1) ~ n^b, eta ~ n^c on every beta line, with the
    exponents through the two lowest map lines (a = 1, b = 2 the affinity laws where those are undefined)."""
    d, e = load_map_data(name), extend_map_data(load_map_data(name))
    new = [v for v in e.speed_values if v < d.speed_values[0]]
    assert new and tuple(new) == tuple(sorted(EXTENSIONS[name].nc_low))  # type: ignore[union-attr]
    n0, n1 = d.speed_values[0], d.speed_values[1]
    W, P, E = (np.array(d.tables[k]) for k in ("WcMap", "PRmap", "effMap"))
    k = 0.4 / 1.4
    for i, n in enumerate(new):
        r = n / n0
        Wn, Pn, En = (np.array(e.tables[key][i]) for key in ("WcMap", "PRmap", "effMap"))
        a = np.clip(np.log(W[1] / W[0]) / math.log(n1 / n0), 0.5, 2.0)
        assert Wn == pytest.approx(W[0] * r ** a, rel=1e-12)
        h0, h1 = P[0] ** k - 1.0, P[1] ** k - 1.0
        with np.errstate(divide="ignore", invalid="ignore"):
            b = np.where((h0 > 0) & (h1 > 0), np.clip(np.log(h1 / h0) / math.log(n1 / n0), 1.0, 3.0), 2.0)
        assert Pn ** k - 1.0 == pytest.approx(h0 * r ** b, rel=1e-9, abs=1e-12)
        assert np.all(En <= E[0] + 1e-15)                         # efficiency does not rise below the map
        # flow and work fall with speed, the affinity trend (Wc ~ n, dH ~ n^2) within the limits
        assert np.all(Wn < W[0]) and np.all(Pn <= P[0])
    m = load_map(name, extended=True)
    assert m.nc_rel_range[0] < load_map(name).nc_rel_range[0]
