"""What each element kind of an engine file computes, on the components' one implementation.

One function per kind of :data:`.element_kinds.KINDS` (registry :data:`EVAL`): it takes its inflows
(``(W [kg/s], Tt [K], Pt [Pa], FAR [-], ht [J/kg])`` by port) from the evaluation state :class:`State` and
returns its outflows by port, recording its outputs (pressure ratio, efficiency, power...), its shaft power
and its residuals. The physics is the components' float kernels, the same the turbofan's gas path calls:
:func:`.compressor.compress_exit` and :func:`.compressor.bled_power`, :func:`.bleed.bleed_state`,
:func:`.combustion.burner_far` and :func:`.combustion.burner_exit_T`, :func:`.turbine.turbine_stream`,
:func:`.flow.mix_state`, :func:`.nozzle.convergent_throat` (and :func:`.nozzle.ideal_nozzle` for the
convergent-divergent nozzle). Nothing here knows an architecture: :mod:`.engine_graph` runs the elements in
flow order and forms the unknowns and residuals from the graph.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5-7. E. S. Hendricks, J. S. Gray,
"pyCycle", Aerospace 6(87), 2019 (the elements, their design and off-design modes, the bleed fractions).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from . import jit_kernels as K
from .bleed import bleed_state
from .combustion import burner_exit_T, burner_far
from .compressor import bled_power, compress_exit
from .errors import OutOfRangeError
from .flow import P_STD_PA, T_STD_K, FlowStation, mix_state
from .nozzle import convergent_throat, ideal_nozzle
from .turbine import turbine_stream

__all__ = ["State", "EVAL", "Flow"]

Flow = tuple[float, float, float, float, float]


class State:
    """One evaluation of the graph: gas arrays, free stream, the unknowns' values, settings, and what the
    elements record (stations, outputs, shaft powers, bleed streams, residuals, thrust)."""

    def __init__(self, g: Any, design: bool, fs: tuple[float, ...], vals: dict[tuple[str, str], float],
                 settings: dict[str, Any]) -> None:
        self.g, self.design, self.fs, self.settings = g, design, fs, settings
        self.vals = {k: float(v) for k, v in vals.items()}
        self.gc, self.gs = g.gc, g.gs
        self.err = np.zeros(2, np.int64)
        self.out: dict[str, dict[str, float]] = {}
        self.flows: dict[tuple[str, str], Flow] = {}
        self.bleed: dict[str, Flow] = {}
        self.resid: dict[str, float] = {}
        self.turb_W: dict[str, float] = {s: 0.0 for s in g.eng.shafts}
        self.comp_W: dict[str, float] = {s: 0.0 for s in g.eng.shafts}
        self.Fg = self.ram = self.Wf = 0.0

    def check(self, e: Any, what: str = "") -> None:
        """Raise one line naming the element where a kernel flagged an error."""
        code = int(self.err[0])
        if code:
            self.err[:] = 0
            msg = {1: f"a temperature leaves the gas tables ({K.T_MIN:g} K to {K.T_MAX:g} K)",
                   2: "a pressure ratio below 1 or an efficiency outside (0, 1]",
                   7: "a cooling flow's pressure is below that of its entry into the turbine",
                   8: "a flow or pressure is not finite or not positive"}.get(code, f"error {code}")
            raise OutOfRangeError(f"element {e.name!r}: {what or msg}")

    def N(self, shaft: str) -> float:
        """Speed of a shaft [rpm]: its unknown, the point's setting, or its design speed."""
        return self.vals.get(("N", shaft), self.settings.get("N_rpm", {}).get(shaft,
                                                                               self.g.eng.shafts[shaft].attrs["N_rpm"]))


def _floats(**kw: Any) -> dict[str, float]:
    return {k: float(v) for k, v in kw.items()}


def _Nc(N: float, T: float) -> float:
    return N / math.sqrt(T / T_STD_K)


def _Wc(W: float, T: float, P: float) -> float:
    return W * math.sqrt(T / T_STD_K) / (P / P_STD_PA)


def _compression(s: State, e: Any, fin: Flow, PR: float, eta: float) -> tuple[float, float, float]:
    W, T, P, f, h = fin
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        raise OutOfRangeError(f"element {e.name!r}: PR={PR:.6g} and eta={eta:.6g} must be >= 1 and in (0, 1]")
    To, ho = compress_exit(s.gc, s.gs, T, f, h, PR, eta, s.err)
    s.check(e)
    return float(To), float(ho), P * PR


def _map_point(s: State, e: Any, Nc: float, W: float, T: float, P: float) -> tuple[float, float, float]:
    """(PR, eta, beta) of a compressor: by design its attributes; off-design its scaled map at its beta (an
    unknown, or held), with the residual map flow = inflow."""
    a = e.attrs
    if s.design:
        return a["PR"], a["eta"], math.nan
    beta = s.g.held_beta.get(e.name)
    if beta is None:
        beta = s.vals[("beta", e.name)]
    m = s.g.maps[e.name]
    try:
        Wc_map, PR, eta = m.evaluate(Nc, beta)
    except OutOfRangeError as exc:
        raise OutOfRangeError(f"element {e.name!r}: {exc}") from None
    s.resid[f"{e.name}.flow"] = (Wc_map * (P / P_STD_PA) / math.sqrt(T / T_STD_K) - W) / W
    return PR, eta, beta


def bleed_frac(s: State, b: Any) -> float:
    """A bleed's W/W_in [-]: the point's setting, else its frac_W, opened by its schedule off-design."""
    fixed = s.settings.get("bleeds", {}).get(b.name)
    if fixed is not None:
        return float(fixed)
    fr = b.frac_W
    sc = b.schedule
    if sc is not None and not s.design:
        o = s.out[sc["of"]]
        x = (sc["Nc_frac"] + 0.5 * sc["ramp_frac"] - o["Nc_rpm"] / s.g.ref[("Nc", sc["of"])]) / sc["ramp_frac"]
        x = 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)
        fr = max(fr, sc["open_frac"] * (x * x * (3.0 - 2.0 * x)))
    return fr


def compressor(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    N = s.N(e.attrs["shaft"])
    Nc = _Nc(N, T)
    PR, eta, beta = _map_point(s, e, Nc, W, T, P)
    T3, h3, P3 = _compression(s, e, fin["in"], PR, eta)
    bl = s.g.bleeds_from[e.name]
    bW, bh = np.zeros(len(bl)), np.zeros(len(bl))
    W_out = W
    for i, b in enumerate(bl):
        if b.stage is not None:
            x = b.stage / e.attrs["stages"]
            fP, fw = ((PR ** x - 1.0) / (PR - 1.0) if PR > 1.0 else 1.0), x
        else:
            fP, fw = b.frac_P, b.frac_work
        bT, bP, bhh = bleed_state(s.gc, s.gs, T, P, f, h, T3, P3, h3, fP, fw, s.err)
        s.check(e, f"bleed {b.name!r}: its state leaves the gas tables")
        bW[i], bh[i] = bleed_frac(s, b) * W, bhh
        s.bleed[b.name] = (float(bW[i]), float(bT), float(bP), f, float(bhh))
        W_out -= bW[i]
    if not W_out > 0.0:
        raise OutOfRangeError(f"element {e.name!r}: its bleeds take all of its flow")
    power = float(bled_power(W, h, h3, bW, bh, len(bl)))
    s.comp_W[e.attrs["shaft"]] += power
    s.out[e.name] = _floats(PR=PR, eta=eta, beta=beta, Wc_kg_s=_Wc(W, T, P), N_rpm=N, Nc_rpm=Nc, power_W=power,
                            Tt_exit_K=T3, Pt_exit_Pa=P3)
    return {"out": (W_out, T3, P3, f, h3)}


def fan(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    a = e.attrs
    N = s.N(a["shaft"])
    Nc = _Nc(N, T)
    PR, eta, beta = _map_point(s, e, Nc, W, T, P)
    BPR = a["BPR"] if s.design else s.vals[("BPR", e.name)]
    fr = 1.0 / (1.0 + BPR)
    Wcore, Wbyp = W * fr, W * (1.0 - fr)
    To, ho, Po = _compression(s, e, (Wbyp, T, P, f, h), PR, eta)
    Ti, hi, Pi = _compression(s, e, (Wcore, T, P, f, h), 1.0 + s.g.k_inner[e.name] * (PR - 1.0),
                              eta * s.g.eff_ratio[e.name])
    power = Wbyp * (ho - h) + Wcore * (hi - h)
    s.comp_W[a["shaft"]] += power
    s.out[e.name] = _floats(PR=PR, eta=eta, PR_inner=Pi / P, beta=beta, BPR=BPR, Wc_kg_s=_Wc(W, T, P), N_rpm=N,
                            Nc_rpm=Nc, power_W=power, Tt_exit_K=To, Pt_exit_Pa=Po)
    return {"core": (Wcore, Ti, Pi, f, hi), "bypass": (Wbyp, To, Po, f, ho)}


def splitter(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    BPR = e.attrs["BPR"] if s.design else s.vals[("BPR", e.name)]
    fr = 1.0 / (1.0 + BPR)
    s.out[e.name] = dict(BPR=BPR)
    return {"core": (W * fr, T, P, f, h), "bypass": (W * (1.0 - fr), T, P, f, h)}


def inlet(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W = s.vals[("W", e.name)] if ("W", e.name) in s.vals else s.g.eng.design["W_kg_s"]
    Tt0, Pt0, V0, _, _, rec = s.fs
    P = Pt0 * e.attrs["pi"] * (rec if e.attrs["recovery"] == "mil_e_5008b" else 1.0)
    h = float(K.h(s.gc, s.gs, Tt0, 0.0, s.err))
    s.check(e)
    s.ram += W * V0
    s.out[e.name] = dict(W_kg_s=W, ram_drag_N=W * V0, Pt_Pa=P)
    return {"out": (W, Tt0, P, 0.0, h)}


def duct(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    W_left = W
    for b in s.g.bleeds_from[e.name]:
        bw = bleed_frac(s, b) * W
        s.bleed[b.name] = (bw, T, P, f, h)
        W_left -= bw
    ins = [s.bleed[b.name] for b in s.g.bleeds_to[e.name]]
    if ins:
        n = len(ins) + 1
        a = np.array([(W_left, T, f, h)] + [(x[0], x[1], x[3], x[4]) for x in ins]).T.copy()
        Wm, Tm, fm, hm = mix_state(s.gc, s.gs, a[0], a[1], a[2], a[3], n, s.err)
        s.check(e)
        W_left, T, f, h = float(Wm), float(Tm), float(fm), float(hm)
    if not W_left > 0.0:
        raise OutOfRangeError(f"element {e.name!r}: its bleeds take all of its flow")
    return {"out": (W_left, T, P * (1.0 - e.attrs["dPqP"]), f, h)}


def burner(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    a = e.attrs
    W_air = W / (1.0 + f)
    main = e.name == s.g.main_burner
    setting = s.settings.get("burners", {}).get(e.name, {})
    Tt = FAR = None
    if main and not s.design:
        Wf = s.vals[("Wf", e.name)]
    elif "Tt_K" in setting or "FAR" in setting:
        Tt, FAR = setting.get("Tt_K"), setting.get("FAR")
    elif a["Tt_K"] is not None and a["FAR"] is None:
        Tt = a["Tt_K"]
    else:
        FAR = a["FAR"] or 0.0
    if Tt is not None:
        if not Tt > T:
            raise OutOfRangeError(f"element {e.name!r}: the exit temperature {Tt:.6g} K is not above the inlet's "
                                  f"{T:.6g} K")
        fo = float(burner_far(s.gc, s.gs, T, f, Tt, a["eta"], s.gs[13], s.err))
        Wf = W_air * (fo - f)
    else:
        if FAR is not None:
            Wf = W_air * FAR
        if not Wf >= 0.0:
            raise OutOfRangeError(f"element {e.name!r}: fuel flow {Wf:.6g} kg/s must be >= 0")
        fo = f + Wf / W_air
        Tt = float(burner_exit_T(s.gc, s.gs, T, f, fo, a["eta"], s.gs[13], s.g.T_guess(e.name, T), s.err)) \
            if Wf > 0 else T
    if not (0.0 <= fo <= s.gs[1]):
        raise OutOfRangeError(f"element {e.name!r}: the fuel-air ratio {fo:.6g} leaves [0, stoichiometric]")
    ho = float(K.h(s.gc, s.gs, Tt, fo, s.err))
    s.check(e)
    s.Wf += Wf
    s.out[e.name] = dict(Wf_kg_s=Wf, FAR=fo, Tt_exit_K=Tt, Tt_in_K=T)
    return {"out": (W + W_air * (fo - f), Tt, P * (1.0 - a["dPqP"]), fo, ho)}


def turbine(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    a = e.attrs
    N = s.N(a["shaft"])
    Nc = _Nc(N, T)
    Wc_in = _Wc(W, T, P)
    PR = s.vals[("PR", e.name)] if ("PR", e.name) in s.vals else a["PR"]
    if s.design:
        eta = a["eta"]
    else:
        try:
            Wc_map, eta = s.g.maps[e.name].evaluate(Nc, PR)
        except OutOfRangeError as exc:
            raise OutOfRangeError(f"element {e.name!r}: {exc}") from None
        s.resid[f"{e.name}.flow"] = (Wc_map - Wc_in) / s.g.ref[("Wc", e.name)]
    cool = [(s.bleed[b.name], b.entry) for b in s.g.bleeds_to[e.name]]
    c = np.array([(x[0], x[1], x[2], x[3], x[4], fp) for x, fp in cool], dtype=float).reshape(len(cool), 6).T.copy()
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        raise OutOfRangeError(f"element {e.name!r}: PR={PR:.6g} and eta={eta:.6g} must be >= 1 and in (0, 1]")
    P_t, Wo, To, Po, fo, ho, W41, T41, f41, h41 = turbine_stream(s.gc, s.gs, W, T, P, f, h, PR, eta, c[0], c[1],
                                                                 c[2], c[3], c[4], c[5], len(cool), s.err)
    s.check(e)
    s.turb_W[a["shaft"]] += float(P_t)
    s.out[e.name] = _floats(PR=PR, eta=eta, Wc_kg_s=Wc_in, N_rpm=N, Nc_rpm=Nc, power_W=P_t, Tt_rotor_in_K=T41)
    return {"out": (float(Wo), float(To), float(Po), float(fo), float(ho))}


def nozzle(s: State, e: Any, fin: dict[str, Flow]) -> dict[str, Flow]:
    W, T, P, f, h = fin["in"]
    a = e.attrs
    Pa = s.fs[3]
    if P < Pa:
        raise OutOfRangeError(f"element {e.name!r}: its inlet total pressure {P:.6g} Pa is below the ambient "
                              f"{Pa:.6g} Pa (reverse flow)")
    if a["type"] == "convergent":
        _, _, V, A, choked, Fg = convergent_throat(s.gc, s.gs, W, T, P, f, h, Pa, a["Cv"], s.err)
        s.check(e)
        Fg, A, V = float(Fg), float(A), float(V)
    else:
        r = ideal_nozzle(FlowStation(W, T, P, f, h), Pa, a["Cv"], s.g.gas)
        Fg, A, V, choked = r.Fg_N, r.throat.A_m2, r.V_ideal_m_s, r.choked
    s.Fg += Fg
    if s.design and a["PR_design"] is not None:
        s.resid[f"{e.name}.PR"] = (P / Pa) / a["PR_design"] - 1.0
    if not s.design and a["area"] == "fixed":
        s.resid[f"{e.name}.area"] = A / s.g.ref[("A", e.name)] - 1.0
    s.out[e.name] = dict(Fg_N=Fg, A_eff_m2=A, A_geom_m2=A / a["Cd"], V_m_s=V, choked=float(bool(choked)),
                         PR=P / Pa)
    return {}


#: The evaluation of each element kind (:data:`.element_kinds.KINDS`).
EVAL: dict[str, Callable[[State, Any, dict[str, Flow]], dict[str, Flow]]] = {
    "inlet": inlet, "compressor": compressor, "fan": fan, "splitter": splitter, "duct": duct, "burner": burner,
    "turbine": turbine, "nozzle": nozzle}
