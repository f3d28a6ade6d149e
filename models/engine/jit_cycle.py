"""The turbofan's matching residuals compiled: :meth:`.offdesign.TurbofanOffDesign._cycle` on plain floats.

One evaluation of the gas path in Python costs about 0.4 ms (some fifty gas-property
calls, sixteen Newton inversions, four map reads, a dozen small dataclasses); the
transient engine makes several per 50 ms step. :func:`cycle` is the same sequence
of component calculations (:mod:`.compressor`, :mod:`.burner`, :mod:`.turbine`,
:mod:`.flow` mixing, :mod:`.nozzle`), in the same order, on floats, compiled by
numba: about 100 times faster. It covers the configuration a mission runs: no
inlet distortion, no booster, any bleeds (cooling, handling, customer, bypass).
Other configurations, and any input the Python components would refuse, go to
the Python version (:class:`FastCycle` returns None and sets nothing), which stays
the reference and raises with its full message. ``tests/engine/test_jit_cycle.py``
checks that both give the same residuals and outputs.

Outputs (``o``, by index): see :data:`OUT`.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5 and 7
(the component models and the matching, as in the Python modules).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import jit_kernels as K
from .jit_freestream import atm_array
from .jit_freestream import free_stream as compiled_free_stream
from .jit_kernels import jit
from .shaft import TERM_INDEX, TURBOFAN_SHAFTS, spool_balance, term_arrays

__all__ = ["OUT", "FastCycle"]

#: Names of the outputs of :func:`cycle`, in order.
OUT = ("Fn", "Fg", "ram", "N1c", "N2c", "Tt4", "T41", "Tt21", "Tt17", "Tt7", "Pt3", "Pt2", "hb", "FAR4",
       "W2", "SM_fan", "SM_hpc", "P_hpt", "P_lpt", "P_hpc", "P_fan")
_T_STD, _P_STD = 288.15, 101325.0
_SINK = {"overboard": 0, "bypass": 1, "hpt": 2, "lpt": 3}
# the declared shaft terms (shaft.TURBOFAN_SHAFTS): spool and kind of each, where each power goes in the vector
_TERM_SPOOL, _TERM_KIND = term_arrays()
_NTERM = len(TURBOFAN_SHAFTS)
_T_HPT, _T_HPC, _T_PHP, _T_LPT, _T_FO, _T_FI, _T_BO, _T_PLP = (
    TERM_INDEX[n] for n in ("hpt", "hpc", "port_hp", "lpt", "fan_outer", "fan_inner", "booster", "port_lp"))
# indices into the engine parameter vector e
(_W2, _PRh, _PRl, _Wf, _N1d, _N2d, _BPRd, _PI, _KIN, _EIN, _D2124, _D2425, _HBF, _HBO, _HBN2, _STG, _NSTG,
 _ETAB, _DPB, _TT4D, _D4445, _D57, _BYB, _D1317, _CVC, _CDC, _CVB, _CDB, _EMH, _EML, _WC4, _WC45, _A8, _A18,
 _PHP, _PLP, _FN, _TT4R) = range(38)


@jit
def _compress(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, PR: float,
              eta: float, err: np.ndarray) -> tuple[float, float, float]:
    """Exit (Tt [K], ht [J/kg], Pt [Pa]) of :func:`.compressor.compressor` without bleeds."""
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        err[0] = 1
        return T, ht, P
    Tis = K.T_isentropic(gc, gs, T, PR, f, T * PR ** 0.2857, err)
    ho = ht + (K.h(gc, gs, Tis, f, err) - ht) / eta
    if not (W >= 0.0 and math.isfinite(W)) or not (P * PR > 0.0 and math.isfinite(P * PR)):
        err[0] = 1
    To = K.T_from_h(gc, gs, ho, f, T + (Tis - T) / eta, err)
    return To, ho, P * PR


@jit
def _expand(gc: np.ndarray, gs: np.ndarray, T: float, f: float, ht: float, P_from: float, P_to: float,
            eta: float, err: np.ndarray) -> float:
    """Exit enthalpy [J/kg] of :func:`.turbine._expand`."""
    Tis = K.T_isentropic(gc, gs, T, P_to / P_from, f, T * (P_to / P_from) ** 0.25, err)
    return ht - eta * (ht - K.h(gc, gs, Tis, f, err))


@jit
def _nozzle(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, Pa: float,
            Cv: float, err: np.ndarray) -> tuple[float, float]:
    """(gross thrust [N], effective area [m2]) of :func:`.nozzle.convergent_nozzle`."""
    if P < Pa:
        err[0] = 1
        return 0.0, 1.0
    Ts, p_pt = K.static_from_total(gc, gs, T, 1.0, f, err)
    Ps = P * p_pt
    choked = Pa <= Ps
    if not choked:
        Ts = K.T_isentropic(gc, gs, T, Pa / P, f, T, err)
        Ps = Pa
    V = math.sqrt(max(2.0 * (ht - K.h(gc, gs, Ts, f, err)), 0.0))
    R_ = K.R(gs, f)
    A = W / (Ps / (R_ * Ts) * V) if V > 0.0 else math.inf
    return Cv * W * V + ((Ps - Pa) * A if choked else 0.0), A


@jit
def _mix_T(gc: np.ndarray, gs: np.ndarray, W: np.ndarray, T: np.ndarray, f: np.ndarray, ht: np.ndarray, n: int,
           err: np.ndarray) -> tuple[float, float, float, float]:
    """(W, Tt, FAR, ht) of :func:`.flow.mix` of the first n streams."""
    Ws = air = fuel = H = WT = 0.0
    for i in range(n):
        Ws += W[i]
    if not Ws > 0.0:
        err[0] = 1
        return 1.0, 300.0, 0.0, 0.0
    for i in range(n):
        air += W[i] / (1.0 + f[i])
    for i in range(n):
        fuel += W[i] * f[i] / (1.0 + f[i])
    for i in range(n):
        H += W[i] * ht[i]
    for i in range(n):
        WT += W[i] * T[i]
    F = fuel / air
    return Ws, K.T_from_h(gc, gs, H / Ws, F, WT / Ws, err), F, H / Ws


@jit
def _turbine(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, PR: float,
             eta: float, cw: np.ndarray, cT: np.ndarray, cP: np.ndarray, cf: np.ndarray, ch: np.ndarray,
             cfp: np.ndarray, nc: int, err: np.ndarray) -> tuple[float, float, float, float, float, float, float]:
    """:func:`.turbine.turbine` with nc cooling streams: (power, exit W, Tt, Pt, FAR, ht, rotor-inlet Tt)."""
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        err[0] = 1
        return 0.0, W, T, P, f, ht, T
    Pin, Pout = P, P / PR
    ho = _expand(gc, gs, T, f, ht, Pin, Pout, eta, err) if PR > 1.0 else ht
    power = W * (ht - ho)
    Tg = T - (ht - ho) / K.cp(gc, gs, T, f, err)
    if not (W >= 0.0 and math.isfinite(W)) or not (Pout > 0.0 and math.isfinite(Pout)):
        err[0] = 1
    To = K.T_from_h(gc, gs, ho, f, Tg, err)
    eW, eT, ef, eh = np.empty(nc + 1), np.empty(nc + 1), np.empty(nc + 1), np.empty(nc + 1)
    eW[0], eT[0], ef[0], eh[0] = W, To, f, ho
    for i in range(nc):
        Pc = Pout + cfp[i] * (Pin - Pout)
        if cP[i] < Pc * (1.0 - 1e-12):
            err[0] = 1
        hc = _expand(gc, gs, cT[i], cf[i], ch[i], Pc, Pout, eta, err) if Pc > Pout else ch[i]
        power += cw[i] * (ch[i] - hc)
        eW[i + 1], eT[i + 1], ef[i + 1], eh[i + 1] = cw[i], cT[i], cf[i], hc
    if nc > 0:
        Wo, To, fo, ho = _mix_T(gc, gs, eW, eT, ef, eh, nc + 1, err)
    else:
        Wo, fo = W, f
    T41 = T
    m = 0
    for i in range(nc):
        if cfp[i] == 1.0:
            m += 1
    if m > 0:
        eW[0], eT[0], ef[0], eh[0] = W, T, f, ht
        m = 1
        for i in range(nc):
            if cfp[i] == 1.0:
                eW[m], eT[m], ef[m], eh[m] = cw[i], cT[i], cf[i], ch[i]
                m += 1
        T41 = _mix_T(gc, gs, eW, eT, ef, eh, m, err)[1]
    return power, Wo, To, Pout, fo, ho, T41


@jit
def _cooling(b: np.ndarray, bW: np.ndarray, bT: np.ndarray, bP: np.ndarray, bh: np.ndarray, where: float,
             cw: np.ndarray, cT: np.ndarray, cP: np.ndarray, cf: np.ndarray, ch: np.ndarray,
             cfp: np.ndarray) -> int:
    """Copy the bleeds returned at turbine ``where`` (column 3 of ``b``: 2 HPT, 3 LPT) into the cooling
    arrays; returns how many."""
    nc = 0
    for i in range(b.shape[0]):
        if b[i, 3] == where:
            cw[nc], cT[nc], cP[nc], cf[nc], ch[nc], cfp[nc] = bW[i], bT[i], bP[i], 0.0, bh[i], b[i, 4]
            nc += 1
    return nc


@jit
def cycle(x: np.ndarray, fs: np.ndarray, ctl: np.ndarray, e: np.ndarray, gc: np.ndarray, gs: np.ndarray,
          bl: np.ndarray, fan: Any, hpc: Any, hpt: Any, lpt: Any, r: np.ndarray, o: np.ndarray,
          with_sm: bool) -> int:
    """Residuals r (9) and outputs o (:data:`OUT`) at unknowns x; returns 0, or 1 where Python would raise.

    fs: free stream (Tt0 [K], Pt0 [Pa], V0 [m/s], p_amb [Pa], Mach [-], ram recovery [-]);
    ctl: demand kind (0 Wf, 1 N1, 2 N1c, 3 Tt4, 4 Fn), demand value, customer bleed [-],
    HP and LP offtakes [W], handling bleed override (NaN: the N2 schedule);
    e: engine parameters (indices ``_W2`` ...); bl: bleeds (frac_W, frac_P, frac_work, sink, sink_frac_P);
    fan, hpc, hpt, lpt: (xg, yg, ihx, ihy, cells, lim, scalars, surge x, surge w) of the scaled maps, scalars
    (s_Wc, s_PR, s_eff, s_Nc, Nc_min clamp, Nc_max clamp).
    """
    err = np.zeros(1, np.int64)
    W2, bfan, bhpc = x[0] * e[_W2], x[1], x[2]
    N1, N2 = x[3] * e[_N1d], x[4] * e[_N2d]
    PRh, PRl, BPR, Wf = x[5] * e[_PRh], x[6] * e[_PRl], x[7] * e[_BPRd], x[8] * e[_Wf]
    cust, off_hp, off_lp = ctl[2], ctl[3], ctl[4]
    if W2 <= 0.0 or N1 <= 0.0 or N2 <= 0.0 or BPR < 0.0 or Wf <= 0.0 or PRh < 1.0 or PRl < 1.0:
        return 1
    if not (W2 >= 0.0 and math.isfinite(W2)):
        return 1
    T2 = fs[0]
    h2 = K.h(gc, gs, T2, 0.0, err)
    P2 = fs[1] * e[_PI] * fs[5]
    sq2 = math.sqrt(T2 / _T_STD)
    N1c = N1 / sq2
    v, gx, gy = np.empty(3), np.empty(3), np.empty(3)
    K.table(fan[0], fan[1], fan[2], fan[3], fan[4], fan[5], N1c / fan[6][3], bfan, v, gx, gy, err)
    Wc, PRf, eff = v[0] * fan[6][0], (v[1] - 1.0) * fan[6][1] + 1.0, v[2] * fan[6][2]
    Wsec = 1.0 * Wc * (P2 / _P_STD) / sq2
    Wt = Wsec * (W2 / Wsec)
    if not (BPR >= 0.0):
        return 1
    fr = 1.0 / (1.0 + BPR)
    Wcore, Wbyp = Wt * fr, Wt * (1.0 - fr)
    T13, h13, P13 = _compress(gc, gs, Wbyp, T2, P2, 0.0, h2, PRf, eff, err)
    T21, h21, P21 = _compress(gc, gs, Wcore, T2, P2, 0.0, h2, 1.0 + e[_KIN] * (PRf - 1.0), eff * e[_EIN], err)
    P_fo = Wbyp * (h13 - h2)
    P_fi = Wcore * (h21 - h2)
    P25 = P21 * (1.0 - e[_D2124]) * (1.0 - e[_D2425])
    T25, h25, W25 = T21, h21, Wcore
    sq25 = math.sqrt(T25 / _T_STD)
    N2c = N2 / sq25
    K.table(hpc[0], hpc[1], hpc[2], hpc[3], hpc[4], hpc[5], N2c / hpc[6][3], bhpc, v, gx, gy, err)
    Wch, PRc, effc = v[0] * hpc[6][0], (v[1] - 1.0) * hpc[6][1] + 1.0, v[2] * hpc[6][2]
    Wsh = 1.0 * Wch * (P25 / _P_STD) / sq25
    # bleeds: the design's, then handling (to the bypass) and customer (overboard)
    nb0 = bl.shape[0]
    b = np.empty((nb0 + 2, 5))
    for i in range(nb0):
        for j in range(5):
            b[i, j] = bl[i, j]
    nb = nb0
    if math.isnan(ctl[5]):
        s = (e[_HBN2] + 0.01 - N2 / e[_N2d]) / 0.02
        s = 0.0 if s < 0.0 else (1.0 if s > 1.0 else s)
        hb = max(e[_HBF], e[_HBO] * (s * s * (3.0 - 2.0 * s)))
    else:
        hb = max(e[_HBF], ctl[5])
    if hb > 0.0:
        if not PRc > 1.0 or not (0.0 <= hb < 1.0):
            return 1
        xs = e[_STG] / e[_NSTG]
        b[nb, 0], b[nb, 1], b[nb, 2], b[nb, 3], b[nb, 4] = hb, (PRc ** xs - 1.0) / (PRc - 1.0), xs, 1.0, 1.0
        nb += 1
    if cust > 0.0:
        if not (cust < 1.0):
            return 1
        b[nb, 0], b[nb, 1], b[nb, 2], b[nb, 3], b[nb, 4] = cust, 1.0, 1.0, 0.0, 1.0
        nb += 1
    Win = Wsh * (W25 / Wsh)
    T3, h3, P3 = _compress(gc, gs, Win, T25, P25, 0.0, h25, PRc, effc, err)
    bW, bT, bP, bh = np.empty(nb), np.empty(nb), np.empty(nb), np.empty(nb)
    W_inter = W_exit = W_all = 0.0
    for i in range(nb):
        bW[i] = b[i, 0] * Win
        if b[i, 1] == 1.0 and b[i, 2] == 1.0:
            bT[i], bP[i], bh[i] = T3, P3, h3
        else:
            bh[i] = h25 + b[i, 2] * (h3 - h25)
            bP[i] = P25 + b[i, 1] * (P3 - P25)
            if not (bP[i] > 0.0 and math.isfinite(bP[i])):
                err[0] = 1
            bT[i] = K.T_from_h(gc, gs, bh[i], 0.0, T25, err)
    for i in range(nb):
        if not (b[i, 1] == 1.0 and b[i, 2] == 1.0):
            W_inter += bW[i]
    for i in range(nb):
        W_all += bW[i]
    if W_all >= Win:
        return 1
    P_b = 0.0
    for i in range(nb):
        P_b += bW[i] * (h3 - bh[i])
    P_hpc = Win * (h3 - h25) - P_b
    W3 = Win - W_inter
    for i in range(nb):
        if b[i, 1] == 1.0 and b[i, 2] == 1.0:
            W_exit += bW[i]
    W31 = W3 - W_exit
    # burner
    if not (Wf >= 0.0) or not (0.0 < e[_ETAB] <= 1.0):
        return 1
    f4 = 0.0 + Wf / (W31 / (1.0 + 0.0))
    if not (0.0 <= f4 <= gs[1]):
        return 1
    ha3, hf3 = K.h_parts(gc, gs, T3, err)
    q = (f4 - 0.0) * (e[_ETAB] * gs[12] + gs[13])
    Tt4 = K.T_from_h(gc, gs, (ha3 + 0.0 * hf3 + q) / (1.0 + f4), f4, e[_TT4D], err) if Wf > 0 else T3
    W4 = W31 + W31 / (1.0 + 0.0) * (f4 - 0.0)
    P4 = P3 * (1.0 - e[_DPB])
    h4 = K.h(gc, gs, Tt4, f4, err)
    # HPT with its cooling
    Nh = N2 / math.sqrt(Tt4 / _T_STD)
    Nh = Nh if Nh > hpt[6][4] else hpt[6][4]
    Nh = Nh if Nh < hpt[6][5] else hpt[6][5]
    K.table(hpt[0], hpt[1], hpt[2], hpt[3], hpt[4], hpt[5], Nh / hpt[6][3], (PRh - 1.0) / hpt[6][1] + 1.0,
            v, gx, gy, err)
    Wc_t1, eff_t1 = v[0] * hpt[6][0], v[1] * hpt[6][2]
    cw, cT, cP, cf, ch, cfp = np.empty(nb), np.empty(nb), np.empty(nb), np.empty(nb), np.empty(nb), np.empty(nb)
    nc = _cooling(b, bW, bT, bP, bh, 2.0, cw, cT, cP, cf, ch, cfp)
    P_hpt, W44, T44, P44, f44, h44, T41 = _turbine(gc, gs, W4, Tt4, P4, f4, h4, PRh, eff_t1, cw, cT, cP, cf, ch,
                                                   cfp, nc, err)
    P45 = P44 * (1.0 - e[_D4445])
    Nl = N1 / math.sqrt(T44 / _T_STD)
    Nl = Nl if Nl > lpt[6][4] else lpt[6][4]
    Nl = Nl if Nl < lpt[6][5] else lpt[6][5]
    K.table(lpt[0], lpt[1], lpt[2], lpt[3], lpt[4], lpt[5], Nl / lpt[6][3], (PRl - 1.0) / lpt[6][1] + 1.0,
            v, gx, gy, err)
    Wc_t2, eff_t2 = v[0] * lpt[6][0], v[1] * lpt[6][2]
    nc = _cooling(b, bW, bT, bP, bh, 3.0, cw, cT, cP, cf, ch, cfp)
    P_lpt, W5, T5, P5, f5, h5, _ = _turbine(gc, gs, W44, T44, P45, f44, h44, PRl, eff_t2, cw, cT, cP, cf, ch,
                                            cfp, nc, err)
    P7 = P5 * (1.0 - e[_D57])
    # bypass: the fan's bypass stream, less a bypass bleed, plus the bleeds returned to it
    mW, mT, mf, mh = np.empty(nb + 1), np.empty(nb + 1), np.empty(nb + 1), np.empty(nb + 1)
    mW[0], mT[0], mf[0], mh[0] = Wbyp * (1.0 - e[_BYB]), T13, 0.0, h13
    m = 1
    for i in range(nb):
        if b[i, 3] == 1.0:
            mW[m], mT[m], mf[m], mh[m] = bW[i], bT[i], 0.0, bh[i]
            m += 1
    if m > 1:
        W17, T17, f17, h17 = _mix_T(gc, gs, mW, mT, mf, mh, m, err)
    else:
        W17, T17, f17, h17 = mW[0], T13, 0.0, h13
    P17 = P13 * (1.0 - e[_D1317])
    Pa = fs[3]
    Fg_c, A8 = _nozzle(gc, gs, W5, T5, P7, f5, h5, Pa, e[_CVC], err)
    Fg_b, A18 = _nozzle(gc, gs, W17, T17, P17, f17, h17, Pa, e[_CVB], err)
    ram = W2 * fs[2]
    Fg = Fg_c + Fg_b
    Fn = Fg - ram
    kind, val = ctl[0], ctl[1]
    if kind == 0.0:
        r9 = (Wf - val) / e[_Wf]
    elif kind == 1.0:
        r9 = (N1 - val) / e[_N1d]
    elif kind == 2.0:
        r9 = (N1c - val) / e[_N1d]
    elif kind == 3.0:
        r9 = (Tt4 - val) / e[_TT4R]
    else:
        r9 = (Fn - val) / e[_FN]
    r[0] = (Wsec - W2) / W2
    r[1] = (Wsh - W25) / W25
    r[2] = (Wc_t1 - W4 * math.sqrt(Tt4 / _T_STD) / (P4 / _P_STD)) / e[_WC4]
    r[3] = (Wc_t2 - W44 * math.sqrt(T44 / _T_STD) / (P45 / _P_STD)) / e[_WC45]
    r[4] = A8 / e[_A8] - 1.0
    r[5] = A18 / e[_A18] - 1.0
    Pt = np.zeros(_NTERM)
    Pt[_T_HPT], Pt[_T_HPC], Pt[_T_PHP], Pt[_T_LPT] = P_hpt, P_hpc, off_hp, P_lpt
    Pt[_T_FO], Pt[_T_FI], Pt[_T_BO], Pt[_T_PLP] = P_fo, P_fi, 0.0, off_lp
    eta_mech, net, loss = np.empty(2), np.empty(2), np.empty(2)
    eta_mech[0], eta_mech[1] = e[_EMH], e[_EML]
    spool_balance(Pt, _TERM_SPOOL, _TERM_KIND, eta_mech, net, loss)
    r[6] = net[0] / e[_PHP]
    r[7] = net[1] / e[_PLP]
    r[8] = r9
    sm_f = sm_h = math.nan
    if with_sm:
        sm_f = K.surge_margin(fan[0], fan[1], fan[2], fan[3], fan[4], fan[5], fan[7], fan[8], N1c / fan[6][3],
                              bfan, fan[6][1])
        sm_h = K.surge_margin(hpc[0], hpc[1], hpc[2], hpc[3], hpc[4], hpc[5], hpc[7], hpc[8], N2c / hpc[6][3],
                              bhpc, hpc[6][1])
    vals = (Fn, Fg, ram, N1c, N2c, Tt4, T41, T21, T17, T5, P3, P2, hb, f4, W2, sm_f, sm_h, P_hpt, P_lpt,
            P_hpc, P_fo + P_fi)
    for i in range(len(vals)):
        o[i] = vals[i]
    return int(err[0])


# ---------------------------------------------------------------------- Python side
def _table_arrays(tab: Any) -> tuple[np.ndarray, ...]:
    """The arrays of a :class:`.map_interp.BicubicTable` (its private layout, read once)."""
    nx, ny = len(tab.x), len(tab.y)
    cells = np.array([[list(tab._cells[i][j]) for j in range(ny - 1)] for i in range(nx - 1)], dtype=float)
    lim = np.array([tab.x_lo, tab.x_hi, tab.y_lo, tab.y_hi, tab.x_min, tab.x_max, tab.y_min, tab.y_max])
    return (np.array(tab.x), np.array(tab.y), np.array(tab._ihx), np.array(tab._ihy), cells, lim)


def _map_tuple(m: Any, compressor: bool) -> tuple[Any, ...] | None:
    """(xg, yg, ihx, ihy, cells, lim, scalars, surge x, surge w) of a scaled map, None if it is of another kind."""
    from .map_scaled import ScaledCompressorMap, ScaledTurbineMap
    lo, hi = -math.inf, math.inf
    if not compressor and hasattr(m, "inner") and hasattr(m, "Nc_min"):      # engine_model's speed clamp:
        lo, m = m.Nc_min, m.inner           # its conditional expression clamps below only (not above Nc_max)
    if not isinstance(m, ScaledCompressorMap if compressor else ScaledTurbineMap):
        return None
    sc = np.array([m.s_Wc, m.s_PR, m.s_eff, m.s_Nc, lo, hi])
    if compressor:
        sx, sw = np.array(m.map._surge_x), np.array(m.map._surge_w)
    else:
        sx, sw = np.zeros(2), np.zeros(2)
    return (*_table_arrays(m.map._table), sc, sx, sw)


class FastCycle:
    """The compiled residuals of one :class:`.offdesign.TurbofanOffDesign` (no distortion, no booster).

    Build with :meth:`build`, which returns None when numba is missing or the engine has
    a configuration the kernel does not cover (a booster, maps of another kind).
    """

    def __init__(self, e: np.ndarray, gc: np.ndarray, gs: np.ndarray, bl: np.ndarray,
                 maps: tuple[Any, Any, Any, Any], gas: Any) -> None:
        self.e, self.gc, self.gs, self.bl, self.maps, self.gas = e, gc, gs, bl, maps, gas
        self.r, self.o = np.empty(9), np.empty(len(OUT))
        self._fs: tuple[tuple[float, float, float], np.ndarray] | None = None
        self._ctl = np.empty(6)
        self.atm = atm_array()                  # the ISA's constants, for the compiled free stream
        self.fsc = np.full(9, math.nan)         # (alt, Mach, dT) and the free stream of jit_solve.chord_solve

    @classmethod
    def build(cls, od: Any) -> FastCycle | None:
        """Pack the design, gas and maps of `od` into arrays, or None (see the class docstring)."""
        from .combustion import h_fuel_liquid
        from .gas import T_MAX_K, T_MIN_K, _h, _phi
        if not K.AVAILABLE or od.nb:
            return None
        p, m, ref, g = od.p, od.maps, od.ref, od.gas
        maps = (_map_tuple(m.fan, True), _map_tuple(m.hpc, True), _map_tuple(m.hpt, False), _map_tuple(m.lpt, False))
        if any(t is None for t in maps):
            return None
        if not all(0.0 <= d < 1.0 for d in (p.dPqP_21_24, p.dPqP_24_25, p.dPqP_burner, p.dPqP_44_45, p.dPqP_5_7,
                                            p.dPqP_13_17)) or not (0.0 < p.inlet_pi <= 1.0):
            return None
        if not all(0.0 < c <= 1.0 for c in (p.Cv_core, p.Cd_core, p.Cv_bypass, p.Cd_bypass)):
            return None
        e = np.array([ref["W2"], ref["PRh"], ref["PRl"], ref["Wf"], p.N1_rpm, p.N2_rpm, p.BPR, p.inlet_pi,
                      od.k_inner, od.eff_ratio_inner, p.dPqP_21_24, p.dPqP_24_25, p.handling_bleed_frac, od.hb_open,
                      od.hb_N2, p.handling_bleed_stage, p.hpc_stages, p.eta_burner, p.dPqP_burner, od.dp.Tt4_K,
                      p.dPqP_44_45, p.dPqP_5_7, p.bypass_bleed_frac, p.dPqP_13_17, p.Cv_core, p.Cd_core,
                      p.Cv_bypass, p.Cd_bypass, p.eta_mech_hp, p.eta_mech_lp, ref["Wc4"], ref["Wc45"], ref["A8"],
                      ref["A18"], ref["P_hp"], ref["P_lp"], ref["Fn"], ref["Tt4"]], dtype=float)
        gc = np.zeros((2, 6, 8))
        for k, iv in enumerate((g._lo, g._hi)):
            for s, c in enumerate(iv):
                gc[k, s, :len(c)] = c
        lo, hi = g._lo, g._hi
        gs = np.array([g._T_mid, g.FAR_stoich, _h(lo[2], T_MIN_K), _h(lo[3], T_MIN_K), _h(hi[2], T_MAX_K),
                       _h(hi[3], T_MAX_K), _phi(lo[4], T_MIN_K), _phi(lo[5], T_MIN_K), _phi(hi[4], T_MAX_K),
                       _phi(hi[5], T_MAX_K), g._RA, g._RB, g.LHV_J_kg, h_fuel_liquid(p.T_fuel_K, g)])
        assert np.allclose(gs[2:10], g._h_bounds + g._phi_bounds, rtol=0.0, atol=0.0)
        bl = np.array([[b.frac_W, b.frac_P, b.frac_work, _SINK[b.sink], b.sink_frac_P] for b in p.bleeds],
                      dtype=float).reshape(-1, 5)
        return cls(e, gc, gs, bl, maps, g)  # type: ignore[arg-type]

    def free_stream(self, cond: tuple[float, float, float]) -> np.ndarray:
        """(Tt0, Pt0, V0, p_amb, Mach, ram recovery) of a flight condition, cached; raises as :func:`.free_stream`.

        Compiled (:func:`.jit_freestream.free_stream`); where that refuses, :func:`.atmosphere.free_stream` (which
        raises, or gives the values)."""
        if self._fs is not None and self._fs[0] == cond:
            return self._fs[1]
        fs = np.empty(6)
        if compiled_free_stream(self.gc, self.gs, self.atm, float(cond[0]), float(cond[1]), float(cond[2]), fs) != 0:
            from .atmosphere import free_stream
            from .inlet import ram_recovery_mil_e_5008b
            fr = free_stream(*cond, self.gas)              # raises with the full message
            fs = np.array([fr.Tt0_K, fr.Pt0_Pa, fr.V0_m_s, fr.amb.P_Pa, cond[1],
                           ram_recovery_mil_e_5008b(cond[1])])
        self._fs = (cond, fs)
        return fs

    def __call__(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[int, float],
                 extras: tuple[float, float, float], hb_frac: float | None, with_sm: bool = False) -> bool:
        """Evaluate at unknowns `x` (9); True with :attr:`r` and :attr:`o` filled, False where Python would raise.

        The free stream is evaluated (and may raise) in Python first.
        """
        fs = self.free_stream(cond)
        c = self._ctl
        c[0], c[1] = demand
        c[2], c[3], c[4] = extras
        c[5] = math.nan if hb_frac is None else hb_frac
        f, h, t, lp = self.maps
        return cycle(x, fs, c, self.e, self.gc, self.gs, self.bl, f, h, t, lp, self.r, self.o, with_sm) == 0


#: Demand kinds of :meth:`.offdesign.TurbofanOffDesign._cycle` as the kernel's codes.
DEMAND = {"Wf_kg_s": 0, "N1_rpm": 1, "N1c_rpm": 2, "Tt4_K": 3, "Fn_N": 4}
