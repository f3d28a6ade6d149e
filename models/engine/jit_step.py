"""One engine step compiled: :meth:`.engine_model.EngineModel.step` with explicit Euler in one kernel call.

Driven from Python, a 50 ms step of the engine paid more for the Python around the gas-path
match (the fuel system's limits, the key of the inputs and the small-change test, the
linearised start, the valve's hysteresis, the state object, the outputs and flags) than for
the match itself. :func:`euler_step` is that step for the configuration a mission flies
(explicit Euler, no inlet distortion, a customer bleed inside its range, a cached Jacobian of
the compiled iteration): the same operations in the same order on the same floats, the
matches by :func:`.jit_solve.chord_solve`, so its results are the Python step's, bit for bit
(``tests/engine/test_one_source.py`` compares both).

It commits nothing until the step has succeeded. Whatever the Python step would treat in
another way (a match that fails or stalls, the surge-side beta floor, a speed that is not
positive, a fuel flow to limit, an input to clip and log, any input not finite) makes it
return :data:`REFUSED` with its arguments untouched (but for the free-stream cache); the
caller then runs the Python step from the same state, which handles it with its messages.

Arrays (indices below): ``par`` the model's constants, ``st`` its state (read and, on success,
written), ``prev`` and ``new`` the match of the last step and of this one (unknowns,
residuals, kernel outputs, inverse Jacobian, fuel sensitivity, the match's inputs: :func:`buffer_layout`), ``vals``
the Real outputs in the order of :data:`.engine_signals.OUTPUTS`.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 8 (the spool
acceleration equation, quasi-steady matching, handling bleed).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numba.core import types
from numba.experimental import structref

from .engine_signals import EO
from .gas_path import OX
from .jit_kernels import borrowed, jit, jit_inline
from .jit_solve import CONVERGED, chord_solve, free_stream_at
from .shaft import spool_acceleration_of

__all__ = ["REFUSED", "PAR", "ST", "BUF_SCALARS", "N_PAR", "N_ST", "buffer_layout", "StepData", "step_data",
           "euler_step", "resolved"]

#: Status of :func:`euler_step` where the Python step must run instead (any other status is >= 0).
REFUSED = -1
#: Slots of ``par``, the model's constants.
PAR = ("Wf_min_kg_s", "Wf_Pt3_min_kg_s_Pa", "Wf_decel_max_kg_s2", "assist_hp_max_W", "offtake_hp_max_W",
       "assist_lp_max_W", "offtake_lp_max_W", "linear_input_frac", "N1_design_rpm", "N2_design_rpm", "Wf_ref_kg_s",
       "P_hp_ref_W", "P_lp_ref_W", "I_lp_kg_m2", "I_hp_kg_m2", "threshold_N1c_pct", "band_pct", "stroke_s",
       "open_frac", "Nc1_design_rpm", "BPR_design", "FAR_lean", "N1_max_pct", "N2_max_pct", "beta_floor",
       "T_std_K", "customer_bleed_max", "n_out")
#: Slots of ``st``, the model's state: speeds [rpm], valve position [-] and command (0/1), fuel burned [kg],
#: time [s]; of the last match: spool accelerations [rpm/s], fuel flow [kg/s] and speeds [rpm] as the match
#: holds them; the last published Pt3 [Pa]; whether a key is held (0/1), the key (14: N1, N2, valve, fuel
#: flow, then the inputs alt ... dTt), the flags (6, 0/1).
ST = ("N1_rpm", "N2_rpm", "valve_pos", "valve_open_cmd", "fuel_burned_kg", "t_s", "dN1_dt_rpm_s", "dN2_dt_rpm_s",
      "Wf_match_kg_s", "N1_match_rpm", "N2_match_rpm", "Pt3_Pa", "key_held") + tuple(f"key{i}" for i in range(14)) + \
     tuple(f"flag{i}" for i in range(6))
#: A match buffer, in order: the unknowns (9), residuals (9), kernel outputs (``n_out`` of ``par``: the
#: length of the compiled cycle's output array), inverse Jacobian (36, row by row), fuel sensitivity (2), then
#: these scalars of the match's inputs and result.
BUF_SCALARS = ("t_s", "Wf_kg_s", "hb", "iterations", "N1_rpm", "N2_rpm", "alt_m", "Mach", "dT_isa_K",
               "customer_bleed_frac", "offtake_hp_W", "offtake_lp_W")
N_PAR, N_ST = len(PAR), len(ST)
_P = {n: i for i, n in enumerate(PAR)}
(_WFMIN, _WFPT3, _DECEL, _AHP, _OHP, _ALP, _OLP, _LIN, _N1D, _N2D, _WFREF, _PHP, _PLP, _ILP, _IHP, _THR, _BAND,
 _STROKE, _OPEN, _NC1D, _BPRD, _FARL, _N1MAX, _N2MAX, _BETA, _TSTD, _CUSTMAX, _NOUT) = range(N_PAR)


def buffer_layout(n_out: int) -> dict[str, Any]:
    """Slices (start, stop) and slots of a match buffer whose kernel outputs have `n_out` entries, and its size."""
    o, h = 18, 18 + n_out
    lay: dict[str, Any] = {"x": (0, 9), "r": (9, 18), "o": (o, h), "H": (h, h + 36), "sens": (h + 36, h + 38)}
    lay.update({name: h + 38 + i for i, name in enumerate(BUF_SCALARS)})
    lay["size"] = h + 38 + len(BUF_SCALARS)
    return lay
(_N1, _N2, _VPOS, _VCMD, _FUEL, _T, _A1, _A2, _WFS, _N1S, _N2S, _PT3, _KEYOK) = range(13)
_KEY, _FLAG = 13, 27
_X, _R, _O = 0, 9, 18
_NFLAG, _SOLVER_FAILED = 6, 3


@structref.register
class _StepDataType(types.StructRef):
    def preprocess_fields(self, fields: Any) -> Any:
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class StepData(structref.StructRefProxy):  # type: ignore[misc]
    """The arrays of :func:`euler_step`, held on the compiled side (:func:`step_data`).

    Passed as one argument: numba unboxes every array of an argument at every call, and the
    compiled cycle's arrays (:func:`.jit_solve.bundle`) alone are some forty (about 5 us a call);
    held here they are unboxed once. The arrays are shared with the caller's NumPy arrays (the
    same memory): the caller reads ``state``, ``vals`` and ``buf`` and writes ``uin`` between calls.
    """


_FIELDS = ("fcb", "par", "state", "uin", "vals", "J_in", "Js_free", "Js_in", "buf")
structref.define_proxy(StepData, _StepDataType, list(_FIELDS))


@jit
def step_data(fcb: Any, par: np.ndarray, state: np.ndarray, uin: np.ndarray, vals: np.ndarray, J_in: np.ndarray,
              Js_free: np.ndarray, Js_in: np.ndarray, buf: np.ndarray) -> StepData:
    """The :class:`StepData` of one model: the compiled cycle's bundle, the constants (:data:`PAR`), the state
    (:data:`ST`), the inputs (11, the fields of :class:`.engine_signals.EngineInputs`), the Real outputs, the
    cached Jacobian's fixed parts and the two match buffers (2, :data:`N_BUF`: the last match and the next)."""
    return StepData(fcb, par, state, uin, vals, J_in, Js_free, Js_in, buf)


@jit_inline
def _port(v: float, assist_max_W: float, offtake_max_W: float) -> tuple[float, bool]:
    """:meth:`.engine_model.EngineModel._port`: the port's power clipped to [-assist, offtake], and if it was."""
    if -assist_max_W <= v <= offtake_max_W:
        return v, False
    return (offtake_max_W if v > offtake_max_W else -assist_max_W) if v == v else 0.0, True


@jit_inline
def _match(N1: float, N2: float, Wf: float, hb: float, uin: np.ndarray, extras: np.ndarray, par: np.ndarray,
           xf: np.ndarray, H0: np.ndarray, J_in: np.ndarray, Js_free: np.ndarray, Js_in: np.ndarray, fcb: Any,
           tol: float, H: np.ndarray, r: np.ndarray, o: np.ndarray, sens: np.ndarray) -> int:
    """:meth:`.transient.TurbofanTransient._compiled` from the previous match xf (9, overwritten with the new
    one): its iteration count, or -1 where the Python step would not take the match (not converged, a map beta
    below the floor: :meth:`.engine_model.EngineModel._evaluate`)."""
    u = np.empty(12)
    u[0], u[1], u[2] = N1 / par[_N1D], N2 / par[_N2D], Wf / par[_WFREF]
    u[3], u[4], u[5], u[6], u[7] = uin[1], uin[2], uin[3], 0.0, Wf
    u[8], u[9], u[10], u[11] = extras[0], extras[1], extras[2], hb
    status, it = chord_solve(xf, u, H0, J_in, Js_free, Js_in, fcb, tol, H, r, o, sens)
    if status != CONVERGED or xf[2] < par[_BETA] or xf[1] < par[_BETA]:
        return -1
    return it


@jit
def euler_step(dt_s: float, h: float, d: StepData, k_prev: int, tol: float) -> int:
    """One step of `dt_s` [s] in internal steps of `h` [s] with the inputs ``d.uin`` held.

    Parameters
    ----------
    dt_s, h : the step, rounded as the Python step rounds it, and its internal step [s].
    d : the model's arrays (:func:`step_data`): inputs ``uin``, state ``state`` (:data:`ST`, written on success),
        constants ``par`` (:data:`PAR`), outputs ``vals`` (written on success), the cached Jacobian's fixed
        parts, the compiled cycle's bundle.
    k_prev : the row of ``d.buf`` holding the last match (read); this step's goes to the other (on success).
    tol : the matching tolerance, max |residual| [-].

    Returns
    -------
    int
        :data:`REFUSED` (nothing written); else bits 0-5 the flags that rose (events), bits 8-13 the flags
        that changed.
    """
    # the model's arrays (held by the EngineModel), as views without reference counts (jit_kernels.borrowed)
    uin, st, par, vals, J_in, Js_free, Js_in, fcb, buf = borrowed((d.uin, d.state, d.par, d.vals, d.J_in, d.Js_free,
                                                                   d.Js_in, d.fcb, d.buf))
    prev, new = buf[k_prev], buf[1 - k_prev]
    n_out = int(par[_NOUT])
    _H = _O + n_out
    _S = _H + 36
    _C = _S + 2                                 # the scalars (BUF_SCALARS)
    for k in range(uin.shape[0]):
        if not math.isfinite(uin[k]):
            return REFUSED
    cust = uin[6]
    if uin[7] != 0.0 or not (0.0 <= cust <= par[_CUSTMAX]):
        return REFUSED
    # EngineModel._kwargs: the fuel system's stops and the shaft ports
    Wf_min, w = par[_WFMIN], par[_WFPT3] * st[_PT3]
    if w > Wf_min:
        Wf_min = w
    Wf = uin[0] if uin[0] >= Wf_min else Wf_min
    hp, hp_cut = _port(uin[4], par[_AHP], par[_OHP])
    lp, lp_cut = _port(uin[5], par[_ALP], par[_OLP])
    extras = np.empty(3)
    extras[0], extras[1], extras[2] = cust, hp, lp
    # EngineModel.step
    Wf_slew = st[_WFS] - par[_DECEL] * dt_s
    if Wf < Wf_slew:
        Wf = Wf_slew
    t0 = st[_T]
    N1, N2, vpos, vcmd = st[_N1], st[_N2], st[_VPOS], st[_VCMD] != 0.0
    key = np.empty(14)
    key[0], key[1], key[2], key[3] = N1, N2, vpos, Wf
    for k in range(10):
        key[4 + k] = uin[1 + k]
    # the state of the last match
    Wf_s, N1_s, N2_s, a1, a2 = st[_WFS], st[_N1S], st[_N2S], st[_A1], st[_A2]
    xf = prev[_X:_X + 9].copy()
    Hm = np.empty((6, 6))                       # (a reshape's error path costs seconds of compilation)
    for i in range(6):
        for j in range(6):
            Hm[i, j] = prev[_H + 6 * i + j]
    sens = prev[_S:_S + 2].copy()
    r, o = prev[_R:_R + 9].copy(), prev[_O:_O + n_out].copy()
    t_m, Wf_m, hb_m, it_m, N1_m, N2_m = prev[_C], prev[_C + 1], prev[_C + 2], prev[_C + 3], prev[_C + 4], prev[_C + 5]
    H = np.empty((6, 6))
    sens_new = np.empty(2)
    same = st[_KEYOK] != 0.0
    for k in range(14):
        if key[k] != st[_KEY + k]:
            same = False
    small = False
    if not same:                                # inputs changed: the derivative at the step start
        small = st[_KEYOK] != 0.0 and par[_LIN] != 0.0               # EngineModel._small_change
        if small:
            for k in range(14):
                if (k < 3 or k >= 7) and key[k] != st[_KEY + k]:
                    small = False
            if abs(key[4] - st[_KEY + 4]) > 10.0 or abs(key[5] - st[_KEY + 5]) > 0.002 or \
                    abs(key[6] - st[_KEY + 6]) > 0.1 or abs(Wf - Wf_s) > par[_LIN] * Wf_s:
                small = False
        if small:                               # TurbofanTransient.fuel_sensitivity, linearised: no match
            per = 1.0 / par[_WFREF]
            s1 = spool_acceleration_of(sens[1] * par[_PLP] * per, N1_s, par[_ILP])
            s2 = spool_acceleration_of(sens[0] * par[_PHP] * per, N2_s, par[_IHP])
            a1, a2 = a1 + s1 * (Wf - Wf_s), a2 + s2 * (Wf - Wf_s)
    # the matches: at the step start if the inputs changed and were not linearised, then at the end of each
    # internal step (one call site: the kernel is compiled once into this function)
    start = not same and not small
    t, t_end, t1 = t0, t0 + dt_s, t0
    while True:
        if start:
            Nm1, Nm2, tm = N1, N2, t0
        else:
            if not t < t_end - 1e-9 * dt_s:
                break
            hh = t_end - t if t_end - t < h else h
            t1 = t + hh
            Nm1, Nm2, tm = N1 + hh * a1, N2 + hh * a2, t1
            if not (Nm1 > 0.0 and Nm2 > 0.0):
                return REFUSED                  # (the Python step halves the step)
            # EngineModel._valve at the new speeds
            if free_stream_at(fcb, uin[1], uin[2], uin[3]) != 0:
                return REFUSED
            sq = math.sqrt(fcb[0][3] / par[_TSTD])
            N1c_pct = 100.0 * Nm1 / sq / par[_NC1D]
            if vcmd and N1c_pct > par[_THR] + 0.5 * par[_BAND]:
                vcmd = False
            elif not vcmd and N1c_pct < par[_THR] - 0.5 * par[_BAND]:
                vcmd = True
            target = 1.0 if vcmd else 0.0
            rate = hh / par[_STROKE]
            if target > vpos:
                vpos = min(target, vpos + rate)
            else:
                vpos = max(target, vpos - rate)
        hb = vpos * par[_OPEN]
        it = _match(Nm1, Nm2, Wf, hb, uin, extras, par, xf, Hm, J_in, Js_free, Js_in, fcb, tol, H, r, o, sens_new)
        if it < 0:
            return REFUSED                      # (the Python step limits the fuel or halves the step)
        Hm, H, sens, sens_new = H, Hm, sens_new, sens
        N1, N2 = Nm1, Nm2
        t_m, Wf_m, hb_m, it_m, N1_m, N2_m = tm, Wf, hb, it, N1, N2
        Wf_s, N1_s, N2_s = xf[8] * par[_WFREF], xf[3] * par[_N1D], xf[4] * par[_N2D]
        a1 = spool_acceleration_of(r[7] * par[_PLP], N1, par[_ILP])
        a2 = spool_acceleration_of(r[6] * par[_PHP], N2, par[_IHP])
        if start:
            start = False
        else:
            t = t1
    # success: commit (EngineModel.step's end and _publish)
    fuel = st[_FUEL] + Wf_s * dt_s
    Fn, Pt3, hb_o, FAR4, sm_f, sm_h = o[OX.Fn], o[OX.Pt3], o[OX.hb], o[OX.FAR4], o[OX.SM_fan], o[OX.SM_hpc]
    sm_fc, sm_hc = o[OX.SM_fan_clean], o[OX.SM_hpc_clean]
    N1_pct, N2_pct = 100.0 * N1_s / par[_N1D], 100.0 * N2_s / par[_N2D]
    vals[EO.Fn_N], vals[EO.Fg_N], vals[EO.ram_drag_N], vals[EO.Wf_kg_s] = Fn, o[OX.Fg], \
        o[OX.ram], Wf_s
    vals[EO.N1_rpm], vals[EO.N2_rpm], vals[EO.N1_pct], vals[EO.N2_pct] = N1_s, N2_s, N1_pct, N2_pct
    vals[EO.N1c_pct] = 100.0 * o[OX.N1c] / par[_NC1D]
    vals[EO.Tt4_K], vals[EO.Tt41_K], vals[EO.Tt21_K] = o[OX.Tt4], o[OX.T41], o[OX.Tt21]
    vals[EO.Tt17_K], vals[EO.Tt7_K] = o[OX.Tt17], o[OX.Tt7]
    vals[EO.Pt3_Pa], vals[EO.OPR], vals[EO.BPR] = Pt3, Pt3 / o[OX.Pt2], xf[7] * par[_BPRD]
    vals[EO.SM_fan], vals[EO.SM_hpc], vals[EO.SM_fan_clean], vals[EO.SM_hpc_clean] = sm_f, sm_h, sm_fc, sm_hc
    vals[EO.SFC_kg_N_s] = Wf_s / Fn if Fn > 0.0 else math.inf
    vals[EO.fuel_burned_kg], vals[EO.dN1_dt_rpm_s], vals[EO.dN2_dt_rpm_s] = fuel, a1, a2
    vals[EO.handling_bleed_frac], vals[EO.FAR4], vals[EO.W2_kg_s] = hb_o, FAR4, o[OX.W2]
    vals[EO.offtake_hp_applied_W], vals[EO.offtake_lp_applied_W] = hp, lp
    vals[EO.Tt3_K] = o[OX.Tt3]
    flags = (sm_f < 0.0 or sm_h < 0.0, FAR4 < par[_FARL] or uin[0] < par[_WFMIN],
             N1_pct > par[_N1MAX] or N2_pct > par[_N2MAX], False, False, hp_cut or lp_cut)
    out = 0
    for k in range(_NFLAG):
        f = 1.0 if flags[k] else 0.0
        if f != st[_FLAG + k]:
            out |= 1 << (8 + k)
            if f != 0.0 and k != _SOLVER_FAILED:
                out |= 1 << k
        st[_FLAG + k] = f
    st[_N1], st[_N2], st[_VPOS], st[_VCMD], st[_FUEL], st[_T] = N1, N2, vpos, 1.0 if vcmd else 0.0, fuel, t0 + dt_s
    st[_A1], st[_A2], st[_WFS], st[_N1S], st[_N2S], st[_PT3], st[_KEYOK] = a1, a2, Wf_s, N1_s, N2_s, Pt3, 1.0
    key[0], key[1], key[2] = N1, N2, vpos
    for k in range(14):
        st[_KEY + k] = key[k]
    for k in range(9):
        new[_X + k], new[_R + k] = xf[k], r[k]
    for k in range(n_out):
        new[_O + k] = o[k]
    for i in range(6):
        for j in range(6):
            new[_H + 6 * i + j] = Hm[i, j]
    new[_S], new[_S + 1] = sens[0], sens[1]
    new[_C], new[_C + 1], new[_C + 2], new[_C + 3], new[_C + 4], new[_C + 5] = t_m, Wf_m, hb_m, it_m, N1_m, N2_m
    new[_C + 6], new[_C + 7], new[_C + 8] = uin[1], uin[2], uin[3]
    new[_C + 9], new[_C + 10], new[_C + 11] = cust, hp, lp
    return out


def resolved(d: StepData) -> Any:
    """:func:`euler_step` compiled (or loaded from the cache) for the type of `d`, as a function that skips numba's
    dispatch: the dispatcher types every argument at every call, a StructRef in Python (about 3 us a call). The
    dispatcher itself where numba keeps no such entry (then the same results, slower)."""
    sig = (types.float64, types.float64, numba.typeof(d), types.int64, types.float64)
    euler_step.compile(sig)
    cres = euler_step.overloads.get(sig)
    return getattr(cres, "entry_point", None) or euler_step
