"""Generate the FCS's performance database from the airframe and engine of the system flown.

    python -m openemss.models.performance.generate [--preset larzac04_sls] [--out FILE]

writes the database of the airframe (as the airframe model flies it: the shipped UPERA) with an engine preset
(default: the shipped one, ``models/fcs/data/performance.json``); ``emss run`` generates the database of the
system it flies before the run, into the cache (:func:`ensure_cached`, the report plugin's ``prepare`` hook).

* Drag: the airframe trimmed in level flight in JSBSim (:func:`openemss.models.airframe.trim.trim_level`) at
  two masses at every point of an altitude x Mach grid. The trimmed polar CD = CD0 + k CL^2 is fitted through
  the two points, so CD0 and k carry whatever the 6-DoF trim holds: the Reynolds number of the altitude, the
  wave drag at the trimmed lift, the lift and drag of the trimmed elevator. The two masses span the aircraft's
  own range (:attr:`.Airframe.mass_range_kg`, operating empty to maximum take-off) within CL 0.6, the linear
  part of the lift curve. Slow points at altitude, where even the empty aircraft needs more lift, take the
  values of the nearest faster point, and the file lists them (``filled``).
* Airbrake and gear: the airframe model's increments (:meth:`AeroModel.cd_airbrake`, ``cd_gear``),
  and the airbrake's deflection, blow-back and rate from the geometry.
* Thrust: the engine's steady states (:class:`openemss.models.engine.offdesign.TurbofanOffDesign`) at a set of
  corrected fan speeds, and the maximum thrust. The maximum is taken at lever 1, which is N1c ``k_delta_pct``,
  held within ``N1_max_pct`` and ``Tt41_max_K`` (the fuel controller's limits of the system flown, by default
  its parameter file's, ``models/fcs/data/fuel_control.yaml``).

Each database records the identities of the airframe's and the engine's configurations it was generated
from (:mod:`openemss.models.airframe.identity`, :mod:`openemss.models.engine.identity`) and the limits; the
flight control flies only a database whose identities are those its airframe and engine publish
(:func:`openemss.models.fcs.performance.performance_for`). Cost (measured on this 2-core machine, loaded by
other work): about 3 s of CPU for the 135 points with a preset engine (0.3 s the trims, 2.7 s the compiled
turbofan's steady states); with an engine file about 100 s (0.73 s a point: its steady states are solved on its
graph, :class:`openemss.models.engine.graph_engine.GraphEngineModel`, the engine FMU's model of it).
``tests/fcs/test_performance.py`` re-computes sampled points and fails when the shipped file is stale.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ..airframe.adapter import Airframe
from ..airframe.aero import aero_model
from ..airframe.errors import AirframeError
from ..airframe.identity import airframe_config_id, airframe_digest
from ..airframe.trim import trim_level
from ..infra.config_id import LIMIT_NAMES, as_config_id, cache_dir, database_key
from ..engine.cycle_design import design
from ..engine.design_params import EngineParams, TurbofanParams, load_params, preset_path
from ..engine.engine_signals import EO, EngineInputs
from ..engine.errors import ModelError
from ..engine.identity import engine_digest, engine_file_digest
from ..engine.offdesign import OffDesignPoint, TurbofanOffDesign, scaled_maps

__all__ = ["ALT_AXIS_M", "MACH_AXIS", "N1C_AXIS_PCT", "CL_FIT_MAX", "polar_point", "thrust_column", "max_thrust",
           "mass_range_kg", "default_limits", "generate", "ensure_cached", "EngineFile", "Engine", "OUT_FILE"]

OUT_FILE = Path(__file__).resolve().parents[1] / "fcs" / "data" / "performance.json"
ALT_AXIS_M = tuple(float(h) for h in range(0, 8001, 1000))
MACH_AXIS = tuple(round(0.15 + 0.05 * i, 2) for i in range(15))  # 0.15 to 0.85
N1C_AXIS_PCT = (30.0, 35.0, 40.0, 45.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0)
CL_FIT_MAX = 0.6
_FUEL_CONTROL = Path(__file__).resolve().parents[1] / "fcs" / "data" / "fuel_control.yaml"


def default_limits() -> dict[str, float]:
    """The fuel controller's limits that set the maximum thrust (``LIMIT_NAMES``: N1c at lever 1 [%], N1 limit
    [%], Tt41 limit [K]) as its parameter file gives them (the flight control's defaults)."""
    doc = yaml.safe_load(_FUEL_CONTROL.read_text(encoding="utf-8"))["fuel_control"]
    return {n: float(doc[n]["value"]) for n in LIMIT_NAMES}


def _limits(limits: Mapping[str, float] | None) -> dict[str, float]:
    """``limits`` by :data:`LIMIT_NAMES` as floats (default: :func:`default_limits`)."""
    given = limits if limits is not None else default_limits()
    return {n: float(given[n]) for n in LIMIT_NAMES}


def mass_range_kg(airframe: Airframe) -> tuple[float, float]:
    """The airframe's (operating empty, maximum take-off) mass [kg], checked: finite, 0 < empty < maximum.

    Raises
    ------
    AirframeError
        One line naming the masses and what is allowed.
    """
    lo, hi = (float(m) for m in airframe.mass_range_kg)
    if not (0.0 < lo < hi < float("inf")):
        raise AirframeError(f"{airframe.geometry.path}: mass: operating empty {lo:g} kg and maximum take-off {hi:g} "
                            "kg: the performance data need 0 < empty < maximum take-off (finite)")
    return lo, hi


def polar_point(alt_m: float, mach: float, airframe: Airframe | None = None) -> tuple[float, float] | None:
    """(CD0, k) of the trimmed polar through two trims at ``alt_m`` [m] and ``mach`` [-], or None.

    The two masses are the lightest and the heaviest of the aircraft's mass range (:func:`mass_range_kg`) that
    keep the level-flight CL within CL_FIT_MAX (the linear range of the lift curve: above 0.8 CL_max the lift
    rounds off and separation drag begins, which the parabola does not describe); None when less than 5 % of
    mass spread is left.
    """
    af = airframe or Airframe()
    m_lo, m_hi = mass_range_kg(af)
    try:
        trimmed = trim_level(alt_m, mach, m_lo, airframe=af)
    except AirframeError:
        return None
    m_cl_max = m_lo * CL_FIT_MAX / trimmed.CL
    m2 = min(m_hi, m_cl_max)
    if trimmed.CL > CL_FIT_MAX or m2 < 1.05 * m_lo:
        return None
    b = trim_level(alt_m, mach, m2, airframe=af)
    k = (b.CD - trimmed.CD) / (b.CL ** 2 - trimmed.CL ** 2)
    return trimmed.CD - k * trimmed.CL ** 2, k


def _solve(od: TurbofanOffDesign | _FileEngine, alt_m: float, mach: float, guess: OffDesignPoint | None,
           **setting: float) -> OffDesignPoint | None:
    try:
        p = od.solve(alt_m, mach, guess=guess, **setting)
    except ModelError:
        return None
    return p if p.residual_max < 1e-7 else None


def thrust_column(od: TurbofanOffDesign | _FileEngine, alt_m: float, mach: float) -> list[float | None]:
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


def max_thrust(od: TurbofanOffDesign | _FileEngine, alt_m: float, mach: float,
               limits: Mapping[str, float] | None = None) -> float:
    """Net thrust at lever 1 within the N1 and Tt41 limits [N] (bisection on N1c when a limit binds); ``limits``
    as :func:`default_limits` (its values by default)."""
    lim = _limits(limits)
    n1c_max, n1_lim, t41_lim = (lim[n] for n in LIMIT_NAMES)
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


@dataclass(frozen=True)
class EngineFile:
    """An engine file (a path or a shipped name, :mod:`openemss.models.engine.engine_file`) flown at a thrust scale,
    as the engine FMU's ``engine_file`` and ``thrust_scale`` give it."""

    engine_file: str
    thrust_scale: float = 1.0


#: An engine: a preset's name, design parameters (a turbofan), or an engine file
Engine = str | EngineParams | EngineFile


@dataclass(frozen=True)
class _Steady:
    """A steady state of an engine file, with the fields :func:`max_thrust` and :func:`thrust_column` read."""

    Fn_N: float
    N1_pct: float
    T41_K: float
    residual_max: float = 0.0  # GraphTransient.steady returns converged points only (else it raises)


class _FileEngine:
    """Steady states of an engine file as the engine FMU flies it (:class:`.graph_engine.GraphEngineModel`), with
    the interface :func:`thrust_column` and :func:`max_thrust` use of :class:`.TurbofanOffDesign`: a corrected fan
    speed asked for is the mechanical speed over the ratio N1c/N1 of the flight condition (fixed by the fan-face
    temperature), read from one steady state."""

    def __init__(self, engine: EngineFile) -> None:
        from ..engine.graph_engine import GraphEngineModel

        self.m = GraphEngineModel(engine.engine_file, engine.thrust_scale)

    def solve(self, alt_m: float, mach: float, guess: object = None, *, N1c_pct: float) -> _Steady:
        u = EngineInputs(0.0, alt_m, mach)
        v = self.m.start(u, N1_pct=N1c_pct)
        v = self.m.start(u, N1_pct=N1c_pct * v[EO.N1_pct] / v[EO.N1c_pct])
        return _Steady(v[EO.Fn_N], v[EO.N1_pct], v[EO.Tt41_K])


def _identity(engine: Engine) -> tuple[str, str]:
    """(digest of the engine's configuration, its name) (:mod:`openemss.models.engine.identity`)."""
    if isinstance(engine, EngineFile):
        return (engine_file_digest(engine.engine_file, engine.thrust_scale),
                f"{Path(engine.engine_file).stem} x {engine.thrust_scale:g}")
    params = _engine_params(engine)
    return engine_digest(params), params.name


def _steady_solver(engine: Engine) -> TurbofanOffDesign | _FileEngine:
    if isinstance(engine, EngineFile):
        return _FileEngine(engine)
    dp = design(_engine_params(engine))
    return TurbofanOffDesign(dp, scaled_maps(dp))


def _engine_params(engine: EngineParams | str) -> TurbofanParams:
    params = load_params(preset_path(engine)) if isinstance(engine, str) else engine
    if not isinstance(params, TurbofanParams):
        raise ModelError(f"performance: engine '{params.name}' is a {type(params).__name__}; a preset engine's "
                         "performance data are generated for a turbofan (TurbofanOffDesign); give it as a file")
    return params


def generate(engine: Engine = "larzac04_sls", airframe: Airframe | None = None,
             limits: Mapping[str, float] | None = None) -> dict[str, Any]:
    """The database of ``airframe`` (default: the airframe model's aircraft) with ``engine`` (a preset's name, its
    parameters, or an :class:`EngineFile`) and the fuel controller's ``limits`` (:func:`default_limits`' names;
    default its values), as a JSON-ready mapping.

    Raises
    ------
    AirframeError, ModelError
        For an aircraft whose mass range is not one, an engine that is not a turbofan, a grid point where the
        engine has no steady state at lever 1 or an altitude with no polar.
    """
    af = airframe if airframe is not None else Airframe()
    e_digest, e_name = _identity(engine)
    lim = _limits(limits)
    m_lo, m_hi = mass_range_kg(af)
    a = aero_model()
    g = af.geometry
    ab = g.section("airbrake")
    filled: list[str] = []
    pol = [[polar_point(h, m, af) for m in MACH_AXIS] for h in ALT_AXIS_M]
    cd0 = _fill_rows([[None if p is None else p[0] for p in row] for row in pol], "polar CD0", filled, False)
    k = _fill_rows([[None if p is None else p[1] for p in row] for row in pol], "polar k", filled, False)
    od = _steady_solver(engine)
    cols = [[thrust_column(od, h, m) for m in MACH_AXIS] for h in ALT_AXIS_M]
    thrust = []
    for jn, n1c in enumerate(N1C_AXIS_PCT):
        thrust.append(_fill_rows([[c[jn] for c in row] for row in cols], f"thrust at N1c {n1c:g} %", filled,
                                 True))
    tmax = [[max_thrust(od, h, m, lim) for m in MACH_AXIS] for h in ALT_AXIS_M]
    r = lambda x: float(np.round(x, 7))  # noqa: E731 - 7 significant decimals are far below any fit error
    a_id, e_id = airframe_config_id(af), as_config_id(e_digest)
    return {
        "_about": ("Performance database of an aircraft with its engine for the FCS's vertical planner "
                   "(models/fcs/performance.py). GENERATED by openemss.models.performance.generate from the airframe "
                   "(JSBSim trims) and the engine model; do not edit by hand. SI units. Licence: MIT, as the "
                   "repository."),
        "source": (f"trim_level (JSBSim, {af.definition_files[0].stem}) at the lightest and heaviest masses of "
                   f"({m_lo:g}, {m_hi:g}) kg with CL <= {CL_FIT_MAX}; engine {e_name}, steady states at N1c "
                   f"{list(N1C_AXIS_PCT)} %; maximum thrust at N1c {lim['k_delta_pct']:g} % within N1 "
                   f"{lim['N1_max_pct']:g} % and Tt41 {lim['Tt41_max_K']:g} K"),
        "key": database_key(a_id, e_id, lim),
        "airframe_config_id": a_id,
        "engine_config_id": e_id,
        "airframe": {"name": af.definition_files[0].stem, "digest": airframe_digest(af), "mass_range_kg": [m_lo, m_hi]},
        "engine": {"name": e_name, "digest": e_digest},
        "limits": lim,
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


def _write(path: Path, doc: Mapping[str, Any]) -> None:
    """Write the database whole or not at all (a temporary file in the same folder, then renamed)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(json.dumps(doc, indent=1) + "\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _key_of(path: Path) -> str | None:
    try:
        return str(json.loads(path.read_text(encoding="utf-8")).get("key"))
    except (OSError, ValueError, AttributeError):
        return None


def ensure_cached(engine: Engine, airframe: Airframe | None = None,
                  limits: Mapping[str, float] | None = None) -> tuple[Path, float | None]:
    """The database of this airframe, engine and limits: the shipped one (``OUT_FILE``) when it is theirs, else
    the cached one (``<cache>/<key>.json``, :func:`openemss.models.infra.config_id.cache_dir`), generated and
    written there first when there is none. Returns the file and the seconds the generation took (None: none
    was needed)."""
    af = airframe if airframe is not None else Airframe()
    lim = _limits(limits)
    key = database_key(airframe_config_id(af), as_config_id(_identity(engine)[0]), lim)
    for path in (OUT_FILE, cache_dir() / f"{key}.json"):
        if path.is_file() and _key_of(path) == key:
            return path, None
    t0 = time.perf_counter()
    doc = generate(engine, af, lim)
    path = cache_dir() / f"{key}.json"
    _write(path, doc)
    return path, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Generate the FCS's performance database from the airframe and "
                                             "engine models.")
    ap.add_argument("--preset", default="larzac04_sls", help="engine preset (default larzac04_sls)")
    ap.add_argument("--out", type=Path, default=OUT_FILE, help=f"output file (default {OUT_FILE})")
    args = ap.parse_args(argv)
    try:
        doc = generate(args.preset)
    except (AirframeError, ModelError) as exc:
        print(f"generate: {exc}", file=sys.stderr)
        return 1
    _write(args.out, doc)
    print(f"wrote {args.out} ({len(doc['filled'])} point(s) filled from neighbours)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
