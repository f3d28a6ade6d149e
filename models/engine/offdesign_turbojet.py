"""Off-design steady state of the single-spool turbojet on scaled compressor and turbine maps.

Unknowns (scaled by their design values): inlet flow W2, compressor map
coordinate beta, spool speed N, turbine pressure ratio PR_t, fuel flow Wf.
Residuals: compressor map flow = W2 corrected; turbine map flow = W4
corrected; nozzle effective throat area = design; spool power balance; the
power setting (Wf, N, Tt4 or Fn). Solved by :func:`.newton.newton_solve`. The
gas path is the design's (:func:`.turbojet_path.turbojet_path`), with the maps.
This is the turbojet of pyCycle's ``simple_turbojet`` example, used to verify
the matching against pyCycle's published off-design numbers.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 7.
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from .atmosphere import free_stream
from .cycle_design import DesignPoint, gas_of
from .design_params import TurbojetParams
from .errors import ModelError, OutOfRangeError
from .flow import T_STD_K, FlowStation
from .newton import newton_solve
from .offdesign import CompressorMapLike, TurbineMapLike
from .shaft import net_power
from .turbojet_path import turbojet_path

__all__ = ["TurbojetOffDesignPoint", "TurbojetOffDesign", "scaled_turbojet_maps", "RESIDUALS_TURBOJET"]

#: Residual names, in order.
RESIDUALS_TURBOJET: tuple[str, ...] = ("compressor_flow", "turbine_flow", "nozzle_area", "power", "power_setting")


def scaled_turbojet_maps(dp: DesignPoint, comp: str = "axi5", turb: str = "lpt2269"
                         ) -> tuple[CompressorMapLike, TurbineMapLike, float]:
    """(compressor map, turbine map, design beta) of :mod:`.maps`, scaled to the design point `dp`."""
    from .map_loading import load_compressor_map, load_turbine_map
    from .map_scaled import ScaledCompressorMap, ScaledTurbineMap
    c, t = dp.components["compressor"], dp.components["turbine"]
    cm = ScaledCompressorMap.from_design(load_compressor_map(comp), c.Wc_kg_s, c.PR, c.eta_is, c.Nc_rpm)
    tm = ScaledTurbineMap.from_design(load_turbine_map(turb), t.Wc_kg_s, t.PR, t.eta_is, t.Nc_rpm)
    return cm, tm, cm.beta_map


@dataclass(frozen=True)
class TurbojetOffDesignPoint:
    """An off-design steady state of the turbojet (SI units).

    Attributes
    ----------
    stations : Mapping[str, FlowStation]
        Stations 0 to 8.
    Fn_N, Fg_N, ram_drag_N, Wf_kg_s, SFC_kg_N_s : float
        Thrust [N], fuel flow [kg/s], SFC [kg/(N s)].
    N_rpm, N_pct, Nc_rpm : float
        Spool speed [rpm], [% of design], corrected to the compressor inlet [rpm].
    Tt4_K, OPR, beta, PR_t : float
        Burner exit temperature [K], Pt3/Pt2, compressor map beta, turbine PR.
    iterations, evaluations : int
        Newton iterations and residual evaluations.
    residual_max : float
        max |r| at the solution [-].
    """

    stations: Mapping[str, FlowStation]
    Fn_N: float
    Fg_N: float
    ram_drag_N: float
    Wf_kg_s: float
    SFC_kg_N_s: float
    N_rpm: float
    N_pct: float
    Nc_rpm: float
    Tt4_K: float
    OPR: float
    beta: float
    PR_t: float
    iterations: int
    evaluations: int
    residual_max: float
    x: tuple[float, ...] = field(repr=False)
    jacobian: np.ndarray = field(repr=False, compare=False)


class TurbojetOffDesign:
    """Off-design model of a turbojet sized by its design point `dp`, on maps scaled to it."""

    def __init__(self, dp: DesignPoint, comp_map: CompressorMapLike, turb_map: TurbineMapLike,
                 beta_design: float = 0.5) -> None:
        if not isinstance(dp.params, TurbojetParams):
            raise ModelError("TurbojetOffDesign needs a turbojet design point")
        self.dp, self.p, self.gas = dp, dp.params, gas_of(dp.params)
        self.cm, self.tm = comp_map, turb_map
        c, t = dp.components["compressor"], dp.components["turbine"]
        self.ref = dict(W2=dp.W2_kg_s, Wc2=c.Wc_kg_s, Wc4=t.Wc_kg_s, A8=dp.nozzles["core"].A_eff_m2,
                        P=c.power_W, Wf=dp.Wf_kg_s, Fn=dp.Fn_N, Tt4=dp.Tt4_K, PRt=t.PR)
        self.x_design = (1.0, beta_design, 1.0, 1.0, 1.0)

    def _cycle(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float]
               ) -> tuple[np.ndarray, dict[str, Any]]:
        p, g, ref = self.p, self.gas, self.ref
        W2, beta, N, PRt, Wf = x[0] * ref["W2"], x[1], x[2] * p.N_rpm, x[3] * ref["PRt"], x[4] * ref["Wf"]
        if W2 <= 0.0 or N <= 0.0 or PRt < 1.0 or Wf <= 0.0:
            raise OutOfRangeError("offdesign_turbojet: unknowns out of range")
        fr = free_stream(*cond, g)
        Nc = N / math.sqrt(fr.Tt0_K / T_STD_K)          # the inlet is adiabatic: Tt2 = Tt0

        def comp_point(st2: FlowStation) -> tuple[float, float, float]:
            Wc, PR, eff = self.cm.evaluate(Nc, beta)
            return PR, eff, Wc

        def turb_point(st4: FlowStation) -> tuple[float, float]:
            Wc, eff = self.tm.evaluate(N / math.sqrt(st4.Tt_K / T_STD_K), PRt)
            return eff, Wc

        gp = turbojet_path(p, g, fr, W2, comp_point, Wf, PRt, turb_point)
        st, Fn = gp.stations, gp.Fn_N
        Wc_c, Wc_t = gp.Wc_map_compressor_kg_s, gp.Wc_map_turbine_kg_s
        kind, value = demand
        r5 = {"Wf_kg_s": lambda: (Wf - value) / ref["Wf"], "N_rpm": lambda: (N - value) / p.N_rpm,
              "Tt4_K": lambda: (st["4"].Tt_K - value) / ref["Tt4"], "Fn_N": lambda: (Fn - value) / ref["Fn"]}[kind]()
        r = np.array([(Wc_c - st["2"].Wc_kg_s) / ref["Wc2"], (Wc_t - st["4"].Wc_kg_s) / ref["Wc4"],
                      gp.nozzle.A_eff_m2 / ref["A8"] - 1.0,
                      net_power(gp.turbine.power_W, [gp.compressor.power_W], p.offtake_W, p.eta_mech) / ref["P"],
                      r5])
        return r, dict(st=st, Fn=Fn, Fg=gp.nozzle.Fg_N, ram=gp.ram_drag_N, Wf=Wf, N=N, Nc=Nc, beta=beta, PRt=PRt)

    def solve(self, alt_m: float = 0.0, Mach: float = 0.0, dT_isa_K: float = 0.0, *,
              Wf_kg_s: float | None = None, N_rpm: float | None = None, Tt4_K: float | None = None,
              Fn_N: float | None = None, guess: TurbojetOffDesignPoint | None = None,
              tol: float = 1e-9) -> TurbojetOffDesignPoint:
        """Steady state at a flight condition [m, -, K] and exactly one power setting.

        Raises
        ------
        ConvergenceError
            If the matching does not converge; the message names the residuals.
        """
        given = {"Wf_kg_s": Wf_kg_s, "N_rpm": N_rpm, "Tt4_K": Tt4_K, "Fn_N": Fn_N}
        set_ = [(k, v) for k, v in given.items() if v is not None]
        if len(set_) != 1:
            raise ModelError(f"offdesign_turbojet.solve: give exactly one power setting of {', '.join(given)}")
        cond, demand = (alt_m, Mach, dT_isa_K), set_[0]
        free_stream(*cond, self.gas)
        x0 = np.array(guess.x if guess is not None else self.x_design)
        last: dict[str, Any] = {}

        def resid(x: np.ndarray) -> np.ndarray:
            r, info = self._cycle(x, cond, demand)
            last["x"], last["info"] = x.copy(), info
            return r

        res = newton_solve(resid, x0, RESIDUALS_TURBOJET, tol=tol,
                           jacobian=guess.jacobian if guess is not None else None,
                           where=f"turbojet offdesign of {self.p.name!r} at alt {alt_m} m, Mach {Mach}")
        i = last["info"] if "x" in last and np.array_equal(last["x"], res.x) else self._cycle(res.x, cond, demand)[1]
        st = i["st"]
        return TurbojetOffDesignPoint(
            MappingProxyType(st), i["Fn"], i["Fg"], i["ram"], i["Wf"], i["Wf"] / i["Fn"] if i["Fn"] > 0 else math.inf,
            i["N"], 100.0 * i["N"] / self.p.N_rpm, i["Nc"], st["4"].Tt_K, st["3"].Pt_Pa / st["2"].Pt_Pa, i["beta"],
            i["PRt"], res.iterations, res.evaluations, float(np.max(np.abs(res.r))), tuple(float(v) for v in res.x),
            res.jacobian)
