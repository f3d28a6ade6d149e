"""Parametric cycle study of SPEC.md: SFC over OPR for a set of bypass ratios, at equal thrust.

From a reference design (the ``reference_study`` preset by default) every
design of the carpet keeps Tt4, the component efficiencies and losses, and
the net thrust (the design mass flow is solved, :func:`.cycle_design.design`),
and changes:

* the bypass ratio BPR (0.5 to 2 in SPEC.md);
* the overall pressure ratio OPR (9 to 20), through the HPC pressure ratio
  PR_hpc = OPR / (PR_fan_inner (1 - dPqP_21_24)(1 - dPqP_24_25));
* the fan pressure ratios, so that the ratio of the ideally expanded core and
  bypass jet velocities V8/V18 equals the reference design's: PR_fan_outer
  is solved by brentq, and the inner pressure rise keeps the reference
  ratio (PR_fan_inner - 1)/(PR_fan_outer - 1).

The velocity ratio does not depend on the mass flow when there is no
absolute power offtake, so it is solved at the reference mass flow, and the
thrust afterwards. A design that cannot meet the ratio (fan PR outside 1.01
to 6, or a turbine that cannot drive its compressors) is kept in the table
with NaN and the reason.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 6.4
(parametric design-point studies, SFC carpets).
J. D. Mattingly, "Elements of Propulsion", AIAA, 2006, sec. 7.4 (optimum fan
pressure ratio and the jet velocity ratio of the separate-flow turbofan).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from scipy.optimize import brentq

from ..infra.files import atomic_write, csv_text, figure_bytes
from .cycle_design import DesignPoint, design
from .design_params import TurbofanParams
from .errors import ModelError

__all__ = ["COLUMNS", "StudyPoint", "jet_velocity_ratio", "cycle_study", "lowest_sfc_design", "point_params",
           "write_csv", "plot_carpet"]

#: Columns of the CSV file, in order.
COLUMNS: tuple[str, ...] = ("BPR", "OPR", "PR_fan_outer", "PR_fan_inner", "PR_hpc", "W2_kg_s", "Fn_N",
                            "Wf_kg_s", "SFC_kg_N_s", "V8_ideal_m_s", "V18_ideal_m_s", "V8_V18", "note")


@dataclass(frozen=True, slots=True)
class StudyPoint:
    """One design of the carpet (NaN where infeasible, the reason in `note`)."""

    BPR: float
    OPR: float
    PR_fan_outer: float
    PR_fan_inner: float
    PR_hpc: float
    W2_kg_s: float
    Fn_N: float
    Wf_kg_s: float
    SFC_kg_N_s: float
    V8_ideal_m_s: float
    V18_ideal_m_s: float
    V8_V18: float
    note: str = ""


def jet_velocity_ratio(dp: DesignPoint) -> float:
    """Ratio V8/V18 [-] of the ideally expanded core and bypass jet velocities."""
    return dp.nozzles["core"].V_ideal_m_s / dp.nozzles["bypass"].V_ideal_m_s


def _variant(ref: TurbofanParams, BPR: float, OPR: float, PR_outer: float, k_inner: float,
             W2_kg_s: float | None) -> TurbofanParams:
    PR_inner = 1.0 + k_inner * (PR_outer - 1.0)
    PR_hpc = OPR / (PR_inner * ref.PR_booster * (1.0 - ref.dPqP_21_24) * (1.0 - ref.dPqP_24_25))
    p = replace(ref, BPR=BPR, PR_fan_outer=PR_outer, PR_fan_inner=PR_inner, PR_hpc=PR_hpc)
    return p if W2_kg_s is None else replace(p, W2_kg_s=W2_kg_s, Fn_target_N=None)


#: Fan pressure ratios scanned for a bracket of the velocity-ratio root.
_PR_SCAN: tuple[float, ...] = (1.05, 1.2, 1.4, 1.6, 1.8, 2.0, 2.3, 2.6, 3.0, 3.5, 4.0, 5.0, 6.0)


def _solve_fan_pr(resid: Callable[[float], float]) -> float:
    """Fan outer PR where resid = 0: scan for a sign change among feasible designs, then brentq."""
    prev: tuple[float, float] | None = None
    for pr in _PR_SCAN:
        try:
            r = resid(pr)
        except ModelError:
            prev = None
            continue
        if prev is not None and prev[1] * r <= 0.0:
            return float(brentq(resid, prev[0], pr, xtol=1e-10))
        prev = (pr, r)
    raise ModelError(f"no feasible fan PR in {_PR_SCAN[0]} to {_PR_SCAN[-1]} meets the jet velocity ratio")


def cycle_study(ref: TurbofanParams, BPRs: Sequence[float], OPRs: Sequence[float]) -> list[StudyPoint]:
    """The carpet: one :class:`StudyPoint` per (BPR, OPR), BPR outer loop.

    Parameters
    ----------
    ref : TurbofanParams
        Reference design with a thrust target (``Fn_target_N``); its jet
        velocity ratio, Tt4, losses and efficiencies are kept.
    BPRs, OPRs : sequences of float
        Bypass ratios [-] and overall pressure ratios [-] to study.
    """
    if ref.Fn_target_N is None:
        raise ModelError(f"{ref.name}: the cycle study needs a reference with a thrust target (Fn_target_N)")
    dp_ref = design(ref)
    target = jet_velocity_ratio(dp_ref)
    W_ref = dp_ref.W2_kg_s
    k_inner = (ref.PR_fan_inner - 1.0) / (ref.PR_fan_outer - 1.0)
    out: list[StudyPoint] = []
    nan = math.nan
    for BPR in BPRs:
        for OPR in OPRs:
            def resid(pr: float, BPR: float = BPR, OPR: float = OPR) -> float:
                return jet_velocity_ratio(design(_variant(ref, BPR, OPR, pr, k_inner, W_ref))) - target
            try:
                pr = _solve_fan_pr(resid)
                dp = design(_variant(ref, BPR, OPR, pr, k_inner, None))
                c = dp.components
                out.append(StudyPoint(BPR, OPR, pr, c["fan_inner"].PR, c["hpc"].PR, dp.W2_kg_s, dp.Fn_N,
                                      dp.Wf_kg_s, dp.SFC_kg_N_s, dp.nozzles["core"].V_ideal_m_s,
                                      dp.nozzles["bypass"].V_ideal_m_s, jet_velocity_ratio(dp)))
            except ModelError as exc:
                out.append(StudyPoint(BPR, OPR, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan,
                                      str(exc).replace("\n", " ")))
    return out


def lowest_sfc_design(ref: TurbofanParams, points: Sequence[StudyPoint]) -> tuple[TurbofanParams, StudyPoint]:
    """The carpet's design of lowest SFC, as design parameters of its own (its mass flow given, no thrust
    target: the engine of that point, as the engine FMU's ``design_*`` parameters take it).

    Raises
    ------
    ModelError
        If no point of the carpet is feasible.
    """
    feasible = [p for p in points if math.isfinite(p.SFC_kg_N_s)]
    if not feasible:
        raise ModelError(f"{ref.name}: no feasible design in the cycle study")
    best = min(feasible, key=lambda p: p.SFC_kg_N_s)
    return point_params(ref, best), best


def point_params(ref: TurbofanParams, point: StudyPoint) -> TurbofanParams:
    """The engine of a feasible point of the carpet as design parameters of its own: the reference's with the
    point's BPR and pressure ratios and its design mass flow given (no thrust target), as the engine FMU's
    ``design_*`` parameters take it."""
    return replace(ref, BPR=float(point.BPR), PR_fan_outer=float(point.PR_fan_outer),
                   PR_fan_inner=float(point.PR_fan_inner), PR_hpc=float(point.PR_hpc), W2_kg_s=float(point.W2_kg_s),
                   Fn_target_N=None)


def write_csv(points: Sequence[StudyPoint], path: str | Path) -> Path:
    """Write the carpet as CSV (SI units in the column names); returns the path."""
    return atomic_write(path, csv_text(COLUMNS, ([getattr(s, c) for c in COLUMNS] for s in points)))


def plot_carpet(points: Sequence[StudyPoint], path: str | Path, title: str = "") -> Path:
    """Plot SFC [kg/(N s)] over OPR, one line per BPR, to a PNG file; returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.0, 4.8))
    for BPR in sorted({s.BPR for s in points}):
        row = [s for s in points if s.BPR == BPR and not math.isnan(s.SFC_kg_N_s)]
        ax.plot([s.OPR for s in row], [s.SFC_kg_N_s for s in row], marker="o", ms=3, label=f"BPR {BPR:g}")
    ax.set_xlabel("overall pressure ratio OPR [-]")
    ax.set_ylabel("SFC [kg/(N s)]")
    ax.set_title(title or "SFC carpet: same thrust, Tt4 and jet velocity ratio")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    p = atomic_write(path, figure_bytes(fig, dpi=120))
    plt.close(fig)
    return p
