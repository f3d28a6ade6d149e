"""Compiled building blocks of the gas path: gas properties, their inverses, map tables, surge margin.

The one implementation of the gas properties (NASA Glenn mixtures of air and lean combustion
products): :class:`.gas.GasModel` checks its arguments and calls these functions, and the
gas path (:mod:`.gas_path`) calls them directly; written on plain floats and arrays
so that numba compiles them (``njit``), and plain Python without numba (``OPENEMSS_NO_JIT``).
The map tables (:func:`table`: the C1 bicubic Hermite tables of :mod:`.map_interp`, whose
``BicubicTable.values`` calls it, with linear extrapolation) and the surge line and margin
(:func:`surge_speed_at_flow`, :func:`surge_margin`, called by :class:`.maps.CompressorMap`)
are the one implementation too; ``tests/engine/test_one_source.py`` runs them compiled and not.

Errors are not raised here: a function that meets an input the Python version would
refuse sets ``err[0] = 1`` and returns a finite dummy value; the caller then raises
(:class:`.gas.GasModel`) or reruns the Python version, which raises with its full message.

Array layouts
-------------
``gc`` : shape (2, 6, 8), per temperature interval (below, above ``T_mid``) the
coefficients of cp_air, cp_fuel (7 used), h_air, h_fuel, phi_air, phi_fuel (8), as
:func:`.gas._poly_coeffs` builds them (per kg of air and per kg of fuel burned).
``gs`` : T_mid, FAR_stoich, h_air(200 K), h_fuel(200 K), h_air(2200 K), h_fuel(2200 K),
the same four for phi, R_air part, R_fuel part, LHV, h of the liquid fuel.
Both from :meth:`.gas.GasModel.kernel_arrays` (the last added by the cycle).
A map table: grid ``xg``, ``yg``, inverse spacings ``ihx``, ``ihy``, ``cells`` of shape
(nx-1, ny-1, n_out, 16) and ``lim`` = (x_lo, x_hi, y_lo, y_hi, x_min, x_max, y_min, y_max).

References
----------
B. J. McBride, M. J. Zehe, S. Gordon, NASA/TP-2002-211556, 2002 (the polynomials).
F. N. Fritsch, R. E. Carlson, SIAM J. Numer. Anal. 17(2), 1980 (the tables' slopes).
"""

from __future__ import annotations

import math

import numpy as np

from ..infra.jit import AVAILABLE, borrowed, jit, jit_inline

__all__ = ["AVAILABLE", "borrowed", "jit", "jit_inline", "T_MIN", "T_MAX"]

T_MIN = 200.0
T_MAX = 2200.0
#: Newton stops once a step is below this [K]; the error left after such a step
#: is about (dcp/dT)/(2 cp) * step^2 < 3e-4/K * (1e-5 K)^2, i.e. < 1e-13 K.
_STEP_TOL = 1e-5
#: Most Newton steps of the gas inverses.
MAX_ITER = 30
_MAX_ITER = MAX_ITER


# ---------------------------------------------------------------------- gas
# The polynomials of one row of ``gc`` (interval k, property j), read element by element: a row taken as an array
# is a view, whose reference count numba raises and lowers atomically at every call (a few per kernel, several
# hundred per gas-path evaluation). cp, T_from_h and T_from_phi share the cp form, phi and T_from_phi the phi form.
@jit_inline
def _cp_row(gc: np.ndarray, k: int, j: int, T: float, i: float) -> float:
    """cp polynomial of row (k, j) at T [K], i = 1/T."""
    return i * (gc[k, j, 0] * i + gc[k, j, 1]) + gc[k, j, 2] + \
        T * (gc[k, j, 3] + T * (gc[k, j, 4] + T * (gc[k, j, 5] + T * gc[k, j, 6])))


@jit_inline
def _h_row(gc: np.ndarray, k: int, j: int, T: float, lnT: float) -> float:
    """Enthalpy polynomial of row (k, j) at T [K], lnT = ln T."""
    return gc[k, j, 0] / T + gc[k, j, 1] * lnT + \
        T * (gc[k, j, 2] + T * (gc[k, j, 3] + T * (gc[k, j, 4] + T * (gc[k, j, 5] + T * gc[k, j, 6])))) + gc[k, j, 7]


@jit_inline
def _phi_row(gc: np.ndarray, k: int, j: int, T: float, i: float, lnT: float) -> float:
    """Entropy-function polynomial of row (k, j) at T [K], i = 1/T, lnT = ln T."""
    return i * (gc[k, j, 0] * i + gc[k, j, 1]) + gc[k, j, 2] * lnT + \
        T * (gc[k, j, 3] + T * (gc[k, j, 4] + T * (gc[k, j, 5] + T * gc[k, j, 6]))) + gc[k, j, 7]


# cp, h, phi and R are inlined into their compiled callers (jit_inline): numba raises and lowers the reference
# count of every array argument of a compiled call, atomically, and these are called some fifty times per
# gas-path evaluation (about a quarter of its reference counting, measured with callgrind)
@jit_inline
def cp(gc: np.ndarray, gs: np.ndarray, T: float, f: float, err: np.ndarray) -> float:
    """cp [J/(kg K)] at T [K], FAR f [-]."""
    if not (T_MIN <= T <= T_MAX) or not (0.0 <= f <= gs[1]):
        err[0] = 1
        return 1000.0
    k = 0 if T <= gs[0] else 1
    i = 1.0 / T
    v = _cp_row(gc, k, 0, T, i)
    if f != 0.0:
        v = (v + f * _cp_row(gc, k, 1, T, i)) / (1.0 + f)
    return v


@jit_inline
def h(gc: np.ndarray, gs: np.ndarray, T: float, f: float, err: np.ndarray) -> float:
    """Sensible enthalpy [J/kg] at T [K], FAR f [-]."""
    if not (T_MIN <= T <= T_MAX) or not (0.0 <= f <= gs[1]):
        err[0] = 1
        return 0.0
    k = 0 if T <= gs[0] else 1
    lnT = math.log(T)
    v = _h_row(gc, k, 2, T, lnT)
    if f != 0.0:
        v = (v + f * _h_row(gc, k, 3, T, lnT)) / (1.0 + f)
    return v


@jit
def h_parts(gc: np.ndarray, gs: np.ndarray, T: float, err: np.ndarray) -> tuple[float, float]:
    """(h_air, h_fuel) [J/kg] at T [K], as :meth:`.gas.GasModel.h_parts`."""
    if not (T_MIN <= T <= T_MAX):
        err[0] = 1
        return 0.0, 0.0
    k = 0 if T <= gs[0] else 1
    lnT = math.log(T)
    return _h_row(gc, k, 2, T, lnT), _h_row(gc, k, 3, T, lnT)


@jit_inline
def phi(gc: np.ndarray, gs: np.ndarray, T: float, f: float, err: np.ndarray) -> float:
    """Entropy function [J/(kg K)] at T [K], FAR f [-]."""
    if not (T_MIN <= T <= T_MAX) or not (0.0 <= f <= gs[1]):
        err[0] = 1
        return 0.0
    k = 0 if T <= gs[0] else 1
    i = 1.0 / T
    lnT = math.log(T)
    v = _phi_row(gc, k, 4, T, i, lnT)
    if f != 0.0:
        v = (v + f * _phi_row(gc, k, 5, T, i, lnT)) / (1.0 + f)
    return v


@jit_inline
def R(gs: np.ndarray, f: float) -> float:
    """Gas constant [J/(kg K)] at FAR f [-]."""
    if f == 0.0:
        return gs[10]
    return (gs[10] + f * gs[11]) / (1.0 + f)


@jit
def T_from_h(gc: np.ndarray, gs: np.ndarray, hv: float, f: float, Tg: float, err: np.ndarray) -> float:
    """Temperature [K] of enthalpy hv [J/kg]: the Newton iteration of :meth:`.gas.GasModel.T_from_h`."""
    if not (0.0 <= f <= gs[1]):
        err[0] = 1
        return 300.0
    inv = 1.0 / (1.0 + f)
    h_min, h_max = (gs[2] + f * gs[3]) * inv, (gs[4] + f * gs[5]) * inv
    slack = 1e-12 * (h_max - h_min)
    if not (h_min - slack <= hv <= h_max + slack):
        err[0] = 1
        return 300.0
    T = Tg if T_MIN <= Tg <= T_MAX else 298.15 + hv / 1100.0
    for _ in range(_MAX_ITER):
        T = T_MIN if T < T_MIN else (T_MAX if T > T_MAX else T)
        k = 0 if T <= gs[0] else 1
        i, lnT = 1.0 / T, math.log(T)
        # the enthalpy polynomial with b0 * (1/T) where h() has b0 / T: the iteration's own rounding, which its
        # results (and the cycle's, to the last digit) depend on
        b = gc[k, 2]
        c_ = _cp_row(gc, k, 0, T, i)
        h_ = b[0] * i + b[1] * lnT + T * (b[2] + T * (b[3] + T * (b[4] + T * (b[5] + T * b[6])))) + b[7]
        if f != 0.0:
            b = gc[k, 3]
            c_ = (c_ + f * _cp_row(gc, k, 1, T, i)) * inv
            h_ = (h_ + f * (b[0] * i + b[1] * lnT + T * (b[2] + T * (b[3] + T * (b[4] + T * (b[5] + T * b[6]))))
                            + b[7])) * inv
        dT = (h_ - hv) / c_
        T -= dT
        if -_STEP_TOL < dT < _STEP_TOL:
            return T
    err[0] = 1
    return T


@jit
def T_from_phi(gc: np.ndarray, gs: np.ndarray, pv: float, f: float, Tg: float, err: np.ndarray) -> float:
    """Temperature [K] of entropy function pv [J/(kg K)]: :meth:`.gas.GasModel.T_from_phi`."""
    if not (0.0 <= f <= gs[1]):
        err[0] = 1
        return 300.0
    inv = 1.0 / (1.0 + f)
    p_min, p_max = (gs[6] + f * gs[7]) * inv, (gs[8] + f * gs[9]) * inv
    slack = 1e-12 * (p_max - p_min)
    if not (p_min - slack <= pv <= p_max + slack):
        err[0] = 1
        return 300.0
    T = Tg if T_MIN <= Tg <= T_MAX else 298.15 * math.exp(pv / 1100.0)
    for _ in range(_MAX_ITER):
        T = T_MIN if T < T_MIN else (T_MAX if T > T_MAX else T)
        k = 0 if T <= gs[0] else 1
        i, lnT = 1.0 / T, math.log(T)
        c_ = _cp_row(gc, k, 0, T, i)
        p_ = _phi_row(gc, k, 4, T, i, lnT)
        if f != 0.0:
            c_ = (c_ + f * _cp_row(gc, k, 1, T, i)) * inv
            p_ = (p_ + f * _phi_row(gc, k, 5, T, i, lnT)) * inv
        T_new = T * math.exp((pv - p_) / c_)
        dT = T_new - T
        T = T_new
        if -_STEP_TOL < dT < _STEP_TOL:
            return T
    err[0] = 1
    return T


@jit
def T_isentropic(gc: np.ndarray, gs: np.ndarray, T1: float, pr: float, f: float, Tg: float,
                 err: np.ndarray) -> float:
    """Temperature [K] after an isentropic pressure change by pr [-] (:meth:`.gas.GasModel.T_isentropic`)."""
    if not pr > 0.0:
        err[0] = 1
        return T1
    p2 = phi(gc, gs, T1, f, err) + R(gs, f) * math.log(pr)
    return T_from_phi(gc, gs, p2, f, Tg, err)


@jit
def static_from_total(gc: np.ndarray, gs: np.ndarray, Tt: float, M: float, f: float,
                      err: np.ndarray) -> tuple[float, float]:
    """Static temperature [K] and p/pt [-] at Mach M (:meth:`.gas.GasModel.static_from_total`)."""
    ht, R_ = h(gc, gs, Tt, f, err), R(gs, f)
    k = 0.5 * M * M * R_
    T = Tt / (1.0 + k / (cp(gc, gs, Tt, f, err) - R_))
    for _ in range(_MAX_ITER):
        c = cp(gc, gs, T, f, err)
        g = c / (c - R_)
        dT = (h(gc, gs, T, f, err) + k * g * T - ht) / (c + k * g)
        T -= dT
        if -1e-7 < dT < 1e-7:
            return T, math.exp((phi(gc, gs, T, f, err) - phi(gc, gs, Tt, f, err)) / R_)
        if err[0]:
            return Tt, 1.0
    err[0] = 1
    return Tt, 1.0


# ---------------------------------------------------------------------- map tables
@jit
def _cell(xg: np.ndarray, v: float, lo: float, hi: float) -> int:
    """bisect_right over the interior breakpoints: the cell index of v in [lo, hi]."""
    i = 0
    n = xg.shape[0]
    while i < n - 2 and xg[i + 1] <= v:
        i += 1
    return i


@jit
def table(xg: np.ndarray, yg: np.ndarray, ihx: np.ndarray, ihy: np.ndarray, cells: np.ndarray, lim: np.ndarray,
          x: float, y: float, out: np.ndarray, gx: np.ndarray, gy: np.ndarray, err: np.ndarray) -> None:
    """Values (and d/dx, d/dy into gx, gy) of every output at (x, y), as :class:`.map_interp.BicubicTable`."""
    inside = lim[0] <= x <= lim[1] and lim[2] <= y <= lim[3]
    if not inside and not (lim[4] <= x <= lim[5] and lim[6] <= y <= lim[7]):
        err[0] = 1
        for k in range(cells.shape[2]):
            out[k] = 1.0
            gx[k] = 0.0
            gy[k] = 0.0
        return
    xc = min(max(x, lim[0]), lim[1])
    yc = min(max(y, lim[2]), lim[3])
    dx, dy = x - xc, y - yc
    i = _cell(xg, xc, lim[0], lim[1])
    j = _cell(yg, yc, lim[2], lim[3])
    hx, hy = ihx[i], ihy[j]
    t = (xc - xg[i]) * hx
    u = (yc - yg[j]) * hy
    for k in range(cells.shape[2]):
        # the cell's 16 coefficients read one by one (a cell taken as an array is a view, with its atomic
        # reference counting, at every output of every table read)
        c0, c1, c2, c3 = cells[i, j, k, 0], cells[i, j, k, 1], cells[i, j, k, 2], cells[i, j, k, 3]
        c4, c5, c6, c7 = cells[i, j, k, 4], cells[i, j, k, 5], cells[i, j, k, 6], cells[i, j, k, 7]
        c8, c9, c10, c11 = cells[i, j, k, 8], cells[i, j, k, 9], cells[i, j, k, 10], cells[i, j, k, 11]
        c12, c13, c14, c15 = cells[i, j, k, 12], cells[i, j, k, 13], cells[i, j, k, 14], cells[i, j, k, 15]
        r0 = c0 + u * (c1 + u * (c2 + u * c3))
        r1 = c4 + u * (c5 + u * (c6 + u * c7))
        r2 = c8 + u * (c9 + u * (c10 + u * c11))
        r3 = c12 + u * (c13 + u * (c14 + u * c15))
        p = r0 + t * (r1 + t * (r2 + t * r3))
        s0 = c1 + u * (2.0 * c2 + 3.0 * u * c3)
        s1 = c5 + u * (2.0 * c6 + 3.0 * u * c7)
        s2 = c9 + u * (2.0 * c10 + 3.0 * u * c11)
        s3 = c13 + u * (2.0 * c14 + 3.0 * u * c15)
        pt = r1 + t * (2.0 * r2 + 3.0 * t * r3)
        pu = s0 + t * (s1 + t * (s2 + t * s3))
        ptu = s1 + t * (2.0 * s2 + 3.0 * t * s3)
        px, py = pt * hx, pu * hy
        if inside:
            out[k] = p
            gx[k] = px
            gy[k] = py
        else:
            pxy = ptu * hx * hy
            out[k] = p + px * dx + py * dy + pxy * dx * dy
            gx[k] = px + pxy * dy
            gy[k] = py + pxy * dx


@jit
def surge_speed_at_flow(xg: np.ndarray, yg: np.ndarray, ihx: np.ndarray, ihy: np.ndarray, cells: np.ndarray,
                        lim: np.ndarray, sx: np.ndarray, sw: np.ndarray, w: float) -> float:
    """Relative speed [-] where the surge line (beta = 0) passes corrected flow `w` (:meth:`.maps.CompressorMap.
    surge_nc_rel_at_flow`): Newton on the surge line safeguarded by bisection, started by linear interpolation
    between its nodes (sx, sw: speeds and flows, the flow rising with speed); NaN where `w` is not on it."""
    # the table's values and slopes, and its error flag: allocated here, read without counts by the callee
    return _surge_speed(xg, yg, ihx, ihy, cells, lim, sx, sw, w, np.empty((3, 3)), np.zeros(1, np.int64))


@jit
def _surge_speed(xg: np.ndarray, yg: np.ndarray, ihx: np.ndarray, ihy: np.ndarray, cells: np.ndarray,
                 lim: np.ndarray, sx: np.ndarray, sw: np.ndarray, w: float, t: np.ndarray, err: np.ndarray) -> float:
    """:func:`surge_speed_at_flow` with the table's work arrays t (3, 3) and err given (held by the caller: views
    without reference counts here, :func:`borrowed`)."""
    xg, yg, ihx, ihy, cells, lim, sx, sw, t, err = borrowed((xg, yg, ihx, ihy, cells, lim, sx, sw, t, err))
    n = sw.shape[0]
    if not sw[0] <= w <= sw[n - 1]:
        return math.nan
    v, gx, gy = t[0], t[1], t[2]
    k = 0                                   # bisect_right(sw, w) - 1, clipped to [0, n - 2]
    while k < n - 1 and sw[k] <= w:
        k += 1
    k = min(max(k - 1, 0), n - 2)
    lo, hi, f_lo = sx[k], sx[k + 1], sw[k] - w
    x = lo + (hi - lo) * (w - sw[k]) / (sw[k + 1] - sw[k])
    for _ in range(60):
        table(xg, yg, ihx, ihy, cells, lim, x, 0.0, v, gx, gy, err)
        f = v[0] - w
        if abs(f) <= 1e-12 * max(1.0, abs(w)):
            break
        if (f < 0.0) == (f_lo < 0.0):
            lo, f_lo = x, f
        else:
            hi = x
        x_new = x - f / gx[0] if gx[0] != 0.0 else 0.5 * (lo + hi)
        x = x_new if lo < x_new < hi else 0.5 * (lo + hi)
        if hi - lo <= 1e-14:
            break
    return x


@jit
def surge_margin(xg: np.ndarray, yg: np.ndarray, ihx: np.ndarray, ihy: np.ndarray, cells: np.ndarray,
                 lim: np.ndarray, sx: np.ndarray, sw: np.ndarray, nc: float, beta: float, s_PR: float) -> float:
    """Flow-basis surge margin [-] (:meth:`.maps.CompressorMap.surge_margin`), PR_surge(Wc) / PR - 1 with the PR
    scaled as (PR - 1) s_PR + 1; NaN where it cannot be formed (off the map, or no surge line at that flow)."""
    return _surge_margin(xg, yg, ihx, ihy, cells, lim, sx, sw, nc, beta, s_PR, np.empty((3, 3)),
                         np.zeros(1, np.int64))


@jit
def _surge_margin(xg: np.ndarray, yg: np.ndarray, ihx: np.ndarray, ihy: np.ndarray, cells: np.ndarray,
                  lim: np.ndarray, sx: np.ndarray, sw: np.ndarray, nc: float, beta: float, s_PR: float, t: np.ndarray,
                  err: np.ndarray) -> float:
    """:func:`surge_margin` with the table's work arrays t (3, 3) and err given (as :func:`_surge_speed`)."""
    xg, yg, ihx, ihy, cells, lim, sx, sw, t, err = borrowed((xg, yg, ihx, ihy, cells, lim, sx, sw, t, err))
    v, gx, gy = t[0], t[1], t[2]
    table(xg, yg, ihx, ihy, cells, lim, nc, beta, v, gx, gy, err)
    if err[0]:
        return math.nan
    w, pr = v[0], (v[1] - 1.0) * s_PR + 1.0
    if beta == 0.0:
        x = nc
    else:
        x = _surge_speed(xg, yg, ihx, ihy, cells, lim, sx, sw, w, t, err)
        err[0] = 0                          # (the surge line's own reads, never checked, as in surge_speed_at_flow)
    if not x == x:
        return math.nan
    table(xg, yg, ihx, ihy, cells, lim, x, 0.0, v, gx, gy, err)
    if err[0]:
        return math.nan
    return ((v[1] - 1.0) * s_PR + 1.0) / pr - 1.0
