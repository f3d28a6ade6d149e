"""Component performance maps: one loader, compressor and turbine maps, scaling to a design point.

The maps are data files in ``maps/`` (JSON, one per map; ``maps/README.md``
states their origin, licence, units and meaning). :func:`load_map_data` is the
one function that reads them; :func:`.map_loading.load_map` builds the interpolating map.

Compressor maps (:class:`CompressorMap`) give corrected flow, pressure ratio
and isentropic efficiency over relative corrected speed ``nc_rel`` (1.0 at the
map's own design speed) and an auxiliary coordinate ``beta``. The source
files use R-lines (NPSS convention, R-line 1.0 on the surge line, growing
toward choke); here ``beta = (Rline - Rline_surge) / (Rline_max - Rline_surge)``,
so ``beta = 0`` is the surge line and ``beta = 1`` the source's last R-line
(the choke side of the map). Turbine maps (:class:`TurbineMap`) keep the
source's form: corrected flow and efficiency over relative corrected speed and
pressure ratio (inlet over exit total pressure).

Corrected flow is ``W sqrt(Tt/T_REF_K) / (Pt/P_REF_PA)`` [kg/s] for both; the
turbine files give ``W sqrt(Tt)/Pt`` in lbm sqrt(degR)/(s psia), converted here
with the exact unit factors (see :data:`WP_TO_WC`).

Interpolation is C1 (piecewise bicubic Hermite, :mod:`.map_interp`), with
partial derivatives on request; outside the map it continues linearly for a
margin (default 10 % of each axis span) and raises
:class:`~.errors.OutOfRangeError` beyond it.

Scaling to a cycle's design point follows pyCycle (``MapScalars``,
``ScaledMapValues`` in ``pycycle/elements/compressor_map.py``)::

    s_Nc  = Nc_design / nc_rel_map             Nc  = s_Nc  * nc_rel
    s_Wc  = Wc_design / Wc_map(design point)   Wc  = s_Wc  * Wc_map
    s_PR  = (PR_design - 1) / (PR_map - 1)     PR  = s_PR  * (PR_map - 1) + 1
    s_eff = eff_design / eff_map               eff = s_eff * eff_map

For a turbine the pressure ratio is the input, so ``PR_map = (PR - 1)/s_PR + 1``.

References
----------
P. P. Walsh, P. Fletcher, *Gas Turbine Performance*, 2nd ed., Blackwell, 2004,
ch. 5 (component maps, beta lines, scaling, surge margin).
SAE ARP1420, *Gas Turbine Engine Inlet Flow Distortion Guidelines*, SAE International
(surge margin at constant corrected flow).
E. S. Hendricks, J. S. Gray, "pyCycle: A Tool for Efficient Optimization of
Gas Turbine Engine Cycles", Aerospace 6(8), 87, 2019.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Literal

import numpy as np

from ..common.atmosphere import G0_M_S2
from . import jit_kernels as _K
from .errors import ModelError, OutOfRangeError
from .flow import P_STD_PA, T_STD_K
from .map_interp import BicubicTable
from .map_points import CompressorPoint, CompressorPointD, TurbinePoint, TurbinePointD

__all__ = [
    "MAP_DIR", "T_REF_K", "P_REF_PA", "LBM_TO_KG", "WP_TO_WC", "DEFAULT_EXTRAPOLATION",
    "MapSource", "MapData", "CompressorPoint", "CompressorPointD", "TurbinePoint", "TurbinePointD",
    "CompressorMap", "TurbineMap",
    "load_map_data",
]

#: Folder of the map data files.
MAP_DIR: Path = Path(__file__).resolve().parent / "maps"
#: Reference state of corrected flow and speed [K], [Pa] (ISA sea level; NPSS uses 518.67 degR, 14.696 psia).
T_REF_K: float = T_STD_K
P_REF_PA: float = P_STD_PA
#: Exact unit factors: pound-mass [kg], pound-force per square inch [Pa], degree Rankine per kelvin.
LBM_TO_KG: float = 0.45359237
PSI_TO_PA: float = LBM_TO_KG * G0_M_S2 / 0.0254**2  # the pound-force is a pound-mass at standard gravity
RANKINE_PER_K: float = 1.8
#: Factor from W*sqrt(Tt)/Pt in lbm sqrt(degR)/(s psia) to corrected flow [kg/s] at T_REF_K, P_REF_PA.
WP_TO_WC: float = LBM_TO_KG * (P_REF_PA / PSI_TO_PA) / math.sqrt(T_REF_K * RANKINE_PER_K)
#: Default extrapolation margin, as a fraction of each axis span.
DEFAULT_EXTRAPOLATION: float = 0.1


@dataclass(frozen=True, slots=True)
class MapSource:
    """Where a map's numbers come from (see ``maps/README.md``)."""

    repository: str
    commit: str
    path: str
    verbatim_copy: str
    licence: str
    upstream: str


@dataclass(frozen=True, slots=True)
class MapData:
    """A map exactly as stored in its data file (source units, source axis values).

    Attributes
    ----------
    name, kind, component : str
        Map name (file stem), ``"compressor"`` or ``"turbine"``, and the
        component of this project it is meant for.
    source : MapSource
        Origin and licence.
    speed_name, speed_values, speed_design :
        Speed axis as in the source (``NcMap`` [-] or ``NpMap`` [rpm/sqrt(degR),
        arbitrary scale]) and the map's design speed on it.
    line_name, line_values, line_design :
        Second axis (``RlineMap`` [-] or ``PRmap`` [-]) and the map's design value.
    line_surge : float or None
        R-line of the surge (stall) line, compressors only.
    tables : mapping of str to tuple of tuple of float
        Output tables, ``tables[name][i][j]`` at ``(speed_values[i], line_values[j])``.
    units : mapping of str to str
        Units of the axes and tables as stored.
    file : Path
        The file read.
    """

    name: str
    kind: Literal["compressor", "turbine"]
    component: str
    source: MapSource
    speed_name: str
    speed_values: tuple[float, ...]
    speed_design: float
    line_name: str
    line_values: tuple[float, ...]
    line_design: float
    line_surge: float | None
    tables: Mapping[str, tuple[tuple[float, ...], ...]]
    units: Mapping[str, str]
    file: Path


_TABLES = {"compressor": ("WcMap", "PRmap", "effMap"), "turbine": ("WpMap", "effMap")}


def _map_file(name_or_path: str | Path) -> Path:
    p = Path(name_or_path)
    if p.suffix == ".json" or p.is_absolute() or len(p.parts) > 1:
        return p
    return MAP_DIR / f"{name_or_path}.json"


def load_map_data(name_or_path: str | Path) -> MapData:
    """Read one map data file: the one loader of map data.

    Parameters
    ----------
    name_or_path : str or Path
        A map name in :data:`MAP_DIR` (``"axi5"``, ``"lpc_hbtf"``,
        ``"hpt1269"``, ``"lpt2269"``) or the path of a JSON file of the same layout.

    Raises
    ------
    ModelError
        If the file is missing or malformed (names the file and the problem).
    """
    path = _map_file(name_or_path)
    try:
        raw: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError as exc:
        known = ", ".join(sorted(p.stem for p in MAP_DIR.glob("*.json")))
        raise ModelError(f"map file {path} not found (maps in {MAP_DIR}: {known})") from exc
    except json.JSONDecodeError as exc:
        raise ModelError(f"map file {path}:{exc.lineno}: invalid JSON: {exc.msg}") from exc
    try:
        kind = raw["kind"]
        if kind not in _TABLES:
            raise ModelError(f"map file {path}: kind must be 'compressor' or 'turbine', got {kind!r}")
        speed, line = raw["speed"], raw["line"]
        sv = tuple(float(v) for v in speed["values"])
        lv = tuple(float(v) for v in line["values"])
        tables = {}
        for key in _TABLES[kind]:
            rows = tuple(tuple(float(v) for v in row) for row in raw["tables"][key])
            if len(rows) != len(sv) or any(len(r) != len(lv) for r in rows):
                raise ModelError(f"map file {path}: table {key} is not {len(sv)} x {len(lv)} "
                                 f"({speed['name']} x {line['name']})")
            tables[key] = rows
        return MapData(
            name=str(raw["name"]), kind=kind, component=str(raw.get("component", "")),
            source=MapSource(**raw["source"]),
            speed_name=str(speed["name"]), speed_values=sv, speed_design=float(speed["design"]),
            line_name=str(line["name"]), line_values=lv, line_design=float(line["design"]),
            line_surge=float(line["surge"]) if "surge" in line else None,
            tables=MappingProxyType(tables), units=MappingProxyType(dict(raw["units"])), file=path)
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelError(f"map file {path}: missing or malformed entry: {exc!r}") from exc


def _margins(x: tuple[float, ...], y: tuple[float, ...], extrapolation: float) -> tuple[float, float]:
    if not extrapolation >= 0.0:
        raise ModelError(f"extrapolation margin must be >= 0 (a fraction of the axis span), got {extrapolation}")
    return extrapolation * (x[-1] - x[0]), extrapolation * (y[-1] - y[0])


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class CompressorMap:
    """Compressor map over relative corrected speed and beta (0 on the surge line).

    Parameters
    ----------
    data : MapData
        A compressor map from :func:`load_map_data`.
    extrapolation : float
        Linear extrapolation margin as a fraction of each axis span [-].

    Attributes
    ----------
    name : str
    data : MapData
    nc_rel : tuple of float
        Speed lines, ``NcMap / NcMap_design`` [-].
    beta : tuple of float
        Beta lines [-], 0 (surge) to 1.
    nc_rel_design, beta_design : float
        The map's own design point (from the data file), where scaling is done by default.

    Notes
    -----
    Immutable (frozen dataclass); the interpolation table ``_table`` is built
    once and shared by the scaled maps of :mod:`.map_scaled`.
    """

    data: MapData
    extrapolation: float = DEFAULT_EXTRAPOLATION
    name: str = field(init=False)
    nc_rel: tuple[float, ...] = field(init=False)
    beta: tuple[float, ...] = field(init=False)
    nc_rel_design: float = field(init=False)
    beta_design: float = field(init=False)
    _table: BicubicTable = field(init=False)
    _surge_x: tuple[float, ...] = field(init=False)
    _surge_w: tuple[float, ...] = field(init=False)

    def __post_init__(self) -> None:
        data = self.data
        if data.kind != "compressor":
            raise ModelError(f"map {data.name!r} is a {data.kind} map, not a compressor map")
        r = data.line_values
        if data.line_surge is None or data.line_surge != r[0]:
            raise ModelError(f"compressor map {data.name!r}: the surge R-line ({data.line_surge}) "
                             f"must be the first R-line ({r[0]})")
        nc_rel = tuple(v / data.speed_design for v in data.speed_values)
        beta = tuple((v - r[0]) / (r[-1] - r[0]) for v in r)
        wc = [[v * LBM_TO_KG for v in row] for row in data.tables["WcMap"]]
        mx, my = _margins(nc_rel, beta, self.extrapolation)
        table = BicubicTable(nc_rel, beta, [wc, data.tables["PRmap"], data.tables["effMap"]],
                             mx, my, ("nc_rel", "beta"), f"compressor map {data.name!r}",
                             monotone=(True, True, False))
        surge_x = (table.x_min, *nc_rel, table.x_max)
        surge_w = tuple(table.values(x, 0.0)[0] for x in surge_x)
        if any(b <= a for a, b in zip(surge_w[:-1], surge_w[1:], strict=True)):
            raise ModelError(f"compressor map {data.name!r}: corrected flow on the surge line must rise with speed")
        for key, value in (("name", data.name), ("nc_rel", nc_rel), ("beta", beta), ("nc_rel_design", 1.0),
                           ("beta_design", (data.line_design - r[0]) / (r[-1] - r[0])), ("_table", table),
                           ("_surge_x", surge_x), ("_surge_w", surge_w)):
            object.__setattr__(self, key, value)

    def kernel_arrays(self) -> tuple[np.ndarray, ...]:
        """The table's arrays (:meth:`.map_interp.BicubicTable.kernel_arrays`), then the surge line's nodes:
        relative speeds and corrected flows (what :func:`.jit_kernels.surge_margin` reads)."""
        return (*self._table.kernel_arrays(), np.array(self._surge_x), np.array(self._surge_w))

    def beta_of_rline(self, rline: float) -> float:
        """Beta [-] of a source R-line value [-]."""
        r = self.data.line_values
        return (rline - r[0]) / (r[-1] - r[0])

    def rline_of_beta(self, beta: float) -> float:
        """Source R-line value [-] of a beta [-]."""
        r = self.data.line_values
        return r[0] + beta * (r[-1] - r[0])

    @property
    def nc_rel_range(self) -> tuple[float, float]:
        """Range of relative speed accepted (map plus extrapolation margin) [-]."""
        return self._table.x_min, self._table.x_max

    @property
    def beta_range(self) -> tuple[float, float]:
        """Range of beta accepted (map plus extrapolation margin) [-]."""
        return self._table.y_min, self._table.y_max

    def evaluate(self, nc_rel: float, beta: float) -> CompressorPoint:
        """Corrected flow [kg/s], pressure ratio [-] and efficiency [-] at (nc_rel [-], beta [-]).

        Raises
        ------
        OutOfRangeError
            Beyond the extrapolation margin; the message names the value and the range.
        """
        return CompressorPoint(*self._table.values(nc_rel, beta))

    def evaluate_with_derivatives(self, nc_rel: float, beta: float) -> CompressorPointD:
        """As :meth:`evaluate`, plus the partial derivatives with respect to nc_rel and beta."""
        (w, p, e), (w_n, p_n, e_n), (w_b, p_b, e_b) = self._table.values_and_gradients(nc_rel, beta)
        return CompressorPointD(w, p, e, w_n, w_b, p_n, p_b, e_n, e_b)

    def surge_pr(self, nc_rel: float) -> float:
        """Pressure ratio [-] on the surge line (beta = 0) at relative speed nc_rel [-]."""
        return self._table.values(nc_rel, 0.0)[1]

    def surge_point(self, nc_rel: float) -> CompressorPoint:
        """Map point on the surge line at relative speed nc_rel [-]."""
        return self.evaluate(nc_rel, 0.0)

    def surge_nc_rel_at_flow(self, Wc_kg_s: float) -> float:
        """Relative speed [-] at which the surge line passes through corrected flow Wc_kg_s [kg/s].

        Newton iteration on the surge line, safeguarded by bisection and
        started by linear interpolation between the speed lines; the surge
        flow must rise with speed (checked when the map is built).

        Raises
        ------
        OutOfRangeError
            If the flow is not reached on the surge line within the speed range
            (map plus extrapolation margin).
        """
        xs, ws = self._surge_x, self._surge_w
        if not ws[0] <= Wc_kg_s <= ws[-1]:
            raise OutOfRangeError(
                f"compressor map {self.name!r}: corrected flow {Wc_kg_s!r} kg/s is not on the surge line "
                f"between nc_rel = {xs[0]:g} and {xs[-1]:g} (surge flow {ws[0]:g} to {ws[-1]:g} kg/s)")
        return float(_K.surge_speed_at_flow(*self.kernel_arrays(), float(Wc_kg_s)))

    def surge_margin(self, nc_rel: float, beta: float, basis: Literal["flow", "speed"] = "flow",
                     s_PR: float = 1.0) -> float:
        """Surge margin [-] of the point (nc_rel, beta); positive away from surge, 0 on the surge line.

        Parameters
        ----------
        nc_rel, beta : float
            Operating point [-].
        basis : {"flow", "speed"}
            ``"flow"`` (default): at constant corrected flow,
            ``SM = PR_surge(Wc) / PR - 1`` with ``PR_surge(Wc)`` the surge-line
            pressure ratio at the operating point's corrected flow (Walsh &
            Fletcher 2004, ch. 5; SAE ARP1420). ``"speed"``: at constant
            corrected speed, ``SM = (PR_surge / PR) (Wc / Wc_surge) - 1``
            (pyCycle's ``SMN``).
        s_PR : float
            PR scalar of a scaled map (1.0 for the map itself); PR is scaled
            as ``(PR - 1) s_PR + 1`` before the ratio is formed. Flow scaling
            cancels.
        """
        w, p, _e = self._table.values(nc_rel, beta)          # raises with the map's message out of range
        pr = (p - 1.0) * s_PR + 1.0
        if basis == "flow":                                 # the one implementation, also the gas path's
            sm = float(_K.surge_margin(*self.kernel_arrays(), float(nc_rel), float(beta), float(s_PR)))
            if sm != sm:                                    # no surge line at this flow: raise with its message
                self.surge_nc_rel_at_flow(w)
            return sm
        if basis == "speed":
            w_s, p_s, _ = self._table.values(nc_rel, 0.0)
            return ((p_s - 1.0) * s_PR + 1.0) / pr * (w / w_s) - 1.0
        raise ModelError(f"surge margin basis must be 'flow' or 'speed', got {basis!r}")

    def __repr__(self) -> str:
        return f"CompressorMap({self.name!r}, nc_rel {self.nc_rel[0]:g}..{self.nc_rel[-1]:g}, beta 0..1)"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class TurbineMap:
    """Turbine map: corrected flow and efficiency over relative corrected speed and pressure ratio.

    Parameters
    ----------
    data : MapData
        A turbine map from :func:`load_map_data`.
    extrapolation : float
        Linear extrapolation margin as a fraction of each axis span [-].

    Attributes
    ----------
    nc_rel : tuple of float
        Speed lines, ``NpMap / NpMap_design`` [-].
    pr : tuple of float
        Pressure ratios of the table [-].
    nc_rel_design, pr_design : float
        The map's own design point (from the data file).
    """

    data: MapData
    extrapolation: float = DEFAULT_EXTRAPOLATION
    name: str = field(init=False)
    nc_rel: tuple[float, ...] = field(init=False)
    pr: tuple[float, ...] = field(init=False)
    nc_rel_design: float = field(init=False)
    pr_design: float = field(init=False)
    _table: BicubicTable = field(init=False)

    def __post_init__(self) -> None:
        data = self.data
        if data.kind != "turbine":
            raise ModelError(f"map {data.name!r} is a {data.kind} map, not a turbine map")
        nc_rel = tuple(v / data.speed_design for v in data.speed_values)
        wc = [[v * WP_TO_WC for v in row] for row in data.tables["WpMap"]]
        mx, my = _margins(nc_rel, data.line_values, self.extrapolation)
        table = BicubicTable(nc_rel, data.line_values, [wc, data.tables["effMap"]], mx, my,
                             ("nc_rel", "pr"), f"turbine map {data.name!r}", monotone=(True, False))
        for key, value in (("name", data.name), ("nc_rel", nc_rel), ("pr", data.line_values), ("nc_rel_design", 1.0),
                           ("pr_design", data.line_design), ("_table", table)):
            object.__setattr__(self, key, value)

    def kernel_arrays(self) -> tuple[np.ndarray, ...]:
        """The table's arrays (:meth:`.map_interp.BicubicTable.kernel_arrays`) and two empty surge nodes."""
        return (*self._table.kernel_arrays(), np.full(2, np.nan), np.full(2, np.nan))

    @property
    def nc_rel_range(self) -> tuple[float, float]:
        """Range of relative speed accepted (map plus extrapolation margin) [-]."""
        return self._table.x_min, self._table.x_max

    @property
    def pr_range(self) -> tuple[float, float]:
        """Range of pressure ratio accepted (map plus extrapolation margin) [-]."""
        return self._table.y_min, self._table.y_max

    def evaluate(self, nc_rel: float, pr: float) -> TurbinePoint:
        """Corrected flow [kg/s] and efficiency [-] at (nc_rel [-], pressure ratio pr [-]).

        Raises
        ------
        OutOfRangeError
            Beyond the extrapolation margin; the message names the value and the range.
        """
        return TurbinePoint(*self._table.values(nc_rel, pr))

    def evaluate_with_derivatives(self, nc_rel: float, pr: float) -> TurbinePointD:
        """As :meth:`evaluate`, plus the partial derivatives with respect to nc_rel and pr."""
        (w, e), (w_n, e_n), (w_p, e_p) = self._table.values_and_gradients(nc_rel, pr)
        return TurbinePointD(w, e, w_n, w_p, e_n, e_p)

    def __repr__(self) -> str:
        return (f"TurbineMap({self.name!r}, nc_rel {self.nc_rel[0]:g}..{self.nc_rel[-1]:g}, "
                f"PR {self.pr[0]:g}..{self.pr[-1]:g})")
