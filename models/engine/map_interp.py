"""Piecewise bicubic Hermite interpolation of map tables on a rectangular grid.

Component maps are tables of several outputs (corrected flow, pressure ratio,
efficiency) over a rectangular grid of two inputs (relative corrected speed and
an R-line or a pressure ratio). :class:`BicubicTable` interpolates them with a
piecewise bicubic Hermite surface:

* the value, the two first partial derivatives and the cross derivative are
  fixed at every grid node; each cell is the tensor-product cubic Hermite patch
  through its four corners. Adjacent cells share the nodal data of their common
  edge, so the surface and both first derivatives are continuous everywhere
  (C1), which is what a Newton solver needs;
* the nodal slopes are those of the monotone piecewise cubic Hermite
  interpolant (PCHIP) along each grid line (Fritsch & Carlson 1980, with the
  weighted harmonic mean of Fritsch & Butland 1984 for unequal spacing and the
  shape-preserving three-point end slopes of Moler 2004, ch. 3.4). Along every
  grid line the surface is therefore exactly the 1-D PCHIP interpolant of that
  line: it never overshoots the data along a line, so a flow that becomes
  constant at choke stays constant and a flow that rises along a speed line
  does not turn back between nodes. The cross derivative is the mean of the
  PCHIP slopes of the two first-derivative arrays;
* outside the grid, by at most a stated margin on each axis, the surface is
  continued by its first-order Taylor expansion at the nearest boundary point
  plus the cross term, f = P + P_x dx + P_y dy + P_xy dx dy, which keeps it C1
  across the boundary; further out :class:`OutOfRangeError` is raised.

Each cell's 16 power-basis coefficients per output are computed once, at
construction. Evaluation is one function, :func:`.jit_kernels.table` (compiled
by numba where installed), which the compiled gas path calls directly and
:meth:`BicubicTable.values` calls from Python: one implementation.

References
----------
F. N. Fritsch, R. E. Carlson, "Monotone piecewise cubic interpolation",
SIAM J. Numer. Anal. 17(2), 238-246, 1980.
F. N. Fritsch, J. Butland, "A method for constructing local monotone piecewise
cubic interpolants", SIAM J. Sci. Stat. Comput. 5(2), 300-304, 1984.
C. Moler, *Numerical Computing with MATLAB*, SIAM, 2004, ch. 3.4 (pchip).
C. de Boor, *A Practical Guide to Splines*, rev. ed., Springer, 2001, ch. IV
(piecewise cubic Hermite interpolation).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .errors import ModelError, OutOfRangeError
from .jit_kernels import table as _table

__all__ = ["BicubicTable", "hyman_slopes", "pchip_slopes"]

_Triple = tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]]

# Hermite-to-power-basis matrix: [c0, c1, c2, c3] = M @ [p(0), p(1), p'(0), p'(1)].
_M = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [-3.0, 3.0, -2.0, -1.0], [2.0, -2.0, 1.0, 1.0]])


def _edge_slope(h0: np.ndarray, h1: np.ndarray, m0: np.ndarray, m1: np.ndarray) -> np.ndarray:
    """Shape-preserving three-point end slope (Moler 2004, pchip)."""
    d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
    big = (np.sign(m0) != np.sign(m1)) & (np.abs(d) > 3.0 * np.abs(m0))
    return np.where(big, 3.0 * m0, d)


def pchip_slopes(x: np.ndarray, f: np.ndarray, axis: int) -> np.ndarray:
    """Nodal slopes df/dx of the monotone piecewise cubic interpolant along one axis.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Strictly increasing abscissae, n >= 2.
    f : ndarray
        Ordinates; ``f.shape[axis] == n``.
    axis : int
        Axis of ``f`` along which ``x`` runs.

    Returns
    -------
    ndarray
        Slopes, same shape as ``f`` [unit of f / unit of x].

    References
    ----------
    Fritsch & Carlson 1980; Fritsch & Butland 1984; Moler 2004, ch. 3.4.
    """
    f = np.moveaxis(np.asarray(f, dtype=float), axis, 0)
    h = np.diff(x).reshape((-1,) + (1,) * (f.ndim - 1))
    m = np.diff(f, axis=0) / h
    d = np.empty_like(f)
    if f.shape[0] == 2:
        d[0] = d[1] = m[0]
        return np.moveaxis(d, 0, axis)
    w1 = 2.0 * h[1:] + h[:-1]
    w2 = h[1:] + 2.0 * h[:-1]
    same = (np.sign(m[1:]) == np.sign(m[:-1])) & (m[1:] != 0.0) & (m[:-1] != 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        inner = (w1 + w2) / (w1 / m[:-1] + w2 / m[1:])
    d[1:-1] = np.where(same, inner, 0.0)
    d[0] = _edge_slope(h[0], h[1], m[0], m[1])
    d[-1] = _edge_slope(h[-1], h[-2], m[-1], m[-2])
    return np.moveaxis(d, 0, axis)


def hyman_slopes(x: np.ndarray, f: np.ndarray, axis: int, limit: bool = True) -> np.ndarray:
    """Nodal slopes df/dx: three-point parabolic estimates, Hyman-filtered where the data are monotone.

    The slope at an interior node is that of the parabola through it and its
    two neighbours (de Boor 2001, "Bessel" slopes; second-order accurate); at
    an end node that of the parabola through the first (last) three nodes.
    With ``limit``, where the data are strictly monotone on both sides of a
    node the slope is clipped to the sign of the data and to three times the
    smaller adjacent secant slope (Hyman 1983), which keeps every monotone
    interval monotone (Fritsch & Carlson 1980); next to a flat interval the
    slope is 0, so a flat stretch (choked flow) stays flat. At a strict local
    extremum of the data the parabolic slope is kept, so a peak between two
    nodes (e.g. of efficiency) is not cut off.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Strictly increasing abscissae, n >= 2.
    f : ndarray
        Ordinates; ``f.shape[axis] == n``.
    axis : int
        Axis of ``f`` along which ``x`` runs.
    limit : bool
        Apply the monotonicity filter (False for derivative arrays).

    Returns
    -------
    ndarray
        Slopes, same shape as ``f`` [unit of f / unit of x].

    References
    ----------
    J. M. Hyman, "Accurate monotonicity preserving cubic interpolation",
    SIAM J. Sci. Stat. Comput. 4(4), 645-654, 1983.
    """
    f = np.moveaxis(np.asarray(f, dtype=float), axis, 0)
    h = np.diff(x).reshape((-1,) + (1,) * (f.ndim - 1))
    m = np.diff(f, axis=0) / h
    d = np.empty_like(f)
    if f.shape[0] == 2:
        d[0] = d[1] = m[0]
        return np.moveaxis(d, 0, axis)
    d[1:-1] = (h[1:] * m[:-1] + h[:-1] * m[1:]) / (h[:-1] + h[1:])
    d[0] = ((2.0 * h[0] + h[1]) * m[0] - h[0] * m[1]) / (h[0] + h[1])
    d[-1] = ((2.0 * h[-1] + h[-2]) * m[-1] - h[-1] * m[-2]) / (h[-1] + h[-2])
    if not limit:
        return np.moveaxis(d, 0, axis)
    # secant slopes left and right of every node (the end nodes see their one secant on both sides)
    ml = np.concatenate([m[:1], m])
    mr = np.concatenate([m, m[-1:]])
    mono = ml * mr > 0.0
    cap = 3.0 * np.minimum(np.abs(ml), np.abs(mr))
    clipped = np.sign(ml) * np.minimum(np.maximum(np.sign(ml) * d, 0.0), cap)
    d = np.where(mono, clipped, d)
    d = np.where((ml == 0.0) | (mr == 0.0), 0.0, d)
    return np.moveaxis(d, 0, axis)


class BicubicTable:
    """C1 piecewise bicubic Hermite interpolation of several tables on one grid.

    Parameters
    ----------
    x, y : sequence of float
        Strictly increasing grid values of the two inputs (at least 2 each).
    tables : sequence of array_like, each shape (len(x), len(y))
        The outputs at the grid nodes, ``table[i][j]`` at ``(x[i], y[j])``.
    margin_x, margin_y : float
        How far outside ``[x[0], x[-1]]`` and ``[y[0], y[-1]]`` the surface is
        continued linearly (same unit as the axis); beyond, evaluation raises.
    names : tuple of str
        Names of the inputs (for error messages), e.g. ``("nc_rel", "beta")``.
    where : str
        What the table is (for error messages), e.g. ``"compressor map 'axi5'"``.
    slopes : {"hyman", "pchip"}
        How the nodal slopes are estimated: :func:`hyman_slopes` (default;
        second-order accurate, monotone where the data are) or
        :func:`pchip_slopes` (monotone everywhere, first-order at extrema).
    monotone : sequence of bool, optional
        Per table, whether :func:`hyman_slopes` applies its monotonicity
        filter (default: all True). Use False for tables whose accuracy near an
        extremum matters more than monotonicity (efficiency); ignored with
        ``slopes="pchip"``.

    Notes
    -----
    Instances are not changed after construction, so one may be shared.
    """

    __slots__ = ("x", "y", "n_out", "names", "where", "x_lo", "x_hi", "y_lo", "y_hi",
                 "x_min", "x_max", "y_min", "y_max", "_cells", "_ihx", "_ihy", "_k")

    def __init__(self, x: Sequence[float], y: Sequence[float], tables: Sequence[np.ndarray | Sequence[Sequence[float]]],
                 margin_x: float, margin_y: float, names: tuple[str, str] = ("x", "y"), where: str = "table",
                 slopes: str = "hyman", monotone: Sequence[bool] | None = None) -> None:
        xa = np.asarray(x, dtype=float)
        ya = np.asarray(y, dtype=float)
        if xa.ndim != 1 or ya.ndim != 1 or xa.size < 2 or ya.size < 2:
            raise ModelError(f"{where}: grid axes need at least 2 values each, got {xa.size} and {ya.size}")
        if np.any(np.diff(xa) <= 0) or np.any(np.diff(ya) <= 0):
            raise ModelError(f"{where}: grid values of {names[0]} and {names[1]} must be strictly increasing")
        if slopes not in ("hyman", "pchip"):
            raise ModelError(f"{where}: slopes must be 'hyman' or 'pchip', got {slopes!r}")
        if margin_x < 0 or margin_y < 0:
            raise ModelError(f"{where}: extrapolation margins must be >= 0, got {margin_x}, {margin_y}")
        fs = [np.asarray(t, dtype=float) for t in tables]
        for f in fs:
            if f.shape != (xa.size, ya.size):
                raise ModelError(f"{where}: table shape {f.shape} differs from the grid ({xa.size}, {ya.size})")
            if not np.all(np.isfinite(f)):
                raise ModelError(f"{where}: table holds non-finite values")
        self.x, self.y = tuple(float(v) for v in xa), tuple(float(v) for v in ya)
        self.n_out, self.names, self.where = len(fs), names, where
        self.x_lo, self.x_hi, self.y_lo, self.y_hi = self.x[0], self.x[-1], self.y[0], self.y[-1]
        self.x_min, self.x_max = self.x_lo - margin_x, self.x_hi + margin_x
        self.y_min, self.y_max = self.y_lo - margin_y, self.y_hi + margin_y
        hx, hy = np.diff(xa), np.diff(ya)
        self._ihx = tuple(float(v) for v in 1.0 / hx)
        self._ihy = tuple(float(v) for v in 1.0 / hy)
        mono = [True] * len(fs) if monotone is None else [bool(b) for b in monotone]
        if len(mono) != len(fs):
            raise ModelError(f"{where}: {len(mono)} monotone flags for {len(fs)} tables")
        # per table, shape (nx-1, ny-1, 16)
        coeffs = [self._cell_coefficients(f, xa, ya, hx, hy, slopes, b) for f, b in zip(fs, mono, strict=True)]
        self._cells = tuple(tuple(tuple(tuple(float(v) for v in c[i, j]) for c in coeffs)
                                  for j in range(ya.size - 1)) for i in range(xa.size - 1))
        self._k = self.kernel_arrays()              # what the one evaluation (jit_kernels.table) reads

    @staticmethod
    def _cell_coefficients(f: np.ndarray, x: np.ndarray, y: np.ndarray, hx: np.ndarray, hy: np.ndarray,
                           method: str, monotone: bool) -> np.ndarray:
        if method == "pchip":
            fx, fy = pchip_slopes(x, f, 0), pchip_slopes(y, f, 1)
            fxy = 0.5 * (pchip_slopes(y, fx, 1) + pchip_slopes(x, fy, 0))
        else:
            fx, fy = hyman_slopes(x, f, 0, monotone), hyman_slopes(y, f, 1, monotone)
            fxy = 0.5 * (hyman_slopes(y, fx, 1, limit=False) + hyman_slopes(x, fy, 0, limit=False))
        nx, ny = f.shape
        g = np.empty((nx - 1, ny - 1, 4, 4))
        sx, sy = hx[:, None], hy[None, :]
        for a, di in enumerate((0, 1)):
            sl_i = slice(di, nx - 1 + di)
            for b, dj in enumerate((0, 1)):
                sl_j = slice(dj, ny - 1 + dj)
                g[:, :, a, b] = f[sl_i, sl_j]
                g[:, :, a, 2 + b] = fy[sl_i, sl_j] * sy
                g[:, :, 2 + a, b] = fx[sl_i, sl_j] * sx
                g[:, :, 2 + a, 2 + b] = fxy[sl_i, sl_j] * sx * sy
        a_kl = np.einsum("km,ijmn,ln->ijkl", _M, g, _M)
        return a_kl.reshape(nx - 1, ny - 1, 16)

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The table as the compiled kernels read it (:func:`.jit_kernels.table`): grid x, grid y, inverse cell
        widths in x and y, cell coefficients (nx-1, ny-1, outputs, 16) and the limits (x_lo, x_hi, y_lo, y_hi,
        x_min, x_max, y_min, y_max)."""
        if hasattr(self, "_k"):
            return self._k
        nx, ny = len(self.x), len(self.y)
        cells = np.array([[list(self._cells[i][j]) for j in range(ny - 1)] for i in range(nx - 1)], dtype=float)
        lim = np.array([self.x_lo, self.x_hi, self.y_lo, self.y_hi, self.x_min, self.x_max, self.y_min, self.y_max])
        return np.array(self.x), np.array(self.y), np.array(self._ihx), np.array(self._ihy), cells, lim

    # ------------------------------------------------------------------ evaluation
    def _out_of_range(self, x: float, y: float) -> OutOfRangeError:
        if not (self.x_min <= x <= self.x_max):
            name, v, lo, hi, lo2, hi2 = self.names[0], x, self.x_lo, self.x_hi, self.x_min, self.x_max
        else:
            name, v, lo, hi, lo2, hi2 = self.names[1], y, self.y_lo, self.y_hi, self.y_min, self.y_max
        return OutOfRangeError(
            f"{self.where}: {name} = {v!r} is outside the map's range [{lo:g}, {hi:g}] and its "
            f"linear extrapolation margin [{lo2:g}, {hi2:g}]")

    def _eval(self, x: float, y: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Values and gradients at (x, y) by :func:`.jit_kernels.table` (the one implementation, also what the
        compiled gas path calls), or :meth:`_out_of_range` raised beyond the margins (or for NaN)."""
        n = self.n_out
        v, gx, gy, err = np.empty(n), np.empty(n), np.empty(n), np.zeros(1, np.int64)
        _table(*self._k, float(x), float(y), v, gx, gy, err)
        if err[0]:
            raise self._out_of_range(x, y)
        return v, gx, gy

    def values(self, x: float, y: float) -> tuple[float, ...]:
        """Outputs at (x, y), interpolated or extrapolated.

        Raises
        ------
        OutOfRangeError
            If x or y lies beyond the extrapolation margin (or is NaN).
        """
        return tuple(self._eval(x, y)[0].tolist())

    def values_and_gradients(self, x: float, y: float) -> _Triple:
        """Outputs and their partial derivatives with respect to x and to y at (x, y).

        Returns
        -------
        (values, d_dx, d_dy) : three tuples of float, one entry per output.
        """
        v, gx, gy = self._eval(x, y)
        return tuple(v.tolist()), tuple(gx.tolist()), tuple(gy.tolist())
