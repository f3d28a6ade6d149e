"""Component maps scaled to a cycle's design point (pyCycle / NPSS map scalars).

A map is scaled by four scalars computed once, at the design point, from a
chosen point of the map (``nc_rel_map``, ``beta_map`` or ``pr_map``; by
default the map's own design point from its data file) and the cycle's design
values::

    s_Nc  = Nc_design / nc_rel_map             Nc  = s_Nc  * nc_rel
    s_Wc  = Wc_design / Wc_map                 Wc  = s_Wc  * Wc_map
    s_PR  = (PR_design - 1) / (PR_map - 1)     PR  = s_PR  * (PR_map - 1) + 1
    s_eff = eff_design / eff_map               eff = s_eff * eff_map

``Nc`` may be given in any unit (rpm/sqrt(K), or relative speed with
``Nc_design = 1.0``); the scaled maps take speeds in that unit. For a turbine
the pressure ratio is an input: ``PR_map = (PR - 1) / s_PR + 1``. Scaling PR
as ``PR - 1`` keeps ``PR = 1`` (no work) at ``PR_map = 1``.

References
----------
P. P. Walsh, P. Fletcher, *Gas Turbine Performance*, 2nd ed., Blackwell, 2004,
ch. 5 (scaling of component maps).
E. S. Hendricks, J. S. Gray, "pyCycle: A Tool for Efficient Optimization of
Gas Turbine Engine Cycles", Aerospace 6(8), 87, 2019 (``MapScalars``,
``ScaledMapValues`` in ``pycycle/elements/compressor_map.py`` and ``turbine_map.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from .errors import ModelError
from .map_interp import BicubicTable
from .map_points import CompressorPoint, CompressorPointD, TurbinePoint, TurbinePointD
from .maps import CompressorMap, TurbineMap

__all__ = ["ScaledCompressorMap", "ScaledTurbineMap", "TabulatedMap", "tabulate_map"]

#: A scaled map as the compiled gas path reads it (:mod:`.gas_path`): the table's arrays (grid x, grid y, inverse
#: widths, cell coefficients, limits), the scalars (s_Wc, s_PR, s_eff, s_Nc, corrected-speed clamp low and
#: high), and the surge line's nodes (relative speed, corrected flow; NaN for a turbine).
KernelMap = tuple[Any, ...]


def _kernel_map(arrays: tuple[np.ndarray, ...], s_Wc: float, s_PR: float, s_eff: float, s_Nc: float,
                Nc_lo: float = -math.inf, Nc_hi: float = math.inf) -> KernelMap:
    """(xg, yg, ihx, ihy, cells, lim, scalars, surge x, surge w) of a map's arrays and its scalars."""
    return (*arrays[:6], np.array([s_Wc, s_PR, s_eff, s_Nc, Nc_lo, Nc_hi]), *arrays[6:])


def _check_design(where: str, Wc_design_kg_s: float, PR_design: float, eff_design: float, Nc_design: float) -> None:
    if not Wc_design_kg_s > 0.0:
        raise ModelError(f"{where}: design corrected flow must be > 0 kg/s, got {Wc_design_kg_s}")
    if not PR_design > 1.0:
        raise ModelError(f"{where}: design pressure ratio must be > 1, got {PR_design}")
    if not 0.0 < eff_design <= 1.0:
        raise ModelError(f"{where}: design efficiency must be in (0, 1], got {eff_design}")
    if not Nc_design > 0.0:
        raise ModelError(f"{where}: design corrected speed must be > 0, got {Nc_design}")


@dataclass(frozen=True, slots=True)
class ScaledCompressorMap:
    """A :class:`~.maps.CompressorMap` scaled to a design point.

    Build it with :meth:`from_design`. Speeds ``Nc`` are in the unit of
    ``Nc_design``; flows in kg/s (corrected).

    Attributes
    ----------
    map : CompressorMap
    s_Wc, s_PR, s_eff, s_Nc : float
        Map scalars (``s_Nc`` in the unit of ``Nc_design``).
    nc_rel_map, beta_map : float
        Map point placed on the design point [-].
    """

    map: CompressorMap
    s_Wc: float
    s_PR: float
    s_eff: float
    s_Nc: float
    nc_rel_map: float
    beta_map: float

    @classmethod
    def from_design(cls, cmap: CompressorMap, Wc_design_kg_s: float, PR_design: float, eff_design: float,
                    Nc_design: float = 1.0, nc_rel_map: float | None = None,
                    beta_map: float | None = None) -> ScaledCompressorMap:
        """Scalars that put the map point (nc_rel_map, beta_map) on the design values.

        Parameters
        ----------
        cmap : CompressorMap
        Wc_design_kg_s : float
            Design corrected flow [kg/s].
        PR_design, eff_design : float
            Design total pressure ratio [-] and isentropic efficiency [-].
        Nc_design : float
            Design corrected speed, in the unit the scaled map will be called
            with (default 1.0: relative speed).
        nc_rel_map, beta_map : float, optional
            Map point to scale to; default the map's design point.
        """
        _check_design(f"compressor map {cmap.name!r}", Wc_design_kg_s, PR_design, eff_design, Nc_design)
        n = cmap.nc_rel_design if nc_rel_map is None else nc_rel_map
        b = cmap.beta_design if beta_map is None else beta_map
        w, p, e = cmap.evaluate(n, b)
        if not p > 1.0:
            raise ModelError(f"compressor map {cmap.name!r}: map PR at nc_rel={n}, beta={b} is {p}, must be > 1")
        return cls(cmap, Wc_design_kg_s / w, (PR_design - 1.0) / (p - 1.0), eff_design / e, Nc_design / n, n, b)

    def evaluate(self, Nc: float, beta: float) -> CompressorPoint:
        """Corrected flow [kg/s], pressure ratio [-], efficiency [-] at corrected speed Nc and beta [-]."""
        w, p, e = self.map._table.values(Nc / self.s_Nc, beta)
        return CompressorPoint(w * self.s_Wc, (p - 1.0) * self.s_PR + 1.0, e * self.s_eff)

    def evaluate_with_derivatives(self, Nc: float, beta: float) -> CompressorPointD:
        """As :meth:`evaluate`, plus partial derivatives with respect to Nc (its unit) and beta."""
        s_n = 1.0 / self.s_Nc
        (w, p, e), (w_n, p_n, e_n), (w_b, p_b, e_b) = self.map._table.values_and_gradients(Nc * s_n, beta)
        sw, sp, se = self.s_Wc, self.s_PR, self.s_eff
        return CompressorPointD(w * sw, (p - 1.0) * sp + 1.0, e * se, w_n * sw * s_n, w_b * sw,
                                p_n * sp * s_n, p_b * sp, e_n * se * s_n, e_b * se)

    def kernel_tuple(self) -> KernelMap:
        """The scaled map as the compiled gas path reads it (:data:`KernelMap`)."""
        return _kernel_map(self.map.kernel_arrays(), self.s_Wc, self.s_PR, self.s_eff, self.s_Nc)

    def surge_pr(self, Nc: float) -> float:
        """Scaled surge-line pressure ratio [-] at corrected speed Nc."""
        return (self.map.surge_pr(Nc / self.s_Nc) - 1.0) * self.s_PR + 1.0

    def surge_margin(self, Nc: float, beta: float, basis: Literal["flow", "speed"] = "flow") -> float:
        """Surge margin [-] on the scaled map; see :meth:`.maps.CompressorMap.surge_margin`."""
        return self.map.surge_margin(Nc / self.s_Nc, beta, basis, self.s_PR)


@dataclass(frozen=True, slots=True)
class ScaledTurbineMap:
    """A :class:`~.maps.TurbineMap` scaled to a design point.

    Attributes
    ----------
    map : TurbineMap
    s_Wc, s_PR, s_eff, s_Nc : float
        Map scalars (``s_Nc`` in the unit of ``Nc_design``).
    nc_rel_map, pr_map : float
        Map point placed on the design point [-].
    """

    map: TurbineMap
    s_Wc: float
    s_PR: float
    s_eff: float
    s_Nc: float
    nc_rel_map: float
    pr_map: float

    @classmethod
    def from_design(cls, tmap: TurbineMap, Wc_design_kg_s: float, PR_design: float, eff_design: float,
                    Nc_design: float = 1.0, nc_rel_map: float | None = None,
                    pr_map: float | None = None) -> ScaledTurbineMap:
        """Scalars that put the map point (nc_rel_map, pr_map) on the design values.

        Parameters
        ----------
        tmap : TurbineMap
        Wc_design_kg_s : float
            Design corrected flow at turbine inlet [kg/s] (reference state of :mod:`.maps`).
        PR_design, eff_design : float
            Design expansion ratio Pt_in/Pt_out [-] and isentropic efficiency [-].
        Nc_design : float
            Design corrected speed, in the unit the scaled map will be called with.
        nc_rel_map, pr_map : float, optional
            Map point to scale to; default the map's design point.
        """
        _check_design(f"turbine map {tmap.name!r}", Wc_design_kg_s, PR_design, eff_design, Nc_design)
        n = tmap.nc_rel_design if nc_rel_map is None else nc_rel_map
        pm = tmap.pr_design if pr_map is None else pr_map
        if not pm > 1.0:
            raise ModelError(f"turbine map {tmap.name!r}: map design pressure ratio must be > 1, got {pm}")
        w, e = tmap.evaluate(n, pm)
        return cls(tmap, Wc_design_kg_s / w, (PR_design - 1.0) / (pm - 1.0), eff_design / e, Nc_design / n, n, pm)

    def kernel_tuple(self, Nc_lo: float = -math.inf, Nc_hi: float = math.inf) -> KernelMap:
        """The scaled map as the compiled gas path reads it (:data:`KernelMap`), its corrected speed clamped to
        [Nc_lo, Nc_hi] (default: not clamped)."""
        return _kernel_map(self.map.kernel_arrays(), self.s_Wc, self.s_PR, self.s_eff, self.s_Nc, Nc_lo, Nc_hi)

    def map_pr(self, PR: float) -> float:
        """Map pressure ratio [-] of a scaled pressure ratio PR [-]."""
        return (PR - 1.0) / self.s_PR + 1.0

    def evaluate(self, Nc: float, PR: float) -> TurbinePoint:
        """Corrected flow [kg/s] and efficiency [-] at corrected speed Nc and pressure ratio PR [-]."""
        w, e = self.map._table.values(Nc / self.s_Nc, (PR - 1.0) / self.s_PR + 1.0)
        return TurbinePoint(w * self.s_Wc, e * self.s_eff)

    def evaluate_with_derivatives(self, Nc: float, PR: float) -> TurbinePointD:
        """As :meth:`evaluate`, plus partial derivatives with respect to Nc (its unit) and PR."""
        s_n, s_p = 1.0 / self.s_Nc, 1.0 / self.s_PR
        (w, e), (w_n, e_n), (w_p, e_p) = self.map._table.values_and_gradients(Nc * s_n, (PR - 1.0) * s_p + 1.0)
        sw, se = self.s_Wc, self.s_eff
        return TurbinePointD(w * sw, e * se, w_n * sw * s_n, w_p * sw * s_p, e_n * se * s_n, e_p * se * s_p)


@dataclass(frozen=True)
class TabulatedMap:
    """A map given as a function, tabulated on a grid (C1 bicubic, :class:`.map_interp.BicubicTable`), in the
    units it is called with: a compressor map ``(Nc, beta) -> (Wc, PR, eff)`` or a turbine map
    ``(Nc, PR) -> (Wc, eff)``. Build it with :func:`tabulate_map`; the gas path reads maps only as tables.

    Attributes
    ----------
    table : BicubicTable
    kind : {"compressor", "turbine"}
    """

    table: BicubicTable
    kind: str

    def evaluate(self, Nc: float, y: float) -> tuple[float, ...]:
        """The tabulated values at (Nc, beta) or (Nc, PR)."""
        return self.table.values(Nc, y)

    def surge_margin(self, Nc: float, beta: float) -> float:
        """No surge line is known for a tabulated function: NaN."""
        return math.nan

    def kernel_tuple(self) -> KernelMap:
        """The table as the compiled gas path reads it (:data:`KernelMap`; scalars 1, no surge line)."""
        nan2 = np.full(2, np.nan)
        return _kernel_map((*self.table.kernel_arrays(), nan2, nan2), 1.0, 1.0, 1.0, 1.0)


def tabulate_map(fn: Callable[[float, float], Sequence[float]], Nc: Sequence[float], y: Sequence[float],
                 kind: Literal["compressor", "turbine"], margin: float = 0.1) -> TabulatedMap:
    """Tabulate a map function on the grid `Nc` x `y` (corrected speed; beta for a compressor, PR for a turbine).

    The table passes through every node exactly (put the design point on a node) and is C1 between them;
    it is continued linearly for `margin` of each axis' span beyond its ends, and refuses beyond.
    """
    n_out = 3 if kind == "compressor" else 2
    vals = np.array([[list(fn(a, b))[:n_out] for b in y] for a in Nc], dtype=float)
    xs, ys = np.asarray(Nc, dtype=float), np.asarray(y, dtype=float)
    table = BicubicTable(xs, ys, [vals[:, :, k] for k in range(n_out)], margin * (xs[-1] - xs[0]),
                         margin * (ys[-1] - ys[0]), ("Nc", "beta" if kind == "compressor" else "PR"),
                         f"tabulated {kind} map", monotone=(True,) * (n_out - 1) + (False,))
    return TabulatedMap(table, kind)
