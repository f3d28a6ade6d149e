"""Before ``emss run``: the flight control's performance data of the system flown (the report plugin's
``prepare`` hook, :mod:`openemss.orchestrator.cli.plugins`).

The flight control flies only the performance database of the airframe and the engine it is wired to
(their identities, :func:`openemss.models.fcs.performance.performance_for`); it cannot make one (the FCS FMU
carries no airframe or engine model). This hook makes it, in the master's process, from the system as it will
fly: the engine of the system's parameters (as the mission check reads them, :func:`.mission_check.
setup_from_system`: ``engine_file`` and ``thrust_scale``, else ``preset``, ``design_override`` and its ``design_*``
values), the airframe model's
aircraft and the flight control's limits (``fuel_control.k_delta_pct``, ``N1_max_pct``, ``Tt41_max_K``), and
keeps it in the cache folder (:func:`openemss.models.infra.config_id.cache_dir`) under its key, so that a
system is generated once (:mod:`openemss.models.performance.generate`: about 3 s of CPU for a preset engine, 100 s
for an engine file, whose steady states are solved on its graph). The shipped system
flies the shipped database: nothing is generated.
"""
from __future__ import annotations

import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from openemss.models.infra.config_id import LIMIT_NAMES

from .mission_check import setup_from_system

__all__ = ["prepare"]


def prepare(components: Mapping[str, Path], parameters: Mapping[str, Any]) -> list[str]:
    """The performance data of the system about to run, generated into the cache when it has none: one line of
    news then (what, in how long, where); nothing for a system without a flight control or whose data exist, and
    nothing for parameters that cannot be read as a system (the FMU that refuses them says why, in one line, at its
    start). A generation that fails raises (one warning line; the flight control then refuses to start without its
    data)."""
    try:
        setup = setup_from_system(components, parameters)
    except Exception:  # noqa: BLE001 -- a value the system's FMUs refuse at their start, each in its own one line
        return []
    if setup is None:
        return []
    from openemss.models.airframe.adapter import Airframe
    from openemss.models.performance.generate import EngineFile, ensure_cached

    limits = {n: setup.parameters[f"fuel_control.{n}"] for n in LIMIT_NAMES}
    engine = EngineFile(setup.engine_file, setup.thrust_scale) if setup.engine_file else setup.engine
    label = f"{setup.engine_file} x {setup.thrust_scale:g}" if setup.engine_file else setup.engine_label
    cpu0 = time.process_time()
    airframe = Airframe(aircraft=setup.aircraft) if setup.aircraft else Airframe()
    path, seconds = ensure_cached(engine, airframe, limits)
    if seconds is None:
        return []
    return [f"performance data of the aircraft with the engine {label} generated in {seconds:.1f} s "
            f"({time.process_time() - cpu0:.1f} s of CPU): {path}"]
