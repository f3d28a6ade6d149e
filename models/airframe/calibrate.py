"""Calibration of UPERA's geometric aerodynamics on a user's CFD or wind-tunnel points.

:func:`load_points` reads a CSV of points (altitude, Mach, angle of attack, lift, drag) and checks
each value where it enters; :func:`fit` finds the bounded correction factors of
:mod:`.corrections` that bring the model's lift and drag coefficients closest to the points
(relative residuals, least squares, :func:`scipy.optimize.least_squares` with bounds); the
:class:`Calibration` it returns holds the per-point comparison before and after.

The data format (``models/airframe/data/upera_cfd.csv`` is an example)::

    # free text: the data's source (kept with the factors and in the aircraft file)
    alt_m,mach,alpha_deg,lift_kN,drag_kN[,p_kPa][,point]
    7500,0.75,0.70,23.74,2.09

Forces may be given as ``lift_N``/``drag_N``, ``lift_kN``/``drag_kN`` or as coefficients
``CL``/``CD`` on the model's reference area (11.2 m^2); a column such as ``lift_cfd_kN`` is read
as a lift in kN (name the columns with ``lift_column``/``drag_column`` when there are several).
A pressure column (``p_Pa`` or ``p_kPa``) replaces the ISA pressure of the altitude in the
dynamic pressure; the Reynolds number is the ISA one of the altitude and Mach number.
"""
from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from .aero import AeroModel, aero_model, build_aero_model, isa
from .corrections import FACTOR_BOUNDS, AeroCorrections
from .errors import CalibrationError
from .geometry import load_geometry

__all__ = ["CalibrationPoint", "PointResult", "Calibration", "read_points", "load_points", "fit", "model_coefficients",
           "ENVELOPE"]

#: Where the model may be compared with data: altitude [m], Mach number [-] (the JSBSim tables and
#: the trim are valid there), angle of attack [deg] (the attached-flow range of the lift table).
ENVELOPE = {"alt_m": (-500.0, 12000.0), "mach": (0.05, 0.90), "alpha_deg": (-10.0, 15.0)}
LIFT_FACTORS = ("cla_factor", "alpha0_shift_deg")
DRAG_FACTORS = ("cd0_factor", "k_factor")
_FORCE = re.compile(r"^(lift|drag)(?:_[A-Za-z0-9]+)*?_(N|kN)$")


@dataclass(frozen=True)
class CalibrationPoint:
    """One measured point: condition, dynamic pressure [Pa], Reynolds number on the reference chord [-], and
    the lift and drag coefficients on the reference area [-] (``None`` where the file gives none)."""

    label: str
    line: int
    alt_m: float
    mach: float
    alpha_rad: float
    qbar_Pa: float
    re_mac: float
    cl: float | None
    cd: float | None
    cl_reference: float | None = None
    cd_reference: float | None = None


@dataclass(frozen=True)
class PointResult:
    """Model against data at one point, before and after the calibration."""

    point: CalibrationPoint
    cl_before: float
    cd_before: float
    cl_after: float
    cd_after: float

    def errors(self) -> dict[str, float]:
        """Relative errors of the model [-]: ``cl_before``, ``cd_before``, ``cl_after``, ``cd_after``."""
        cl, cd = float(self.point.cl or math.nan), float(self.point.cd or math.nan)
        return {"cl_before": self.cl_before / cl - 1, "cd_before": self.cd_before / cd - 1,
                "cl_after": self.cl_after / cl - 1, "cd_after": self.cd_after / cd - 1}


@dataclass(frozen=True)
class Calibration:
    """The fitted factors and the per-point comparison."""

    corrections: AeroCorrections
    results: tuple[PointResult, ...]

    def worst(self) -> dict[str, float]:
        """Largest absolute relative error over the points, per column of :meth:`PointResult.errors`."""
        errs = [r.errors() for r in self.results]
        return {k: max(abs(e[k]) for e in errs) for k in errs[0]}


def _fail(path: Path, line: int | None, msg: str) -> CalibrationError:
    where = f"{path}:{line}" if line else f"{path}"
    return CalibrationError(f"{where}: {msg}")


def _pick(path: Path, header: list[str], quantity: str, given: str | None) -> str:
    """The column holding lift or drag: the given name, or the only candidate (CFD preferred)."""
    coef = "CL" if quantity == "lift" else "CD"
    if given is not None:
        if given not in header:
            raise _fail(path, None, f"no column {given!r}; columns: {', '.join(header)}")
        return given
    cands = [h for h in header if h == coef or ((m := _FORCE.match(h)) and m.group(1) == quantity)]
    if len(cands) > 1:
        cfd = [h for h in cands if "cfd" in h.lower()]
        cands = cfd if len(cfd) == 1 else cands
    if len(cands) != 1:
        what = "none" if not cands else ", ".join(cands)
        raise _fail(path, None, f"needs exactly one {quantity} column ({coef}, {quantity}_N, {quantity}_kN or "
                                f"{quantity}_<name>_kN), found {what}; name it with --{quantity}-column")
    return cands[0]


def _to_coefficient(col: str, value: float, qs_N: float) -> float:
    if col in ("CL", "CD"):
        return value
    return value * (1000.0 if col.endswith("_kN") else 1.0) / qs_N


def read_points(path: Path | str, s_ref_m2: float, mac_m: float, lift_column: str | None = None, drag_column: str | None = None,
                reference_columns: tuple[str, str] | None = None,
                require_forces: bool = True) -> tuple[tuple[CalibrationPoint, ...], str]:
    """Read and check a points file; return the points and the source text (its ``#`` lines).

    The one reader of points files (``emss airframe calibrate`` and ``emss airframe compare``).
    Coefficients are referred to ``s_ref_m2`` [m^2], Reynolds numbers to the chord ``mac_m`` [m]. Without ``require_forces`` the lift and drag
    columns may be absent (the points' ``cl`` and ``cd`` are then ``None``). ``reference_columns``
    (lift, drag) names another code's values in the same file (for example the reference flight
    simulator's), carried along for comparison and not fitted.

    Raises
    ------
    CalibrationError
        One line naming the file and every problem with its line and column: a missing file or
        column, a value that is not a finite number, a condition outside :data:`ENVELOPE`, a
        non-positive lift or drag.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise _fail(path, None, f"cannot read the points file ({getattr(exc, 'strerror', None) or exc})") from None
    source, rows = [], []
    for n, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if s.startswith("#"):
            source.append(s.lstrip("#").strip())
        elif s:
            rows.append((n, raw))
    if not rows:
        raise _fail(path, None, "no header and no data rows")
    header_line, header_text = rows[0]
    header = [h.strip() for h in next(csv.reader([header_text]))]
    if len(set(header)) != len(header):
        dup = sorted({h for h in header if header.count(h) > 1})
        raise _fail(path, header_line, f"duplicate column(s) {', '.join(dup)}")
    missing = [c for c in ("alt_m", "mach", "alpha_deg") if c not in header]
    if missing:
        raise _fail(path, header_line, f"missing column(s) {', '.join(missing)}; required: alt_m, "
                                        "mach, alpha_deg" + (", a lift and a drag column" if require_forces else ""))
    has_forces = require_forces or any(h in ("CL", "CD") or _FORCE.match(h) for h in header)
    lcol = _pick(path, header, "lift", lift_column) if has_forces else None
    dcol = _pick(path, header, "drag", drag_column) if has_forces else None
    pcol = next((h for h in ("p_Pa", "p_kPa") if h in header), None)
    refs = tuple(reference_columns or ())
    for col in refs:
        if col not in header or not (_FORCE.match(col) or col in ("CL", "CD")):
            raise _fail(path, header_line, f"reference column {col!r} is not a lift or drag column of the file "
                                           f"(columns: {', '.join(header)})")
    points: list[CalibrationPoint] = []
    problems: list[str] = []
    for n, raw in rows[1:]:
        cells = [c.strip() for c in next(csv.reader([raw]))]
        if len(cells) != len(header):
            problems.append(f"line {n}: {len(cells)} values for {len(header)} columns")
            continue
        rec = dict(zip(header, cells, strict=True))
        val: dict[str, float] = {}
        bad = []
        for col in ("alt_m", "mach", "alpha_deg", *(c for c in (lcol, dcol, pcol) if c), *refs):
            try:
                v = float(rec[col])
            except ValueError:
                bad.append(f"line {n}: column {col}: {rec[col]!r} is not a number")
                continue
            if not math.isfinite(v):
                bad.append(f"line {n}: column {col}: {rec[col]!r} is not a finite number")
            val[col] = v
        bad += [f"line {n}: column {col} = {val[col]:g} is outside the model's envelope [{lo:g}, {hi:g}]"
                for col, (lo, hi) in ENVELOPE.items() if col in val and math.isfinite(val[col])
                and not lo <= val[col] <= hi]
        if bad:
            problems += bad
            continue
        _, p_isa, rho, a_snd, mu = isa(val["alt_m"])
        p = p_isa if pcol is None else val[pcol] * (1000.0 if pcol == "p_kPa" else 1.0)
        if not 0.2 * p_isa <= p <= 5.0 * p_isa:
            problems.append(f"line {n}: column {pcol} = {val[pcol]:g} is not a pressure near the ISA "
                            f"{p_isa:.0f} Pa of {val['alt_m']:g} m")
            continue
        qs = 0.7 * p * val["mach"] ** 2 * s_ref_m2
        cl = _to_coefficient(lcol, val[lcol], qs) if lcol else None
        cd = _to_coefficient(dcol, val[dcol], qs) if dcol else None
        if (cl is not None and cl <= 0.0) or (cd is not None and cd <= 0.0):
            problems.append(f"line {n}: lift and drag must be positive (relative errors are compared); got CL "
                            f"{cl:.4g}, CD {cd:.4g}")
            continue
        ref = [_to_coefficient(c, val[c], qs) for c in refs] or [None, None]
        points.append(CalibrationPoint(rec.get("point") or str(len(points) + 1), n, val["alt_m"], val["mach"],
                                       math.radians(val["alpha_deg"]), qs / s_ref_m2,
                                       rho * val["mach"] * a_snd * mac_m / mu,
                                       cl, cd, *ref))
    if problems:
        more = f" ({len(problems)} problems)" if len(problems) > 1 else ""
        raise _fail(path, None, "; ".join(problems) + more)
    if not points:
        raise _fail(path, header_line, "no data rows under the header")
    src = " ".join(source) if source else "no source given in the file"
    return tuple(points), f"{path.name}: {src}"


def load_points(path: Path | str, model: AeroModel | None = None, lift_column: str | None = None,
                drag_column: str | None = None,
                reference_columns: tuple[str, str] | None = None) -> tuple[tuple[CalibrationPoint, ...], str]:
    """Points to calibrate ``model`` (default: the shipped one) on: :func:`read_points` with lift and
    drag required, and each point in the model's linear lift range (where the factors are defined).

    Raises
    ------
    CalibrationError
        As :func:`read_points`, and for points beyond the linear lift range (CL_linear above 0.8 CL_max).
    """
    model = model or aero_model()
    pts, src = read_points(path, model.geom.wing.area_m2, model.geom.wing.mac_m, lift_column, drag_column,
                           reference_columns)
    problems = []
    for p in pts:
        cl_lin = abs(float(model.cl_linear(p.alpha_rad, p.mach)))
        if cl_lin > 0.8 * model.clmax_clean:
            problems.append(f"line {p.line}: alpha_deg = {math.degrees(p.alpha_rad):g} is beyond the model's linear "
                            f"lift range at Mach {p.mach:g} (CL {cl_lin:.2f} above 0.8 CL_max = "
                            f"{0.8 * model.clmax_clean:.2f}), where the factors are not defined")
    if problems:
        more = f" ({len(problems)} problems)" if len(problems) > 1 else ""
        raise _fail(Path(path), None, "; ".join(problems) + more)
    return pts, src


def model_coefficients(model: AeroModel, p: CalibrationPoint) -> tuple[float, float]:
    """Lift and drag coefficients of the model at the point's condition, controls neutral, clean [-]."""
    return float(model.cl_basic(p.alpha_rad, p.mach)), model.drag_coefficient(p.alpha_rad, p.mach, p.re_mac)


def _with(base: AeroCorrections, names: tuple[str, ...], x: np.ndarray) -> AeroCorrections:
    return replace(base, **{n: float(v) for n, v in zip(names, x, strict=True)})


def fit(points: tuple[CalibrationPoint, ...], factors: tuple[str, ...] = (*LIFT_FACTORS, *DRAG_FACTORS),
        source: str = "", geometry: str | None = None) -> Calibration:
    """Fit ``factors`` (names of :data:`~.corrections.FACTOR_BOUNDS`) to ``points``.

    The residuals are the relative errors of CL and of CD at every point; the factors start neutral.

    Raises
    ------
    CalibrationError
        An unknown factor; fewer points than the lift factors (or than the drag factors) to fit;
        points that leave a factor undetermined (for example every point at one lift coefficient
        for ``cd0_factor`` and ``k_factor``); a fit that ends on a bound of a factor.
    """
    unknown = [f for f in factors if f not in FACTOR_BOUNDS]
    if unknown or not factors:
        raise CalibrationError(f"unknown or no factor(s) {unknown}; choose from {', '.join(FACTOR_BOUNDS)}")
    names = tuple(dict.fromkeys(factors))
    if any(p.cl is None or p.cd is None for p in points):
        raise CalibrationError("every point to fit needs a lift and a drag (read them with load_points)")
    for group in (LIFT_FACTORS, DRAG_FACTORS):
        k = sum(f in names for f in group)
        if len(points) < k:
            raise CalibrationError(f"{len(points)} point(s) cannot determine {k} factors "
                                   f"({', '.join(f for f in group if f in names)}): give at least {k} points")
    neutral = AeroCorrections()
    geom = load_geometry(geometry)
    before = [model_coefficients(build_aero_model(geom, neutral), p) for p in points]
    cl_d = np.array([p.cl for p in points])
    cd_d = np.array([p.cd for p in points])

    def residuals(x: np.ndarray) -> np.ndarray:
        m = build_aero_model(geom, _with(neutral, names, x))
        c = np.array([model_coefficients(m, p) for p in points])
        return np.concatenate([c[:, 0] / cl_d - 1.0, c[:, 1] / cd_d - 1.0])

    lo = np.array([FACTOR_BOUNDS[n][0] for n in names])
    hi = np.array([FACTOR_BOUNDS[n][1] for n in names])
    x0 = np.array([getattr(neutral, n) for n in names], dtype=float)
    sol = least_squares(residuals, x0, bounds=(lo, hi), x_scale=np.where(np.array(names) == "alpha0_shift_deg",
                                                                          1.0, 0.1), diff_step=1e-6)
    jac = sol.jac
    sv = np.linalg.svd(jac, compute_uv=False)
    if sv[-1] < 1e-6 * sv[0]:
        raise CalibrationError(f"the {len(points)} point(s) do not determine the factors {', '.join(names)} "
                               "independently (e.g. all points at one lift coefficient or one angle of attack): "
                               "add points that differ, or fit fewer factors (--factors)")
    span = hi - lo
    at_bound = [n for n, v, a, b, s in zip(names, sol.x, lo, hi, span, strict=True)
                if min(v - a, b - v) < 1e-3 * s]
    if at_bound:
        vals = ", ".join(f"{n} = {sol.x[names.index(n)]:.4g} (bounds {FACTOR_BOUNDS[n][0]:g} to "
                         f"{FACTOR_BOUNDS[n][1]:g})" for n in at_bound)
        raise CalibrationError(f"the fit ends on a bound: {vals}; the data and the geometric model disagree more "
                               "than these factors can explain (check the data's units and conditions)")
    corr = _with(AeroCorrections(source=source or "unnamed data", fitted=names), names, sol.x)
    after_model = build_aero_model(geom, corr)
    results = tuple(PointResult(p, b[0], b[1], *model_coefficients(after_model, p))
                    for p, b in zip(points, before, strict=True))
    return Calibration(corr, results)


def jsbsim_coefficients(p: CalibrationPoint, airframe: object | None = None) -> tuple[float, float]:
    """Lift and drag coefficients that JSBSim computes from the shipped aircraft file at the point's
    condition (wings level, no rates, controls neutral, clean, gear up, far from the ground) [-].

    This reads the forces of the file as flown (JSBSim's own table look-up and functions), not the
    Python model the file was written from.
    """
    from .adapter import Airframe

    af = airframe if isinstance(airframe, Airframe) else Airframe()
    _, _, _, a_snd, _ = isa(p.alt_m)
    af.start_air(p.alt_m, p.mach * a_snd, 0.0, alpha_rad=p.alpha_rad, elevator=0.0, gear_down=False)
    forces = af.aero_forces()
    return forces.CL, forces.CD
