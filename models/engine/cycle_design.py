"""Design point of the single-spool turbojet and the two-spool separate-flow turbofan.

From the design parameters (:mod:`.design_params`) the cycle is computed
station by station (:mod:`.stations`) on the engine's one gas path, the one its
off-design uses too: the turbofan's :func:`.gas_path.turbofan` in design mode,
the turbojet's :func:`.turbojet_path.turbojet_path`. Each spool's turbine delivers
the power its compressors and offtakes need (:mod:`.shaft`), which fixes the
turbine pressure ratios. With a thrust
target the inlet mass flow is solved with :func:`scipy.optimize.brentq` (the
cycle is linear in W except for absolute power offtakes, so two linear
steps give a tight bracket around the root).

The result carries every station, thrust, ram drag, fuel flow, SFC, the
nozzle areas that the off-design calculation keeps, and the design values
that map scaling needs (corrected flows, pressure ratios, efficiencies,
corrected speeds).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5-7
(design-point calculation, thrust, SFC).
J. D. Mattingly, "Elements of Propulsion: Gas Turbines and Rockets", AIAA,
2006, ch. 7 (parametric cycle analysis of the separate-flow turbofan).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .atmosphere import FreeStream, free_stream
from .bleed import BleedSpec, stage_fractions
from .compressor import CompressorResult
from .design_params import EngineParams, TurbofanParams, TurbojetParams
from .errors import ConvergenceError, ModelError, OutOfRangeError
from .flow import T_STD_K, FlowStation
from .gas import GasModel
from .gas_path import pack_params
from .inlet import ram_recovery_mil_e_5008b
from .nozzle import NozzleResult, convergent_nozzle, ideal_nozzle
from .shaft import TURBOFAN_SHAFTS
from .turbine import TurbineResult

__all__ = ["ComponentDesign", "DesignPoint", "design", "gas_of"]

#: Names of the gas path's power vector: the declared shaft terms, then the spools' mechanical losses.
PW_NAMES: tuple[str, ...] = tuple(t.name for t in TURBOFAN_SHAFTS) + ("mech_hp", "mech_lp")

_GASES: dict[tuple[float, float], GasModel] = {}


def gas_of(params: EngineParams) -> GasModel:
    """The gas model of a parameter set (cached per fuel H/C ratio and LHV)."""
    key = (params.hc_ratio, params.LHV_J_kg)
    if key not in _GASES:
        _GASES[key] = GasModel(hc_ratio=params.hc_ratio, LHV_J_kg=params.LHV_J_kg)
    return _GASES[key]


@dataclass(frozen=True, slots=True)
class ComponentDesign:
    """Design values of a turbomachine, for map scaling.

    Attributes
    ----------
    Wc_kg_s : float
        Inlet corrected flow W sqrt(Tt/288.15 K)/(Pt/101325 Pa) [kg/s].
    PR : float
        Total pressure ratio [-] (compressors out/in, turbines in/out).
    eta_is : float
        Isentropic efficiency [-].
    N_rpm, Nc_rpm : float
        Mechanical and corrected speed N/sqrt(Tt_in/288.15 K) [rpm].
    power_W : float
        Shaft power absorbed (compressor) or delivered (turbine) [W].
    """

    Wc_kg_s: float
    PR: float
    eta_is: float
    N_rpm: float
    Nc_rpm: float
    power_W: float


@dataclass(frozen=True)
class DesignPoint:
    """A design-point cycle.

    Attributes
    ----------
    params : TurbofanParams or TurbojetParams
        The parameters it was computed from.
    free : FreeStream
        Flight condition.
    stations : Mapping[str, FlowStation]
        Every station of :data:`.stations.TURBOFAN_STATIONS` or ``TURBOJET_STATIONS``.
    bleeds : Mapping[str, FlowStation]
        Every bleed stream by name, as taken from its compressor.
    components : Mapping[str, ComponentDesign]
        ``fan_outer``, ``fan_inner``, ``booster``, ``hpc``, ``hpt``, ``lpt`` (turbofan) or
        ``compressor``, ``turbine`` (turbojet).
    nozzles : Mapping[str, NozzleResult]
        ``core`` and, for the turbofan, ``bypass``.
    Fn_N, Fg_N, ram_drag_N : float
        Net thrust, gross thrust, ram drag [N].
    Wf_kg_s : float
        Fuel flow [kg/s].
    SFC_kg_N_s : float
        Specific fuel consumption Wf/Fn [kg/(N s)].
    OPR, BPR : float
        Overall pressure ratio Pt3/Pt2 and bypass ratio [-].
    mech_loss_W, offtake_W, heat_unreleased_W, heat_added_W : float
        Energy terms [W]: spool mechanical losses, shaft offtakes, fuel energy
        not released, fuel energy added to the gas (eta_b Wf LHV + Wf h_fuel).
    """

    params: EngineParams
    free: FreeStream
    stations: Mapping[str, FlowStation]
    bleeds: Mapping[str, FlowStation]
    components: Mapping[str, ComponentDesign]
    nozzles: Mapping[str, NozzleResult]
    Fn_N: float
    Fg_N: float
    ram_drag_N: float
    Wf_kg_s: float
    SFC_kg_N_s: float
    OPR: float
    BPR: float
    mech_loss_W: float
    offtake_W: float
    heat_unreleased_W: float
    heat_added_W: float

    @property
    def Tt4_K(self) -> float:
        """Burner exit temperature [K]."""
        return self.stations["4"].Tt_K

    @property
    def W2_kg_s(self) -> float:
        """Inlet mass flow [kg/s]."""
        return self.stations["2"].W_kg_s

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary with SI units in the key names (for JSON output)."""
        noz = {k: {"A_eff_m2": n.A_eff_m2, "A_geom_m2": n.A_geom_m2, "choked": n.choked, "Fg_N": n.Fg_N,
                   "PR": n.PR, "V_m_s": n.throat.V_m_s, "Ps_Pa": n.throat.Ps_Pa}
               for k, n in self.nozzles.items()}
        return {
            "engine": "turbofan" if isinstance(self.params, TurbofanParams) else "turbojet",
            "name": self.params.name, "alt_m": self.params.alt_m, "Mach": self.params.Mach,
            "dT_isa_K": self.params.dT_isa_K,
            "Fn_N": self.Fn_N, "Fg_N": self.Fg_N, "ram_drag_N": self.ram_drag_N,
            "W2_kg_s": self.W2_kg_s, "Wf_kg_s": self.Wf_kg_s, "SFC_kg_N_s": self.SFC_kg_N_s,
            "SFC_kg_kN_h": self.SFC_kg_N_s * 3.6e6, "OPR": self.OPR, "BPR": self.BPR,
            "Tt4_K": self.Tt4_K, "FAR4": self.stations["4"].FAR,
            "A8_m2": self.nozzles["core"].A_geom_m2,
            **({"A18_m2": self.nozzles["bypass"].A_geom_m2} if "bypass" in self.nozzles else {}),
            "stations": {k: {"W_kg_s": s.W_kg_s, "Tt_K": s.Tt_K, "Pt_Pa": s.Pt_Pa, "FAR": s.FAR}
                         for k, s in self.stations.items()},
            "components": {k: {"Wc_kg_s": c.Wc_kg_s, "PR": c.PR, "eta_is": c.eta_is, "N_rpm": c.N_rpm,
                               "Nc_rpm": c.Nc_rpm, "power_W": c.power_W} for k, c in self.components.items()},
            "nozzles": noz,
            "bleeds_kg_s": {k: b.W_kg_s for k, b in self.bleeds.items()},
        }


def _comp(res: CompressorResult | TurbineResult, fs_in: FlowStation, N_rpm: float) -> ComponentDesign:
    return ComponentDesign(fs_in.Wc_kg_s, res.PR, res.eta_is, N_rpm, N_rpm / math.sqrt(fs_in.Tt_K / T_STD_K),
                           res.power_W)


def _nozzle(p: EngineParams, fs: FlowStation, P_amb: float, Cv: float, Cd: float, gas: GasModel) -> NozzleResult:
    if p.nozzle_type == "ideal":
        return ideal_nozzle(fs, P_amb, Cv, gas)
    return convergent_nozzle(fs, P_amb, Cv, Cd, gas)


def _turbojet(p: TurbojetParams, W2: float, gas: GasModel) -> DesignPoint:
    """The turbojet's design point: its one gas path (:func:`.turbojet_path.turbojet_path`) at the design
    values, the turbine delivering the compressor's and the offtake's power."""
    from .turbojet_path import turbojet_path
    fr = free_stream(p.alt_m, p.Mach, p.dT_isa_K, gas)
    g = turbojet_path(p, gas, fr, W2, lambda _st: (p.PR_c, p.eta_c, math.nan))
    st, c, t, bu, n = g.stations, g.compressor, g.turbine, g.burner, g.nozzle
    comps = {"compressor": _comp(c, st["2"], p.N_rpm), "turbine": _comp(t, st["4"], p.N_rpm)}
    return DesignPoint(p, fr, MappingProxyType(st), MappingProxyType(g.bleeds), MappingProxyType(comps),
                       MappingProxyType({"core": n}), g.Fn_N, n.Fg_N, g.ram_drag_N, bu.Wf_kg_s,
                       bu.Wf_kg_s / g.Fn_N if g.Fn_N > 0 else math.inf, st["3"].Pt_Pa / st["2"].Pt_Pa, 0.0,
                       (1.0 - p.eta_mech) * t.power_W, p.offtake_W, bu.heat_unreleased_W, bu.heat_released_W)


def _turbofan_params(p: TurbofanParams, W2: float, P_hp_ref: float, P_lp_ref: float) -> np.ndarray:
    """The gas path's parameters (:data:`.gas_path.PARAMS`) in design mode: the turbomachines at their design
    pressure ratios and efficiencies, the unknowns (turbine PRs) unscaled, the bleed schedules off."""
    one = 1.0
    return pack_params(dict(
        mode=1.0, W2_ref=W2, PRh_ref=one, PRl_ref=one, Wf_ref=one, N1_design_rpm=p.N1_rpm, N2_design_rpm=p.N2_rpm,
        BPR_ref=p.BPR if p.BPR > 0.0 else one, Nc1_design_rpm=one, inlet_pi=p.inlet_pi,
        k_inner=(p.PR_fan_inner - 1.0) / (p.PR_fan_outer - 1.0), eff_ratio_inner=p.eta_fan_inner / p.eta_fan_outer,
        booster=1.0 if p.PR_booster > 1.0 else 0.0, dPqP_21_24=p.dPqP_21_24, dPqP_24_25=p.dPqP_24_25,
        dPqP_burner=p.dPqP_burner, dPqP_44_45=p.dPqP_44_45, dPqP_5_7=p.dPqP_5_7, dPqP_13_17=p.dPqP_13_17,
        handling_bleed_frac=p.handling_bleed_frac, hb_open_frac=0.0, hb_N1c_frac=0.0, hb_ramp_frac=one,
        handling_bleed_stage=p.handling_bleed_stage, hpc_stages=p.hpc_stages, bypass_bleed_frac=p.bypass_bleed_frac,
        eta_burner=p.eta_burner, Tt4_guess_K=p.Tt4_K, Cv_core=p.Cv_core, Cv_bypass=p.Cv_bypass,
        eta_mech_hp=p.eta_mech_hp, eta_mech_lp=p.eta_mech_lp, Wc21_ref=one, Wc4_ref=one, Wc45_ref=one, A8_ref=one,
        A18_ref=one, P_hp_ref=P_hp_ref, P_lp_ref=P_lp_ref, Fn_ref=one, Tt4_ref=p.Tt4_K,
        PR_fan_outer=p.PR_fan_outer, eta_fan_outer=p.eta_fan_outer, PR_booster=p.PR_booster,
        eta_booster=p.eta_booster if p.PR_booster > 1.0 else 1.0, PR_hpc=p.PR_hpc, eta_hpc=p.eta_hpc,
        eta_hpt=p.eta_hpt, eta_lpt=p.eta_lpt))


def _turbofan(p: TurbofanParams, W2: float, gas: GasModel) -> DesignPoint:
    """The turbofan's design point: the one gas path (:func:`.gas_path.turbofan`) in design mode, its two
    turbine pressure ratios matched to the spools' power balances (compressors, offtakes, mechanical losses)."""
    from .combustion import h_fuel_liquid
    from .gas_path import MAX_BLEEDS, OUT, SINK, STATIONS, turbofan, work_arrays
    from .newton import newton_solve
    if p.nozzle_type != "convergent":
        raise ModelError(f"{p.name}: the turbofan's nozzles are convergent (nozzle_type={p.nozzle_type!r} is for "
                         "the turbojet)")
    fr = free_stream(p.alt_m, p.Mach, p.dT_isa_K, gas)
    specs = list(p.bleeds) + ([BleedSpec("handling", p.handling_bleed_frac, *stage_fractions(
        p.handling_bleed_stage, p.hpc_stages, p.PR_hpc), "bypass")] if p.handling_bleed_frac > 0.0 else []) + (
        [BleedSpec("customer", p.customer_bleed_frac, 1.0, 1.0, "overboard")] if p.customer_bleed_frac > 0.0 else [])
    if len({b.name for b in specs}) != len(specs):
        raise ModelError(f"{p.name}: bleed names must be unique, got {[b.name for b in specs]}")
    if len(p.bleeds) + 2 > MAX_BLEEDS:                  # the handling and customer bleeds come on top
        raise ModelError(f"{p.name}: at most {MAX_BLEEDS - 2} bleeds, got {len(p.bleeds)}")
    fs = np.array([fr.Tt0_K, fr.Pt0_Pa, fr.V0_m_s, fr.amb.P_Pa, p.Mach, ram_recovery_mil_e_5008b(p.Mach)])
    ctl = np.array([3.0, p.Tt4_K, p.customer_bleed_frac, p.offtake_hp_W, p.offtake_lp_W, 0.0])
    gc, gs0 = gas.kernel_arrays()
    gs = np.append(gs0, h_fuel_liquid(p.T_fuel_K, gas))
    bl = np.array([[b.frac_W, b.frac_P, b.frac_work, SINK[b.sink], b.sink_frac_P] for b in p.bleeds],
                  dtype=float).reshape(-1, 5)
    dummy = (*(np.zeros(2),) * 4, np.zeros((1, 1, 3, 16)), np.zeros(8), np.ones(6), np.zeros(2), np.zeros(2))
    S, B, PW = np.empty((len(STATIONS), 5)), np.empty((MAX_BLEEDS, 6)), np.empty(len(PW_NAMES))
    r, o, err, dist = np.empty(12), np.empty(len(OUT)), np.zeros(2, np.int64), np.zeros((2, 4))
    work = work_arrays()
    x = np.ones(9 + (p.PR_booster > 1.0))
    box = {"e": _turbofan_params(p, W2, 1.0, 1.0)}

    def run(prs: np.ndarray) -> np.ndarray:
        x[5], x[6] = prs
        err[:] = 0
        code = turbofan(x, fs, ctl, box["e"], gc, gs, bl, dummy, dummy, dummy, dummy, dummy, dist, S, B, PW, r, o,
                        err, work, False)
        if code:
            from .gas_path import ERRORS, STAGES
            raise OutOfRangeError(f"{STAGES[int(err[1])] or 'gas path'}: {ERRORS.get(code, f'error {code}')}")
        return r[6:8].copy()

    prs0 = np.array([2.5, 2.5])
    run(prs0)                                           # the compressors' powers: the balances' scales
    box["e"] = _turbofan_params(p, W2, max(PW[PW_NAMES.index("hpc")], 1.0),
                                max(PW[PW_NAMES.index("fan_outer")] + PW[PW_NAMES.index("fan_inner")]
                                    + PW[PW_NAMES.index("booster")], 1.0))
    res = newton_solve(run, prs0, ("hp_power", "lp_power"), tol=1e-13, where=f"design of {p.name!r}")
    run(res.x)
    out = dict(zip(OUT, o.tolist(), strict=True))
    st = {k: FlowStation(*(float(v) for v in S[i])) for i, k in enumerate(STATIONS)}
    st["8"], st["18"] = st["7"], st["17"]
    bl_st = {b.name: FlowStation(*(float(v) for v in B[i, :5])) for i, b in enumerate(specs)}
    if p.bypass_bleed_frac > 0.0:
        bl_st["bypass_overboard"] = st["13"].with_W(st["13"].W_kg_s * p.bypass_bleed_frac)
    P = dict(zip(PW_NAMES, PW.tolist(), strict=True))
    sq = {k: math.sqrt(st[k].Tt_K / T_STD_K) for k in ("2", "21", "25", "4", "45")}
    W2c, fr_core = out["Wc2"], 1.0 / (1.0 + p.BPR)
    comps = {"fan_outer": ComponentDesign(W2c * (1.0 - fr_core), p.PR_fan_outer, p.eta_fan_outer, p.N1_rpm,
                                          p.N1_rpm / sq["2"], P["fan_outer"]),
             "fan_inner": ComponentDesign(W2c * fr_core, p.PR_fan_inner, p.eta_fan_inner, p.N1_rpm,
                                          p.N1_rpm / sq["2"], P["fan_inner"]),
             "booster": ComponentDesign(out["Wc21"], out["PR_booster"], out["eta_booster"], p.N1_rpm,
                                        p.N1_rpm / sq["21"], P["booster"]),
             "hpc": ComponentDesign(out["Wc25"], p.PR_hpc, p.eta_hpc, p.N2_rpm, p.N2_rpm / sq["25"], P["hpc"]),
             "hpt": ComponentDesign(out["Wc4"], out["PRh"], p.eta_hpt, p.N2_rpm, p.N2_rpm / sq["4"], P["hpt"]),
             "lpt": ComponentDesign(out["Wc45"], out["PRl"], p.eta_lpt, p.N1_rpm, p.N1_rpm / sq["45"], P["lpt"])}
    nc = _nozzle(p, st["7"], fr.amb.P_Pa, p.Cv_core, p.Cd_core, gas)      # the throats' details (views)
    nb = _nozzle(p, st["17"], fr.amb.P_Pa, p.Cv_bypass, p.Cd_bypass, gas)
    Wf, Fn = out["Wf"], out["Fn"]
    return DesignPoint(p, fr, MappingProxyType(st), MappingProxyType(bl_st), MappingProxyType(comps),
                       MappingProxyType({"core": nc, "bypass": nb}), Fn, out["Fg"], out["ram"], Wf,
                       Wf / Fn if Fn > 0 else math.inf, st["3"].Pt_Pa / st["2"].Pt_Pa, p.BPR,
                       P["mech_hp"] + P["mech_lp"], p.offtake_hp_W + p.offtake_lp_W,
                       Wf * (1.0 - p.eta_burner) * gas.LHV_J_kg,
                       Wf * (p.eta_burner * gas.LHV_J_kg + h_fuel_liquid(p.T_fuel_K, gas)))


def _run(p: EngineParams, W2: float, gas: GasModel) -> DesignPoint:
    try:
        return _turbofan(p, W2, gas) if isinstance(p, TurbofanParams) else _turbojet(p, W2, gas)
    except OutOfRangeError as exc:
        raise OutOfRangeError(f"design of {p.name!r}: {exc}") from None


def design(params: EngineParams, gas: GasModel | None = None) -> DesignPoint:
    """Design point of the engine described by `params`.

    Parameters
    ----------
    params : TurbofanParams or TurbojetParams
        Design parameters; with ``Fn_target_N`` the inlet mass flow is solved.
    gas : GasModel, optional
        Gas model; default the one of the parameters' fuel (H/C ratio, LHV).

    Returns
    -------
    DesignPoint

    Raises
    ------
    ModelError
        For inconsistent parameters, or (ConvergenceError) if no mass flow meets
        the thrust target, e.g. because the cycle gives no positive thrust.
    """
    g = gas if gas is not None else gas_of(params)
    if params.W2_kg_s is not None:
        return _run(params, params.W2_kg_s, g)
    F = params.Fn_target_N
    assert F is not None
    W_ref = 100.0
    F_ref = _run(params, W_ref, g).Fn_N
    if not F_ref > 0.0:
        raise ConvergenceError(f"{params.name}: the cycle gives no positive net thrust "
                               f"(Fn={F_ref:.6g} N at W2={W_ref} kg/s); no mass flow meets Fn_target_N={F!r}")
    # Fn is linear in W2 but for absolute offtakes: one linear step lands within a
    # fraction of a percent; brentq then polishes inside a bracket around it.
    W1 = W_ref * F / F_ref
    seen: dict[float, DesignPoint] = {}

    def resid(w: float) -> float:
        if w not in seen:
            seen[w] = _run(params, w, g)
        return seen[w].Fn_N - F

    r1 = resid(W1)
    W2 = W1 * F / (r1 + F)
    delta = 4.0 * abs(W2 - W1) + 1e-9 * W1
    for _ in range(20):
        lo, hi = W2 - delta, W2 + delta
        if lo > 0.0 and resid(lo) * resid(hi) <= 0.0:
            break
        delta *= 4.0
    else:
        raise ConvergenceError(f"{params.name}: no mass flow found that meets Fn_target_N={F!r} "
                               f"(searched {lo:.6g} to {hi:.6g} kg/s)")
    W = brentq(resid, lo, hi, xtol=1e-12 * W1, rtol=1e-13)
    return seen[W] if W in seen else _run(params, W, g)
