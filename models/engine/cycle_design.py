"""Design point of the single-spool turbojet and the two-spool separate-flow turbofan.

From the design parameters (:mod:`.design_params`) the cycle is computed
station by station (:mod:`.stations`) with the components of this package;
each spool's turbine delivers the power its compressors and offtakes need
(:mod:`.shaft`), which fixes the turbine pressure ratios. With a thrust
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

from scipy.optimize import brentq

from .atmosphere import FreeStream, free_stream
from .bleed import BleedSpec, stage_fractions
from .burner import burner_to_temperature
from .compressor import CompressorResult, compressor
from .design_params import EngineParams, TurbofanParams, TurbojetParams
from .duct import duct
from .errors import ConvergenceError, ModelError, OutOfRangeError
from .flow import T_STD_K, FlowStation, mix
from .gas import GasModel
from .inlet import inlet
from .nozzle import NozzleResult, convergent_nozzle, ideal_nozzle
from .shaft import turbine_power_required
from .splitter import splitter
from .turbine import Cooling, TurbineResult, turbine_for_power

__all__ = ["ComponentDesign", "DesignPoint", "design", "gas_of"]

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


def _cooling(bleeds: Mapping[str, FlowStation], specs: tuple[BleedSpec, ...], sink: str) -> list[Cooling]:
    return [Cooling(bleeds[b.name], b.sink_frac_P) for b in specs if b.sink == sink]


def _turbojet(p: TurbojetParams, W2: float, gas: GasModel) -> DesignPoint:
    fr = free_stream(p.alt_m, p.Mach, p.dT_isa_K, gas)
    st: dict[str, FlowStation] = {"0": fr.station(W2, gas)}
    st["2"] = inlet(st["0"], p.Mach, p.inlet_pi)
    c = compressor(st["2"], p.PR_c, p.eta_c, p.bleeds, gas)
    bl = {b.name: s for b, s in zip(p.bleeds, c.bleeds, strict=True)}
    if len(bl) != len(p.bleeds):
        raise ModelError(f"{p.name}: bleed names must be unique, got {[b.name for b in p.bleeds]}")
    st["3"] = c.out
    st["31"] = c.out.with_W(c.out.W_kg_s - sum(bl[b.name].W_kg_s for b in p.bleeds if b.at_exit))
    bu = burner_to_temperature(st["31"], p.Tt4_K, p.eta_burner, p.dPqP_burner, p.T_fuel_K, gas)
    st["4"] = bu.out
    P_t = turbine_power_required([c.power_W], p.offtake_W, p.eta_mech)
    t = turbine_for_power(st["4"], P_t, p.eta_t, _cooling(bl, p.bleeds, "hpt") + _cooling(bl, p.bleeds, "lpt"),
                          gas)
    st["41"], st["5"] = t.rotor_in, t.out
    st["7"] = duct(t.out, p.dPqP_jetpipe)
    n = _nozzle(p, st["7"], fr.amb.P_Pa, p.Cv, p.Cd, gas)
    st["8"] = st["7"]
    if any(b.sink == "bypass" for b in p.bleeds):
        raise ModelError(f"{p.name}: a turbojet has no bypass to return a bleed to")
    ram = W2 * fr.V0_m_s
    Fn = n.Fg_N - ram
    comps = {"compressor": _comp(c, st["2"], p.N_rpm), "turbine": _comp(t, st["4"], p.N_rpm)}
    return DesignPoint(p, fr, MappingProxyType(st), MappingProxyType(bl), MappingProxyType(comps),
                       MappingProxyType({"core": n}), Fn, n.Fg_N, ram, bu.Wf_kg_s,
                       bu.Wf_kg_s / Fn if Fn > 0 else math.inf, st["3"].Pt_Pa / st["2"].Pt_Pa, 0.0,
                       (1.0 - p.eta_mech) * P_t, p.offtake_W, bu.heat_unreleased_W, bu.heat_released_W)


def _turbofan(p: TurbofanParams, W2: float, gas: GasModel) -> DesignPoint:
    fr = free_stream(p.alt_m, p.Mach, p.dT_isa_K, gas)
    st: dict[str, FlowStation] = {"0": fr.station(W2, gas)}
    st["2"] = inlet(st["0"], p.Mach, p.inlet_pi)
    core2, byp2 = splitter(st["2"], p.BPR)
    fo = compressor(byp2, p.PR_fan_outer, p.eta_fan_outer, (), gas)
    fi = compressor(core2, p.PR_fan_inner, p.eta_fan_inner, (), gas)
    st["13"], st["21"] = fo.out, fi.out
    d21 = duct(fi.out, p.dPqP_21_24)
    bo = compressor(d21, p.PR_booster, p.eta_booster if p.PR_booster > 1.0 else 1.0, (), gas)
    st["24"] = bo.out
    st["25"] = duct(bo.out, p.dPqP_24_25)
    specs = list(p.bleeds)
    if p.handling_bleed_frac > 0.0:
        fP, fw = stage_fractions(p.handling_bleed_stage, p.hpc_stages, p.PR_hpc)
        specs.append(BleedSpec("handling", p.handling_bleed_frac, fP, fw, "bypass"))
    if p.customer_bleed_frac > 0.0:
        specs.append(BleedSpec("customer", p.customer_bleed_frac, 1.0, 1.0, "overboard"))
    specs_t = tuple(specs)
    hc = compressor(st["25"], p.PR_hpc, p.eta_hpc, specs_t, gas)
    bl = {b.name: s for b, s in zip(specs_t, hc.bleeds, strict=True)}
    if len(bl) != len(specs_t):
        raise ModelError(f"{p.name}: bleed names must be unique, got {[b.name for b in specs_t]}")
    st["3"] = hc.out
    st["31"] = hc.out.with_W(hc.out.W_kg_s - sum(bl[b.name].W_kg_s for b in specs_t if b.at_exit))
    bu = burner_to_temperature(st["31"], p.Tt4_K, p.eta_burner, p.dPqP_burner, p.T_fuel_K, gas)
    st["4"] = bu.out
    P_hpt = turbine_power_required([hc.power_W], p.offtake_hp_W, p.eta_mech_hp)
    ht = turbine_for_power(st["4"], P_hpt, p.eta_hpt, _cooling(bl, specs_t, "hpt"), gas)
    st["41"], st["44"] = ht.rotor_in, ht.out
    st["45"] = duct(ht.out, p.dPqP_44_45)
    P_lpt = turbine_power_required([fo.power_W, fi.power_W, bo.power_W], p.offtake_lp_W, p.eta_mech_lp)
    lt = turbine_for_power(st["45"], P_lpt, p.eta_lpt, _cooling(bl, specs_t, "lpt"), gas)
    st["5"] = lt.out
    st["7"] = duct(lt.out, p.dPqP_5_7)
    st["8"] = st["7"]
    b13 = st["13"].with_W(st["13"].W_kg_s * (1.0 - p.bypass_bleed_frac))
    back = [bl[b.name] for b in specs_t if b.sink == "bypass"]
    st["16"] = mix([b13, *back], b13.Pt_Pa, gas) if back else b13
    st["17"] = duct(st["16"], p.dPqP_13_17)
    st["18"] = st["17"]
    if p.bypass_bleed_frac > 0.0:
        bl["bypass_overboard"] = st["13"].with_W(st["13"].W_kg_s * p.bypass_bleed_frac)
    nc = _nozzle(p, st["7"], fr.amb.P_Pa, p.Cv_core, p.Cd_core, gas)
    nb = _nozzle(p, st["17"], fr.amb.P_Pa, p.Cv_bypass, p.Cd_bypass, gas)
    ram = W2 * fr.V0_m_s
    Fg = nc.Fg_N + nb.Fg_N
    Fn = Fg - ram
    comps = {"fan_outer": _comp(fo, byp2, p.N1_rpm), "fan_inner": _comp(fi, core2, p.N1_rpm),
             "booster": _comp(bo, d21, p.N1_rpm), "hpc": _comp(hc, st["25"], p.N2_rpm),
             "hpt": _comp(ht, st["4"], p.N2_rpm), "lpt": _comp(lt, st["45"], p.N1_rpm)}
    mech = (1.0 - p.eta_mech_hp) * P_hpt + (1.0 - p.eta_mech_lp) * P_lpt
    return DesignPoint(p, fr, MappingProxyType(st), MappingProxyType(bl), MappingProxyType(comps),
                       MappingProxyType({"core": nc, "bypass": nb}), Fn, Fg, ram, bu.Wf_kg_s,
                       bu.Wf_kg_s / Fn if Fn > 0 else math.inf, st["3"].Pt_Pa / st["2"].Pt_Pa, p.BPR,
                       mech, p.offtake_hp_W + p.offtake_lp_W, bu.heat_unreleased_W, bu.heat_released_W)


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
