"""UPERA's handbook aerodynamics side by side with AeroSandbox's two methods and with CFD.

``emss airframe compare`` runs this module. It evaluates, at the points of a CSV file
(by default the CFD points in ``data/upera_cfd.csv``) and over alpha sweeps:

* ours: :func:`.aero.geometric_model`'s (the handbook model without calibration) ``cl_basic``, ``drag_coefficient``, ``cd0``,
  ``k_induced`` and ``cm_basic`` (zero elevator and flap, clean);
* AeroBuildup and the vortex lattice of :mod:`.asb_estimate`;
* the CFD, where the file gives it. Its coefficients use the file's static pressure
  ``p_kPa`` where given (q = gamma/2 p M^2), otherwise the ISA.

It also gives the lift-curve slopes of the whole aircraft and of the wing alone
by each method, to show where the methods part.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..infra.files import atomic_write, csv_text, figure_bytes
from .aero import aero_model, geometric_model, isa
from .errors import AirframeError, OutOfEnvelopeError

__all__ = ["PointSpec", "CompareRow", "SlopeRow", "read_points", "compare_point", "sweep", "lift_slopes",
           "points_table", "drag_table", "slopes_table", "write_csv", "plot", "DEFAULT_POINTS",
           "SWEEP_ALPHAS_DEG", "sweep_alphas", "sweep_conditions"]

DEFAULT_POINTS = Path(__file__).resolve().parent / "data" / "upera_cfd.csv"
SWEEP_ALPHAS_DEG = tuple(float(a) for a in np.arange(-2.0, 10.01, 1.0))
MAX_SWEEPS = 3
SLOPE_STEP_RAD = math.radians(0.5)


@dataclass(frozen=True)
class PointSpec:
    """One row of a points file: a condition, the dynamic pressure [Pa] the file's coefficients refer to,
    and, optionally, the CFD's lift and drag coefficients on the wing area [-]."""

    label: str
    alt_m: float
    mach: float
    alpha_rad: float
    qbar_file_Pa: float | None = None
    cl_cfd: float | None = None
    cd_cfd: float | None = None


@dataclass(frozen=True)
class CompareRow:
    """All methods at one condition; coefficients on the wing area S, moments about the design CG.

    ``CDi_ours`` is k CL^2. The rest of ``CD_ours`` beyond ``CD0_ours + CDi_ours`` is wave and
    separation drag. ``CDp_buildup`` is AeroBuildup's profile drag (wave included). The lattice
    gives lift and induced drag only. The CFD fields are NaN where the file gives no CFD.
    """

    kind: str
    label: str
    alt_m: float
    mach: float
    alpha_deg: float
    tas_m_s: float
    qbar_Pa: float
    re_mac: float
    CL_ours: float
    CD_ours: float
    CD0_ours: float
    CDi_ours: float
    Cm_ours: float
    CL_buildup: float
    CD_buildup: float
    CDp_buildup: float
    CDi_buildup: float
    Cm_buildup: float
    CL_htail_buildup: float
    CL_vlm: float
    CDi_vlm: float
    CL_htail_vlm: float
    CL_cfd: float
    CD_cfd: float
    CL_cal: float
    CD_cal: float


@dataclass(frozen=True)
class SlopeRow:
    """Lift-curve slopes [1/rad] at one Mach number: whole aircraft and wing alone (no incidence)."""

    alt_m: float
    mach: float
    cla_ours: float
    cla_buildup: float
    cla_vlm: float
    cla_wing_buildup: float
    cla_wing_vlm: float
    cla_wing_helmbold: float


def _problem_list(path: Path, problems: list[str]) -> AirframeError:
    more = f" ({len(problems)} problems)" if len(problems) > 1 else ""
    return AirframeError(f"{path}: " + "; ".join(problems) + more)


def read_points(path: Path) -> list[PointSpec]:
    """Read a points file with :func:`.calibrate.read_points` (the one reader of points files): columns
    ``alt_m, mach, alpha_deg``, optionally a lift and a drag column (the CFD), ``p_kPa``/``p_Pa`` and
    ``point``; then check each condition against AeroSandbox's range (:func:`.asb_estimate.check_condition`).

    Raises
    ------
    AirframeError
        One line naming every problem with its line number.
    """
    from .asb_estimate import check_condition
    from .calibrate import read_points as read_calibration_points

    g = geometric_model().geom
    pts, _ = read_calibration_points(path, g.wing.area_m2, g.wing.mac_m, require_forces=False)
    problems = []
    for p in pts:
        try:
            check_condition(p.alt_m, p.mach, p.alpha_rad)
        except OutOfEnvelopeError as exc:
            problems.append(f"line {p.line}: {exc}")
    if problems:
        raise _problem_list(path, problems)
    return [PointSpec(p.label, p.alt_m, p.mach, p.alpha_rad, p.qbar_Pa, p.cl, p.cd) for p in pts]


def compare_point(spec: PointSpec, kind: str = "point") -> CompareRow:
    """Every method at the condition of ``spec``."""
    from .asb_estimate import buildup_point, lattice_point

    a = geometric_model()
    cal = aero_model()
    _, _, rho, sound, mu = isa(spec.alt_m)
    tas = spec.mach * sound
    re = rho * tas * a.geom.wing.mac_m / mu
    cl = float(a.cl_basic(spec.alpha_rad, spec.mach))
    cd0 = float(a.cd0(spec.mach, re))
    b = buildup_point(spec.alt_m, spec.mach, spec.alpha_rad)
    v = lattice_point(spec.alt_m, spec.mach, spec.alpha_rad)
    cl_cfd = spec.cl_cfd if spec.cl_cfd is not None else math.nan
    cd_cfd = spec.cd_cfd if spec.cd_cfd is not None else math.nan
    return CompareRow(
        kind=kind, label=spec.label, alt_m=spec.alt_m, mach=spec.mach, alpha_deg=math.degrees(spec.alpha_rad),
        tas_m_s=tas, qbar_Pa=0.5 * rho * tas ** 2, re_mac=re,
        CL_ours=cl, CD_ours=a.drag_coefficient(spec.alpha_rad, spec.mach, re), CD0_ours=cd0,
        CDi_ours=a.k_induced() * cl ** 2, Cm_ours=float(a.cm_basic(spec.alpha_rad, spec.mach)),
        CL_buildup=b.CL, CD_buildup=b.CD, CDp_buildup=b.CD_profile, CDi_buildup=b.CD_induced, Cm_buildup=b.Cm,
        CL_htail_buildup=b.CL_htail, CL_vlm=v.CL, CDi_vlm=v.CDi, CL_htail_vlm=v.CL_htail,
        CL_cfd=cl_cfd, CD_cfd=cd_cfd, CL_cal=float(cal.cl_basic(spec.alpha_rad, spec.mach)),
        CD_cal=cal.drag_coefficient(spec.alpha_rad, spec.mach, re))


def sweep_conditions(points: Sequence[PointSpec]) -> list[tuple[float, float]]:
    """The distinct (altitude [m], Mach) of ``points``, in file order, at most :data:`MAX_SWEEPS`."""
    seen: list[tuple[float, float]] = []
    for p in points:
        if (p.alt_m, p.mach) not in seen:
            seen.append((p.alt_m, p.mach))
    return seen[:MAX_SWEEPS]


def sweep_alphas(start_deg: float, stop_deg: float, step_deg: float) -> tuple[float, ...]:
    """Angles from ``start_deg`` to ``stop_deg`` (inclusive) by ``step_deg`` [deg], checked.

    Raises
    ------
    AirframeError
        If the step is not positive, the range is empty or beyond the valid alphas, or it holds
        more than 200 angles.
    """
    from .asb_estimate import ALPHA_RANGE_DEG

    lo, hi = ALPHA_RANGE_DEG
    vals = (start_deg, stop_deg, step_deg)
    if not all(math.isfinite(v) for v in vals) or step_deg <= 0 or stop_deg < start_deg:
        raise AirframeError(f"--sweep-alpha-deg {start_deg:g} {stop_deg:g} {step_deg:g}: need START <= STOP "
                            "and STEP > 0, all finite")
    if start_deg < lo or stop_deg > hi:
        raise AirframeError(f"--sweep-alpha-deg {start_deg:g} {stop_deg:g}: alpha must lie in {lo:g} to {hi:g} deg")
    n = int(math.floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1
    if n > 200:
        raise AirframeError(f"--sweep-alpha-deg: {n} angles; at most 200")
    return tuple(start_deg + i * step_deg for i in range(n))


def sweep(conditions: Iterable[tuple[float, float]], alphas_deg: Sequence[float] = SWEEP_ALPHAS_DEG,
          tick: Callable[[], None] | None = None) -> list[CompareRow]:
    """:func:`compare_point` over ``alphas_deg`` at each (altitude [m], Mach)."""
    rows = []
    for alt, mach in conditions:
        for al in alphas_deg:
            rows.append(compare_point(PointSpec(f"{alt:g} m M{mach:g}", alt, mach, math.radians(al)), "sweep"))
            if tick is not None:
                tick()
    return rows


def _helmbold(aspect: float, tan_sweep: float, mach: float, eta: float = 0.95) -> float:
    """Helmbold/DATCOM lift-curve slope with Prandtl-Glauert (Raymer eq. 12.6) [1/rad]."""
    b2 = 1.0 - mach ** 2
    return 2 * math.pi * aspect / (2 + math.sqrt(4 + aspect ** 2 * b2 / eta ** 2 * (1 + tan_sweep ** 2 / b2)))


def lift_slopes(alt_m: float, mach: float, alpha_rad: float = math.radians(2.0)) -> SlopeRow:
    """Lift-curve slopes by central differences of +-0.5 deg about ``alpha_rad`` [1/rad]."""
    from .asb_estimate import buildup_point, lattice_point, upera_airplane

    h = SLOPE_STEP_RAD
    wing_ab = upera_airplane(parts=("wing",), incidence=False)
    wing_vlm = upera_airplane(parts=("wing",), incidence=False, x_stretch=1 / math.sqrt(1 - mach ** 2))

    def d(f: Callable[[float], float]) -> float:
        return (f(alpha_rad + h) - f(alpha_rad - h)) / (2 * h)

    a = geometric_model()
    w = a.geom.wing
    return SlopeRow(
        alt_m=alt_m, mach=mach, cla_ours=float(a.cl_alpha(mach)),
        cla_buildup=d(lambda al: buildup_point(alt_m, mach, al).CL),
        cla_vlm=d(lambda al: lattice_point(alt_m, mach, al).CL),
        cla_wing_buildup=d(lambda al: buildup_point(alt_m, mach, al, airplane=wing_ab).CL),
        cla_wing_vlm=d(lambda al: lattice_point(alt_m, mach, al, airplane=wing_vlm).CL),
        cla_wing_helmbold=_helmbold(w.aspect_ratio, w.tan_sweep(w.x_t_c), mach))


Column = tuple[str, str, str | Callable[[Any], float | str]]  # header, format spec, attribute or getter
SEP = "|"


def _cell(value: float | str, spec: str, width: int) -> str:
    if isinstance(value, str):
        return value.rjust(width)
    return (format(value, spec) if math.isfinite(value) else "-").rjust(width)


def _table(rows: Sequence[Any], columns: Sequence[Column | str]) -> str:
    """Fixed-width text table; a column is (header, format spec, attribute name or getter), ``SEP`` a
    separator."""
    head, body = [], [[] for _ in rows]  # type: ignore[var-annotated]
    for c in columns:
        if c == SEP:
            head.append(SEP)
            for cells in body:
                cells.append(SEP)
            continue
        title, spec, get = c  # type: ignore[misc]
        m = re.match(r"[+ -]?(\d+)", spec)
        width = max(len(title), int(m.group(1)) if m else 0)
        head.append(title.rjust(width))
        for cells, r in zip(body, rows, strict=True):
            cells.append(_cell(getattr(r, get) if isinstance(get, str) else get(r), spec, width))
    return "\n".join(" ".join(cells) for cells in [head, *body])


def _pct(x: float, ref: float) -> float:
    """100 (x/ref - 1) [%], NaN without a reference."""
    return 100.0 * (x / ref - 1.0) if math.isfinite(ref) and ref != 0 else math.nan


def _k(cdi: float, cl: float) -> float:
    return cdi / cl ** 2 if cl else math.nan


_SHORT = {"ours": "ours", "buildup": "bu.", "vlm": "VLM", "cal": "cal."}


def _vs_cfd(quantity: str, methods: Sequence[str]) -> list[Column | str]:
    """Columns of the differences of ``quantity`` (``"CL"``, ``"CD"``) by each method from the CFD [%]."""
    return [(f"d{quantity}% {_SHORT[m]}" if i == 0 else _SHORT[m], "+6.1f",
             lambda r, m=m: _pct(getattr(r, f"{quantity}_{m}"), getattr(r, f"{quantity}_cfd")))
            for i, m in enumerate(methods)]


_CONDITION: list[Column | str] = [("pt", "3", "label"), ("alt_m", "6.0f", "alt_m"),
                                  ("mach", "5.2f", "mach"), ("a_deg", "5.2f", "alpha_deg")]


def points_table(rows: Sequence[CompareRow]) -> str:
    """Lift and drag coefficients by each method, and their differences from the CFD [%]."""
    return _table(rows, [*_CONDITION, SEP,
                         ("CL ours", "7.4f", "CL_ours"), ("buildup", "7.4f", "CL_buildup"),
                         ("VLM", "7.4f", "CL_vlm"), ("CFD", "7.4f", "CL_cfd"), SEP,
                         ("CD ours", "7.5f", "CD_ours"), ("buildup", "7.5f", "CD_buildup"),
                         ("CFD", "7.5f", "CD_cfd"), SEP,
                         *_vs_cfd("CL", ("ours", "buildup", "vlm", "cal")), SEP,
                         *_vs_cfd("CD", ("ours", "buildup", "cal"))])


def drag_table(rows: Sequence[CompareRow]) -> str:
    """Drag decomposed: zero-lift/profile, induced (k CL^2, AeroBuildup, lattice), tail lift and Cm."""
    return _table(rows, [("pt", "3", "label"), SEP,
                         ("CD0 ours", "8.5f", "CD0_ours"), ("CDp bu.", "8.5f", "CDp_buildup"), SEP,
                         ("CDi ours", "8.5f", "CDi_ours"), ("CDi bu.", "8.5f", "CDi_buildup"),
                         ("CDi VLM", "8.5f", "CDi_vlm"), SEP,
                         *[(f"k {_SHORT[m]}", "6.4f", lambda r, m=m: _k(getattr(r, f"CDi_{m}"), getattr(r, f"CL_{m}")))
                           for m in ("ours", "buildup", "vlm")], SEP,
                         ("CLh bu.", "7.4f", "CL_htail_buildup"),
                         ("CLh VLM", "7.4f", "CL_htail_vlm"), SEP,
                         ("Cm ours", "7.4f", "Cm_ours"), ("Cm bu.", "7.4f", "Cm_buildup")])


def slopes_table(rows: Sequence[SlopeRow]) -> str:
    """Lift-curve slopes [1/rad]: aircraft by each method, wing alone by AeroBuildup, lattice, Helmbold."""
    return _table(rows, [("alt_m", "6.0f", "alt_m"), ("mach", "5.2f", "mach"), SEP,
                         ("aircraft: ours", "6.3f", "cla_ours"),
                         ("buildup", "7.3f", "cla_buildup"), ("VLM", "6.3f", "cla_vlm"), SEP,
                         ("wing alone: buildup", "7.3f", "cla_wing_buildup"),
                         ("VLM", "6.3f", "cla_wing_vlm"),
                         ("Helmbold", "8.3f", "cla_wing_helmbold")])


def write_csv(path: Path, rows: Sequence[CompareRow] | Sequence[SlopeRow]) -> None:
    """Write dataclass rows as CSV (column names carry the units where they have one)."""
    dicts = [asdict(r) for r in rows]
    atomic_write(path, csv_text(list(dicts[0]), ([f"{v:.6g}" if isinstance(v, float) else v for v in d.values()]
                                                 for d in dicts)))


def plot(path: Path, points: Sequence[CompareRow], sweeps: Sequence[CompareRow]) -> None:
    """CL over alpha and CD over CL per method and Mach number, with the CFD points marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.5))
    groups = sorted({(r.alt_m, r.mach) for r in sweeps}, key=lambda c: c[1])
    for i, (alt, mach) in enumerate(groups):
        sel = [r for r in sweeps if (r.alt_m, r.mach) == (alt, mach)]
        col = f"C{i}"
        al = [r.alpha_deg for r in sel]
        tag = f"M {mach:g}, {alt:g} m"
        ax1.plot(al, [r.CL_ours for r in sel], "-", color=col, label=f"ours, {tag}")
        ax1.plot(al, [r.CL_buildup for r in sel], "--", color=col, label=f"AeroBuildup, {tag}")
        ax1.plot(al, [r.CL_vlm for r in sel], ":", color=col, label=f"VLM (Göthert), {tag}")
        ax1.plot(al, [r.CL_cal for r in sel], "-.", color=col, lw=1, label=f"ours calibrated, {tag}")
        ax2.plot([r.CD_cal for r in sel], [r.CL_cal for r in sel], "-.", color=col, lw=1,
                 label=f"ours calibrated, {tag}")
        ax2.plot([r.CD_ours for r in sel], [r.CL_ours for r in sel], "-", color=col, label=f"ours, {tag}")
        ax2.plot([r.CD_buildup for r in sel], [r.CL_buildup for r in sel], "--", color=col,
                 label=f"AeroBuildup, {tag}")
        ax2.plot([r.CDi_vlm for r in sel], [r.CL_vlm for r in sel], ":", color=col, lw=1,
                 label=f"VLM induced only, {tag}")
    cfd = [r for r in points if math.isfinite(r.CL_cfd)]
    if cfd:
        ax1.plot([r.alpha_deg for r in cfd], [r.CL_cfd for r in cfd], "k*", ms=11, label="CFD")
        ax2.plot([r.CD_cfd for r in cfd], [r.CL_cfd for r in cfd], "k*", ms=11, label="CFD")
        for r in cfd:
            ax1.annotate(f" {r.label}: M {r.mach:g}", (r.alpha_deg, r.CL_cfd), fontsize=8)
            ax2.annotate(f" {r.label}: M {r.mach:g}", (r.CD_cfd, r.CL_cfd), fontsize=8)
    ax1.set(xlabel="alpha [deg]", ylabel="CL [-]", title="UPERA lift: handbook, AeroBuildup, vortex lattice")
    ax2.set(xlabel="CD [-]", ylabel="CL [-]", title="UPERA drag polar (zero elevator, clean)")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6.5, ncol=2)
    fig.tight_layout()
    atomic_write(path, figure_bytes(fig, dpi=120))
    plt.close(fig)
