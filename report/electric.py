"""The electrical figures of a hybrid run's summary: energy per section, SOC, peak powers, limits hit.

Read from the electrical system's outputs (``fmus/electric.py``): its energy counters (``E_*_J``, each the
sum of ``P dt`` over the steps) give exact energies per mission section by difference, with the
convention of :mod:`.summary` (a section owns the intervals ``(t[k], t[k+1]]`` that start while it is
active). The balances (machines: shaft = electrical + losses; bus: sources = loads served; battery:
counter = sum of the recorded ``V I`` over the steps) are reported as residuals, so a broken ledger shows.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from openemss.models.electric.ems import MODES

from .rundata import RunData
from .series import flag_stats, held_increments

__all__ = ["electric_summary", "ELECTRIC_FLAGS", "J_PER_KWH"]

J_PER_KWH = 3.6e6
#: Boolean outputs of the electrical system reported as limits.
ELECTRIC_FLAGS = ("hp_limited", "lp_limited", "battery_limited", "load_shed")
#: Counters summed per section: summary key -> output.
_COUNTERS = (("battery_kWh", "E_batt_J"), ("hp_shaft_kWh", "E_shaft_hp_J"), ("lp_shaft_kWh", "E_shaft_lp_J"),
             ("losses_kWh", "E_loss_J"), ("loads_kWh", "E_loads_J"), ("shed_kWh", "E_shed_J"))


def _col(run: RunData, name: str) -> np.ndarray:
    c = run.get("electric", name)
    if c is None:
        raise ValueError(f"the electrical summary needs {run.roles.electric}.{name} recorded")
    return c


def _peak(t: np.ndarray, y: np.ndarray, largest: bool = True) -> dict[str, float]:
    k = int(np.argmax(y) if largest else np.argmin(y))
    return {"value": float(y[k]), "time_s": float(t[k])}


def electric_summary(run: RunData) -> dict[str, Any] | None:
    """The electrical figures of a run, or None when it has no electrical system.

    Keys: ``mass_kg``; ``soc`` (start, end, min, max, time of the min); ``energy_kWh`` (whole run, from the
    counters: battery delivered (< 0 charged), shaft energy taken from each spool (< 0 delivered), losses,
    loads, shed); ``per_section`` (the same per mission section); ``peak_W`` (battery discharge and charge,
    LP boost and charge, HP offtake, load); ``mode_time_s`` (time in each energy management mode);
    ``limits_hit`` (as the summary's); ``balance_residual_J`` (machines, bus and battery; the battery's
    only when every step was recorded, else None).
    """
    if run.roles.electric is None:
        return None
    t = run.time_s
    soc, batt_W = _col(run, "soc"), _col(run, "battery_W")
    V, I = _col(run, "battery_V"), _col(run, "battery_A")
    lp, hp, load = _col(run, "offtake_lp_W"), _col(run, "offtake_hp_W"), _col(run, "load_W")
    E = {key: _col(run, name) for key, name in _COUNTERS}
    out: dict[str, Any] = {"component": run.roles.electric, "mass_kg": float(_col(run, "added_mass_kg")[-1])}
    kmin = int(np.argmin(soc))
    out["soc"] = {"start": float(soc[0]), "end": float(soc[-1]), "min": float(soc[kmin]),
                  "min_time_s": float(t[kmin]), "max": float(np.max(soc))}
    out["energy_kWh"] = {key: float(e[-1] - e[0]) / J_PER_KWH for key, e in E.items()}
    idx = run.get("fcs", "section_index")
    if idx is not None and len(t) > 1:
        owner = np.round(idx[:-1]).astype(int)
        out["per_section"] = [{"index": int(s), **{key: float(np.diff(e)[owner == s].sum()) / J_PER_KWH
                                                   for key, e in E.items()}} for s in np.unique(owner)]
    out["peak_W"] = {"battery_discharge": _peak(t, batt_W), "battery_charge": _peak(t, batt_W, largest=False),
                     "lp_boost": _peak(t, lp, largest=False), "lp_charge": _peak(t, lp),
                     "hp_offtake": _peak(t, hp), "load": _peak(t, load)}
    mode = run.get("electric", "ems_mode")
    if mode is not None and len(t) > 1:
        m = np.round(mode[1:]).astype(int)
        out["mode_time_s"] = {name: float(np.diff(t)[m == i].sum()) for i, name in enumerate(MODES)}
    out["limits_hit"] = {f: {**flag_stats(t, c), "source": f"{run.roles.electric}.{f}"}
                         for f in ELECTRIC_FLAGS if (c := run.get("electric", f)) is not None}
    res: dict[str, float] = {}
    cols = {n: run.get("electric", n) for n in ("E_shaft_hp_J", "E_shaft_lp_J", "E_elec_hp_J", "E_elec_lp_J",
                                                "E_loss_J", "E_loads_J", "E_shed_J", "E_batt_J")}
    if all(c is not None for c in cols.values()):
        d = {n: float(c[-1] - c[0]) for n, c in cols.items()}
        res["machines"] = d["E_shaft_hp_J"] + d["E_shaft_lp_J"] - d["E_elec_hp_J"] - d["E_elec_lp_J"] - d["E_loss_J"]
        res["bus"] = d["E_elec_hp_J"] + d["E_elec_lp_J"] + d["E_batt_J"] - d["E_loads_J"] + d["E_shed_J"]
        # the recorded V and I held over each step: exact with every step recorded, else not computed (None)
        step = run.info.get("step_size_s")
        every = len(t) > 1 and step is not None and bool(np.allclose(np.diff(t), step, rtol=1e-9, atol=1e-12))
        res["battery_VI"] = d["E_batt_J"] - float(held_increments(t, V * I).sum()) if every else None
    out["balance_residual_J"] = res
    return out
