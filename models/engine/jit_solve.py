"""The transient's per-step matching compiled: free stream and the chord/Broyden iteration in one kernel call.

:meth:`.transient.TurbofanTransient._chord` matches the gas path at every step with a
predictor (first order in the change of N1, N2, Wf) and quasi-Newton iterations on a cached
inverse Jacobian kept current by Broyden's update. Driven from Python, each step paid for
its small NumPy operations and for four to five calls into the compiled residuals
(:func:`.jit_cycle.cycle`) more than for the residuals themselves. :func:`chord_solve` is
that iteration compiled with the residuals: the same predictor, the same update, the same
convergence test (max |r| < tol on the six matched residuals), the same stall test (max |r|
not halved) and the same limit of eight iterations. Its matrix products are ``np.dot``, which
numba hands to the same BLAS routines (gemv, dot) as NumPy's ``@`` in the Python iteration, so
where NumPy and SciPy ship the same BLAS kernels (the project's environment) the iterates are
the same numbers, bit for bit; elsewhere they differ by rounding.
:func:`.jit_freestream.free_stream` is evaluated only when the flight condition changes (the
first entries of the ``fsc`` array remember the last one).

Nothing here raises: a status tells the caller what Python would do. ``tests/engine/
test_one_source.py`` checks the free stream against :func:`.atmosphere.free_stream` and the
solver against the Python iteration on the same steps. Needs SciPy (numba's ``np.dot``).

References
----------
C. G. Broyden, "A class of methods for solving nonlinear simultaneous equations",
Math. Comp. 19 (1965) 577-593 (the inverse update).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import jit_kernels as K
from .gas_path import OX
from .jit_cycle import cycle, scratch
from .jit_freestream import free_stream
from .jit_kernels import borrowed, jit, jit_inline

__all__ = ["CONVERGED", "STALLED", "REFUSED", "FREE", "INPUTS", "bundle", "chord_solve", "free_stream_at"]

#: :func:`chord_solve` statuses: converged; stalled (max |r| not halved, a step refused by
#: Python's rules, or eight iterations), Python's chord would give up there too; refused: the
#: residual kernel or the free stream met an input Python may raise on (rerun in Python).
CONVERGED, STALLED, REFUSED = 0, 1, 2
#: Indices of the six matched unknowns and of the three inputs (N1, N2, Wf) in the unknowns (9).
FREE = (0, 1, 2, 5, 6, 7)
INPUTS = (3, 4, 8)
_MAX_IT = 8


def bundle(fc: Any) -> tuple[Any, ...]:
    """The arrays of a :class:`.jit_cycle.FastCycle` that :func:`chord_solve` needs, as one tuple passed through
    unopened by its callers (:mod:`.transient`, :mod:`.jit_step`); :func:`_open` is its only reader."""
    return (fc.fsc, fc.atm, fc.e, fc.gc, fc.gs, fc.bl, *fc.maps, scratch())


@jit_inline
def _open(fcb: Any) -> Any:
    """The parts of a :func:`bundle`: (fsc, atm, e, gc, gs, bl, fan, hpc, hpt, lpt, scratch)."""
    fsc, atm, e, gc, gs, bl, fan, hpc, hpt, lpt, scr = fcb
    return fsc, atm, e, gc, gs, bl, fan, hpc, hpt, lpt, scr


@jit_inline
def free_stream_at(fcb: Any, alt: float, Mach: float, dT: float) -> int:
    """Make the free-stream cache of the bundle (its ``fsc``: (alt, Mach, dT) then the six values of
    :func:`.jit_freestream.free_stream`) hold the flight condition (alt [m], Mach [-], dT [K]), computing it only
    if it differs from the one held; 0, or 1 (the cache untouched) where the free stream refuses it."""
    fsc, atm, _, gc, gs = _open(fcb)[:5]
    if fsc[0] == alt and fsc[1] == Mach and fsc[2] == dT:
        return 0
    fs_new = np.empty(6)
    if free_stream(gc, gs, atm, alt, Mach, dT, fs_new) != 0:
        return 1
    fsc[0], fsc[1], fsc[2] = alt, Mach, dT
    for k in range(6):
        fsc[3 + k] = fs_new[k]
    return 0


@jit_inline
def _resid(xf: np.ndarray, xr: np.ndarray, fs: np.ndarray, ctl: np.ndarray, e: np.ndarray, gc: np.ndarray,
           gs: np.ndarray, bl: np.ndarray, fan: Any, hpc: Any, hpt: Any, lpt: Any, scr: Any, r: np.ndarray,
           o: np.ndarray) -> float:
    """Residuals at the matched unknowns xr (6) put into xf; max |r| of the six matched ones, or NaN where
    the kernel refuses or a residual is not a number (the caller hands over to Python)."""
    for k in range(6):
        xf[FREE[k]] = xr[k]
    if cycle(xf, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, scr, r, o, False) != 0:
        return math.nan
    m = 0.0
    for k in range(6):
        a = abs(r[k])
        if not a == a:
            return math.nan
        if a > m:
            m = a
    return m


@jit
def chord_solve(xf: np.ndarray, u: np.ndarray, H0: np.ndarray, J_in: np.ndarray, Js_free: np.ndarray,
                Js_in: np.ndarray, fcb: Any, tol: float, H: np.ndarray, r: np.ndarray, o: np.ndarray,
                sens: np.ndarray) -> tuple[int, int]:
    """One transient match: :meth:`.transient.TurbofanTransient._chord` on the compiled residuals.

    Parameters
    ----------
    xf : the unknowns (9) of the previous match; on return the new match (inputs and matched unknowns).
    u : the step's inputs, one array (fewer arguments to pass): the new inputs (N1, N2, Wf) scaled as xf, then
        cond (alt [m], Mach [-], dT_isa [K]), then ctl, the residual kernel's control vector (demand kind 0 and
        the fuel flow [kg/s], customer bleed [-], HP and LP offtakes [W], handling bleed [-] or NaN).
    H0, J_in, Js_free, Js_in : the cached inverse Jacobian (6, 6) of the matched residuals, their derivatives
        by the inputs (6, 3), the shaft residuals' (HP, LP) derivatives by the matched unknowns (2, 6) and by
        the inputs (2, 3); H0 is not changed.
    fcb : the compiled cycle's arrays (:func:`bundle`); its free-stream cache ``fsc`` is updated
        (:func:`free_stream_at`).
    tol : convergence when max |r| of the six matched residuals < tol.
    H, r, o, sens : outputs: the updated inverse Jacobian, the residuals (9) and outputs (:data:`.gas_path.OUT`,
        surge margins included) at the match, and the shaft residuals' (HP, LP) change per unit of scaled fuel
        flow with the gas path re-matched (-Js_free H J_in[:, 2] + Js_in[:, 2], for
        :meth:`.transient.TurbofanTransient.fuel_sensitivity`).

    Returns
    -------
    (status, iterations) : status :data:`CONVERGED`, :data:`STALLED` or :data:`REFUSED`; the outputs are
        set only when converged.
    """
    # the arrays held by the caller, as views without reference counts (numba's would cost half the match)
    fcb, xf, u, H0, J_in, Js_free, Js_in, H, r, o, sens = borrowed((fcb, xf, u, H0, J_in, Js_free, Js_in, H, r, o,
                                                                    sens))
    fsc, _, e, gc, gs, bl, fan, hpc, hpt, lpt, scr = _open(fcb)
    xin, cond = u[0:3], u[3:6]
    # ctl and fs copied into the scratch's contiguous vectors: the gas path is compiled once, for FastCycle's types
    fs, ctl = scr[7], scr[8]
    for k in range(6):
        ctl[k] = u[6 + k]
    if free_stream_at(fcb, cond[0], cond[1], cond[2]) != 0:
        return REFUSED, 0
    for k in range(6):
        fs[k] = fsc[3 + k]
    din = np.empty(3)
    for k in range(3):
        din[k] = xin[k] - xf[INPUTS[k]]
        xf[INPUTS[k]] = xin[k]
    x = np.empty(6)
    for k in range(6):
        x[k] = xf[FREE[k]]
    # the operations of TurbofanTransient._chord, as NumPy forms them: np.dot is the same BLAS call as the
    # operator @ there (gemv, dot), so the iterates are the same numbers where both use the same BLAS kernels
    x = x - np.dot(H0, np.dot(J_in, din))                  # predictor
    norm = _resid(xf, x, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, scr, r, o)
    if not norm == norm:
        return REFUSED, 0
    Hc = H0.copy()              # updated in place (Broyden), as are the residuals and differences below
    rr = r[:6].copy()
    y, uu = np.empty(6), np.empty(6)
    for it in range(_MAX_IT):
        if norm < tol:
            for k in range(6):
                xf[FREE[k]] = x[k]
            o[OX.SM_fan] = K.surge_margin(fan[0], fan[1], fan[2], fan[3], fan[4], fan[5], fan[7], fan[8],
                                          o[OX.N1c] / fan[6][3], x[1], fan[6][1])
            o[OX.SM_hpc] = K.surge_margin(hpc[0], hpc[1], hpc[2], hpc[3], hpc[4], hpc[5], hpc[7], hpc[8],
                                          o[OX.N2c] / hpc[6][3], x[2], hpc[6][1])
            o[OX.SM_fan_clean], o[OX.SM_hpc_clean] = o[OX.SM_fan], o[OX.SM_hpc]     # one sector: the same
            dxw = np.dot(-Hc, np.ascontiguousarray(J_in[:, 2]))  # as TurbofanTransient.fuel_sensitivity
            sv = np.dot(Js_free, dxw) + Js_in[:, 2]
            # element by element: an array assignment's shape check costs seconds of compilation
            for i in range(6):
                for j in range(6):
                    H[i, j] = Hc[i, j]
            sens[0], sens[1] = sv[0], sv[1]
            return CONVERGED, it
        dx = np.dot(-Hc, rr)
        xn = x + dx
        norm_new = _resid(xf, xn, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, scr, r, o)
        if not norm_new == norm_new:
            return REFUSED, it
        if norm_new > 0.5 * norm:
            return STALLED, it
        for k in range(6):      # y = r_new - r, and r_new kept: element by element, the same differences
            y[k] = r[k] - rr[k]
            rr[k] = r[k]
        Hy = np.dot(Hc, y)
        # Broyden's good update of the inverse, H + outer(dx - Hy, dx H) / (dx Hy), element by element (the same
        # products and quotients as np.outer's; numba's np.outer cost a second and a half of compilation), in
        # place: dx H and dx - Hy are formed before
        w, d = np.dot(dx, Hc), np.dot(dx, Hy)
        for k in range(6):
            uu[k] = dx[k] - Hy[k]
        for i in range(6):
            for j in range(6):
                Hc[i, j] = Hc[i, j] + uu[i] * w[j] / d
        x = xn
        norm = norm_new
    return STALLED, _MAX_IT
