"""JSBSim alone on the flight a coupled run flew: the airframe model replayed on the run's recorded inputs.

Used by ``benchmarks/mission.py`` (the same process, right after the coupled run, so that the ratio of the two
is free of the machine's load): the airframe's connected inputs are read from the run's recorded columns (each
input's source output, through its link's affine map; with Jacobi the step from t_k takes the samples at t_k),
and the airframe model (:class:`openemss.models.airframe.adapter.Airframe`, JSBSim with our SI conversions, no
FMU, no master) is started as the Airframe FMU starts it and stepped over the same macro steps with them. Two
loops are timed, each the best of ``repeat``:

* ``model``: what the FMU's ``do_step`` asks of the model (every input set through the adapter, then its step);
* ``JSBSim``: the same inputs written straight to JSBSim's property nodes and ``FGFDMExec.run`` at the
  internal rate, with the tank's fuel written every internal step as the adapter does: the flight dynamics'
  own cost, the floor of the airframe.

The fuel on board at the end of each replay is returned beside the run's: equal numbers show the replay flew
the run's flight. Only a runway start with the default mission's runway and the FMU's default weather is
replayed (the shipped system); anything else returns None with the reason.
"""
from __future__ import annotations

import gc
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: The airframe's inputs the FMU's do_step passes to the model, in its order.
INPUTS = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "airbrake_norm", "gear_down",
          "brakes_norm", "steering_norm", "Fn_N", "Wf_kg_s", "added_mass_kg")
#: The airframe's parameters the replay starts the model with; any other away from its default is refused.
HONOURED = ("fuel0_kg", "flaps0_norm", "rate_hz")


@dataclass(frozen=True)
class Replay:
    """Timings of the replays [s per macro step] and the fuel at their end [kg]."""

    model_s: float
    jsbsim_s: float
    steps: int
    fuel_kg: float
    run_fuel_kg: float


def _columns(run_file: Path) -> Any:
    import pandas as pd
    return pd.read_parquet(run_file) if run_file.suffix == ".parquet" else pd.read_csv(run_file)


def airframe_inputs(bound: Any, component: str, table: Any, steps: int) -> tuple[dict[str, np.ndarray], str]:
    """Per input of ``INPUTS``: its value at each of ``steps`` macro steps (its source's recorded column, or its
    start value when unconnected); and a reason when the run's columns do not hold them ("" when they do)."""
    i = next((k for k, c in enumerate(bound.components) if c.name == component), None)
    if i is None:
        return {}, f"no component '{component}'"
    defaults, starts = _starts(bound, i)
    out: dict[str, np.ndarray] = {}
    for name in INPUTS:
        ln = next((ln for ln in bound.links if ln.target == i and ln.target_var.name == name), None)
        if ln is None:
            out[name] = np.full(steps, float(starts[name]))
            continue
        col = f"{bound.components[ln.source].name}.{ln.source_var.name}"
        if col not in table:
            return {}, f"the run did not record {col}"
        x = table[col].to_numpy(dtype=float)[:steps]
        out[name] = ln.affine.scale * x + ln.affine.offset
    from openemss.models.airframe.airframe_signals import SIGNALS
    for key in sorted(s.name for s in SIGNALS if s.causality == "parameter" and s.name not in HONOURED
                      and starts[s.name] != defaults[s.name]):
        return {}, f"the airframe's parameter {key} is not its default (only the shipped start is replayed)"
    return out, ""


def _starts(bound: Any, i: int) -> tuple[dict[str, Any], dict[str, Any]]:
    """The airframe's start values: the table's, and those with the system's parameters of component ``i``."""
    from openemss.models.airframe.airframe_signals import SIGNALS
    defaults = {s.name: s.start for s in SIGNALS}
    return defaults, {**defaults, **{p.variable.name: p.value for p in bound.parameters if p.component == i}}


def _started(rate_hz: float, fuel_kg: float, flaps: float, added_kg: float) -> Any:
    from openemss.models.airframe.adapter import Airframe
    from openemss.models.mission.mission import departure_runway, load_mission
    rwy = departure_runway(load_mission(ROOT / "missions" / "munich.yaml"))  # the FMU's DEFAULT_MISSION
    m = Airframe(rate_hz=rate_hz)
    m.set_added_mass(added_kg)
    m.start_runway(rwy.threshold.lat_deg, rwy.threshold.lon_deg, math.degrees(rwy.heading_rad), rwy.elevation_m,
                   fuel_kg=fuel_kg, flaps=flaps)
    return m


def _model_loop(m: Any, u: dict[str, np.ndarray], h: float) -> None:
    cols = [u[n].tolist() for n in INPUTS]
    for ail, ele, rud, flp, ab, gear, brk, steer, thr, wf, added in zip(*cols, strict=True):
        m.set_surfaces(ail, ele, rud)
        m.set_flaps(flp)
        m.set_airbrake(ab)
        m.set_gear(gear)
        m.set_brakes(brk, brk)
        m.set_steering(steer)
        m.set_thrust(thr)
        m.set_fuel_flow(wf)
        m.set_added_mass(added)
        m.step(h)


def _jsbsim_loop(m: Any, u: dict[str, np.ndarray], h: float) -> float:
    """The inputs straight into JSBSim's property nodes (English units, clipped as the adapter clips them)."""
    from openemss.models.airframe.adapter import LBF, LBM
    fdm = m.fdm
    pm = fdm.get_property_manager()
    nodes = [pm.get_node(p, True).set_double_value for p in (
        "fcs/aileron-cmd-norm", "fcs/elevator-cmd-norm", "fcs/rudder-cmd-norm", "fcs/flap-cmd-norm",
        "fcs/airbrake-cmd-norm", "gear/gear-cmd-norm", "fcs/left-brake-cmd-norm", "fcs/right-brake-cmd-norm",
        "fcs/steer-cmd-norm", "external_reactions/thrust/magnitude")]
    tank = pm.get_node("propulsion/tank[0]/contents-lbs").set_double_value
    run = fdm.run
    n = round(h * m.rate_hz)
    dt = m.dt_s
    fuel = m.fuel_kg
    cols = [np.clip(u[k], lo, 1.0).tolist() for k, lo in (("aileron_norm", -1.0), ("elevator_norm", -1.0),
                                                            ("rudder_norm", -1.0), ("flaps_norm", 0.0),
                                                            ("airbrake_norm", 0.0))]
    cols.append(np.where(u["gear_down"] >= 0.5, 1.0, 0.0).tolist())
    brakes = np.clip(u["brakes_norm"], 0.0, 1.0).tolist()
    cols += [brakes, brakes, np.clip(u["steering_norm"], -1.0, 1.0).tolist(), (u["Fn_N"] / LBF).tolist()]
    burns = (u["Wf_kg_s"] * dt).tolist()
    for row in zip(*cols, burns, strict=True):
        for set_value, x in zip(nodes, row, strict=False):
            set_value(x)
        burn = row[-1]
        for _ in range(n):
            if burn > 0.0:
                fuel = fuel - burn if fuel > burn else 0.0
                tank(fuel / LBM)
            run()
    return fuel


def replay(bound: Any, run_file: Path, steps: int, h: float, repeat: int = 3,
           component: str = "airframe") -> Replay | str:
    """Replay the airframe of ``bound`` over the first ``steps`` macro steps of ``h`` [s] recorded in
    ``run_file`` (parquet or csv); the best of ``repeat`` per loop. A string says why it could not."""
    table = _columns(run_file)
    if len(table) < steps + 1:
        return f"the run recorded {len(table)} rows for {steps} steps (record every step for the replay)"
    u, why = airframe_inputs(bound, component, table, steps)
    if why:
        return why
    _, starts = _starts(bound, next(k for k, c in enumerate(bound.components) if c.name == component))
    args = (float(starts["rate_hz"]), float(starts["fuel0_kg"]), float(starts["flaps0_norm"]),
            float(u["added_mass_kg"][0]))
    best = {"model": math.inf, "jsbsim": math.inf}
    fuel = {}
    for _ in range(repeat):
        for way in best:
            m = _started(*args)
            gc.collect()
            gc.disable()
            t0 = time.perf_counter()
            try:
                if way == "model":
                    _model_loop(m, u, h)
                    f = m.fuel_kg
                else:
                    f = _jsbsim_loop(m, u, h)
            finally:
                dt = time.perf_counter() - t0
                gc.enable()
            m.close()
            best[way] = min(best[way], dt)
            fuel[way] = f
    col = f"{component}.fuel_kg"
    run_fuel = float(table[col].iloc[steps]) if col in table else math.nan
    return Replay(best["model"] / steps, best["jsbsim"] / steps, steps, fuel["model"], run_fuel)
