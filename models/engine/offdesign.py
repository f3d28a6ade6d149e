"""Off-design steady state of the two-spool separate-flow turbofan, matched on component maps.

Unknowns (scaled to order 1 by their design values): inlet flow W2, fan and
HPC map coordinates beta_fan and beta_hpc, spool speeds N1 and N2, turbine
pressure ratios PR_hpt and PR_lpt, bypass ratio BPR and fuel flow Wf. Residuals:

1. fan map corrected flow = W2 corrected;       2. HPC map flow = W25 corrected;
3. HPT map flow = W4 corrected;                  4. LPT map flow = W45 corrected;
5. core nozzle: effective throat area = design;  6. bypass nozzle: same;
7. HP spool power balance;                       8. LP spool power balance;
9. the power setting: Wf, N1, N1 corrected, Tt4 or Fn equal to the demand.

Solved with :func:`.newton.newton_solve` (Broyden updates, Jacobian reuse for
warm starts) to max |r| < 1e-9 by default; if it fails, a
:class:`~.errors.ConvergenceError` names every residual.

The fan is one map for the whole fan (scaled to the bypass stream's design
PR and efficiency); the core (inner) stream keeps the design ratio of the
pressure rises, (PR_inner - 1) = k (PR_outer - 1), and of the efficiencies.
Duct and burner pressure losses and nozzle coefficients keep their design
values. The handling bleed (HPC stage k into the bypass) opens as the corrected
fan speed N1c = N1 / sqrt(Tt2 / 288.15 K) falls below its threshold (default 60 %
of the design's corrected N1), with a C1 ramp 10 % wide (a parameter): the reference
engine (the Larzac 04 of the reference study) blows handling air off behind the
second HPC stage "under a relative speed of 60 %" of its LP spool. The ramp is this
wide so that the steady working line stays monotonic in fuel flow: opening the bleed
(10 % of the HPC flow) at a given N1 needs 12 to 16 % more fuel; over a ramp of 2 % (or
6 %: the C1 ramp's steepest slope is 1.5 times its mean) that is more than the fuel the
same change of N1 saves, and one fuel flow would have three steady states, between
which Newton stalls (a start at a given fuel flow near the switch failed). In time the valve is an on/off valve with
hysteresis (:class:`.engine_signals.BleedValve`).

Maps are anything with the methods of :class:`CompressorMapLike` and
:class:`TurbineMapLike`, scaled to the design point (corrected speeds in rpm,
corrected flows in kg/s at 288.15 K, 101325 Pa) -- :mod:`.map_scaled` provides
them, :func:`scaled_maps` builds the default set.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 7
(off-design matching, the matching unknowns and equations).
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (balances of the
off-design turbofan: W, BPR, N1, N2, turbine PRs, FAR).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol

import numpy as np

from .atmosphere import free_stream
from .cycle_design import DesignPoint, gas_of
from .design_params import TurbofanParams
from .distortion import Distortion
from .errors import ConvergenceError, ModelError, OutOfRangeError
from .flow import FlowStation
from .gas_path import SINK as _SINK_CODE
from .inlet import ram_recovery_mil_e_5008b
from .newton import newton_solve
from .offdesign_result import OffDesignPoint
from .shaft import TURBOFAN_SHAFTS

__all__ = ["CompressorMapLike", "TurbineMapLike", "TurbofanMaps", "OffDesignPoint", "TurbofanOffDesign",
           "scaled_maps", "RESIDUALS"]

#: Residual names, in order.
RESIDUALS: tuple[str, ...] = ("fan_flow", "hpc_flow", "hpt_flow", "lpt_flow", "core_nozzle_area",
                              "bypass_nozzle_area", "hp_power", "lp_power", "power_setting")


class CompressorMapLike(Protocol):
    """A compressor map scaled to the design point, as a table the gas path reads
    (:class:`.map_scaled.ScaledCompressorMap`, or a function tabulated by :func:`.map_scaled.tabulate_map`)."""

    def evaluate(self, Nc: float, beta: float) -> tuple[float, float, float]:
        """(corrected flow [kg/s], pressure ratio [-], isentropic efficiency [-]) at corrected speed [rpm], beta [-]."""
        ...

    def kernel_tuple(self) -> tuple[Any, ...]:
        """The table's arrays and scalars (:data:`.map_scaled.KernelMap`)."""
        ...


class TurbineMapLike(Protocol):
    """A turbine map scaled to the design point, as a table the gas path reads."""

    def evaluate(self, Nc: float, PR: float) -> tuple[float, float]:
        """(inlet corrected flow [kg/s], isentropic efficiency [-]) at corrected speed [rpm], PR in/out [-]."""
        ...

    def kernel_tuple(self) -> tuple[Any, ...]:
        """The table's arrays and scalars (:data:`.map_scaled.KernelMap`)."""
        ...


@dataclass(frozen=True)
class TurbofanMaps:
    """The maps of the turbofan (a booster map only for an engine with a booster) and the beta
    of the design point on the compressor maps."""

    fan: CompressorMapLike
    hpc: CompressorMapLike
    hpt: TurbineMapLike
    lpt: TurbineMapLike
    beta_fan_design: float = 0.5
    beta_hpc_design: float = 0.5
    booster: CompressorMapLike | None = None
    beta_booster_design: float = 0.5


def scaled_maps(dp: DesignPoint, fan: str = "lpc_hbtf", hpc: str = "axi5", hpt: str = "hpt1269",
                lpt: str = "lpt2269", booster: str = "lpc_hbtf", extended: bool = True) -> TurbofanMaps:
    """Maps of :mod:`.maps` scaled to the design point `dp` (corrected speeds in rpm); the booster
    map only if the design has a booster (PR_booster > 1). With `extended` (default) the maps carry
    the sub-idle extension of :mod:`.map_extension` (the original nodes unchanged)."""
    from .map_loading import load_compressor_map, load_turbine_map
    from .map_scaled import ScaledCompressorMap, ScaledTurbineMap
    c = dp.components
    fo = c["fan_outer"]
    W2c = dp.stations["2"].Wc_kg_s
    ext = {"extended": extended}
    f = ScaledCompressorMap.from_design(load_compressor_map(fan, **ext), W2c, fo.PR, fo.eta_is, fo.Nc_rpm)
    h = ScaledCompressorMap.from_design(load_compressor_map(hpc, **ext), c["hpc"].Wc_kg_s, c["hpc"].PR,
                                        c["hpc"].eta_is, c["hpc"].Nc_rpm)
    t1 = ScaledTurbineMap.from_design(load_turbine_map(hpt, **ext), c["hpt"].Wc_kg_s, c["hpt"].PR,
                                      c["hpt"].eta_is, c["hpt"].Nc_rpm)
    t2 = ScaledTurbineMap.from_design(load_turbine_map(lpt, **ext), c["lpt"].Wc_kg_s, c["lpt"].PR,
                                      c["lpt"].eta_is, c["lpt"].Nc_rpm)
    b, b_beta = None, 0.5
    if isinstance(dp.params, TurbofanParams) and dp.params.PR_booster > 1.0:
        cb = c["booster"]
        b = ScaledCompressorMap.from_design(load_compressor_map(booster, **ext), cb.Wc_kg_s, cb.PR, cb.eta_is,
                                            cb.Nc_rpm)
        b_beta = b.beta_map
    return TurbofanMaps(f, h, t1, t2, f.beta_map, h.beta_map, b, b_beta)


class TurbofanOffDesign:
    """Off-design model of a turbofan sized by a design point.

    Parameters
    ----------
    dp : DesignPoint
        Turbofan design point (sizes the nozzles, scales the maps).
    maps : TurbofanMaps
        Maps scaled to `dp`.
    handling_bleed_open_frac : float
        Handling bleed W/W25 [-] when fully open.
    handling_bleed_N1c_pct : float
        Corrected N1 [% of the design's corrected N1] below which the bleed is open (centre of the ramp).
    handling_bleed_ramp_pct : float
        Width of the steady schedule's C1 ramp [% of the design's corrected N1]: closed above threshold +
        width/2, fully open below threshold - width/2 (see the module docstring for why 10 %).
    """

    def __init__(self, dp: DesignPoint, maps: TurbofanMaps, handling_bleed_open_frac: float = 0.10,
                 handling_bleed_N1c_pct: float = 60.0, handling_bleed_ramp_pct: float = 10.0) -> None:
        p = dp.params
        if not isinstance(p, TurbofanParams):
            raise ModelError("TurbofanOffDesign needs a turbofan design point")
        if p.PR_booster > 1.0 and maps.booster is None:
            raise ModelError(f"{p.name}: off-design of an engine with a booster (PR_booster={p.PR_booster}) "
                             "needs a booster map (TurbofanMaps.booster)")
        self.nb = 1 if p.PR_booster > 1.0 else 0
        if not (0.0 <= handling_bleed_open_frac < 0.5):
            raise OutOfRangeError(f"handling_bleed_open_frac={handling_bleed_open_frac!r} is outside [0, 0.5)")
        self.dp, self.p, self.maps, self.gas = dp, p, maps, gas_of(p)
        if not handling_bleed_ramp_pct > 0.0:
            raise OutOfRangeError(f"handling_bleed_ramp_pct={handling_bleed_ramp_pct!r} must be > 0")
        self.hb_open, self.hb_N1c = handling_bleed_open_frac, handling_bleed_N1c_pct / 100.0
        self.hb_ramp = handling_bleed_ramp_pct / 100.0
        c = dp.components
        self.k_inner = (p.PR_fan_inner - 1.0) / (p.PR_fan_outer - 1.0)
        self.eff_ratio_inner = p.eta_fan_inner / p.eta_fan_outer
        st = dp.stations
        self.ref: dict[str, float] = dict(
                        W2=st["2"].W_kg_s, Wc2=st["2"].Wc_kg_s, Wc25=c["hpc"].Wc_kg_s, Wc4=c["hpt"].Wc_kg_s,
                        Wc45=c["lpt"].Wc_kg_s, A8=dp.nozzles["core"].A_eff_m2, A18=dp.nozzles["bypass"].A_eff_m2,
                        P_hp=c["hpc"].power_W, P_lp=c["fan_outer"].power_W + c["fan_inner"].power_W,
                        Wf=dp.Wf_kg_s, Fn=dp.Fn_N, Tt4=dp.Tt4_K, PRh=c["hpt"].PR, PRl=c["lpt"].PR)
        self.ref["Wc21"] = c["booster"].Wc_kg_s
        self.ref["Nc1"] = c["fan_outer"].Nc_rpm                     # design corrected N1 [rpm]
        self.eta_mech = np.array([p.eta_mech_hp, p.eta_mech_lp])     # per spool of shaft.SPOOLS
        losses = dict(dPqP_21_24=p.dPqP_21_24, dPqP_24_25=p.dPqP_24_25, dPqP_burner=p.dPqP_burner,
                      dPqP_44_45=p.dPqP_44_45, dPqP_5_7=p.dPqP_5_7, dPqP_13_17=p.dPqP_13_17)
        for k, v in losses.items():
            if not 0.0 <= v < 1.0:
                raise OutOfRangeError(f"{p.name}: {k}={v!r} is outside [0, 1)")
        for k, v in dict(inlet_pi=p.inlet_pi, Cv_core=p.Cv_core, Cd_core=p.Cd_core, Cv_bypass=p.Cv_bypass,
                         Cd_bypass=p.Cd_bypass).items():
            if not 0.0 < v <= 1.0:
                raise OutOfRangeError(f"{p.name}: {k}={v!r} is outside (0, 1]")
        self._fast: Any = None                              # the compiled residuals, built on first use
        self.x_design = (1.0, maps.beta_fan_design, maps.beta_hpc_design, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0) + (
            (maps.beta_booster_design,) if self.nb else ())

    def residual_names(self, dist: tuple[Distortion | None, Distortion | None]) -> tuple[str, ...]:
        """Names of the residuals for a distortion configuration, in order."""
        return RESIDUALS + ("booster_flow",) * self.nb + tuple(
            n for n, d in zip(("fan_sector_pressure", "hpc_sector_pressure"), dist, strict=True) if d is not None)

    # ------------------------------------------------------------------ cycle
    @property
    def fast(self) -> Any:
        """The gas path's packed arguments and output arrays (:class:`.jit_cycle.FastCycle`), built on first use."""
        if self._fast is None:
            from .jit_cycle import FastCycle
            self._fast = FastCycle.build(self)
        return self._fast

    def n_unknowns(self, dist: tuple[Distortion | None, Distortion | None]) -> int:
        """Number of unknowns (and residuals) for a distortion configuration."""
        return 9 + self.nb + sum(d is not None for d in dist)

    def _evaluate(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float],
                  extras: tuple[float, float, float], dist: tuple[Distortion | None, Distortion | None],
                  hb_frac: float | None, with_sm: bool = False) -> Any:
        """The gas path (:func:`.gas_path.turbofan`) at unknowns `x`, into the arrays of :attr:`fast`; raises
        :class:`~.errors.OutOfRangeError` with the component and the cause where it cannot be evaluated."""
        from .gas_path import ERRORS, STAGES
        from .jit_cycle import DEMAND
        n = self.n_unknowns(dist)
        if x.shape != (n,):
            raise ModelError(f"offdesign of {self.p.name!r}: {x.shape} unknowns given, {n} expected")
        fc = self.fast
        code = fc.evaluate(x, cond, (DEMAND[demand[0]], demand[1]), extras, hb_frac, _dist_array(dist), with_sm)
        if code:
            raise OutOfRangeError(f"offdesign of {self.p.name!r}: {STAGES[int(fc.err[1])] or 'gas path'}: "
                                  f"{ERRORS.get(code, f'error {code}')}")
        return fc

    def _residuals(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float],
                   extras: tuple[float, float, float], dist: tuple[Distortion | None, Distortion | None] = (None, None),
                   hb_frac: float | None = None) -> np.ndarray:
        """The residuals (:func:`residual_names`) at unknowns `x`."""
        return self._evaluate(x, cond, demand, extras, dist, hb_frac).r[:x.size].copy()

    def _cycle(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float],
               extras: tuple[float, float, float], dist: tuple[Distortion | None, Distortion | None] = (None, None),
               hb_frac: float | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Residuals and every station at unknowns `x`; `hb_frac` [-] overrides the handling bleed's
        corrected-N1 schedule (a valve position set from outside, e.g. with hysteresis by the transient model).
        The stations are views of the gas path's arrays (:func:`.gas_path.turbofan`)."""
        fc = self._evaluate(x, cond, demand, extras, dist, hb_frac, with_sm=True)
        return fc.r[:x.size].copy(), _info(fc, self.p, extras[0])

    # ------------------------------------------------------------------ solve
    def solve(self, alt_m: float = 0.0, Mach: float = 0.0, dT_isa_K: float = 0.0, *,
              Wf_kg_s: float | None = None, N1_rpm: float | None = None, N1_pct: float | None = None,
              N1c_pct: float | None = None, Tt4_K: float | None = None, Fn_N: float | None = None,
              customer_bleed_frac: float | None = None, offtake_hp_W: float | None = None,
              offtake_lp_W: float | None = None, distortion_fan: Distortion | None = None,
              distortion_hpc: Distortion | None = None, guess: OffDesignPoint | None = None,
              tol: float = 1e-9, handling_bleed_frac: float | None = None) -> OffDesignPoint:
        """Steady state at a flight condition and one power setting.

        Parameters
        ----------
        alt_m, Mach, dT_isa_K : float
            Flight condition: geopotential altitude [m], Mach [-], ISA deviation [K].
        Wf_kg_s, N1_rpm, N1_pct, N1c_pct, Tt4_K, Fn_N : float, optional
            The power setting: exactly one of fuel flow [kg/s], N1 [rpm or % of
            design], corrected N1 [% of design corrected N1], Tt4 [K], net thrust [N].
        customer_bleed_frac, offtake_hp_W, offtake_lp_W : float, optional
            Customer bleed W/W25 [-] and shaft port powers [W], signed: + taken from the spool (offtake,
            generator), - delivered to it (motor assist); default the design's.
        distortion_fan, distortion_hpc : Distortion, optional
            Sector distortion at the fan or HPC face (parallel compressor model,
            :mod:`.distortion`); each adds one unknown and one residual.
        guess : OffDesignPoint, optional
            A neighbouring solution: its unknowns and Jacobian start the iteration.
        tol : float
            Convergence tolerance on max |residual| [-].
        handling_bleed_frac : float, optional
            Handling bleed W/W25 [-] held fixed instead of the corrected-N1 schedule (a valve position,
            e.g. the transient model's on/off valve at a start).

        Raises
        ------
        ConvergenceError
            If the matching does not converge; the message names the residuals.
        """
        p = self.p
        given = {"Wf_kg_s": Wf_kg_s, "N1_rpm": N1_rpm, "N1_pct": N1_pct, "N1c_pct": N1c_pct, "Tt4_K": Tt4_K,
                 "Fn_N": Fn_N}
        set_ = [(k, v) for k, v in given.items() if v is not None]
        if len(set_) != 1:
            raise ModelError(f"offdesign.solve: give exactly one power setting of {', '.join(given)}; got "
                             f"{[k for k, _ in set_] or 'none'}")
        kind, value = set_[0]
        if kind == "N1_pct":
            kind, value = "N1_rpm", value / 100.0 * p.N1_rpm
        elif kind == "N1c_pct":
            kind, value = "N1c_rpm", value / 100.0 * self.dp.components["fan_outer"].Nc_rpm
        extras = (p.customer_bleed_frac if customer_bleed_frac is None else customer_bleed_frac,
                  p.offtake_hp_W if offtake_hp_W is None else offtake_hp_W,
                  p.offtake_lp_W if offtake_lp_W is None else offtake_lp_W)
        cond = (alt_m, Mach, dT_isa_K)
        free_stream(*cond, self.gas)                       # range checks before iterating
        hb = handling_bleed_frac
        if hb is not None and not (0.0 <= hb < 0.5):
            raise OutOfRangeError(f"offdesign.solve: handling_bleed_frac={hb!r} is outside [0, 0.5)")
        dist = (distortion_fan, distortion_hpc)
        try:
            return self._solve(cond, kind, value, extras, dist, guess, tol, hb)
        except ConvergenceError as exc:
            if guess is not None:
                raise
            first = exc
        # continuation from the design's corrected operating point at this flight condition
        try:
            g = self._solve(cond, "N1c_rpm", self.dp.components["fan_outer"].Nc_rpm, extras, dist, None, tol, hb)
            v0 = {"Wf_kg_s": g.Wf_kg_s, "N1_rpm": g.N1_rpm, "N1c_rpm": g.N1c_rpm, "Tt4_K": g.Tt4_K,
                  "Fn_N": g.Fn_N}[kind]
            for f in (0.25, 0.5, 0.75, 1.0):
                g = self._solve(cond, kind, v0 + f * (value - v0), extras, dist, g, tol, hb)
            return g
        except ConvergenceError:
            raise first from None

    def _solve(self, cond: tuple[float, float, float], kind: str, value: float, extras: tuple[float, float, float],
               dist: tuple[Distortion | None, Distortion | None], guess: OffDesignPoint | None,
               tol: float, hb: float | None = None) -> OffDesignPoint:
        x0, J0 = self.start(dist, guess, cond)
        names = self.residual_names(dist)

        def resid(x: np.ndarray) -> np.ndarray:
            return self._residuals(x, cond, (kind, value), extras, dist, hb)

        res = newton_solve(resid, x0, names, tol=tol, jacobian=J0,
                           where=f"offdesign of {self.p.name!r} at alt {cond[0]} m, Mach {cond[1]}, "
                                 f"{kind}={value:.6g}")
        info = self._cycle(res.x, cond, (kind, value), extras, dist, hb)[1]   # the stations, once
        return self._result(res, info, cond, dist)

    def start(self, dist: tuple[Distortion | None, Distortion | None], guess: OffDesignPoint | None,
              cond: tuple[float, float, float] | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """Starting unknowns and Jacobian for a distortion configuration, from a guess if it fits.

        Without a guess: the design point moved to the flight condition `cond` by
        similarity (same corrected flow, speeds and fuel flow W/(delta sqrt(theta)) at the fan face).
        """
        if guess is None:
            base, J0 = list(self.x_design), None
            if cond is not None:
                fr = free_stream(*cond, self.gas)
                d2 = self.dp.stations["2"]
                theta = fr.Tt0_K / d2.Tt_K
                delta = fr.Pt0_Pa * self.p.inlet_pi * ram_recovery_mil_e_5008b(cond[1]) / d2.Pt_Pa
                base[0] *= delta / math.sqrt(theta)
                base[3] *= math.sqrt(theta)
                base[4] *= math.sqrt(theta)
                base[8] *= delta * math.sqrt(theta)
        elif tuple(d is None for d in guess.distortion) == tuple(d is None for d in dist):
            return np.array(guess.x), guess.jacobian
        else:
            base, J0 = list(guess.x[:9 + self.nb]), None
        if dist[0] is not None:
            base.append(base[1])
        if dist[1] is not None:
            base.append(base[2])
        return np.array(base), J0

    def _result(self, res: Any, info: dict[str, Any], cond: tuple[float, float, float],
                dist: tuple[Distortion | None, Distortion | None] = (None, None)) -> OffDesignPoint:
        p, st, o = self.p, info["st"], info["o"]
        over = [f for sink, f in info["bleeds"].values() if sink == "overboard"]
        if p.bypass_bleed_frac > 0.0:
            over.append(st["13"].with_W(st["13"].W_kg_s * p.bypass_bleed_frac))
        Fn = o["Fn"]
        N1, N2, Wf = o["N1"], o["N2"], o["Wf"]
        return OffDesignPoint(
            *cond, MappingProxyType(st), Fn, o["Fg"], o["ram"], Wf, Wf / Fn if Fn > 0.0 else math.inf, N1, N2,
            100.0 * N1 / p.N1_rpm, 100.0 * N2 / p.N2_rpm, o["N1c"], 100.0 * o["N1c"] / self.ref["Nc1"], st["4"].Tt_K,
            st["41"].Tt_K, st["21"].Tt_K, st["17"].Tt_K, st["7"].Tt_K, st["3"].Pt_Pa, st["3"].Pt_Pa / st["2"].Pt_Pa,
            o["BPR"], o["SM_fan"], o["SM_hpc"], o["SM_fan_clean"], o["SM_hpc_clean"], o["beta_fan_1"],
            o["beta_hpc_1"], o["PRh"], o["PRl"], o["hb"], MappingProxyType(info["powers"]),
            sum(f.W_kg_s for f in over), sum(f.H_W for f in over), res.iterations, res.evaluations,
            float(np.max(np.abs(res.r))), tuple(float(v) for v in res.x), res.jacobian, dist)


def _dist_array(dist: tuple[Distortion | None, Distortion | None]) -> np.ndarray:
    """The (fan, HPC) distortions as the gas path reads them: on, sector share, attenuated Pt deficit [-] and
    Tt excess [K] (:attr:`.distortion.Distortion.attenuation`)."""
    a = np.zeros((2, 4))
    for k, d in enumerate(dist):
        if d is not None:
            a[k] = (1.0, d.sector_frac, d.attenuation * d.dPt_frac, d.attenuation * d.dTt_K)
    return a


def _info(fc: Any, p: TurbofanParams, customer_bleed_frac: float) -> dict[str, Any]:
    """Stations, bleeds, powers and outputs of the gas path's last evaluation, as Python objects (views)."""
    from .gas_path import OUT, STATIONS
    S, B, PW = fc.S, fc.B, fc.PW
    st = {k: FlowStation(*(float(v) for v in S[i])) for i, k in enumerate(STATIONS)}
    st["8"], st["18"] = st["7"], st["17"]
    o = dict(zip(OUT, fc.o.tolist(), strict=True))
    names = [b.name for b in p.bleeds] + (["handling"] if o["hb"] > 0.0 else []) + (
        ["customer"] if customer_bleed_frac > 0.0 else [])
    sinks = {v: k for k, v in _SINK_CODE.items()}
    bleeds = {n: (sinks[int(B[i, 5])], FlowStation(*(float(v) for v in B[i, :5]))) for i, n in enumerate(names)}
    powers = {t.name: float(PW[i]) for i, t in enumerate(TURBOFAN_SHAFTS)}
    powers["mech_hp"], powers["mech_lp"] = float(PW[len(TURBOFAN_SHAFTS)]), float(PW[len(TURBOFAN_SHAFTS) + 1])
    return dict(st=st, o=o, bleeds=bleeds, powers=powers)
