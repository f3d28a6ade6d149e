"""Tests of the component maps (models/engine/maps.py, map_interp.py, map_scaled.py, maps/*.json).

References used, each independent of the code under test:
- the verbatim pyCycle source modules kept in ``maps/pycycle_src/``, parsed
  here with :mod:`ast` (the data files must equal them exactly);
- NPSS results for the ``axi5`` and ``lpt2269`` maps at off-node points
  (pyCycle's regression files, ``maps/reference/``), compared within the
  truncation error of the linear interpolation NPSS used;
- SciPy's ``PchipInterpolator`` (an independent implementation of the PCHIP
  slopes and of cubic Hermite evaluation);
- exact identities: reproduction of polynomials, definitions of the scaling
  law and of surge margin, finite-difference derivatives, convergence order.
"""

from __future__ import annotations

import ast
import csv
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

from openemss.models.engine.errors import ModelError, OutOfRangeError
from openemss.models.engine.map_interp import BicubicTable
from openemss.models.engine.map_loading import load_compressor_map, load_map, load_turbine_map
from openemss.models.engine.map_scaled import ScaledCompressorMap, ScaledTurbineMap
from openemss.models.engine.maps import (
    LBM_TO_KG,
    MAP_DIR,
    WP_TO_WC,
    CompressorMap,
    TurbineMap,
    load_map_data,
)

NAMES = ("lpc_hbtf", "axi5", "hpt1269", "lpt2269")
MAPS = {n: load_map(n) for n in NAMES}
COMPRESSORS = ("lpc_hbtf", "axi5")
TURBINES = ("hpt1269", "lpt2269")


def _raw_tables(name: str) -> dict[str, np.ndarray]:
    d = MAPS[name].data
    f = LBM_TO_KG if d.kind == "compressor" else WP_TO_WC
    keys = ("WcMap", "PRmap", "effMap") if d.kind == "compressor" else ("WpMap", "effMap")
    return {k: np.array(d.tables[k]) * (f if k in ("WcMap", "WpMap") else 1.0) for k in keys}


# --------------------------------------------------------------------------- data files
def _parse_pycycle_module(text: str) -> dict[str, object]:
    """Independent reading of a pyCycle map module: ``X.a = np.array([...])``, ``X.defaults['k'] = v``."""
    out: dict[str, object] = {}
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Assign):
            tgt = node.targets[0]
            if isinstance(tgt, ast.Attribute) and isinstance(node.value, ast.Call):
                out[tgt.attr] = np.array(ast.literal_eval(node.value.args[0]), dtype=float)
            elif isinstance(tgt, ast.Attribute) and isinstance(node.value, ast.Constant):
                out[tgt.attr] = node.value.value
            elif isinstance(tgt, ast.Subscript) and getattr(tgt.value, "attr", "") == "defaults":
                out["default_" + ast.literal_eval(tgt.slice)] = ast.literal_eval(node.value)
    return out


@pytest.mark.parametrize("name", NAMES)
def test_data_file_equals_verbatim_pycycle_module(name: str) -> None:
    """Every number of the JSON file equals the source module's (first alphaMap plane), exactly."""
    d = load_map_data(name)
    src = _parse_pycycle_module((MAP_DIR / d.source.verbatim_copy).read_text(encoding="utf-8"))
    assert d.source.commit == "65faca6c95506122812f74a3e66079266327d95e"
    assert d.source.licence == "Apache-2.0"
    assert d.speed_values == tuple(src[d.speed_name])
    assert d.line_values == tuple(src[d.line_name])
    assert d.speed_design == src["default_" + d.speed_name]
    assert d.line_design == src["default_" + d.line_name]
    if d.kind == "compressor":
        assert d.line_surge == src["RlineStall"]
    for key, table in d.tables.items():
        assert np.array_equal(np.array(table), src[key][0]), key


@pytest.mark.parametrize("name", NAMES)
def test_map_reproduces_every_node(name: str) -> None:
    """At each grid node the map returns the file's value (unit-converted) to rounding (1e-12 relative)."""
    m = MAPS[name]
    tab = _raw_tables(name)
    second = m.beta if isinstance(m, CompressorMap) else m.pr
    for i, x in enumerate(m.nc_rel):
        for j, y in enumerate(second):
            got = m.evaluate(x, y)
            for k, key in enumerate(tab):
                assert got[k] == pytest.approx(tab[key][i, j], rel=1e-12, abs=1e-14), (key, x, y)


def test_unit_factors_from_their_definitions() -> None:
    """lbm = 0.45359237 kg, psi = lbf/in^2 with lbf = 0.45359237 kg * 9.80665 m/s^2, degR = K * 1.8."""
    psi = 0.45359237 * 9.80665 / 0.0254**2
    assert psi == pytest.approx(6894.757293168, rel=1e-12)
    assert LBM_TO_KG == 0.45359237
    # W sqrt(T)/P [lbm sqrt(R)/(s psia)] -> W sqrt(T/288.15 K)/(P/101325 Pa) [kg/s]
    assert WP_TO_WC == pytest.approx(0.45359237 * (101325 / psi) / math.sqrt(288.15 * 1.8), rel=1e-14)


def test_loader_errors_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="nope.json"):
        load_map_data("nope")
    bad = tmp_path / "bad.json"
    bad.write_text('{"kind": "compressor",', encoding="utf-8")
    with pytest.raises(ModelError, match="bad.json"):
        load_map_data(bad)
    short = tmp_path / "short.json"
    short.write_text((MAP_DIR / "axi5.json").read_text(encoding="utf-8").replace("[1.0, 1.2, 1.4", "[1.2, 1.4"),
                     encoding="utf-8")
    with pytest.raises(ModelError, match="not 10 x 8"):
        load_map_data(short)
    with pytest.raises(ModelError, match="turbine map, not a compressor"):
        load_compressor_map("hpt1269")
    with pytest.raises(ModelError, match="compressor map, not a turbine"):
        load_turbine_map("axi5")


# --------------------------------------------------------------------------- interpolation
def _npss_rows(fname: str) -> list[dict[str, float]]:
    with open(MAP_DIR / "reference" / fname, encoding="utf-8") as fh:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(ln for ln in fh if not ln.startswith("#"))]


def _linear_truncation_bound(xv: tuple[float, ...], yv: tuple[float, ...], f: np.ndarray, x: float, y: float) -> float:
    """Error bound of bilinear interpolation at (x, y): t(1-t)/2 hx^2 |f_xx| + u(1-u)/2 hy^2 |f_yy|.

    The second derivatives are the largest second divided differences of the
    data at the nodes of the cell.
    """
    xa, ya = np.asarray(xv), np.asarray(yv)
    i = int(np.clip(np.searchsorted(xa, x) - 1, 0, xa.size - 2))
    j = int(np.clip(np.searchsorted(ya, y) - 1, 0, ya.size - 2))

    def dd2(v: np.ndarray, g: np.ndarray) -> np.ndarray:  # along axis 0, at interior nodes
        h = np.diff(v)[:, None]
        return np.abs(2.0 * np.diff(np.diff(g, axis=0) / h, axis=0) / (h[:-1] + h[1:]))

    dx, dy = dd2(xa, f), dd2(ya, f.T)
    fxx = max(dx[k - 1, m] for k in (i, i + 1) if 1 <= k <= xa.size - 2 for m in (j, j + 1))
    fyy = max(dy[k - 1, m] for k in (j, j + 1) if 1 <= k <= ya.size - 2 for m in (i, i + 1))
    hx, hy = xa[i + 1] - xa[i], ya[j + 1] - ya[j]
    t, u = (x - xa[i]) / hx, (y - ya[j]) / hy
    return 0.5 * t * (1 - t) * hx**2 * fxx + 0.5 * u * (1 - u) * hy**2 * fyy


def test_axi5_against_npss_points() -> None:
    """NPSS's map reads (linear interpolation) agree within linear interpolation's own truncation error.

    A smooth interpolant of the same nodes and NPSS's bilinear one may differ
    by the bilinear error, estimated from the data's second divided
    differences; 25 % is allowed on that estimate. On a node they must agree
    exactly (to the 10 digits of the file).
    """
    m = MAPS["axi5"]
    tab = _raw_tables("axi5")
    for r in _npss_rows("npss_axi5_points.csv"):
        n, rline = r["comp.NcMap"], r["comp.RlineMap"]
        got = m.evaluate(n, m.beta_of_rline(rline))
        for k, key in enumerate(tab):
            ref = r["comp." + key] * (LBM_TO_KG if key == "WcMap" else 1.0)
            bound = _linear_truncation_bound(m.data.speed_values, m.data.line_values, tab[key], n, rline)
            assert abs(got[k] - ref) <= 1.25 * bound + 1e-9 * abs(ref), (key, n, rline, got[k], ref, bound)


def test_lpt2269_against_npss_points() -> None:
    m = MAPS["lpt2269"]
    tab = _raw_tables("lpt2269")
    for r in _npss_rows("npss_lpt2269_points.csv"):
        np_map, pr = r["turb.NpMap"], r["turb.PRmap"]
        got = m.evaluate(np_map / 100.0, pr)
        for k, key in enumerate(tab):
            ref = r["turb." + key] * (WP_TO_WC if key == "WpMap" else 1.0)
            bound = _linear_truncation_bound(m.data.speed_values, m.data.line_values, tab[key], np_map, pr)
            assert abs(got[k] - ref) <= 1.25 * bound + 1e-9 * abs(ref), (key, np_map, pr, got[k], ref, bound)


def test_surge_margin_at_constant_speed_equals_npss_on_a_node() -> None:
    """At a node (NcMap 1, R-line 2) NPSS's SMN is 19.99995 %; the definition gives 20.000 %."""
    r = _npss_rows("npss_axi5_points.csv")[0]
    m = MAPS["axi5"]
    sm = m.surge_margin(r["comp.NcMap"], m.beta_of_rline(r["comp.RlineMap"]), basis="speed")
    assert 100.0 * sm == pytest.approx(r["comp.SMN"], abs=1e-4)


def test_grid_lines_equal_scipy_pchip() -> None:
    """With PCHIP slopes, the surface along every grid line is SciPy's 1-D PCHIP interpolant (1e-12)."""
    d = MAPS["axi5"].data
    x, y = np.array(d.speed_values), np.array(d.line_values)
    f = np.array(d.tables["PRmap"])
    t = BicubicTable(x, y, [f], 0.0, 0.0, slopes="pchip")
    ys, xs = np.linspace(y[0], y[-1], 53), np.linspace(x[0], x[-1], 53)
    for i, xi in enumerate(x):
        ref = PchipInterpolator(y, f[i])(ys)
        assert np.allclose([t.values(xi, v)[0] for v in ys], ref, rtol=0, atol=1e-12)
    for j, yj in enumerate(y):
        ref = PchipInterpolator(x, f[:, j])(xs)
        assert np.allclose([t.values(v, yj)[0] for v in xs], ref, rtol=0, atol=1e-12)


def test_biquadratic_polynomials_are_reproduced() -> None:
    """Parabolic nodal slopes are exact for quadratics, so any f of degree <= 2 in x and in y is reproduced."""
    d = MAPS["lpc_hbtf"].data  # unequal speed spacing
    x, y = np.array(d.speed_values), np.array(d.line_values)

    def f(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return 1.0 + 2.0 * a - 3.0 * b + 0.5 * a * a * b * b - 1.5 * a * b + 0.7 * a * a - 0.4 * b * b * a

    t = BicubicTable(x, y, [f(x[:, None], y[None, :])], 0.0, 0.0, monotone=[False])
    rng = np.random.default_rng(1)
    for a, b in zip(rng.uniform(x[0], x[-1], 300), rng.uniform(y[0], y[-1], 300), strict=True):
        assert t.values(a, b)[0] == pytest.approx(f(a, b), abs=1e-12)


def _max_error(n: int, func: object) -> float:
    x, y = np.linspace(0.3, 1.2, n), np.linspace(1.0, 3.0, n)
    t = BicubicTable(x, y, [func(x[:, None], y[None, :])], 0.0, 0.0, monotone=[False])  # type: ignore[operator]
    xs, ys = np.meshgrid(np.linspace(0.3, 1.2, 61), np.linspace(1.0, 3.0, 61), indexing="ij")
    got = np.array([t.values(a, b)[0] for a, b in zip(xs.ravel(), ys.ravel(), strict=True)])
    return float(np.max(np.abs(got - func(xs.ravel(), ys.ravel()))))  # type: ignore[operator]


def test_accuracy_and_convergence_on_a_smooth_surface() -> None:
    """A smooth surface sampled on a map-like grid (10 x 11) is reproduced to 0.1 % of its range,
    and the error falls at least 6-fold when the grid spacing halves (third order: 8-fold)."""

    def g(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.sin(2.5 * a) * np.cos(1.3 * b) + 0.3 * a * b**2

    e1, e2 = _max_error(11, g), _max_error(21, g)
    assert e1 < 1e-3 * 2.0  # range of g on the box is about 2
    assert e1 / e2 > 6.0


@pytest.mark.parametrize("name", NAMES)
def test_c1_continuity_across_grid_lines(name: str) -> None:
    """Value and both partial derivatives agree on both sides of every interior grid line.

    Left and right derivatives come from the two adjacent cells' polynomials,
    0.5e-9 either side; jumps must be below 1e-6 of the derivative's scale.
    """
    t = MAPS[name]._table
    eps = 0.5e-9
    ys = np.linspace(t.y_lo, t.y_hi, 23)[1:-1]
    xs = np.linspace(t.x_lo, t.x_hi, 23)[1:-1]
    scale = [max(1.0, float(np.max(np.abs(v)))) for v in _raw_tables(name).values()]
    for xi in t.x[1:-1]:
        for y in ys:
            a, b = t.values_and_gradients(xi - eps, y), t.values_and_gradients(xi + eps, y)
            for k in range(t.n_out):
                assert abs(a[1][k] - b[1][k]) < 1e-6 * scale[k] / (t.x_hi - t.x_lo)
                assert abs(a[2][k] - b[2][k]) < 1e-6 * scale[k] / (t.y_hi - t.y_lo)
    for yj in t.y[1:-1]:
        for x in xs:
            a, b = t.values_and_gradients(x, yj - eps), t.values_and_gradients(x, yj + eps)
            for k in range(t.n_out):
                assert abs(a[1][k] - b[1][k]) < 1e-6 * scale[k] / (t.x_hi - t.x_lo)
                assert abs(a[2][k] - b[2][k]) < 1e-6 * scale[k] / (t.y_hi - t.y_lo)


@pytest.mark.parametrize("name", NAMES)
def test_derivatives_equal_central_differences(name: str) -> None:
    """evaluate_with_derivatives agrees with central differences of evaluate (h = 1e-6, rel. 1e-5),
    inside the map and in its extrapolated margin."""
    m = MAPS[name]
    t = m._table
    h = 1e-6
    pts = [(0.77, 0.31 * t.y_hi + 0.69 * t.y_lo), (t.x_lo - 0.02, t.y_lo + 0.4 * (t.y_hi - t.y_lo)),
           (t.x_hi + 0.01, t.y_hi + 0.03), (0.87, t.y_lo - 0.05)]  # off grid lines (C1, not C2)
    for x, y in pts:
        d = m.evaluate_with_derivatives(x, y)
        n_out = t.n_out
        for k in range(n_out):
            fd_x = (m.evaluate(x + h, y)[k] - m.evaluate(x - h, y)[k]) / (2 * h)
            fd_y = (m.evaluate(x, y + h)[k] - m.evaluate(x, y - h)[k]) / (2 * h)
            assert d[n_out + 2 * k] == pytest.approx(fd_x, rel=1e-5, abs=1e-6), (k, x, y)
            assert d[n_out + 2 * k + 1] == pytest.approx(fd_y, rel=1e-5, abs=1e-6), (k, x, y)
            assert d[k] == m.evaluate(x, y)[k]


@pytest.mark.parametrize("name", NAMES)
def test_flow_monotone_toward_choke(name: str) -> None:
    """Where the source's flow never falls along two neighbouring speed lines, the map's flow does not fall
    along them (exactly, slope filter), nor between them by more than 2e-5 of its value (tensor product)."""
    t = MAPS[name]._table
    w = next(iter(_raw_tables(name).values()))
    ys = np.linspace(t.y_lo, t.y_hi, 301)
    for i in range(len(t.x) - 1):
        if np.any(np.diff(w[i]) < 0) or np.any(np.diff(w[i + 1]) < 0):
            continue
        for s in np.linspace(0.0, 1.0, 9):
            v = np.array([t.values(t.x[i] + s * (t.x[i + 1] - t.x[i]), y)[0] for y in ys])
            tol = 0.0 if s in (0.0, 1.0) else 2e-5 * float(np.max(v))
            assert np.min(np.diff(v)) >= -tol - 1e-12, (name, i, s)


# --------------------------------------------------------------------------- extrapolation and range
@pytest.mark.parametrize("name", NAMES)
def test_linear_extrapolation_is_c1_and_linear(name: str) -> None:
    t = MAPS[name]._table
    y = 0.5 * (t.y_lo + t.y_hi)
    inside = t.values_and_gradients(t.x_lo, y)
    outside = t.values_and_gradients(t.x_lo - 1e-12, y)
    step = 0.5 * (t.x_lo - t.x_min)
    v0, v1, v2 = (t.values(t.x_lo - k * step, y) for k in (0, 1, 2))
    for k in range(t.n_out):
        assert outside[0][k] == pytest.approx(inside[0][k], abs=1e-9)
        assert outside[1][k] == pytest.approx(inside[1][k], rel=1e-9, abs=1e-9)
        assert outside[2][k] == pytest.approx(inside[2][k], rel=1e-6, abs=1e-6)
        assert v0[k] - 2 * v1[k] + v2[k] == pytest.approx(0.0, abs=1e-10)  # linear in the margin


def test_out_of_range_raises_naming_value_and_range() -> None:
    hpc, lpt = MAPS["axi5"], MAPS["lpt2269"]
    with pytest.raises(OutOfRangeError, match=r"nc_rel = 0\.2 .*\[0\.4, 1\.1\].*\[0\.33, 1\.17\]"):
        hpc.evaluate(0.2, 0.5)
    with pytest.raises(OutOfRangeError, match=r"beta = 1\.5 .*\[0, 1\]"):
        hpc.evaluate(1.0, 1.5)
    with pytest.raises(OutOfRangeError, match=r"pr = 2\.0 .*\[3, 8\].*\[2\.5, 8\.5\]"):
        lpt.evaluate(1.0, 2.0)
    with pytest.raises(ValueError):  # OutOfRangeError is also a ValueError
        lpt.evaluate_with_derivatives(float("nan"), 6.0)
    assert hpc.evaluate(0.35, -0.05).PR > 0.0  # inside the margin: no error


# --------------------------------------------------------------------------- surge margin
@pytest.mark.parametrize("name", COMPRESSORS)
def test_surge_margin_zero_on_surge_line_positive_below_negative_beyond(name: str) -> None:
    m = MAPS[name]
    for n in np.linspace(m.nc_rel[0], m.nc_rel[-2], 7):
        assert m.surge_margin(n, 0.0, "speed") == pytest.approx(0.0, abs=1e-14)
        assert m.surge_margin(n, 0.0, "flow") == pytest.approx(0.0, abs=1e-14)
        assert m.surge_pr(n) == m.evaluate(n, 0.0).PR
    # flow basis: a beta slightly off the surge line (the Newton solve must land back on it)
    n = 0.8
    assert m.surge_margin(n, 1e-9, "flow") == pytest.approx(0.0, abs=1e-7)
    assert m.surge_margin(0.9, 0.5, "flow") > 0.0
    assert m.surge_margin(0.9, -0.05, "speed") < 0.0


@pytest.mark.parametrize("name", COMPRESSORS)
def test_surge_margin_at_constant_flow_follows_its_definition(name: str) -> None:
    """SM = PR_surge(Wc)/PR - 1 with the surge point at equal corrected flow found here by Brent's method."""
    m = MAPS[name]
    for n, b in ((0.7, 0.4), (0.95, 0.6), (0.55, 0.8)):
        w, pr, _ = m.evaluate(n, b)
        lo, hi = m.nc_rel_range
        n_s = brentq(lambda v, w=w: m.evaluate(v, 0.0).Wc_kg_s - w, lo, hi, xtol=1e-14)
        assert m.surge_margin(n, b, "flow") == pytest.approx(m.evaluate(n_s, 0.0).PR / pr - 1.0, rel=1e-9)
        w_s, pr_s, _ = m.evaluate(n, 0.0)
        assert m.surge_margin(n, b, "speed") == pytest.approx(pr_s / pr * w / w_s - 1.0, rel=1e-12)


# --------------------------------------------------------------------------- scaling
def test_compressor_scaling_puts_design_point_on_requested_values() -> None:
    hpc = MAPS["axi5"]
    # Larzac-like HPC: 4.7 PR, 0.85 efficiency, corrected flow 6.2 kg/s at 300 rpm/sqrt(K)
    s = ScaledCompressorMap.from_design(hpc, 6.2, 4.7, 0.85, Nc_design=300.0)
    p = s.evaluate(300.0, hpc.beta_design)
    assert (p.Wc_kg_s, p.PR, p.eff) == pytest.approx((6.2, 4.7, 0.85), rel=1e-14)
    # a chosen map point other than the map's own design point
    s2 = ScaledCompressorMap.from_design(hpc, 6.2, 4.7, 0.85, Nc_design=1.0, nc_rel_map=0.95, beta_map=0.3)
    assert tuple(s2.evaluate(1.0, 0.3)) == pytest.approx((6.2, 4.7, 0.85), rel=1e-14)
    # the scaling law elsewhere on the map
    q, qm = s.evaluate(0.8 * 300.0, 0.7), hpc.evaluate(0.8, 0.7)
    assert q.PR - 1.0 == pytest.approx(s.s_PR * (qm.PR - 1.0), rel=1e-14)
    assert q.Wc_kg_s == pytest.approx(s.s_Wc * qm.Wc_kg_s, rel=1e-14)
    assert q.eff == pytest.approx(s.s_eff * qm.eff, rel=1e-14)
    assert s.surge_pr(300.0) - 1.0 == pytest.approx(s.s_PR * (hpc.surge_pr(1.0) - 1.0), rel=1e-14)
    assert s.surge_margin(0.9 * 300.0, 0.0) == pytest.approx(0.0, abs=1e-14)
    # derivatives of the scaled map by central differences
    d, h = s.evaluate_with_derivatives(270.0, 0.4), 1e-4
    assert d.dPR_dnc == pytest.approx((s.evaluate(270.0 + h, 0.4).PR - s.evaluate(270.0 - h, 0.4).PR) / (2 * h),
                                      rel=1e-6)
    assert d.dWc_dbeta == pytest.approx(
        (s.evaluate(270.0, 0.4 + 1e-6).Wc_kg_s - s.evaluate(270.0, 0.4 - 1e-6).Wc_kg_s) / 2e-6, rel=1e-6)


def test_turbine_scaling_puts_design_point_on_requested_values() -> None:
    lpt = MAPS["lpt2269"]
    s = ScaledTurbineMap.from_design(lpt, 4.1, 2.1, 0.88, Nc_design=250.0)
    p = s.evaluate(250.0, 2.1)
    assert (p.Wc_kg_s, p.eff) == pytest.approx((4.1, 0.88), rel=1e-14)
    assert s.map_pr(2.1) == pytest.approx(lpt.pr_design, rel=1e-14)
    q, qm = s.evaluate(200.0, 1.8), lpt.evaluate(0.8, (1.8 - 1.0) / s.s_PR + 1.0)
    assert (q.Wc_kg_s, q.eff) == pytest.approx((s.s_Wc * qm.Wc_kg_s, s.s_eff * qm.eff), rel=1e-14)
    d, h = s.evaluate_with_derivatives(200.0, 1.5), 1e-6
    assert d.deff_dpr == pytest.approx((s.evaluate(200.0, 1.5 + h).eff - s.evaluate(200.0, 1.5 - h).eff) / (2 * h),
                                       rel=1e-5)


def test_scaling_rejects_impossible_design_values() -> None:
    with pytest.raises(ModelError, match="pressure ratio must be > 1"):
        ScaledCompressorMap.from_design(MAPS["axi5"], 6.0, 0.9, 0.85)
    with pytest.raises(ModelError, match="efficiency"):
        ScaledTurbineMap.from_design(MAPS["hpt1269"], 6.0, 2.5, 1.2)
    assert isinstance(MAPS["hpt1269"], TurbineMap)
