"""Sub-idle extension of the turbine maps: extra grid nodes from stated physical laws.

The shipped turbine maps (``hpt1269``, ``lpt2269``, ``maps/README.md``) cover
pressure ratios 3 to 8 and relative corrected speeds 0.6 to 1.1 (1.2). A
turbofan at ground or flight idle runs its LP turbine below both (low
expansion ratio once the core nozzle unchokes, low N1), so the maps are
extended *as data*: :func:`extend_map_data` takes a map as loaded
(:class:`~.maps.MapData`, source units) and returns a map on a larger grid
whose original nodes are copied unchanged and whose new nodes follow:

* **flow, below the lowest pressure ratio** -- the ellipse law of Stodola, in
  the form with a finite choking expansion ratio: with ``x = 1/PR``,

      Wc = Wc* sqrt(1 - ((x - x*) / (1 - x*))**2)      for x* <= x <= 1,

  an ellipse through ``Wc = 0`` at ``PR = 1`` with its vertex (``Wc*``,
  zero slope) at ``x* = 1/PR*``. ``x* = 0`` is Stodola's cone law
  ``Wc ~ sqrt(1 - 1/PR**2)``; ``x* = x_j`` is a speed line choked down to its
  lowest map point. ``Wc*`` and ``x*`` are fitted on every speed line to the
  value and slope dWc/dPR of the original map (its interpolating surface) at
  the lowest pressure ratio ``PR_j``, so the extension joins the data with
  continuous value and slope (closed form, :func:`fit_ellipse`);
* **efficiency** -- a function of the blade-speed (velocity) ratio
  ``u/c_is``, which at corrected conditions is proportional to
  ``nu = nc_rel / sqrt(1 - PR**(-(gamma - 1)/gamma))`` (gamma = 4/3 for
  combustion products). The map's own efficiencies collapse onto a parabola
  ``eta = eta_pk (1 - C (nu/nu_opt - 1)**2)`` (least squares over all the
  nodes, :func:`fit_velocity_ratio_parabola`; within about 1.5 % for both
  maps). Along each line leaving the map the efficiency keeps its ratio to the
  parabola: ``eta(nu) = eta_j P(nu) / P(nu_j)`` with ``P`` the parabola and
  ``(nu_j, eta_j)`` the line's last map node, so the value joins the data and
  the trend is the law's. Far from the optimum, where the parabola gives
  nonsense (a turbine at very high ``u/c`` is a brake, not a turbine), the
  efficiency is held above ``ETA_FLOOR`` by a smooth maximum;
* **flow, outside the speed range** (at every pressure ratio, including the
  new ones) -- continued to first order in speed with the slope of the map at
  its last speed line: a turbine's flow capacity is set by its nozzle guide
  vanes and depends only weakly on speed (Walsh & Fletcher 2004, ch. 5.4), the
  same continuation :class:`~.map_interp.BicubicTable` uses in its margin, over
  a longer range (a change of about 1 % over the extension on the shipped maps).

The interpolating surface over the extended grid is again piecewise bicubic
Hermite (:mod:`.map_interp`, unchanged), so it is C1 everywhere; it passes
through every original node exactly. Between the original nodes of the first
cell next to the old edge it differs from the unextended surface by the change
of the kernel's end-slope estimate (an interior three-point slope instead of
the one-sided one; well below the map's own digits).

References
----------
A. Stodola, *Steam and Gas Turbines*, vol. 1, McGraw-Hill, 1927 (the cone or
ellipse law of turbine flow).
S. L. Dixon, C. A. Hall, *Fluid Mechanics and Thermodynamics of
Turbomachinery*, 7th ed., Butterworth-Heinemann, 2014, ch. 4 (stage efficiency
against blade-speed ratio u/c).
J. Kurzke, "How to get component maps for aircraft gas turbine performance
calculations", ASME 96-GT-164, 1996 (turbine maps over velocity ratio and
pressure ratio; extrapolation of maps).
J. Kurzke, I. Halliwell, *Propulsion and Power*, Springer, 2018, ch. 7
(turbine maps; efficiency over u/c_is).
P. P. Walsh, P. Fletcher, *Gas Turbine Performance*, 2nd ed., Blackwell, 2004,
ch. 5.4 (turbine flow capacity and efficiency characteristics).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from types import MappingProxyType

import numpy as np

from .errors import ModelError
from .map_interp import BicubicTable
from .maps import MapData

__all__ = ["GAMMA_TURBINE", "K_TURBINE", "GAMMA_AIR", "ETA_FLOOR", "EXTENSIONS", "EXPONENT_LIMITS",
           "TurbineExtension", "CompressorExtension", "velocity_ratio", "ellipse_flow", "fit_ellipse",
           "fit_velocity_ratio_parabola", "parabola", "smooth_floor", "similarity_exponent",
           "extend_map_data", "extend_turbine_data", "extend_compressor_data"]

#: Ratio of specific heats of the expanding gas [-] (combustion products, Walsh & Fletcher ch. 3).
GAMMA_TURBINE: float = 4.0 / 3.0
#: Exponent (gamma - 1)/gamma of the isentropic expansion [-].
K_TURBINE: float = (GAMMA_TURBINE - 1.0) / GAMMA_TURBINE
#: Lowest efficiency [-] the extension gives (smooth maximum, width ETA_FLOOR_WIDTH).
ETA_FLOOR: float = 0.2
ETA_FLOOR_WIDTH: float = 0.05




@dataclasses.dataclass(frozen=True)
class TurbineExtension:
    """Where a turbine map is extended: the extra grid values (map units).

    Attributes
    ----------
    pr_low : tuple of float
        Extra pressure ratios below the map's lowest [-], descending toward 1.
    nc_low, nc_high : tuple of float
        Extra relative corrected speeds below the lowest and above the highest speed line [-].
    """

    pr_low: tuple[float, ...] = (2.75, 2.5, 2.25, 2.0, 1.8, 1.6, 1.45, 1.3, 1.2, 1.1, 1.05)
    nc_low: tuple[float, ...] = (0.5, 0.4, 0.3, 0.2)
    nc_high: tuple[float, ...] = ()


@dataclasses.dataclass(frozen=True)
class CompressorExtension:
    """Extra relative corrected speeds below a compressor map's lowest speed line [-], descending."""

    nc_low: tuple[float, ...] = ()


#: The extension of each shipped map: the turbines also above their last speed lines (the HPT passes
#: 1.1 at part power, where N2 stays high while Tt4 falls, and both pass it in a fuel chop, where Tt4
#: falls faster than the speeds); the fan below its 30 % line, reached below ground idle.
EXTENSIONS: MappingProxyType[str, TurbineExtension | CompressorExtension] = MappingProxyType({
    "hpt1269": TurbineExtension(nc_high=(1.2, 1.3, 1.4, 1.6, 1.8)),
    "lpt2269": TurbineExtension(nc_high=(1.3, 1.4, 1.6, 1.8)),
    "lpc_hbtf": CompressorExtension(nc_low=(0.25, 0.2, 0.15)),
    "axi5": CompressorExtension(nc_low=(0.3, 0.2)),
})
#: Ratio of specific heats of air in the compressors [-].
GAMMA_AIR: float = 1.4
#: Limits of the similarity exponents of flow, isentropic enthalpy rise and efficiency fitted on a beta
#: line, and the affinity-law values used where the fit is undefined (a zero enthalpy rise or efficiency).
EXPONENT_LIMITS: MappingProxyType[str, tuple[float, float, float]] = MappingProxyType(
    {"flow": (0.5, 2.0, 1.0), "work": (1.0, 3.0, 2.0), "eff": (0.0, 1.0, 0.0)})


def velocity_ratio(nc_rel: float | np.ndarray, pr: float | np.ndarray) -> float | np.ndarray:
    """Blade-speed ratio u/c_is up to a constant factor [-]: ``nc_rel / sqrt(1 - pr**-K_TURBINE)``.

    ``u ~ N`` and ``c_is = sqrt(2 cp Tt_in (1 - PR**(-(gamma-1)/gamma)))``, so at corrected
    conditions (``N/sqrt(Tt_in)``) u/c_is is this ratio times a constant of the machine.

    References
    ----------
    Dixon & Hall 2014, ch. 4; Kurzke 1996.
    """
    return nc_rel / np.sqrt(1.0 - np.asarray(pr, dtype=float) ** -K_TURBINE)


def ellipse_flow(pr: float | np.ndarray, Wc_star: float, x_star: float) -> float | np.ndarray:
    """Corrected flow of the ellipse law at pressure ratio `pr` [-] (same unit as `Wc_star`).

    ``Wc = Wc* sqrt(1 - ((1/pr - x*)/(1 - x*))**2)`` for ``1/pr >= x*``, ``Wc*`` (choked) below.

    References
    ----------
    Stodola 1927 (x* = 0: the cone law Wc ~ sqrt(1 - 1/PR**2)).
    """
    x = 1.0 / np.asarray(pr, dtype=float)
    u = np.clip((x - x_star) / (1.0 - x_star), 0.0, 1.0)
    return Wc_star * np.sqrt(1.0 - u * u)


def fit_ellipse(pr_j: float, Wc_j: float, dWc_dpr_j: float) -> tuple[float, float]:
    """(Wc*, x*) of the ellipse law through (pr_j, Wc_j) with slope dWc/dPR = dWc_dpr_j there.

    With ``x = 1/PR`` and ``m = -dWc/dx = dWc_dpr_j pr_j**2 >= 0``, the law's slope condition
    gives ``(x_j - x*)/(1 + x_j - 2 x*) = c`` with ``c = m (1 - x_j)/Wc_j``, so
    ``x* = (c (1 + x_j) - x_j)/(2 c - 1)``; ``Wc* = Wc_j / sqrt(1 - u_j**2)``. A negative slope
    (flow falling toward choke, not physical) is taken as zero; a slope steeper than the law
    allows (``c >= 1/2``) is limited to just below it.

    Raises
    ------
    ModelError
        If pr_j <= 1 or Wc_j <= 0.
    """
    if not (pr_j > 1.0 and Wc_j > 0.0):
        raise ModelError(f"ellipse law: need pr_j > 1 and Wc_j > 0, got pr_j={pr_j}, Wc_j={Wc_j}")
    x_j = 1.0 / pr_j
    c = min(max(dWc_dpr_j, 0.0) * pr_j * pr_j * (1.0 - x_j) / Wc_j, 0.45)
    x_star = (c * (1.0 + x_j) - x_j) / (2.0 * c - 1.0)
    u_j = (x_j - x_star) / (1.0 - x_star)
    return Wc_j / math.sqrt(1.0 - u_j * u_j), x_star


def parabola(nu: float | np.ndarray, nu_opt: float, C: float) -> float | np.ndarray:
    """Parabolic efficiency law over velocity ratio, relative to its peak: ``1 - C (nu/nu_opt - 1)**2`` [-]."""
    r = np.asarray(nu, dtype=float) / nu_opt - 1.0
    return 1.0 - C * r * r


def fit_velocity_ratio_parabola(nu: np.ndarray, eta: np.ndarray) -> tuple[float, float, float]:
    """(eta_pk, nu_opt, C) of ``eta = eta_pk (1 - C (nu/nu_opt - 1)**2)``, least squares over all points.

    A linear least-squares fit of ``eta = a + b nu + c nu**2``, then ``nu_opt = -b/(2c)``,
    ``eta_pk = a - b**2/(4c)``, ``C = -c nu_opt**2 / eta_pk``.

    Raises
    ------
    ModelError
        If the fitted parabola does not open downward (no optimum).
    """
    nu, eta = np.ravel(nu), np.ravel(eta)
    a, b, c = np.linalg.lstsq(np.column_stack([np.ones_like(nu), nu, nu * nu]), eta, rcond=None)[0]
    if not c < 0.0:
        raise ModelError(f"velocity-ratio parabola: efficiency data give no optimum (curvature {c:.4g} >= 0)")
    nu_opt = -b / (2.0 * c)
    eta_pk = a - b * b / (4.0 * c)
    return float(eta_pk), float(nu_opt), float(-c * nu_opt * nu_opt / eta_pk)


def smooth_floor(eta: float | np.ndarray, floor: float = ETA_FLOOR,
                 width: float = ETA_FLOOR_WIDTH) -> float | np.ndarray:
    """Smooth maximum of `eta` and `floor`: ``(eta + floor + sqrt((eta - floor)**2 + width**2))/2`` [-]."""
    d = np.asarray(eta, dtype=float) - floor
    return floor + 0.5 * (d + np.sqrt(d * d + width * width))


def _table(nc: Sequence[float], pr: Sequence[float], W: np.ndarray, E: np.ndarray) -> BicubicTable:
    return BicubicTable(nc, pr, [W, E], 0.0, 0.0, ("nc_rel", "pr"), "turbine map extension",
                        monotone=(True, False))


def extend_turbine_data(data: MapData, ext: TurbineExtension | None = None) -> MapData:
    """A turbine map's data on an extended grid (original nodes unchanged, new ones from the laws above).

    Parameters
    ----------
    data : MapData
        A turbine map as loaded (:func:`.maps.load_map_data`), source units.
    ext : TurbineExtension, optional
        Extra grid values; default :data:`EXTENSIONS` for the map's name, else :class:`TurbineExtension()`.

    Returns
    -------
    MapData
        Same name, source and units; ``speed_values``, ``line_values`` and ``tables`` extended.

    Raises
    ------
    ModelError
        If `data` is not a turbine map or the extra values do not lie outside the map's axes.
    """
    if data.kind != "turbine":
        raise ModelError(f"map {data.name!r}: extend_turbine_data needs a turbine map, got a {data.kind} map")
    ext = EXTENSIONS.get(data.name, TurbineExtension()) if ext is None else ext
    s_design = data.speed_design
    nc0 = np.array(data.speed_values) / s_design
    pr0 = np.array(data.line_values)
    pr_low = np.array(sorted(ext.pr_low))
    nc_low, nc_high = np.array(sorted(ext.nc_low)), np.array(sorted(ext.nc_high))
    if (pr_low.size and not (pr_low[0] > 1.0 and pr_low[-1] < pr0[0])) or \
            (nc_low.size and not (nc_low[0] > 0.0 and nc_low[-1] < nc0[0])) or \
            (nc_high.size and not nc_high[0] > nc0[-1]):
        raise ModelError(f"turbine map {data.name!r}: extension values must lie outside the map "
                         f"(PR in (1, {pr0[0]:g}), speeds in (0, {nc0[0]:g}) or above {nc0[-1]:g}); got {ext}")
    W0, E0 = np.array(data.tables["WpMap"]), np.array(data.tables["effMap"])
    eta_pk, nu_opt, C = fit_velocity_ratio_parabola(velocity_ratio(nc0[:, None], pr0[None, :]), E0)

    # 1. pressure ratios below the map, on every original speed line
    base = _table(nc0, pr0, W0, E0)
    W1 = np.empty((nc0.size, pr_low.size))
    E1 = np.empty_like(W1)
    for i, n in enumerate(nc0):
        (w_j, e_j), _, (dw_j, _de) = base.values_and_gradients(float(n), float(pr0[0]))
        Wc_star, x_star = fit_ellipse(float(pr0[0]), w_j, dw_j)
        W1[i] = ellipse_flow(pr_low, Wc_star, x_star)
        P_j = parabola(velocity_ratio(n, pr0[0]), nu_opt, C)
        E1[i] = e_j * parabola(velocity_ratio(n, pr_low), nu_opt, C) / P_j
    pr = np.concatenate([pr_low, pr0])
    W = np.concatenate([W1, W0], axis=1)
    E = np.concatenate([E1, E0], axis=1)
    E_raw = E.copy()                       # before the floor, for the speed extension's ratios

    # 2. speeds outside the map, on every pressure ratio (original and new)
    mid = _table(nc0, pr, W, smooth_floor(E))
    rows_W, rows_E = [], []
    for n_new, n_b, i_b in [(n, nc0[0], 0) for n in nc_low] + [(n, nc0[-1], -1) for n in nc_high]:
        dW = np.array([mid.values_and_gradients(float(n_b), float(p))[1][0] for p in pr])
        rows_W.append(W[i_b] + dW * (n_new - n_b))
        ratio = parabola(velocity_ratio(n_new, pr), nu_opt, C) / parabola(velocity_ratio(n_b, pr), nu_opt, C)
        rows_E.append(E_raw[i_b] * ratio)
    k_lo, k_hi = nc_low.size, len(rows_W) - nc_low.size
    W = np.vstack(rows_W[:k_lo] + [W] + rows_W[k_lo:k_lo + k_hi]) if rows_W else W
    E = np.vstack(rows_E[:k_lo] + [E_raw] + rows_E[k_lo:k_lo + k_hi]) if rows_E else E_raw
    E = smooth_floor(E)
    # the original nodes exactly as stored (the floor and float round trips must not touch them)
    i0, j0 = nc_low.size, pr_low.size
    W[i0:i0 + nc0.size, j0:] = W0
    E[i0:i0 + nc0.size, j0:] = E0
    if not (np.all(np.isfinite(W)) and np.all(W > 0.0) and np.all(E < 1.0)):
        raise ModelError(f"turbine map {data.name!r}: the extension gives flows <= 0 or efficiencies >= 1")
    tables = {"WpMap": tuple(tuple(float(v) for v in row) for row in W),
              "effMap": tuple(tuple(float(v) for v in row) for row in E)}
    speeds = tuple(float(v) * s_design for v in nc_low) + data.speed_values + tuple(
        float(v) * s_design for v in nc_high)                  # the original axis values exactly as stored
    return dataclasses.replace(data, speed_values=speeds,
                               line_values=tuple(float(v) for v in pr), tables=MappingProxyType(tables))


def similarity_exponent(v0: np.ndarray, v1: np.ndarray, n0: float, n1: float, kind: str) -> np.ndarray:
    """Exponent e of ``v ~ n**e`` through (n0, v0) and (n1, v1), limited per :data:`EXPONENT_LIMITS`.

    Where v0 or v1 is not positive the affinity-law value is used.
    """
    lo, hi, default = EXPONENT_LIMITS[kind]
    ok = (v0 > 0.0) & (v1 > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.log(np.where(ok, v1, 1.0) / np.where(ok, v0, 1.0)) / math.log(n1 / n0)
    return np.where(ok, np.clip(e, lo, hi), default)


def extend_compressor_data(data: MapData, ext: CompressorExtension | None = None) -> MapData:
    """A compressor map's data with speed lines added below its lowest, by similarity along beta lines.

    On every R-line (beta line), from the two lowest speed lines ``n0 < n1`` of the map:

        Wc = Wc0 (n/n0)**a,   (PR**k - 1) = (PR0**k - 1) (n/n0)**b,   eta = eta0 (n/n0)**c,

    ``k = (gamma - 1)/gamma`` of air, so the second law is the isentropic enthalpy rise. The
    affinity (fan) laws are ``a = 1``, ``b = 2``, ``c = 0``; here, as in the generalised similarity
    laws of the sub-idle literature, each exponent is the one through the two lowest lines
    (``a = ln(Wc1/Wc0)/ln(n1/n0)`` and likewise), which continues each line's trend with
    continuous value and secant slope, limited to :data:`EXPONENT_LIMITS` (the affinity value
    where a line's enthalpy rise or efficiency is zero).

    References
    ----------
    S. Gaudet, J. E. D. Gauthier, "A simple sub-idle component map extrapolation method",
    ASME GT2007-27193, 2007 (similarity along beta lines, exponents from the lowest lines).
    J. Kurzke, "An enhanced compressor map extension method suited for spool speeds down to 1 %",
    J. Global Power Propuls. Soc., 2023 (sub-idle compressor maps).
    """
    if data.kind != "compressor":
        raise ModelError(f"map {data.name!r}: extend_compressor_data needs a compressor map, got a {data.kind}")
    found = EXTENSIONS.get(data.name)
    ext = (found if isinstance(found, CompressorExtension) else CompressorExtension()) if ext is None else ext
    nc0 = np.array(data.speed_values) / data.speed_design
    new = np.array(sorted(ext.nc_low))
    if not new.size:
        return data
    if not (new[0] > 0.0 and new[-1] < nc0[0]):
        raise ModelError(f"compressor map {data.name!r}: extra speeds must lie in (0, {nc0[0]:g}), got {ext}")
    k = (GAMMA_AIR - 1.0) / GAMMA_AIR
    W, P, E = (np.array(data.tables[t]) for t in ("WcMap", "PRmap", "effMap"))
    n0, n1 = float(nc0[0]), float(nc0[1])
    h0, h1 = P[0] ** k - 1.0, P[1] ** k - 1.0
    a = similarity_exponent(W[0], W[1], n0, n1, "flow")
    b = similarity_exponent(h0, h1, n0, n1, "work")
    c = similarity_exponent(E[0], E[1], n0, n1, "eff")
    r = (new / n0)[:, None]
    W_new = W[0] * r ** a
    P_new = (1.0 + h0 * r ** b) ** (1.0 / k)
    E_new = E[0] * r ** c
    tables = {"WcMap": np.vstack([W_new, W]), "PRmap": np.vstack([P_new, P]), "effMap": np.vstack([E_new, E])}
    for key, orig in (("WcMap", W), ("PRmap", P), ("effMap", E)):
        tables[key][new.size:] = orig                               # original nodes exactly as stored
    return dataclasses.replace(
        data, speed_values=tuple(float(v) * data.speed_design for v in new) + data.speed_values,
        tables=MappingProxyType({key: tuple(tuple(float(v) for v in row) for row in t) for key, t in tables.items()}))


def extend_map_data(data: MapData) -> MapData:
    """The map's data extended for sub-idle operation (:func:`extend_turbine_data`,
    :func:`extend_compressor_data`), with the extension of :data:`EXTENSIONS` for its name."""
    return extend_turbine_data(data) if data.kind == "turbine" else extend_compressor_data(data)
