"""Generate the FCS's performance database (``models/fcs/data/performance.json``) from the models.

    python -m openemss.models.performance.generate [--preset larzac04_sls] [--out FILE]

* Drag: the UPERA airframe trimmed in level flight in JSBSim
  (:func:`openemss.models.airframe.trim.trim_level`) at two masses at every point of an altitude x
  Mach grid. The trimmed polar CD = CD0 + k CL^2 is fitted through the two points, so CD0 and k
  carry whatever the 6-DoF trim holds: the Reynolds number of the altitude, the wave drag at the
  trimmed lift, the lift and drag of the trimmed elevator. The two masses span 1500 to 2100 kg
  within CL 0.6, the linear part of the lift curve. Slow points at altitude, where even 1500 kg
  needs more lift, take the values of the nearest faster point, and the file lists them (``filled``).
* Airbrake and gear: the airframe model's increments (:meth:`AeroModel.cd_airbrake`, ``cd_gear``),
  and the airbrake's deflection, blow-back and rate from the geometry.
* Thrust: the engine's steady states (:class:`openemss.models.engine.offdesign.TurbofanOffDesign`,
  default preset Larzac 04) at a set of corrected fan speeds, and the maximum thrust. The maximum is
  taken at lever 1, which is N1c 100 % (``fuel_control.k_delta_pct``), held within N1 103 % and
  Tt41 1400 K (the fuel controller's limits, ``models/fcs/data/fuel_control.yaml``).

The database is what the models give. ``tests/fcs/test_performance.py`` re-computes sampled points
and fails when the file is stale.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ..airframe.adapter import Airframe
from ..airframe.aero import aero_model
from ..airframe.errors import AirframeError
from ..airframe.geometry import load_geometry
from ..airframe.trim import trim_level
from ..engine.cycle_design import design
from ..engine.design_params import load_params, preset_path
from ..engine.errors import ModelError
from ..engine.offdesign import OffDesignPoint, TurbofanOffDesign, scaled_maps

__all__ = ["ALT_AXIS_M", "MACH_AXIS", "N1C_AXIS_PCT", "MASS_RANGE_KG", "CL_FIT_MAX", "polar_point", "thrust_column",
           "max_thrust",
           "generate", "OUT_FILE"]

OUT_FILE = Path(__file__).resolve().parents[1] / "fcs" / "data" / "performance.json"
ALT_AXIS_M = tuple(float(h) for h in range(0, 8001, 1000))
MACH_AXIS = tuple(round(0.15 + 0.05 * i, 2) for i in range(15))  # 0.15 to 0.85
N1C_AXIS_PCT = (30.0, 35.0, 40.0, 45.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0)
MASS_RANGE_KG = (1500.0, 2100.0)  # operating empty to maximum take-off
CL_FIT_MAX = 0.6
_FUEL_CONTROL = Path(__file__).resolve().parents[1] / "fcs" / "data" / "fuel_control.yaml"


def _limits() -> tuple[float, float, float]:
    """(N1c at lever 1 [%], N1 limit [%], Tt41 limit [K]) of the fuel controller's parameter file."""
    doc = yaml.safe_load(_FUEL_CONTROL.read_text(encoding="utf-8"))["fuel_control"]
    return (float(doc["k_delta_pct"]["value"]), float(doc["N1_max_pct"]["value"]),
            float(doc["Tt41_max_K"]["value"]))


def polar_point(alt_m: float, mach: float, airframe: Airframe | None = None) -> tuple[float, float] | None:
    """(CD0, k) of the trimmed polar through two trims at ``alt_m`` [m] and ``mach`` [-], or None.

    The two masses are the lightest and the heaviest of MASS_RANGE_KG that keep the level-flight CL
    within CL_FIT_MAX (the linear range of the lift curve: above 0.8 CL_max the lift rounds off and
    separation drag begins, which the parabola does not describe); None when less than 5 % of mass
    spread is left.
    """
    af = airframe or Airframe()
    try:
        trimmed = trim_level(alt_m, mach, MASS_RANGE_KG[0], airframe=af)
    except AirframeError:
        return None
    m_cl_max = MASS_RANGE_KG[0] * CL_FIT_MAX / trimmed.CL
    m2 = min(MASS_RANGE_KG[1], m_cl_max)
    if trimmed.CL > CL_FIT_MAX or m2 < 1.05 * MASS_RANGE_KG[0]:
        return None
    b = trim_level(alt_m, mach, m2, airframe=af)
    k = (b.CD - trimmed.CD) / (b.CL ** 2 - trimmed.CL ** 2)
    return trimmed.CD - k * trimmed.CL ** 2, k


def _solve(od: TurbofanOffDesign, alt_m: float, mach: float, guess: OffDesignPoint | None,
           **setting: float) -> OffDesignPoint | None:
    try:
        p = od.solve(alt_m, mach, guess=guess, **setting)
    except ModelError:
        return None
    return p if p.residual_max < 1e-7 else None


def thrust_column(od: TurbofanOffDesign, alt_m: float, mach: float) -> list[float | None]:
    """Net thrust [N] at each fan speed of N1C_AXIS_PCT (None where the engine has no steady state),
    solved from the highest fan speed down, each from the last solution."""
    out: list[float | None] = []
    guess = None
    for n1c in reversed(N1C_AXIS_PCT):
        p = _solve(od, alt_m, mach, guess, N1c_pct=n1c)
        if p is None and guess is not None:
            p = _solve(od, alt_m, mach, None, N1c_pct=n1c)
        out.append(None if p is None else p.Fn_N)
        guess = p if p is not None else guess
    return out[::-1]


def max_thrust(od: TurbofanOffDesign, alt_m: float, mach: float) -> float:
    """Net thrust at lever 1 within the N1 and Tt41 limits [N] (bisection on N1c when a limit binds)."""
    n1c_max, n1_lim, t41_lim = _limits()
    p = _solve(od, alt_m, mach, None, N1c_pct=n1c_max)
    if p is None:
        raise ModelError(f"performance: no steady state at N1c {n1c_max} % at {alt_m} m, Mach {mach}")
    if p.N1_pct <= n1_lim and p.T41_K <= t41_lim:
        return p.Fn_N
    lo, hi = 50.0, n1c_max
    q = p
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        q = _solve(od, alt_m, mach, q, N1c_pct=mid)
        if q is None:
            raise ModelError(f"performance: no steady state at N1c {mid:.2f} % at {alt_m} m, Mach {mach}")
        if q.N1_pct <= n1_lim and q.T41_K <= t41_lim:
            lo = mid
        else:
            hi = mid
    return _solve(od, alt_m, mach, q, N1c_pct=lo).Fn_N  # type: ignore[union-attr]


def _fill_rows(table: list[list[float | None]], what: str, filled: list[str], extrapolate: bool) -> list[list[float]]:
    """Fill the None of each altitude row along Mach: held from the nearest point that has a value, or
    (``extrapolate``) extended linearly through the two nearest, for quantities that change steadily with
    Mach (thrust)."""
    out = []
    for i, row in enumerate(table):
        have = [j for j, v in enumerate(row) if v is not None]
        if not have:
            raise ModelError(f"performance: no {what} at {ALT_AXIS_M[i]} m")
        new = []
        for j, v in enumerate(row):
            if v is None:
                near = sorted(have, key=lambda jj: (abs(jj - j), -jj))[:2]
                if extrapolate and len(near) == 2:
                    j0, j1 = near
                    v = row[j0] + (row[j1] - row[j0]) * (j - j0) / (j1 - j0)  # type: ignore[operator]
                    how = f"extrapolated from Mach {MACH_AXIS[j0]:g} and {MACH_AXIS[j1]:g}"
                else:
                    v, how = row[near[0]], f"from Mach {MACH_AXIS[near[0]]:g}"
                filled.append(f"{what} at {ALT_AXIS_M[i]:g} m, Mach {MACH_AXIS[j]:g}: {how}")
            new.append(float(v))  # type: ignore[arg-type]
        out.append(new)
    return out


def generate(preset: str = "larzac04_sls") -> dict[str, Any]:
    """The database as a JSON-ready mapping."""
    a = aero_model()
    g = load_geometry()
    ab = g.section("airbrake")
    af = Airframe()
    filled: list[str] = []
    pol = [[polar_point(h, m, af) for m in MACH_AXIS] for h in ALT_AXIS_M]
    cd0 = _fill_rows([[None if p is None else p[0] for p in row] for row in pol], "polar CD0", filled, False)
    k = _fill_rows([[None if p is None else p[1] for p in row] for row in pol], "polar k", filled, False)
    dp = design(load_params(preset_path(preset)))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    cols = [[thrust_column(od, h, m) for m in MACH_AXIS] for h in ALT_AXIS_M]
    thrust = []
    for jn, n1c in enumerate(N1C_AXIS_PCT):
        thrust.append(_fill_rows([[c[jn] for c in row] for row in cols], f"thrust at N1c {n1c:g} %", filled,
                                 True))
    tmax = [[max_thrust(od, h, m) for m in MACH_AXIS] for h in ALT_AXIS_M]
    n1c_max, n1_lim, t41_lim = _limits()
    r = lambda x: float(np.round(x, 7))  # noqa: E731 - 7 significant decimals are far below any fit error
    return {
        "_about": ("Performance database of UPERA with its engine for the FCS's vertical planner "
                   "(models/fcs/performance.py). GENERATED by python -m openemss.models.performance.generate "
                   "from the airframe (JSBSim trims) and the engine model; do not edit by hand. SI units. "
                   "Licence: MIT, as the repository."),
        "source": (f"trim_level (JSBSim UPERA) at the lightest and heaviest masses of {MASS_RANGE_KG} kg with CL "
                   f"<= {CL_FIT_MAX}; engine preset {preset}, steady states at N1c {list(N1C_AXIS_PCT)} %; maximum "
                   f"thrust at N1c {n1c_max:g} % within N1 {n1_lim:g} % and Tt41 {t41_lim:g} K"),
        "S_m2": g.wing.area_m2,
        "alt_m": list(ALT_AXIS_M),
        "mach": list(MACH_AXIS),
        "cd0": [[r(v) for v in row] for row in cd0],
        "k": [[r(v) for v in row] for row in k],
        "cd_gear": r(a.cd_gear),
        "airbrake": {"cd_full": r(float(a.cd_airbrake(1.0))), "max_deg": ab["max_deg"],
                     "blowback_qbar_Pa": ab["blowback_qbar_Pa"], "full_travel_s": ab["full_travel_s"]},
        "n1c_pct": list(N1C_AXIS_PCT),
        "Fn_N": [[[round(v, 3) for v in row] for row in t] for t in thrust],
        "thrust_max_N": [[round(v, 3) for v in row] for row in tmax],
        "filled": filled,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Generate the FCS's performance database from the airframe and "
                                             "engine models.")
    ap.add_argument("--preset", default="larzac04_sls", help="engine preset (default larzac04_sls)")
    ap.add_argument("--out", type=Path, default=OUT_FILE, help=f"output file (default {OUT_FILE})")
    args = ap.parse_args(argv)
    doc = generate(args.preset)
    args.out.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {args.out} ({len(doc['filled'])} point(s) filled from neighbours)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())


