"""Life usage of an engine over a mission: low-cycle fatigue of the discs, creep of the HP turbine blades.

Computed after a run from the recorded time series (the report plugin, ``report/life.py``): nothing runs
per macro step.

* **Disc LCF.** A disc's peak stress follows its spool speed squared, ``sigma = sigma_d (N / N_design)^2``
  (centrifugal load; ``sigma_d`` the assumed peak elastic stress at the design speed). The stress history
  is counted by rainflow (ASTM E1049-85, the ``rainflow`` package: a well-kept implementation of the
  standard, so the counting is not written here again). Each counted cycle (range, mean, count 0.5 or 1)
  gets a life from the strain-life curve (Basquin and Coffin-Manson) with the Smith-Watson-Topper mean-
  stress correction for an elastic stress history::

      sigma_max * sigma_a / E = sigma_f'^2 / E (2 N_f)^(2 b) + sigma_f' eps_f' (2 N_f)^(b + c)

  and the damage is summed by Miner's rule, ``D = sum(n_i / N_f,i)``. Equivalent full cycles are ``D``
  times the life of the reference cycle 0 -> 100 % -> 0 of the design speed.
* **Blade creep.** The blade's metal temperature is ``T_m = T_g - phi (T_g - T_c)`` with the gas at
  Tt41, the cooling air at Tt3 (HPC exit) and a cooling effectiveness ``phi``; its stress follows N2
  squared. The rupture time comes from the alloy's Larson-Miller curve, ``LMP = T (C + log10 t_r[h])``,
  interpolated linearly in (log10 sigma, LMP) between the published points (extrapolated linearly beyond
  them), and the damage is Robinson's time fraction, ``D = sum(dt / t_r)``.
* **Time above thresholds** of Tt41 and of the blade's metal temperature.

Material constants and assumptions are data (``models/life/data/life_materials.json``, sources in
``models/life/data/README.md``).

References
----------
ASTM E1049-85 (reapproved 2017), Standard Practices for Cycle Counting in Fatigue Analysis, sec. 5.4.4.
K. N. Smith, P. Watson, T. H. Topper, "A stress-strain function for the fatigue of metals", J. Materials
5(4), 767-778, 1970.
M. A. Miner, "Cumulative damage in fatigue", J. Appl. Mech. 12, A159-A164, 1945.
F. R. Larson, J. Miller, "A time-temperature relationship for rupture and creep stresses", Trans. ASME 74,
765-775, 1952.
E. L. Robinson, "Effect of temperature variation on the long-time rupture strength of steels", Trans. ASME
74, 777-781, 1952.
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., Blackwell, 2004 (turbine cooling; cited from memory,
not checked against a copy: the cooling effectiveness used is an assumption, models/life/data/README.md).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..infra import safe_yaml
from .errors import LifeDataError

__all__ = ["StrainLife", "LarsonMiller", "DiscSpec", "BladeSpec", "LifeSpec", "load_life_spec", "rainflow_cycles",
           "disc_lcf", "blade_creep", "time_above", "LIFE_DATA", "DiscLife", "BladeLife"]

#: The data file of the materials and the life model's assumptions.
LIFE_DATA: Path = Path(__file__).resolve().parent / "data" / "life_materials.json"
_S_PER_H = 3600.0


@dataclass(frozen=True)
class StrainLife:
    """A strain-life (Basquin + Coffin-Manson) curve: E [Pa], sigma_f' [Pa], b [-], eps_f' [-], c [-]."""

    name: str
    E_Pa: float
    sigma_f_Pa: float
    b: float
    eps_f: float
    c: float
    source: str = ""
    checked: str = ""             #: which constants were checked against which readable source ("" not said)

    def swt(self, two_Nf: np.ndarray) -> np.ndarray:
        """The Smith-Watson-Topper parameter sigma_max eps_a [Pa] at 2 N_f reversals."""
        x = np.asarray(two_Nf, dtype=float)
        return self.sigma_f_Pa ** 2 / self.E_Pa * x ** (2.0 * self.b) + \
            self.sigma_f_Pa * self.eps_f * x ** (self.b + self.c)

    def cycles_to_failure(self, sigma_max_Pa: np.ndarray, sigma_a_Pa: np.ndarray) -> np.ndarray:
        """Cycles to crack initiation N_f [-] of elastic cycles (SWT); inf where sigma_max or sigma_a <= 0.

        Solved for log10(2 N_f) by bisection on the monotonic SWT curve (60 halvings of [-1, 30]: exact to
        round-off), vectorised over the cycles."""
        smax, sa = np.broadcast_arrays(np.asarray(sigma_max_Pa, float), np.asarray(sigma_a_Pa, float))
        target = np.where((smax > 0.0) & (sa > 0.0), smax * sa / self.E_Pa, np.nan)
        lo, hi = np.full(target.shape, -1.0), np.full(target.shape, 30.0)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            above = self.swt(10.0 ** mid) > target     # the curve falls with life: more life needed
            lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
        n = 0.5 * 10.0 ** (0.5 * (lo + hi))
        return np.where(np.isnan(target), np.inf, n)


@dataclass(frozen=True)
class LarsonMiller:
    """A Larson-Miller rupture curve: its constant C [-] and published (T [K], t_r [h], stress [Pa]) points."""

    name: str
    C: float
    T_K: tuple[float, ...]
    t_h: tuple[float, ...]
    stress_Pa: tuple[float, ...]
    source: str = ""
    checked: str = ""             #: whether the points were checked against a readable source ("" not said)

    def __post_init__(self) -> None:
        if not len(self.T_K) == len(self.t_h) == len(self.stress_Pa) or len(set(self.stress_Pa)) < 2:
            raise LifeDataError(f"Larson-Miller curve {self.name!r}: needs points of (temperature, time, stress) at "
                                "two stresses at least")

    @property
    def lmp(self) -> np.ndarray:
        """The points' Larson-Miller parameters T (C + log10 t_r) [K]."""
        return np.asarray(self.T_K) * (self.C + np.log10(self.t_h))

    def _curve(self) -> tuple[np.ndarray, np.ndarray]:
        """(log10 stress ascending, LMP) of the master curve: the points' LMP averaged per stress."""
        ls = np.log10(self.stress_Pa)
        keys = np.unique(ls)
        return keys, np.array([self.lmp[ls == k].mean() for k in keys])

    def parameter(self, stress_Pa: np.ndarray) -> np.ndarray:
        """LMP [K] at a stress: linear in log10(stress) between the points, continued by the end segments."""
        x, y = self._curve()
        s = np.log10(np.maximum(np.asarray(stress_Pa, float), 1.0))
        out = np.interp(s, x, y)
        lo, hi = s < x[0], s > x[-1]
        out = np.where(lo, y[0] + (s - x[0]) * (y[1] - y[0]) / (x[1] - x[0]), out)
        return np.where(hi, y[-1] + (s - x[-1]) * (y[-1] - y[-2]) / (x[-1] - x[-2]), out)

    def rupture_time_s(self, stress_Pa: np.ndarray, T_K: np.ndarray) -> np.ndarray:
        """Time to rupture [s] at a stress [Pa] and metal temperature [K]; inf where the stress is <= 0."""
        st, T = np.broadcast_arrays(np.asarray(stress_Pa, float), np.asarray(T_K, float))
        with np.errstate(over="ignore"):
            t = _S_PER_H * 10.0 ** np.minimum(self.parameter(st) / np.maximum(T, 1.0) - self.C, 300.0)
        return np.where(st > 0.0, t, np.inf)


@dataclass(frozen=True)
class DiscSpec:
    """A disc: its name, spool (``N1`` or ``N2``), strain-life curve and peak stress at the design speed [Pa]."""

    name: str
    spool: str
    material: StrainLife
    stress_at_design_speed_Pa: float
    note: str = ""


@dataclass(frozen=True)
class BladeSpec:
    """The HP turbine blade: Larson-Miller curve, stress at the design N2 [Pa], cooling effectiveness [-]."""

    name: str
    material: LarsonMiller
    stress_at_design_speed_Pa: float
    cooling_effectiveness: float
    note: str = ""

    def metal_K(self, T_gas_K: np.ndarray, T_coolant_K: np.ndarray) -> np.ndarray:
        """Metal temperature [K]: T_g - phi (T_g - T_c)."""
        return T_gas_K - self.cooling_effectiveness * (T_gas_K - T_coolant_K)


@dataclass(frozen=True)
class LifeSpec:
    """The discs, the blade and the temperature thresholds [K] (by signal: ``Tt41_K``, ``blade_metal_K``)."""

    discs: tuple[DiscSpec, ...]
    blade: BladeSpec
    thresholds_K: dict[str, tuple[float, ...]]
    source: str = ""


def _num(d: dict, key: str, where: str, lo: float = -math.inf, hi: float = math.inf) -> float:
    v = d.get(key)
    if isinstance(v, bool) or not isinstance(v, int | float) or not (lo <= float(v) <= hi) or not math.isfinite(v):
        raise LifeDataError(f"{where}: '{key}' must be a finite number in [{lo:g}, {hi:g}], got {v!r}")
    return float(v)


@lru_cache(maxsize=8)
def load_life_spec(path: str | Path = LIFE_DATA) -> LifeSpec:
    """Read a life data file (the shipped :data:`LIFE_DATA` by default); raises :class:`LifeDataError` naming the
    file and the entry for a missing or bad value."""
    path = Path(path)
    src = str(path)
    data = safe_yaml.load_json(safe_yaml.read_text(path, "life data file"), src)
    try:
        sl = {name: StrainLife(name, _num(d, "E_Pa", f"{src}: {name}", 1e9, 1e12),
                               _num(d, "sigma_f_Pa", f"{src}: {name}", 1e6, 1e11),
                               _num(d, "b", f"{src}: {name}", -1, 0), _num(d, "eps_f", f"{src}: {name}", 0, 100),
                               _num(d, "c", f"{src}: {name}", -2, 0), str(d.get("source", "")),
                               str(d.get("checked", "")))
              for name, d in data["strain_life"].items()}
        lm = {}
        for name, d in data["larson_miller"].items():
            pts = d["points"]
            lm[name] = LarsonMiller(name, _num(d, "C", f"{src}: {name}", 1, 60),
                                    tuple(_num(p, "T_C", f"{src}: {name}", -273.15, 3000) + 273.15 for p in pts),
                                    tuple(_num(p, "t_h", f"{src}: {name}", 1e-6, 1e9) for p in pts),
                                    tuple(_num(p, "stress_Pa", f"{src}: {name}", 1e3, 1e11) for p in pts),
                                    str(d.get("source", "")), str(d.get("checked", "")))
        discs = tuple(DiscSpec(str(d["name"]), str(d["spool"]), sl[d["material"]],
                               _num(d, "stress_at_design_speed_Pa", f"{src}: {d['name']}", 1e6, 1e10),
                               str(d.get("note", ""))) for d in data["discs"])
        b = data["blade"]
        blade = BladeSpec(str(b["name"]), lm[b["material"]],
                          _num(b, "stress_at_design_speed_Pa", f"{src}: blade", 1e6, 1e10),
                          _num(b, "cooling_effectiveness", f"{src}: blade", 0.0, 0.95), str(b.get("note", "")))
        th = {k: tuple(_num({"v": v}, "v", f"{src}: thresholds_K.{k}", 0, 5000) for v in vals)
              for k, vals in data["thresholds_K"].items()}
    except (KeyError, TypeError, AttributeError) as exc:
        raise LifeDataError(f"{src}: missing or malformed entry {exc}") from None
    for d in discs:
        if d.spool not in ("N1", "N2"):
            raise LifeDataError(f"{src}: disc {d.name!r}: spool must be N1 or N2, got {d.spool!r}")
    shipped = path.resolve() == LIFE_DATA
    return LifeSpec(discs, blade, th, "models/life/data/life_materials.json" if shipped else src)


def rainflow_cycles(x: Sequence[float] | np.ndarray) -> np.ndarray:
    """Rainflow cycles of a series (ASTM E1049-85 by the ``rainflow`` package).

    Returns
    -------
    numpy.ndarray
        One row per cycle: range, mean, count (0.5 or 1.0), index of its first and of its last sample.
    """
    import rainflow

    rows = list(rainflow.extract_cycles(np.asarray(x, dtype=float)))
    return np.array(rows, dtype=float).reshape(-1, 5)


@dataclass(frozen=True)
class DiscLife:
    """A disc's LCF over a run: the counted cycles and their damage."""

    spec: DiscSpec
    cycles: np.ndarray            #: rainflow rows (range, mean, count, i_start, i_end) of the stress [Pa]
    damage: np.ndarray            #: Miner damage of each cycle [-]
    reference_cycles: float       #: life of the 0 -> 100 % -> 0 cycle [-]

    @property
    def total(self) -> float:
        """Miner's sum over the run [-] (the fraction of the disc's crack-initiation life used)."""
        return float(self.damage.sum())

    @property
    def equivalent_cycles(self) -> float:
        """The run's damage in reference cycles (0 -> 100 % -> 0 of the design speed) [-]."""
        return self.total * self.reference_cycles


def disc_lcf(speed_pct: np.ndarray, disc: DiscSpec, from_rest: bool = False) -> DiscLife:
    """LCF of a disc from its spool speed [% of design] (any sampling that keeps the turning points).

    With `from_rest` the spool is taken to start from rest before the first sample and to stop after the last
    (a flight recorded from a running engine: the start-stop cycle is the flight's major cycle); the cycles'
    sample indices stay those of `speed_pct` (the rest points clipped to its ends)."""
    n = np.asarray(speed_pct, float)
    if from_rest:
        n = np.concatenate(([0.0], n, [0.0]))
    sigma = disc.stress_at_design_speed_Pa * (n / 100.0) ** 2
    cyc = rainflow_cycles(sigma) if len(sigma) > 1 else np.zeros((0, 5))
    if from_rest and len(cyc):
        cyc[:, 3:] = np.clip(cyc[:, 3:] - 1.0, 0.0, len(speed_pct) - 1.0)
    rng, mean, count = cyc[:, 0], cyc[:, 1], cyc[:, 2]
    nf = disc.material.cycles_to_failure(mean + 0.5 * rng, 0.5 * rng)
    s_d = disc.stress_at_design_speed_Pa
    ref = float(disc.material.cycles_to_failure(np.array(s_d), np.array(0.5 * s_d)))
    return DiscLife(disc, cyc, count / nf, ref)


@dataclass(frozen=True)
class BladeLife:
    """The HP turbine blade over a run: metal temperature [K], rupture time [s] and damage of each interval."""

    spec: BladeSpec
    metal_K: np.ndarray           #: per sample
    rupture_s: np.ndarray         #: per sample
    damage: np.ndarray            #: per interval (t[k], t[k+1]], the sample at t[k+1] held over it

    @property
    def total(self) -> float:
        """Robinson's time-fraction sum over the run [-]."""
        return float(self.damage.sum())


def blade_creep(time_s: np.ndarray, N2_pct: np.ndarray, Tt41_K: np.ndarray, Tt3_K: np.ndarray,
                blade: BladeSpec) -> BladeLife:
    """Creep of the HP turbine blade from the recorded N2 [%], Tt41 [K] and Tt3 [K] (the cooling air)."""
    t = np.asarray(time_s, float)
    Tm = blade.metal_K(np.asarray(Tt41_K, float), np.asarray(Tt3_K, float))
    stress = blade.stress_at_design_speed_Pa * (np.asarray(N2_pct, float) / 100.0) ** 2
    tr = blade.material.rupture_time_s(stress, Tm)
    return BladeLife(blade, Tm, tr, np.diff(t) / tr[1:] if len(t) > 1 else np.zeros(0))


def time_above(time_s: np.ndarray, y: np.ndarray, thresholds: Sequence[float]) -> dict[str, float]:
    """Time [s] the signal spent above each threshold (intervals whose closing sample is above it)."""
    dt = np.diff(np.asarray(time_s, float))
    y1 = np.asarray(y, float)[1:]
    return {f"{th:g}": float(dt[y1 > th].sum()) for th in thresholds}
