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
values. The handling bleed (HPC stage k into the bypass) opens as N2 falls
below its threshold (default 60 % of design N2), with a C1 ramp 2 % wide.

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
from .bleed import BleedSpec, stage_fractions
from .burner import burner_with_fuel
from .compressor import CompressorResult, compressor
from .cycle_design import DesignPoint, gas_of
from .design_params import TurbofanParams
from .distortion import Distortion, flow_residual, map_sectors, pressure_residual
from .duct import duct
from .errors import ConvergenceError, ModelError, OutOfRangeError
from .flow import T_STD_K, FlowStation, mix
from .inlet import inlet, ram_recovery_mil_e_5008b
from .newton import newton_solve
from .nozzle import convergent_nozzle
from .offdesign_result import OffDesignPoint
from .shaft import TURBOFAN_SHAFTS, spool_balance, term_arrays
from .splitter import splitter
from .turbine import Cooling, turbine

__all__ = ["CompressorMapLike", "TurbineMapLike", "TurbofanMaps", "OffDesignPoint", "TurbofanOffDesign",
           "scaled_maps", "RESIDUALS"]

#: Residual names, in order.
RESIDUALS: tuple[str, ...] = ("fan_flow", "hpc_flow", "hpt_flow", "lpt_flow", "core_nozzle_area",
                              "bypass_nozzle_area", "hp_power", "lp_power", "power_setting")


class CompressorMapLike(Protocol):
    """A compressor map scaled to the design point."""

    def evaluate(self, Nc: float, beta: float) -> tuple[float, float, float]:
        """(corrected flow [kg/s], pressure ratio [-], isentropic efficiency [-]) at corrected speed [rpm], beta [-]."""
        ...


class TurbineMapLike(Protocol):
    """A turbine map scaled to the design point."""

    def evaluate(self, Nc: float, PR: float) -> tuple[float, float]:
        """(inlet corrected flow [kg/s], isentropic efficiency [-]) at corrected speed [rpm], PR in/out [-]."""
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


def _mixed(streams: list[FlowStation], gas: Any) -> FlowStation:
    """One stream, or the mixture of sector streams at their flow-weighted total pressure."""
    if len(streams) == 1:
        return streams[0]
    W = sum(f.W_kg_s for f in streams)
    return mix(streams, sum(f.W_kg_s * f.Pt_Pa for f in streams) / W, gas)


def _merge(results: list[CompressorResult], gas: Any) -> CompressorResult:
    """Sectors of a compressor merged: exits and each bleed mixed, powers added."""
    first = results[0]
    bleeds = tuple(_mixed([r.bleeds[k] for r in results], gas) for k in range(len(first.bleeds)))
    return CompressorResult(_mixed([r.out for r in results], gas), bleeds, sum(r.power_W for r in results),
                            first.PR, first.eta_is, first.eta_poly, sum(r.Wc_in_kg_s for r in results))


_TERM_SPOOL, _TERM_KIND = term_arrays()           # the declared shaft terms (shaft.TURBOFAN_SHAFTS)


def _smoothstep(s: float) -> float:
    s = 0.0 if s < 0.0 else (1.0 if s > 1.0 else s)
    return s * s * (3.0 - 2.0 * s)


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
    handling_bleed_N2_pct : float
        N2 [% of design] below which the bleed is open (centre of a 2 %-wide ramp).
    """

    def __init__(self, dp: DesignPoint, maps: TurbofanMaps, handling_bleed_open_frac: float = 0.10,
                 handling_bleed_N2_pct: float = 60.0) -> None:
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
        self.hb_open, self.hb_N2 = handling_bleed_open_frac, handling_bleed_N2_pct / 100.0
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
        self.eta_mech = np.array([p.eta_mech_hp, p.eta_mech_lp])     # per spool of shaft.SPOOLS
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
        """The compiled residuals (:class:`.jit_cycle.FastCycle`), or None where they do not apply."""
        if self._fast is None:
            from .jit_cycle import FastCycle
            self._fast = FastCycle.build(self) or False
        return self._fast or None

    def _residuals(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float],
                   extras: tuple[float, float, float], dist: tuple[Distortion | None, Distortion | None] = (None, None),
                   hb_frac: float | None = None) -> np.ndarray:
        """The residuals of :meth:`_cycle` (the same numbers), from the compiled kernel where it applies."""
        fc = self.fast
        if fc is not None and dist[0] is None and dist[1] is None and x.size == 9:
            from .jit_cycle import DEMAND
            if fc(x, cond, (DEMAND[demand[0]], demand[1]), extras, hb_frac):
                return fc.r.copy()
        return self._cycle(x, cond, demand, extras, dist, hb_frac)[0]

    def _cycle(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[str, float],
               extras: tuple[float, float, float], dist: tuple[Distortion | None, Distortion | None] = (None, None),
               hb_frac: float | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Residuals and every station at unknowns `x`; `hb_frac` [-] overrides the handling bleed's
        N2 schedule (a valve position set from outside, e.g. with hysteresis by the transient model)."""
        p, g, ref, m = self.p, self.gas, self.ref, self.maps
        W2, b_fan, b_hpc = x[0] * ref["W2"], x[1], x[2]
        N1, N2 = x[3] * p.N1_rpm, x[4] * p.N2_rpm
        PRh, PRl, BPR, Wf = x[5] * ref["PRh"], x[6] * ref["PRl"], x[7] * p.BPR, x[8] * ref["Wf"]
        cust, off_hp, off_lp = extras
        if W2 <= 0.0 or N1 <= 0.0 or N2 <= 0.0 or BPR < 0.0 or Wf <= 0.0 or PRh < 1.0 or PRl < 1.0:
            raise OutOfRangeError("offdesign: unknowns out of range")
        betas_fan, betas_hpc, i = [b_fan], [b_hpc], 9 + self.nb
        if dist[0] is not None:
            betas_fan.append(x[i])
            i += 1
        if dist[1] is not None:
            betas_hpc.append(x[i])
        fr = free_stream(*cond, g)
        st: dict[str, FlowStation] = {"0": fr.station(W2, g)}
        st["2"] = inlet(st["0"], cond[1], p.inlet_pi)
        sq = math.sqrt
        N1c = N1 / sq(st["2"].Tt_K / T_STD_K)
        fan = map_sectors(st["2"], dist[0], m.fan, N1, betas_fan, g)
        scale = W2 / sum(sp.inlet.W_kg_s for sp in fan)           # streams carry exactly W2
        outer, inner, P_fo, P_fi = [], [], 0.0, 0.0
        for sp in fan:
            core_s, byp_s = splitter(sp.inlet.with_W(sp.inlet.W_kg_s * scale), BPR)
            fo = compressor(byp_s, sp.PR, sp.eff, (), g)
            fi = compressor(core_s, 1.0 + self.k_inner * (sp.PR - 1.0), sp.eff * self.eff_ratio_inner, (), g)
            outer.append(fo.out)
            inner.append(fi.out)
            P_fo += fo.power_W
            P_fi += fi.power_W
        st["13"], st["21"] = _mixed(outer, g), _mixed(inner, g)
        d21 = duct(st["21"], p.dPqP_21_24)
        r_booster: list[float] = []
        P_bo = 0.0
        if self.nb:
            assert m.booster is not None
            Wc_b, PR_b, eff_b = m.booster.evaluate(N1 / sq(d21.Tt_K / T_STD_K), x[9])
            r_booster.append((Wc_b - d21.Wc_kg_s) / ref["Wc21"])
            bo = compressor(d21, PR_b, eff_b, (), g)
            st["24"], P_bo = bo.out, bo.power_W
        else:
            st["24"] = d21
        st["25"] = duct(st["24"], p.dPqP_24_25)
        N2c = N2 / sq(st["25"].Tt_K / T_STD_K)
        hpc = map_sectors(st["25"], dist[1], m.hpc, N2, betas_hpc, g)
        PR_h = hpc[0].PR
        specs = list(p.bleeds)
        if hb_frac is None:
            hb = max(p.handling_bleed_frac, self.hb_open * _smoothstep((self.hb_N2 + 0.01 - N2 / p.N2_rpm) / 0.02))
        else:
            hb = max(p.handling_bleed_frac, hb_frac)
        if hb > 0.0:
            fP, fw = stage_fractions(p.handling_bleed_stage, p.hpc_stages, PR_h)
            specs.append(BleedSpec("handling", hb, fP, fw, "bypass"))
        if cust > 0.0:
            specs.append(BleedSpec("customer", cust, 1.0, 1.0, "overboard"))
        scale = st["25"].W_kg_s / sum(sp.inlet.W_kg_s for sp in hpc)
        hcs = [compressor(sp.inlet.with_W(sp.inlet.W_kg_s * scale), sp.PR, sp.eff, specs, g) for sp in hpc]
        hc = hcs[0] if len(hcs) == 1 else _merge(hcs, g)
        bl = {b.name: s for b, s in zip(specs, hc.bleeds, strict=True)}
        st["3"] = hc.out
        st["31"] = hc.out.with_W(hc.out.W_kg_s - sum(bl[b.name].W_kg_s for b in specs if b.at_exit))
        bu = burner_with_fuel(st["31"], Wf, p.eta_burner, p.dPqP_burner, p.T_fuel_K, g, self.dp.Tt4_K)
        st["4"] = bu.out
        Tt4 = bu.out.Tt_K
        Wc_t1, eff_t1 = m.hpt.evaluate(N2 / sq(Tt4 / T_STD_K), PRh)
        cool = [Cooling(bl[b.name], b.sink_frac_P) for b in specs if b.sink == "hpt"]
        ht = turbine(st["4"], PRh, eff_t1, cool, g)
        st["41"], st["44"] = ht.rotor_in, ht.out
        st["45"] = duct(ht.out, p.dPqP_44_45)
        Wc_t2, eff_t2 = m.lpt.evaluate(N1 / sq(st["45"].Tt_K / T_STD_K), PRl)
        cool = [Cooling(bl[b.name], b.sink_frac_P) for b in specs if b.sink == "lpt"]
        lt = turbine(st["45"], PRl, eff_t2, cool, g)
        st["5"] = lt.out
        st["7"] = st["8"] = duct(lt.out, p.dPqP_5_7)
        b13 = st["13"].with_W(st["13"].W_kg_s * (1.0 - p.bypass_bleed_frac))
        back = [bl[b.name] for b in specs if b.sink == "bypass"]
        st["16"] = mix([b13, *back], b13.Pt_Pa, g) if back else b13
        st["17"] = st["18"] = duct(st["16"], p.dPqP_13_17)
        nc = convergent_nozzle(st["7"], fr.amb.P_Pa, p.Cv_core, p.Cd_core, g, with_ideal=False)
        nb = convergent_nozzle(st["17"], fr.amb.P_Pa, p.Cv_bypass, p.Cd_bypass, g, with_ideal=False)
        ram = W2 * fr.V0_m_s
        Fg = nc.Fg_N + nb.Fg_N
        Fn = Fg - ram
        kind, value = demand
        if kind == "Wf_kg_s":
            r9 = (Wf - value) / ref["Wf"]
        elif kind == "N1_rpm":
            r9 = (N1 - value) / p.N1_rpm
        elif kind == "N1c_rpm":
            r9 = (N1c - value) / p.N1_rpm
        elif kind == "Tt4_K":
            r9 = (Tt4 - value) / ref["Tt4"]
        else:
            r9 = (Fn - value) / ref["Fn"]
        powers = {"fan_outer": P_fo, "fan_inner": P_fi, "booster": P_bo, "hpc": hc.power_W, "hpt": ht.power_W,
                  "lpt": lt.power_W, "port_hp": off_hp, "port_lp": off_lp}
        net, loss = np.empty(2), np.empty(2)
        spool_balance(np.array([powers[t.name] for t in TURBOFAN_SHAFTS]), _TERM_SPOOL, _TERM_KIND, self.eta_mech,
                      net, loss)
        powers["mech_hp"], powers["mech_lp"] = float(loss[0]), float(loss[1])
        r = np.array([
            flow_residual(fan, W2),
            flow_residual(hpc, st["25"].W_kg_s),
            (Wc_t1 - st["4"].Wc_kg_s) / ref["Wc4"],
            (Wc_t2 - st["45"].Wc_kg_s) / ref["Wc45"],
            nc.A_eff_m2 / ref["A8"] - 1.0,
            nb.A_eff_m2 / ref["A18"] - 1.0,
            net[0] / ref["P_hp"],
            net[1] / ref["P_lp"],
            r9] + r_booster + [pressure_residual(sec) for sec in (fan, hpc) if len(sec) > 1])
        info = dict(st=st, Fn=Fn, Fg=Fg, ram=ram, Wf=Wf, N1=N1, N2=N2, N1c=N1c, BPR=BPR, hb=hb,
                    b_fan=b_fan, b_hpc=b_hpc, N2c=N2c, PRh=PRh, PRl=PRl,
                    fan_sectors=[(sp.Nc, sp.beta) for sp in fan], hpc_sectors=[(sp.Nc, sp.beta) for sp in hpc],
                    powers=powers,
                    bleeds={b.name: (b.sink, bl[b.name]) for b in specs})
        return r, info

    # ------------------------------------------------------------------ solve
    def solve(self, alt_m: float = 0.0, Mach: float = 0.0, dT_isa_K: float = 0.0, *,
              Wf_kg_s: float | None = None, N1_rpm: float | None = None, N1_pct: float | None = None,
              N1c_pct: float | None = None, Tt4_K: float | None = None, Fn_N: float | None = None,
              customer_bleed_frac: float | None = None, offtake_hp_W: float | None = None,
              offtake_lp_W: float | None = None, distortion_fan: Distortion | None = None,
              distortion_hpc: Distortion | None = None, guess: OffDesignPoint | None = None,
              tol: float = 1e-9) -> OffDesignPoint:
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
        dist = (distortion_fan, distortion_hpc)
        try:
            return self._solve(cond, kind, value, extras, dist, guess, tol)
        except ConvergenceError as exc:
            if guess is not None:
                raise
            first = exc
        # continuation from the design's corrected operating point at this flight condition
        try:
            g = self._solve(cond, "N1c_rpm", self.dp.components["fan_outer"].Nc_rpm, extras, dist, None, tol)
            v0 = {"Wf_kg_s": g.Wf_kg_s, "N1_rpm": g.N1_rpm, "N1c_rpm": g.N1c_rpm, "Tt4_K": g.Tt4_K,
                  "Fn_N": g.Fn_N}[kind]
            for f in (0.25, 0.5, 0.75, 1.0):
                g = self._solve(cond, kind, v0 + f * (value - v0), extras, dist, g, tol)
            return g
        except ConvergenceError:
            raise first from None

    def _solve(self, cond: tuple[float, float, float], kind: str, value: float, extras: tuple[float, float, float],
               dist: tuple[Distortion | None, Distortion | None], guess: OffDesignPoint | None,
               tol: float) -> OffDesignPoint:
        x0, J0 = self.start(dist, guess, cond)
        names = self.residual_names(dist)

        def resid(x: np.ndarray) -> np.ndarray:
            return self._residuals(x, cond, (kind, value), extras, dist)

        res = newton_solve(resid, x0, names, tol=tol, jacobian=J0,
                           where=f"offdesign of {self.p.name!r} at alt {cond[0]} m, Mach {cond[1]}, "
                                 f"{kind}={value:.6g}")
        info = self._cycle(res.x, cond, (kind, value), extras, dist)[1]       # the stations, once
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
        p, st, m = self.p, info["st"], self.maps
        sm = []
        for cmap, sectors in ((m.fan, info["fan_sectors"]), (m.hpc, info["hpc_sectors"])):
            f = getattr(cmap, "surge_margin", None)
            per = []
            for Nc, beta in sectors:
                try:
                    per.append(float(f(Nc, beta)) if f is not None else math.nan)
                except ModelError:
                    per.append(math.nan)
            sm.append((min(per), per[0]))
        Nc1_d = self.dp.components["fan_outer"].Nc_rpm
        over = [f for sink, f in info["bleeds"].values() if sink == "overboard"]
        if p.bypass_bleed_frac > 0.0:
            over.append(st["13"].with_W(st["13"].W_kg_s * p.bypass_bleed_frac))
        Fn = info["Fn"]
        return OffDesignPoint(
            *cond, MappingProxyType(st), Fn, info["Fg"], info["ram"], info["Wf"],
            info["Wf"] / Fn if Fn > 0.0 else math.inf, info["N1"], info["N2"], 100.0 * info["N1"] / p.N1_rpm,
            100.0 * info["N2"] / p.N2_rpm, info["N1c"], 100.0 * info["N1c"] / Nc1_d, st["4"].Tt_K, st["41"].Tt_K,
            st["21"].Tt_K, st["17"].Tt_K, st["7"].Tt_K, st["3"].Pt_Pa, st["3"].Pt_Pa / st["2"].Pt_Pa, info["BPR"],
            sm[0][0], sm[1][0], sm[0][1], sm[1][1], info["b_fan"], info["b_hpc"], info["PRh"], info["PRl"], info["hb"],
            MappingProxyType(info["powers"]), sum(f.W_kg_s for f in over), sum(f.H_W for f in over), res.iterations,
            res.evaluations, float(np.max(np.abs(res.r))), tuple(float(v) for v in res.x), res.jacobian, dist)
