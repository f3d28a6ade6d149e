"""Result of an off-design (or transient) steady match of the turbofan: :class:`OffDesignPoint`.

Kept apart from :mod:`.offdesign` (the matching) so that both modules stay small;
:mod:`.offdesign` re-exports it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .distortion import Distortion
from .flow import FlowStation

__all__ = ["OffDesignPoint"]


@dataclass(frozen=True)
class OffDesignPoint:
    """An off-design steady state (all SI; ``_pct`` in percent of the design value).

    Attributes
    ----------
    stations : Mapping[str, FlowStation]
        Every station, as in the design point.
    Fn_N, Fg_N, ram_drag_N, Wf_kg_s, SFC_kg_N_s : float
        Net and gross thrust, ram drag [N], fuel flow [kg/s], SFC [kg/(N s)].
    N1_rpm, N2_rpm, N1_pct, N2_pct, N1c_rpm, N1c_pct : float
        Spool speeds, and N1 corrected to the fan-face temperature.
    Tt4_K, T41_K, Tt21_K, Tt17_K, Tt7_K, Pt3_Pa, OPR, BPR : float
        Cycle temperatures [K], HPC delivery pressure [Pa], ratios [-].
    SM_fan, SM_hpc : float
        Surge margins [-] of the worst sector (NaN if the map does not provide them).
    SM_fan_clean, SM_hpc_clean : float
        Surge margins of the clean sector [-] (equal to SM_fan, SM_hpc without distortion).
    beta_fan, beta_hpc, PR_hpt, PR_lpt, handling_bleed_frac : float
        Map coordinates, turbine pressure ratios, handling bleed W/W25.
    iterations, evaluations : int
        Newton iterations and residual evaluations.
    residual_max : float
        max |r| at the solution [-].
    distortion : (Distortion or None, Distortion or None)
        Distortion at the fan and at the HPC face.
    """

    alt_m: float
    Mach: float
    dT_isa_K: float
    stations: Mapping[str, FlowStation]
    Fn_N: float
    Fg_N: float
    ram_drag_N: float
    Wf_kg_s: float
    SFC_kg_N_s: float
    N1_rpm: float
    N2_rpm: float
    N1_pct: float
    N2_pct: float
    N1c_rpm: float
    N1c_pct: float
    Tt4_K: float
    T41_K: float
    Tt21_K: float
    Tt17_K: float
    Tt7_K: float
    Pt3_Pa: float
    OPR: float
    BPR: float
    SM_fan: float
    SM_hpc: float
    SM_fan_clean: float
    SM_hpc_clean: float
    beta_fan: float
    beta_hpc: float
    PR_hpt: float
    PR_lpt: float
    handling_bleed_frac: float
    powers_W: Mapping[str, float]
    overboard_W_kg_s: float
    overboard_H_W: float
    iterations: int
    evaluations: int
    residual_max: float
    x: tuple[float, ...] = field(repr=False)
    jacobian: np.ndarray = field(repr=False, compare=False)
    distortion: tuple[Distortion | None, Distortion | None] = (None, None)

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (SI units in the key names) for JSON output."""
        skip = {"stations", "x", "jacobian", "powers_W", "distortion"}
        out: dict[str, Any] = {k: getattr(self, k) for k in self.__dataclass_fields__ if k not in skip}
        out["powers_W"] = dict(self.powers_W)
        for name, d in zip(("distortion_fan", "distortion_hpc"), self.distortion, strict=True):
            out[name] = None if d is None else {"sector_frac": d.sector_frac, "dPt_frac": d.dPt_frac,
                                                "dTt_K": d.dTt_K}
        out["stations"] = {k: {"W_kg_s": s.W_kg_s, "Tt_K": s.Tt_K, "Pt_Pa": s.Pt_Pa, "FAR": s.FAR}
                           for k, s in self.stations.items()}
        return out
