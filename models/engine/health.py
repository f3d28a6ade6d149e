"""Health parameters of the turbomachines: deterioration as changes of flow capacity and efficiency.

Gas path analysis describes a deteriorated compressor or turbine by two health parameters, the relative
changes of its flow capacity and of its isentropic efficiency against the clean component at the same
corrected speed and map position (fouling: both fall; erosion and tip clearance: efficiency falls, flow
capacity falls for a compressor and rises for a turbine). They act where the map scalars act
(:mod:`.map_scaled`): ``Wc = Wc_map s_Wc (1 + Wc_frac)`` and ``eta = eta_map s_eff (1 + eta_frac)``, on
the fan, HPC, HPT and LPT maps (a booster keeps its clean map), so the surge line moves with the map.

The engine FMU takes them as tunable parameters ``health_<component>_<eta|Wc>_frac`` (a parameter set
gives a degraded engine, a scenario ramps them over a run); :meth:`.engine_model.EngineModel.set_health`
applies them between steps.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., Blackwell, 2004 (engine deterioration,
component fouling and erosion as changes of flow capacity and efficiency; cited from memory, chapters not
checked against a copy).
A. J. Volponi, "Gas turbine engine health management: past, present, and future trends", J. Eng. Gas
Turbines Power 136(5), 051201, 2014 (health parameters of gas path analysis).
H. I. H. Saravanamuttoo, B. D. MacIsaac, "Thermodynamic models for pipeline gas turbine diagnostics",
J. Eng. Power 105(4), 875-884, 1983.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

from .errors import OutOfRangeError

__all__ = ["HealthDeltas", "COMPONENTS", "HEALTH_LIMIT", "health_parameter_names", "health_parameters",
           "MID_LIFE"]

#: The components with health parameters, in the order of the gas path's maps (fan, HPC, HPT, LPT).
COMPONENTS: tuple[str, ...] = ("fan", "hpc", "hpt", "lpt")
#: Largest magnitude of a health delta [-]: beyond 20 % a map scaled this way is no longer a deteriorated
#: engine of the same design (deterioration over an engine's life is a few per cent; a bound, not a measurement).
HEALTH_LIMIT = 0.2


@dataclass(frozen=True)
class HealthDeltas:
    """Relative changes of flow capacity and efficiency per component [-], 0 for a clean engine."""

    fan_eta_frac: float = 0.0
    fan_Wc_frac: float = 0.0
    hpc_eta_frac: float = 0.0
    hpc_Wc_frac: float = 0.0
    hpt_eta_frac: float = 0.0
    hpt_Wc_frac: float = 0.0
    lpt_eta_frac: float = 0.0
    lpt_Wc_frac: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v) or \
                    abs(v) > HEALTH_LIMIT:
                raise OutOfRangeError(f"health_{f.name}={v!r}: a health delta must be a finite number in "
                                      f"[-{HEALTH_LIMIT:g}, {HEALTH_LIMIT:g}] (relative change)")

    def factors(self) -> tuple[tuple[float, float], ...]:
        """Per component of :data:`COMPONENTS`: (flow capacity factor, efficiency factor) [-]."""
        return tuple((1.0 + getattr(self, f"{c}_Wc_frac"), 1.0 + getattr(self, f"{c}_eta_frac")) for c in COMPONENTS)

    @property
    def clean(self) -> bool:
        """No delta set."""
        return all(getattr(self, f.name) == 0.0 for f in fields(self))


def health_parameter_names() -> tuple[str, ...]:
    """The FMU parameters, ``health_<field>``, in the order of :class:`HealthDeltas`' fields."""
    return tuple(f"health_{f.name}" for f in fields(HealthDeltas))


#: A mid-life deterioration for studies (``ssp/engine_degraded.ssv``): compressors fouled and eroded (flow
#: capacity and efficiency down), turbines eroded with opened tip clearances (efficiency down, flow capacity
#: up), a few per cent at most, the size of deterioration over an engine's time between overhauls.
#: Illustrative, not a measured engine, and not checked against a published deterioration table.
MID_LIFE = HealthDeltas(fan_eta_frac=-0.01, fan_Wc_frac=-0.01, hpc_eta_frac=-0.02, hpc_Wc_frac=-0.02,
                        hpt_eta_frac=-0.015, hpt_Wc_frac=0.01, lpt_eta_frac=-0.01, lpt_Wc_frac=0.005)


def health_parameters(h: HealthDeltas) -> dict[str, float]:
    """The engine FMU's parameters (``health_<field>``) of a set of health deltas."""
    return {f"health_{f.name}": float(getattr(h, f.name)) for f in fields(h)}
