"""The turbofan's gas path, written once: design, off-design and transient all evaluate :func:`turbofan`.

One function on floats and arrays, compiled by numba where it is installed and plain Python
where it is not (the :func:`.jit_kernels.jit` decorator), computes the whole separate-flow
turbofan from its unknowns: inlet, fan (outer and inner streams), booster, HPC with its bleeds
(the design's, the handling bleed into the bypass, the customer bleed), burner, HPT and LPT with
their cooling flows, the bypass duct with the bleeds returned to it, both convergent nozzles,
the spools' power balances over the declared shaft terms (:data:`.shaft.TURBOFAN_SHAFTS`), and
the matching residuals. Inlet distortion at the fan and/or HPC face is the parallel compressor
model of :mod:`.distortion` (a clean and a distorted sector on the same map, one more unknown
and one more residual each). It calls the components' float kernels (:func:`.compressor.compress_exit`,
:func:`.turbine.expand_h`, :func:`.flow.mix_state`, :func:`.nozzle.convergent_throat`,
:func:`.combustion.burner_exit_T`, :func:`.shaft.spool_balance`) and the map tables
(:func:`.jit_kernels.table`): each piece of physics has one implementation.

Every station goes into the station array ``S`` (rows :data:`ROW`, columns W [kg/s], Tt [K],
Pt [Pa], FAR [-], ht [J/kg]); the bleed streams into ``B`` (columns W, Tt, Pt, FAR, ht, sink
code of :data:`SINK`), the shaft terms' powers into ``PW``; the Python objects
(:class:`.offdesign_result.OffDesignPoint`, :class:`.cycle_design.DesignPoint`, their
:class:`.flow.FlowStation` objects) are views built from these arrays.

Two modes (parameter ``mode``):

* off-design (0): the compressors and turbines read their scaled maps; the unknowns are those of
  :mod:`.offdesign` (W2, beta_fan, beta_hpc, N1, N2, PR_hpt, PR_lpt, BPR, Wf, then beta_booster,
  beta of the fan's and HPC's distorted sectors) and the residuals its :data:`.offdesign.RESIDUALS`;
* design (1): each turbomachine runs at its design pressure ratio and efficiency
  (parameters ``PR_fan_outer`` ...), W2, BPR and the speeds are given, the burner heats to the
  design Tt4 (the fuel flow follows in closed form, :func:`.combustion.burner_far`); the unknowns
  that remain are the turbine pressure ratios, matched to the spools' power balances (residuals 6
  and 7); the other residuals are zero and the corrected flows and nozzle areas are outputs
  (:mod:`.cycle_design` solves this).

Nothing here raises: the return value is 0, or an error code (:data:`ERRORS`) with the component
where it arose (:data:`STAGES`) in ``err[1]``, and the Python callers raise one clear line.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5-7 (components,
design point and off-design matching). E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87),
2019 (one model of the elements for design and off-design, the balances of the turbofan).
"""

from __future__ import annotations

import enum
import math
from typing import Any

import numpy as np

from . import jit_kernels as K
from .bleed import bleed_state
from .combustion import burner_exit_T, burner_far
from .compressor import bled_power, compress_exit
from .flow import P_STD_PA, T_STD_K, mix_state
from .jit_kernels import borrowed, jit, jit_inline
from .nozzle import convergent_throat
from .shaft import TERM_INDEX, TURBOFAN_SHAFTS, spool_balance, term_arrays
from .turbine import turbine_stream as _turbine

__all__ = ["EP", "PARAMS", "STATIONS", "ROW", "OUT", "OX", "SINK", "ERRORS", "STAGES", "MAX_BLEEDS", "turbofan",
           "pack_params"]

#: The engine's parameters as the gas path reads them, by name (one declaration; the vector is packed by name).
PARAMS: tuple[str, ...] = (
    "mode",                                   # 0 off-design, 1 design
    "W2_ref", "PRh_ref", "PRl_ref", "Wf_ref", "N1_design_rpm", "N2_design_rpm", "BPR_ref", "Nc1_design_rpm",
    "inlet_pi", "k_inner", "eff_ratio_inner", "booster",
    "dPqP_21_24", "dPqP_24_25", "dPqP_burner", "dPqP_44_45", "dPqP_5_7", "dPqP_13_17",
    "handling_bleed_frac", "hb_open_frac", "hb_N1c_frac", "hb_ramp_frac", "handling_bleed_stage", "hpc_stages",
    "bypass_bleed_frac", "eta_burner", "Tt4_guess_K", "Cv_core", "Cv_bypass", "eta_mech_hp", "eta_mech_lp",
    "Wc21_ref", "Wc4_ref", "Wc45_ref", "A8_ref", "A18_ref", "P_hp_ref", "P_lp_ref", "Fn_ref", "Tt4_ref",
    # design mode: the turbomachines' design pressure ratios and efficiencies
    "PR_fan_outer", "eta_fan_outer", "PR_booster", "eta_booster", "PR_hpc", "eta_hpc", "eta_hpt", "eta_lpt")
#: Index of each parameter in the vector (an IntEnum: numba reads its members as constants).
EP = enum.IntEnum("EP", [(n, i) for i, n in enumerate(PARAMS)])

#: Station rows of ``S`` (:mod:`.stations`; 8 is 7 and 18 is 17: the nozzles' throats have the inlet totals).
STATIONS: tuple[str, ...] = ("0", "2", "13", "21", "24", "25", "3", "31", "4", "41", "44", "45", "5", "7", "16",
                             "17")
ROW: dict[str, int] = {s: i for i, s in enumerate(STATIONS)}
(_S0, _S2, _S13, _S21, _S24, _S25, _S3, _S31, _S4, _S41, _S44, _S45, _S5, _S7, _S16, _S17) = range(len(STATIONS))
#: Where a bleed goes (column 5 of ``B``): the codes of :data:`.bleed.SINKS`.
SINK: dict[str, int] = {"overboard": 0, "bypass": 1, "hpt": 2, "lpt": 3}
#: Most bleeds of one engine: the design's (at most 14) and the handling and customer bleeds.
MAX_BLEEDS = 16

#: Outputs ``o`` by index (:data:`OX`): thrusts [N], corrected speeds [rpm], temperatures [K], pressures [Pa],
#: handling bleed [-], FAR4 [-], W2 [kg/s], surge margins (worst sector, clean sector) [-], powers [W] ...
OUT: tuple[str, ...] = ("Fn", "Fg", "ram", "N1c", "N2c", "Tt4", "T41", "Tt21", "Tt17", "Tt7", "Pt3", "Pt2", "hb",
                        "FAR4", "W2", "SM_fan", "SM_hpc", "P_hpt", "P_lpt", "P_hpc", "P_fan", "SM_fan_clean",
                        "SM_hpc_clean", "n_bleeds", "Fg_core", "Fg_bypass", "A8_eff", "A18_eff", "choked_core",
                        "choked_bypass", "Wc2", "Wc25", "Wc4", "Wc45", "Wc21", "PR_fan", "eta_fan", "PR_booster",
                        "eta_booster", "PR_hpc", "eta_hpc", "eta_hpt", "eta_lpt", "Nc_fan_1", "beta_fan_1",
                        "Nc_hpc_1", "beta_hpc_1", "Wf", "N1", "N2", "BPR", "PRh", "PRl", "Tt3")
OX = enum.IntEnum("OX", [(n, i) for i, n in enumerate(OUT)])

#: Error codes (``err[0]``): 1 a temperature outside the gas tables or a map read beyond its margin (the
#: kernels' code), then the gas path's own checks.
ERRORS: dict[int, str] = {
    1: f"a temperature leaves the gas tables ({K.T_MIN:g} K to {K.T_MAX:g} K)",
    2: "unknowns out of range (W2, N1, N2, Wf > 0, BPR >= 0, turbine PRs >= 1 required)",
    3: "the bleeds take all of the HPC flow",
    4: "the handling bleed needs an HPC pressure ratio above 1 and a fraction in [0, 1)",
    5: "the burner's fuel-air ratio leaves [0, stoichiometric] (or, at design, Tt4 is not above Tt3)",
    6: "a nozzle's inlet total pressure is below the ambient pressure (reverse flow)",
    7: "a cooling flow's pressure is below that of its entry into the turbine",
    8: "a flow or pressure is not finite or not positive",
    9: "its map is read beyond the map's extrapolation margin (corrected speed, beta or pressure ratio off the map)",
    10: f"more than {MAX_BLEEDS - 2} bleeds besides the handling and customer bleeds",
}
#: Where the first error arose (``err[1]``).
STAGES: tuple[str, ...] = ("", "inlet", "fan", "booster", "HPC", "burner", "HPT", "LPT", "bypass duct", "nozzles",
                           "surge margin")
_ST_INLET, _ST_FAN, _ST_BOO, _ST_HPC, _ST_BURN, _ST_HPT, _ST_LPT, _ST_BYP, _ST_NOZ = range(1, 10)

#: Rows of the evaluation's scratch arrays (:func:`turbofan`): of 3 (sector vectors...), of MAX_BLEEDS + 1 (bleeds).
_N_T3, _N_TB = 35, 15


def work_arrays() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scratch arrays :func:`turbofan` works in (the small vectors of its stages, its bleeds' rows, the bleeds
    per sector), allocated once by the caller: held there, the gas path reads them without reference counts
    (:func:`.jit_kernels.borrowed`), and an allocation per evaluation costs more than the arithmetic around it."""
    return np.empty((_N_T3, 3)), np.empty((_N_TB, MAX_BLEEDS + 1)), np.empty((4, MAX_BLEEDS, 2))

_TERM_SPOOL, _TERM_KIND = term_arrays()
_NTERM = len(TURBOFAN_SHAFTS)
_T_HPT, _T_HPC, _T_PHP, _T_LPT, _T_FO, _T_FI, _T_BO, _T_PLP = (
    TERM_INDEX[n] for n in ("hpt", "hpc", "port_hp", "lpt", "fan_outer", "fan_inner", "booster", "port_lp"))


def pack_params(values: dict[str, float]) -> np.ndarray:
    """The parameter vector of :func:`turbofan` from a mapping by name (every name of :data:`PARAMS`)."""
    missing = [n for n in PARAMS if n not in values]
    if missing:
        raise KeyError(f"gas_path.pack_params: missing {', '.join(missing)}")
    return np.array([float(values[n]) for n in PARAMS])


# ---------------------------------------------------------------------- pieces
@jit_inline
def _mark(err: np.ndarray, code: int, stage: int) -> None:
    """Record the first error: its code (if the kernels did not set one) and its stage."""
    if err[0] == 0:
        err[0] = code
    if err[1] == 0:
        err[1] = stage


@jit_inline
def _stage(err: np.ndarray, stage: int) -> None:
    """Name the stage of an error a kernel has just set."""
    if err[0] != 0 and err[1] == 0:
        err[1] = stage


@jit_inline
def _put(S: np.ndarray, k: int, W: float, T: float, P: float, f: float, h: float) -> None:
    S[k, 0], S[k, 1], S[k, 2], S[k, 3], S[k, 4] = W, T, P, f, h


@jit
def _compress(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, PR: float,
              eta: float, err: np.ndarray) -> tuple[float, float, float]:
    """Exit (Tt [K], ht [J/kg], Pt [Pa]) of a compression (:func:`.compressor.compress_exit`), with its checks."""
    if not (PR >= 1.0) or not (0.0 < eta <= 1.0):
        err[0] = err[0] or 2
        return T, ht, P
    if not (W >= 0.0 and math.isfinite(W)) or not (P * PR > 0.0 and math.isfinite(P * PR)):
        err[0] = err[0] or 8
    To, ho = compress_exit(gc, gs, T, f, ht, PR, eta, err)
    return To, ho, P * PR


@jit_inline
def _map_c(m: Any, Nc: float, beta: float, v: np.ndarray, gx: np.ndarray, gy: np.ndarray,
           err: np.ndarray) -> tuple[float, float, float]:
    """(corrected flow [kg/s], PR [-], efficiency [-]) of a scaled compressor map at corrected speed Nc, beta."""
    sc = m[6]
    first = err[0] == 0
    K.table(m[0], m[1], m[2], m[3], m[4], m[5], Nc / sc[3], beta, v, gx, gy, err)
    if first and err[0] != 0:
        err[0] = 9
    return v[0] * sc[0], (v[1] - 1.0) * sc[1] + 1.0, v[2] * sc[2]


@jit_inline
def _map_t(m: Any, Nc: float, PR: float, v: np.ndarray, gx: np.ndarray, gy: np.ndarray,
           err: np.ndarray) -> tuple[float, float]:
    """(corrected flow [kg/s], efficiency [-]) of a scaled turbine map; speed clamped to the map's [lo, hi]."""
    sc = m[6]
    N = Nc if Nc > sc[4] else sc[4]
    N = N if N < sc[5] else sc[5]
    first = err[0] == 0
    K.table(m[0], m[1], m[2], m[3], m[4], m[5], N / sc[3], (PR - 1.0) / sc[1] + 1.0, v, gx, gy, err)
    if first and err[0] != 0:
        err[0] = 9
    return v[0] * sc[0], v[1] * sc[2]


@jit_inline
def _turbine_point(m: Any, design: bool, eta_d: float, W: float, T: float, P: float, N: float, PR: float,
                   v: np.ndarray, gx: np.ndarray, gy: np.ndarray, err: np.ndarray) -> tuple[float, float]:
    """(corrected flow [kg/s], efficiency [-]) of a turbine with inlet (W, Tt, Pt) at speed N [rpm] and pressure
    ratio PR: its map's, or by design its inlet's corrected flow and the design efficiency eta_d."""
    if design:
        return W * math.sqrt(T / T_STD_K) / (P / P_STD_PA), eta_d
    return _map_t(m, N / math.sqrt(T / T_STD_K), PR, v, gx, gy, err)


@jit_inline
def _mix_T(gc: np.ndarray, gs: np.ndarray, W: np.ndarray, T: np.ndarray, f: np.ndarray, ht: np.ndarray, n: int,
           err: np.ndarray) -> tuple[float, float, float, float]:
    """(W, Tt, FAR, ht) of the adiabatic mixture of the first n streams (:func:`.flow.mix_state`)."""
    return mix_state(gc, gs, W, T, f, ht, n, err)


@jit_inline
def _faces(gc: np.ndarray, gs: np.ndarray, T: float, P: float, f: float, h: float, d: np.ndarray,
           sT: np.ndarray, sP: np.ndarray, sh: np.ndarray, sfrac: np.ndarray, err: np.ndarray) -> int:
    """Sector inlet states of a compressor face (:mod:`.distortion`): one sector, or clean and distorted when
    d[0] (on, share, attenuated Pt deficit, attenuated Tt excess); returns the number of sectors."""
    sT[0], sP[0], sh[0], sfrac[0] = T, P, h, 1.0
    if d[0] == 0.0:
        return 1
    sfrac[0], sfrac[1] = 1.0 - d[1], d[1]
    sT[1], sP[1] = T + d[3], P * (1.0 - d[2])
    sh[1] = K.h(gc, gs, sT[1], f, err) if sT[1] != T else h
    return 2


@jit_inline
def _on_map(m: Any, design: bool, PR_d: float, eta_d: float, W_face: float, N: float, b_clean: float, b_dist: float,
            n: int, sT: np.ndarray, sP: np.ndarray, sfr: np.ndarray, PR: np.ndarray, eff: np.ndarray, Nc: np.ndarray,
            beta: np.ndarray, sW: np.ndarray, v: np.ndarray, gx: np.ndarray, gy: np.ndarray, err: np.ndarray) -> float:
    """The n sectors of a compressor face on map `m` at mechanical speed N [rpm] (or, by design, at PR_d and eta_d
    with the face passing W_face [kg/s]): each sector's corrected speed, beta, PR, efficiency and the flow it
    passes [kg/s] (its share of the annulus at the map's corrected flow); returns their sum [kg/s]."""
    Wsum = 0.0
    for k in range(n):
        sqk = math.sqrt(sT[k] / T_STD_K)
        Nc[k] = N / sqk
        beta[k] = b_clean if k == 0 else b_dist
        if design:
            PR[k], eff[k], Wck = PR_d, eta_d, W_face * sqk / (sP[k] / P_STD_PA)
        else:
            Wck, PR[k], eff[k] = _map_c(m, Nc[k], beta[k], v, gx, gy, err)
        sW[k] = sfr[k] * Wck * (sP[k] / P_STD_PA) / sqk
        Wsum += sW[k]
    return Wsum


@jit_inline
def _mix_sectors(gc: np.ndarray, gs: np.ndarray, n: int, W: np.ndarray, T: np.ndarray, P: np.ndarray, f: float,
                 h: np.ndarray, err: np.ndarray) -> tuple[float, float, float, float]:
    """(W, Tt, Pt, ht) of sector streams mixed at their flow-weighted total pressure (one: itself)."""
    if n == 1:
        return W[0], T[0], P[0], h[0]
    fa = np.full(n, f)
    Wm, Tm, _, hm = _mix_T(gc, gs, W, T, fa, h, n, err)
    Pw = 0.0
    for i in range(n):
        Pw += W[i] * P[i]
    return Wm, Tm, Pw / Wm, hm


@jit
def _cooling(B: np.ndarray, nb: int, bfp: np.ndarray, sink: float, cw: np.ndarray, cT: np.ndarray, cP: np.ndarray,
             cf: np.ndarray, ch: np.ndarray, cfp: np.ndarray) -> int:
    """Copy the bleeds that go to turbine ``sink`` (2 HPT, 3 LPT) into the cooling arrays; returns how many."""
    nc = 0
    for i in range(nb):
        if B[i, 5] == sink:
            cw[nc], cT[nc], cP[nc], cf[nc], ch[nc], cfp[nc] = B[i, 0], B[i, 1], B[i, 2], B[i, 3], B[i, 4], bfp[i]
            nc += 1
    return nc


@jit
def _nozzle(gc: np.ndarray, gs: np.ndarray, W: float, T: float, P: float, f: float, ht: float, Pa: float,
            Cv: float, err: np.ndarray) -> tuple[float, float, bool]:
    """(gross thrust [N], effective area [m2], choked) of a convergent nozzle (:func:`.nozzle.convergent_throat`)."""
    if P < Pa:
        err[0] = err[0] or 6
        return 0.0, 1.0, False
    res = convergent_throat(gc, gs, W, T, P, f, ht, Pa, Cv, err)
    return res[5], res[3], res[4]


# ---------------------------------------------------------------------- the gas path
@jit
def turbofan(x: np.ndarray, fs: np.ndarray, ctl: np.ndarray, e: np.ndarray, gc: np.ndarray, gs: np.ndarray,
             bl: np.ndarray, fan: Any, hpc: Any, hpt: Any, lpt: Any, boo: Any, dist: np.ndarray, S: np.ndarray,
             B: np.ndarray, PW: np.ndarray, r: np.ndarray, o: np.ndarray, err: np.ndarray, w: Any,
             with_sm: bool) -> int:
    """The separate-flow turbofan at unknowns `x`: stations, bleeds, powers, residuals and outputs.

    Parameters
    ----------
    x : unknowns (scaled by their design values; see the module docstring), 9 + booster + distorted faces.
    fs : free stream (Tt0 [K], Pt0 [Pa], V0 [m/s], p_amb [Pa], Mach [-], ram recovery [-]).
    ctl : demand kind (0 Wf, 1 N1, 2 N1c, 3 Tt4, 4 Fn), demand value, customer bleed [-], HP and LP shaft
        ports [W] (signed: + taken), handling bleed [-] (NaN: the corrected-N1 schedule).
    e : parameters (:data:`PARAMS`, indices :data:`EP`).
    gc, gs : the gas's arrays (:meth:`.gas.GasModel.kernel_arrays`; gs extended by the liquid fuel's enthalpy).
    bl : the design's bleeds (frac_W, frac_P, frac_work, sink code, sink_frac_P), one row each.
    fan, hpc, hpt, lpt, boo : scaled maps (xg, yg, ihx, ihy, cells, lim, scalars, surge x, surge w), scalars
        (s_Wc, s_PR, s_eff, s_Nc, Nc clamp low, Nc clamp high); ``boo`` is read only with a booster.
    dist : (2, 4), fan and HPC faces: on, sector share, attenuated Pt deficit [-], attenuated Tt excess [K].
    S, B, PW, r, o : outputs: stations (:data:`ROW`, 5 columns), bleeds (:data:`MAX_BLEEDS`, 6 columns),
        shaft terms' powers (:data:`.shaft.TURBOFAN_SHAFTS`, then the HP and LP mechanical losses) [W],
        residuals, outputs (:data:`OUT`).
    err : (2,) int: error code and stage, zero on entry.
    w : the scratch arrays (:func:`work_arrays`), overwritten.
    with_sm : compute the surge margins (outputs SM_*; NaN otherwise).

    Returns
    -------
    int : 0, or the error code (:data:`ERRORS`); the outputs are then incomplete.
    """
    # the arguments, held by the caller for the call, as views without reference counts (jit_kernels.borrowed)
    x, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, boo = borrowed((x, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, boo))
    dist, S, B, PW, r, o, err, w = borrowed((dist, S, B, PW, r, o, err, w))
    design = e[EP.mode] == 1.0
    nb_on = e[EP.booster] != 0.0
    W2, bfan, bhpc = x[0] * e[EP.W2_ref], x[1], x[2]
    N1, N2 = x[3] * e[EP.N1_design_rpm], x[4] * e[EP.N2_design_rpm]
    PRh, PRl, BPR, Wf = x[5] * e[EP.PRh_ref], x[6] * e[EP.PRl_ref], x[7] * e[EP.BPR_ref], x[8] * e[EP.Wf_ref]
    cust, off_hp, off_lp = ctl[2], ctl[3], ctl[4]
    if W2 <= 0.0 or N1 <= 0.0 or N2 <= 0.0 or BPR < 0.0 or Wf <= 0.0 or PRh < 1.0 or PRl < 1.0:
        _mark(err, 2, _ST_INLET)
        return err[0]
    if not (W2 >= 0.0 and math.isfinite(W2)):
        _mark(err, 8, _ST_INLET)
        return err[0]
    ix = 9
    b_boo = 0.0
    if nb_on:
        b_boo = x[ix]
        ix += 1
    b_fan_d = b_hpc_d = 0.0
    if dist[0, 0] != 0.0:
        b_fan_d = x[ix]
        ix += 1
    if dist[1, 0] != 0.0:
        b_hpc_d = x[ix]
    # the small vectors of the stages (per sector, a map's outputs and slopes, a spool's terms) and the bleeds' are
    # rows of the caller's scratch arrays: some sixty allocations per evaluation were a third of its time
    t3, tb, sb = w
    v, gx, gy = t3[0], t3[1], t3[2]
    # free stream and inlet
    T2 = fs[0]
    h0 = K.h(gc, gs, T2, 0.0, err)
    _put(S, _S0, W2, T2, fs[1], 0.0, h0)
    P2 = fs[1] * e[EP.inlet_pi] * fs[5]
    _put(S, _S2, W2, T2, P2, 0.0, h0)
    sq2 = math.sqrt(T2 / T_STD_K)
    N1c = N1 / sq2
    _stage(err, _ST_INLET)
    # fan: sectors on the map, each split into bypass and core and compressed
    sT, sP, sh, sfr, sW = t3[3], t3[4], t3[5], t3[6], t3[7]
    nsf = _faces(gc, gs, T2, P2, 0.0, h0, dist[0], sT, sP, sh, sfr, err)
    PRs, effs, Ncs, bets = t3[8], t3[9], t3[10], t3[11]
    Wfan = _on_map(fan, design, e[EP.PR_fan_outer], e[EP.eta_fan_outer], W2, N1, bfan, b_fan_d, nsf, sT, sP, sfr,
                   PRs, effs, Ncs, bets, sW, v, gx, gy, err)
    if not (BPR >= 0.0):
        _mark(err, 2, _ST_FAN)
        return err[0]
    fr = 1.0 / (1.0 + BPR)
    oW, oT, oP, oh = t3[12], t3[13], t3[14], t3[15]
    iW, iT, iP, ih = t3[16], t3[17], t3[18], t3[19]
    P_fo = P_fi = 0.0
    r_fan_p = sP[1] * PRs[1] / (sP[0] * PRs[0]) - 1.0 if nsf == 2 else 0.0
    for k in range(nsf):
        Wt = sW[k] * (W2 / Wfan)
        Wcore, Wbyp = Wt * fr, Wt * (1.0 - fr)
        oT[k], oh[k], oP[k] = _compress(gc, gs, Wbyp, sT[k], sP[k], 0.0, sh[k], PRs[k], effs[k], err)
        iT[k], ih[k], iP[k] = _compress(gc, gs, Wcore, sT[k], sP[k], 0.0, sh[k],
                                        1.0 + e[EP.k_inner] * (PRs[k] - 1.0), effs[k] * e[EP.eff_ratio_inner], err)
        oW[k], iW[k] = Wbyp, Wcore
        P_fo += Wbyp * (oh[k] - sh[k])
        P_fi += Wcore * (ih[k] - sh[k])
    W13, T13, P13, h13 = _mix_sectors(gc, gs, nsf, oW, oT, oP, 0.0, oh, err)
    W21, T21, P21, h21 = _mix_sectors(gc, gs, nsf, iW, iT, iP, 0.0, ih, err)
    _put(S, _S13, W13, T13, P13, 0.0, h13)
    _put(S, _S21, W21, T21, P21, 0.0, h21)
    _stage(err, _ST_FAN)
    # booster (LP spool) between the ducts 21-24 and 24-25
    P21d = P21 * (1.0 - e[EP.dPqP_21_24])
    Wc21 = W21 * math.sqrt(T21 / T_STD_K) / (P21d / P_STD_PA)
    T24, h24, P24, P_bo = T21, h21, P21d, 0.0
    r_boo = 0.0
    PR_b = eff_b = 1.0
    if nb_on:
        if design:
            PR_b, eff_b = e[EP.PR_booster], e[EP.eta_booster]
        else:
            Wc_b, PR_b, eff_b = _map_c(boo, N1 / math.sqrt(T21 / T_STD_K), b_boo, v, gx, gy, err)
            r_boo = (Wc_b - Wc21) / e[EP.Wc21_ref]
        T24, h24, P24 = _compress(gc, gs, W21, T21, P21d, 0.0, h21, PR_b, eff_b, err)
        P_bo = W21 * (h24 - h21)
        _stage(err, _ST_BOO)
    _put(S, _S24, W21, T24, P24, 0.0, h24)
    P25 = P24 * (1.0 - e[EP.dPqP_24_25])
    T25, h25, W25 = T24, h24, W21
    _put(S, _S25, W25, T25, P25, 0.0, h25)
    sq25 = math.sqrt(T25 / T_STD_K)
    N2c = N2 / sq25
    # HPC: sectors on the map
    nsh = _faces(gc, gs, T25, P25, 0.0, h25, dist[1], sT, sP, sh, sfr, err)
    hPR, heff, hNc, hbet = t3[20], t3[21], t3[22], t3[23]
    Whpc = _on_map(hpc, design, e[EP.PR_hpc], e[EP.eta_hpc], W25, N2, bhpc, b_hpc_d, nsh, sT, sP, sfr, hPR, heff, hNc,
                   hbet, sW, v, gx, gy, err)
    PRc = hPR[0]
    r_hpc_p = sP[1] * hPR[1] / (sP[0] * hPR[0]) - 1.0 if nsh == 2 else 0.0
    # the bleeds: the design's, then handling (to the bypass) and customer (overboard)
    nb0 = bl.shape[0]
    if nb0 + 2 > MAX_BLEEDS:                    # (the scratch rows hold MAX_BLEEDS; FastCycle refuses it before)
        _mark(err, 10, _ST_HPC)
        return err[0]
    bfw, bfP, bwk, bsink, bfp = tb[0], tb[1], tb[2], tb[3], tb[4]
    for i in range(nb0):
        bfw[i], bfP[i], bwk[i], bsink[i], bfp[i] = bl[i, 0], bl[i, 1], bl[i, 2], bl[i, 3], bl[i, 4]
    nb = nb0
    if math.isnan(ctl[5]):
        s = (e[EP.hb_N1c_frac] + 0.5 * e[EP.hb_ramp_frac] - N1c / e[EP.Nc1_design_rpm]) / e[EP.hb_ramp_frac]
        s = 0.0 if s < 0.0 else (1.0 if s > 1.0 else s)
        hb = max(e[EP.handling_bleed_frac], e[EP.hb_open_frac] * (s * s * (3.0 - 2.0 * s)))
    else:
        hb = max(e[EP.handling_bleed_frac], ctl[5])
    if hb > 0.0:
        if not PRc > 1.0 or not (0.0 <= hb < 1.0):
            _mark(err, 4, _ST_HPC)
            return err[0]
        xs = e[EP.handling_bleed_stage] / e[EP.hpc_stages]
        bfw[nb], bfP[nb], bwk[nb], bsink[nb], bfp[nb] = hb, (PRc ** xs - 1.0) / (PRc - 1.0), xs, 1.0, 1.0
        nb += 1
    if cust > 0.0:
        if not (cust < 1.0):
            _mark(err, 3, _ST_HPC)
            return err[0]
        bfw[nb], bfP[nb], bwk[nb], bsink[nb], bfp[nb] = cust, 1.0, 1.0, 0.0, 1.0
        nb += 1
    # each sector compressed with its bleeds; exits and each bleed mixed over the sectors
    xW, xT, xP, xh = t3[24], t3[25], t3[26], t3[27]
    sbW, sbT, sbP, sbh = sb[0], sb[1], sb[2], sb[3]
    P_hpc = W_inter_all = 0.0
    for k in range(nsh):
        Win = sW[k] * (W25 / Whpc)
        T3, h3, P3 = _compress(gc, gs, Win, sT[k], sP[k], 0.0, sh[k], hPR[k], heff[k], err)
        W_inter = W_all = 0.0
        for i in range(nb):
            bW = bfw[i] * Win
            sbT[i, k], sbP[i, k], sbh[i, k] = bleed_state(gc, gs, sT[k], sP[k], 0.0, sh[k], T3, P3, h3, bfP[i],
                                                          bwk[i], err)
            if not (bfP[i] == 1.0 and bwk[i] == 1.0):
                W_inter += bW
            sbW[i, k] = bW
            W_all += bW
        if W_all >= Win:
            _mark(err, 3, _ST_HPC)
            return err[0]
        P_hpc += bled_power(Win, sh[k], h3, sbW[:, k], sbh[:, k], nb)
        xW[k], xT[k], xP[k], xh[k] = Win - W_inter, T3, P3, h3
        W_inter_all += W_inter
    W3, T3, P3, h3 = _mix_sectors(gc, gs, nsh, xW, xT, xP, 0.0, xh, err)
    _put(S, _S3, W3, T3, P3, 0.0, h3)
    W_exit = 0.0
    tW, tT, tP, th = t3[28], t3[29], t3[30], t3[31]
    for i in range(nb):
        for k in range(nsh):
            tW[k], tT[k], tP[k], th[k] = sbW[i, k], sbT[i, k], sbP[i, k], sbh[i, k]
        bW_, bT_, bP_, bh_ = _mix_sectors(gc, gs, nsh, tW, tT, tP, 0.0, th, err)
        B[i, 0], B[i, 1], B[i, 2], B[i, 3], B[i, 4], B[i, 5] = bW_, bT_, bP_, 0.0, bh_, bsink[i]
        if bfP[i] == 1.0 and bwk[i] == 1.0:
            W_exit += bW_
    W31 = W3 - W_exit
    _put(S, _S31, W31, T3, P3, 0.0, h3)
    _stage(err, _ST_HPC)
    # burner: the fuel flow given (off-design), or the exit temperature (design)
    if not (0.0 < e[EP.eta_burner] <= 1.0):
        _mark(err, 2, _ST_BURN)
        return err[0]
    f31 = 0.0
    W_air = W31 / (1.0 + f31)
    if design:
        Tt4 = e[EP.Tt4_ref]
        if not Tt4 > T3:
            _mark(err, 5, _ST_BURN)
            return err[0]
        f4 = burner_far(gc, gs, T3, f31, Tt4, e[EP.eta_burner], gs[13], err)
        Wf = W_air * (f4 - f31)
    else:
        if not (Wf >= 0.0):
            _mark(err, 2, _ST_BURN)
            return err[0]
        f4 = f31 + Wf / W_air
    if not (0.0 <= f4 <= gs[1]):
        _mark(err, 5, _ST_BURN)
        return err[0]
    if not design:
        Tt4 = burner_exit_T(gc, gs, T3, f31, f4, e[EP.eta_burner], gs[13], e[EP.Tt4_guess_K], err) if Wf > 0 else T3
    W4 = W31 + W_air * (f4 - f31)
    P4 = P3 * (1.0 - e[EP.dPqP_burner])
    h4 = K.h(gc, gs, Tt4, f4, err)
    _put(S, _S4, W4, Tt4, P4, f4, h4)
    _stage(err, _ST_BURN)
    # HPT with its cooling
    Wc_t1, eff_t1 = _turbine_point(hpt, design, e[EP.eta_hpt], W4, Tt4, P4, N2, PRh, v, gx, gy, err)
    cw, cT, cP, cf, ch, cfp = tb[5], tb[6], tb[7], tb[8], tb[9], tb[10]
    nc = _cooling(B, nb, bfp, 2.0, cw, cT, cP, cf, ch, cfp)
    P_hpt, W44, T44, P44, f44, h44, W41, T41, f41, h41 = _turbine(gc, gs, W4, Tt4, P4, f4, h4, PRh, eff_t1, cw, cT,
                                                                  cP, cf, ch, cfp, nc, err)
    _put(S, _S41, W41, T41, P4, f41, h41)
    _put(S, _S44, W44, T44, P44, f44, h44)
    P45 = P44 * (1.0 - e[EP.dPqP_44_45])
    _put(S, _S45, W44, T44, P45, f44, h44)
    _stage(err, _ST_HPT)
    Wc_t2, eff_t2 = _turbine_point(lpt, design, e[EP.eta_lpt], W44, T44, P45, N1, PRl, v, gx, gy, err)
    nc = _cooling(B, nb, bfp, 3.0, cw, cT, cP, cf, ch, cfp)
    P_lpt, W5, T5, P5, f5, h5, _, _, _, _ = _turbine(gc, gs, W44, T44, P45, f44, h44, PRl, eff_t2, cw, cT, cP, cf, ch,
                                            cfp, nc, err)
    _put(S, _S5, W5, T5, P5, f5, h5)
    P7 = P5 * (1.0 - e[EP.dPqP_5_7])
    _put(S, _S7, W5, T5, P7, f5, h5)
    _stage(err, _ST_LPT)
    # bypass: the fan's bypass stream, less a bypass bleed, plus the bleeds returned to it
    mW, mT, mf, mh = tb[11], tb[12], tb[13], tb[14]
    mW[0], mT[0], mf[0], mh[0] = W13 * (1.0 - e[EP.bypass_bleed_frac]), T13, 0.0, h13
    m = 1
    for i in range(nb):
        if B[i, 5] == 1.0:
            mW[m], mT[m], mf[m], mh[m] = B[i, 0], B[i, 1], 0.0, B[i, 4]
            m += 1
    if m > 1:
        W17, T17, f17, h17 = _mix_T(gc, gs, mW, mT, mf, mh, m, err)
    else:
        W17, T17, f17, h17 = mW[0], T13, 0.0, h13
    _put(S, _S16, W17, T17, P13, f17, h17)
    P17 = P13 * (1.0 - e[EP.dPqP_13_17])
    _put(S, _S17, W17, T17, P17, f17, h17)
    _stage(err, _ST_BYP)
    Pa = fs[3]
    Fg_c, A8, ch_c = _nozzle(gc, gs, W5, T5, P7, f5, h5, Pa, e[EP.Cv_core], err)
    Fg_b, A18, ch_b = _nozzle(gc, gs, W17, T17, P17, f17, h17, Pa, e[EP.Cv_bypass], err)
    _stage(err, _ST_NOZ)
    ram = W2 * fs[2]
    Fg = Fg_c + Fg_b
    Fn = Fg - ram
    # residuals
    kind, val = ctl[0], ctl[1]
    if kind == 0.0:
        r9 = (Wf - val) / e[EP.Wf_ref]
    elif kind == 1.0:
        r9 = (N1 - val) / e[EP.N1_design_rpm]
    elif kind == 2.0:
        r9 = (N1c - val) / e[EP.N1_design_rpm]
    elif kind == 3.0:
        r9 = (Tt4 - val) / e[EP.Tt4_ref]
    else:
        r9 = (Fn - val) / e[EP.Fn_ref]
    for i in range(_NTERM):
        PW[i] = 0.0
    PW[_T_HPT], PW[_T_HPC], PW[_T_PHP], PW[_T_LPT] = P_hpt, P_hpc, off_hp, P_lpt
    PW[_T_FO], PW[_T_FI], PW[_T_BO], PW[_T_PLP] = P_fo, P_fi, P_bo, off_lp
    eta_mech, net, loss = t3[32, :2], t3[33, :2], t3[34, :2]
    eta_mech[0], eta_mech[1] = e[EP.eta_mech_hp], e[EP.eta_mech_lp]
    spool_balance(PW[:_NTERM], _TERM_SPOOL, _TERM_KIND, eta_mech, net, loss)
    PW[_NTERM], PW[_NTERM + 1] = loss[0], loss[1]
    if design:
        for i in range(6):
            r[i] = 0.0
    else:
        r[0] = (Wfan - W2) / W2
        r[1] = (Whpc - W25) / W25
        r[2] = (Wc_t1 - W4 * math.sqrt(Tt4 / T_STD_K) / (P4 / P_STD_PA)) / e[EP.Wc4_ref]
        r[3] = (Wc_t2 - W44 * math.sqrt(T44 / T_STD_K) / (P45 / P_STD_PA)) / e[EP.Wc45_ref]
        r[4] = A8 / e[EP.A8_ref] - 1.0
        r[5] = A18 / e[EP.A18_ref] - 1.0
    r[6] = net[0] / e[EP.P_hp_ref]
    r[7] = net[1] / e[EP.P_lp_ref]
    r[8] = r9
    ir = 9
    if nb_on:
        r[ir] = r_boo
        ir += 1
    if nsf == 2:
        r[ir] = r_fan_p
        ir += 1
    if nsh == 2:
        r[ir] = r_hpc_p
    # outputs
    sm_f = sm_h = sm_fc = sm_hc = math.nan
    if with_sm and not design:
        sm_f, sm_fc = _surge(fan, Ncs, bets, nsf)
        sm_h, sm_hc = _surge(hpc, hNc, hbet, nsh)
    vals = (Fn, Fg, ram, N1c, N2c, Tt4, T41, T21, T17, T5, P3, P2, hb, f4, W2, sm_f, sm_h, P_hpt, P_lpt,
            P_hpc, P_fo + P_fi, sm_fc, sm_hc, 1.0 * nb, Fg_c, Fg_b, A8)
    for i in range(len(vals)):                  # two tuples: a longer one is a list to numba
        o[i] = vals[i]
    n1 = len(vals)
    vals2 = (A18, 1.0 if ch_c else 0.0, 1.0 if ch_b else 0.0, W2 * sq2 / (P2 / P_STD_PA),
             W25 * sq25 / (P25 / P_STD_PA), W4 * math.sqrt(Tt4 / T_STD_K) / (P4 / P_STD_PA),
             W44 * math.sqrt(T44 / T_STD_K) / (P45 / P_STD_PA), Wc21, PRs[0], effs[0], PR_b, eff_b, PRc, heff[0],
             eff_t1, eff_t2, Ncs[0], bfan, hNc[0], bhpc, Wf, N1, N2, BPR, PRh, PRl, T3)
    for i in range(len(vals2)):
        o[n1 + i] = vals2[i]
    return int(err[0])


@jit
def _surge(m: Any, Nc: np.ndarray, beta: np.ndarray, n: int) -> tuple[float, float]:
    """(worst sector's, clean sector's) flow-basis surge margin [-] on a scaled compressor map
    (:func:`.jit_kernels.surge_margin`; NaN where it cannot be formed)."""
    sc = m[6]
    worst = clean = math.nan
    for k in range(n):
        sm = K.surge_margin(m[0], m[1], m[2], m[3], m[4], m[5], m[7], m[8], Nc[k] / sc[3], beta[k], sc[1])
        if k == 0:
            clean = worst = sm
        elif sm < worst or not worst == worst:
            worst = sm
    return worst, clean
