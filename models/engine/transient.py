"""Transient turbofan: spool speeds as states, fuel flow as input.

The two spool speeds N1, N2 are the states. At every instant the gas path is
matched with the speeds and the fuel flow given: the six unknowns W2,
beta_fan, beta_hpc, PR_hpt, PR_lpt and BPR satisfy the six flow-continuity
residuals of :mod:`.offdesign` (fan, HPC, HPT, LPT, core and bypass nozzle),
without the shaft power balances. What the spools do not balance
accelerates them (:func:`.shaft.spool_acceleration`):

    dN/dt = (eta_mech P_T - sum P_C - P_X) / (I omega) * 30/pi   [rpm/s].

Heat soakage, volume dynamics and tip-clearance changes are not modelled (a
quasi-steady gas path, as in most real-time engine models). Integration is a
fixed step, explicit Euler or Heun (2nd-order), each evaluation warm-started
from the previous one: a first-order predictor in the change of (N1, N2, Wf)
and quasi-Newton iterations on a cached finite-difference Jacobian (inverse
kept current by Broyden updates, rebuilt when the iteration stalls).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 8
(transient performance: the spool acceleration equation, quasi-steady matching).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .distortion import Distortion
from .errors import ModelError, OutOfRangeError
from .newton import NewtonResult, newton_solve
from .offdesign import OffDesignPoint, TurbofanOffDesign
from .shaft import spool_acceleration

__all__ = ["TransientState", "TurbofanTransient"]

_FREE = (0, 1, 2, 5, 6, 7)          # indices of the matched unknowns in the off-design vector
_INPUTS = [3, 4, 8]                 # N1, N2, Wf: states and input
_FREE_L, _ROWS9 = list(_FREE), list(range(6))
_KEY_CLEAN = ((True, True), 9)      # the cache key without distortion or booster: the compiled iteration's case
_CONVERGED, _STALLED, _REFUSED = 0, 1, 2  # statuses of jit_solve.chord_solve (that module needs numba)
_chord_solve: Callable[..., tuple[int, int]] | None = None     # jit_solve.chord_solve, imported on first use


class TransientState:
    """The engine at one instant.

    Attributes
    ----------
    t_s : float
        Time [s].
    point : OffDesignPoint
        The matched gas path (its shaft residuals are the imbalances, not zero). Built on first
        access from the matched unknowns (one Python evaluation of the gas path): a transient
        step needs only :attr:`fast` and the unknowns.
    dN1_dt_rpm_s, dN2_dt_rpm_s : float
        Spool accelerations [rpm/s].
    net_lp_W, net_hp_W : float
        Spool power imbalances [W].
    x : tuple of float
        The matched unknowns (scaled, as :attr:`.offdesign_result.OffDesignPoint.x`).
    distortion : (Distortion or None, Distortion or None)
        Distortion at the fan and HPC faces.
    fast : numpy.ndarray
        The outputs of the gas path (:data:`.gas_path.OUT`) at the match, surge margins included.
    N1_rpm, N2_rpm, Wf_kg_s, beta_fan, beta_hpc : float
        Speeds [rpm], fuel flow [kg/s] and map coordinates [-] of the match.
    """

    __slots__ = ("t_s", "dN1_dt_rpm_s", "dN2_dt_rpm_s", "net_lp_W", "net_hp_W", "x", "distortion", "fast",
                 "N1_rpm", "N2_rpm", "Wf_kg_s", "beta_fan", "beta_hpc", "_point", "_jac", "_jbase", "_xa")

    def __init__(self, t_s: float, point: OffDesignPoint | Callable[[], OffDesignPoint], dN1_dt_rpm_s: float,
                 dN2_dt_rpm_s: float, net_lp_W: float, net_hp_W: float, x: tuple[float, ...] = (),
                 distortion: tuple[Distortion | None, Distortion | None] = (None, None),
                 fast: np.ndarray | None = None, scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
                 jacobian: Callable[[], np.ndarray] | None = None, jbase: np.ndarray | None = None,
                 x_array: np.ndarray | None = None) -> None:
        self.t_s, self.dN1_dt_rpm_s, self.dN2_dt_rpm_s = t_s, dN1_dt_rpm_s, dN2_dt_rpm_s
        self.net_lp_W, self.net_hp_W = net_lp_W, net_hp_W
        self._point = point
        if isinstance(point, OffDesignPoint):
            x, distortion = point.x, point.distortion
        self.x, self.distortion, self.fast, self._jac = x, distortion, fast, jacobian
        self._jbase = jbase             # the Jacobian entries outside the matched block (shared, never changed)
        self._xa = x_array              # x as an array (never changed; copied by the next step)
        self.N1_rpm, self.N2_rpm, self.Wf_kg_s = x[3] * scale[0], x[4] * scale[1], x[8] * scale[2]
        self.beta_fan, self.beta_hpc = x[1], x[2]

    @property
    def point(self) -> OffDesignPoint:
        """The matched gas path (see the class docstring)."""
        p = self._point
        if not isinstance(p, OffDesignPoint):
            p = self._point = p()
        return p

    @property
    def jacobian(self) -> np.ndarray:
        """Jacobian of all residuals with respect to all unknowns at the match (for warm starts)."""
        if self._jac is None:
            return self.point.jacobian
        J = self._jac()
        self._jac = lambda: J
        return J


class _LazyResult:
    """A :class:`.newton.NewtonResult` of the chord iteration whose Jacobian (the inverse of the cached
    inverse) is formed only when read."""

    __slots__ = ("x", "r", "_H", "iterations", "evaluations", "_J")

    def __init__(self, x: np.ndarray | None, r: np.ndarray | None, H: np.ndarray, iterations: int,
                 evaluations: int) -> None:
        self.x, self.r, self._H, self.iterations, self.evaluations, self._J = x, r, H, iterations, evaluations, None

    @property
    def jacobian(self) -> np.ndarray:
        if self._J is None:
            self._J = np.linalg.inv(self._H)
        return self._J


class TurbofanTransient:
    """Quasi-steady transient model over a :class:`.offdesign.TurbofanOffDesign`.

    Parameters
    ----------
    od : TurbofanOffDesign
        The off-design model (design point and maps).
    I_lp_kg_m2, I_hp_kg_m2 : float, optional
        Polar moments of inertia of the LP and HP spools [kg m^2]; default the
        design parameters' ``I_lp_kg_m2`` and ``I_hp_kg_m2``.
    """

    def __init__(self, od: TurbofanOffDesign, I_lp_kg_m2: float | None = None,
                 I_hp_kg_m2: float | None = None) -> None:
        p = od.p
        self.od = od
        self.I_lp = p.I_lp_kg_m2 if I_lp_kg_m2 is None else I_lp_kg_m2
        self.I_hp = p.I_hp_kg_m2 if I_hp_kg_m2 is None else I_hp_kg_m2
        self._c: tuple[Any, ...] | None = None
        #: Forms the cache when it is first read, or None; set by a caller that keeps the cache in its own
        #: arrays between calls (:class:`.engine_model.EngineModel`'s compiled step).
        self.cache_source: Callable[[], tuple[Any, ...] | None] | None = None
        self._u = np.empty(12)                      # inputs of jit_solve.chord_solve, filled per call
        self._bundle: tuple[Any, tuple[Any, ...]] | None = None     # (FastCycle, its jit_solve.bundle)
        #: Match with the compiled iteration (:mod:`.jit_solve`) where it applies; False: the Python iteration on
        #: the compiled residuals (the same numbers, slower; for benchmarks and tests).
        self.compiled_iteration = True
        if not (self.I_lp > 0.0 and self.I_hp > 0.0):
            raise OutOfRangeError(f"{p.name}: spool inertias I_lp_kg_m2={self.I_lp!r}, I_hp_kg_m2={self.I_hp!r} "
                                  "must be > 0 (set them in the parameter file)")

    @property
    def _cache(self) -> tuple[Any, ...] | None:
        """The cached Jacobian: (key, H, J_in, Js_free, Js_in[, fuel sensitivity of the shaft residuals]) or None."""
        if self.cache_source is not None:
            self._c, self.cache_source = self.cache_source(), None
        return self._c

    @_cache.setter
    def _cache(self, c: tuple[Any, ...] | None) -> None:
        self._c, self.cache_source = c, None

    def state(self, t_s: float, N1_rpm: float, N2_rpm: float, Wf_kg_s: float, alt_m: float = 0.0,
              Mach: float = 0.0, dT_isa_K: float = 0.0, guess: TransientState | OffDesignPoint | None = None,
              tol: float = 1e-9, distortion: tuple[Distortion | None, Distortion | None] = (None, None),
              customer_bleed_frac: float | None = None, offtake_hp_W: float | None = None,
              offtake_lp_W: float | None = None, handling_bleed_frac: float | None = None) -> TransientState:
        """Matched gas path and spool accelerations at speeds [rpm] and fuel flow [kg/s].

        The residuals are those of the one gas path (:func:`.gas_path.turbofan`, through
        :meth:`.offdesign.TurbofanOffDesign._residuals`); without distortion or booster the whole
        iteration runs compiled (:func:`.jit_solve.chord_solve`).

        `distortion` is the (fan, HPC) sector distortion of :mod:`.distortion`, switchable
        from one call to the next. `customer_bleed_frac` (W/W25 [-]), `offtake_hp_W` and
        `offtake_lp_W` [W] default to the design parameters'; `handling_bleed_frac` [-], if
        given, replaces the handling bleed's corrected-N1 schedule (a valve position set by the caller).
        The cached Jacobian is kept across changes of flight condition, offtakes and bleeds
        (chord iterations with Broyden updates absorb them) and rebuilt when the distortion
        configuration changes or the iteration stalls.

        Raises
        ------
        ConvergenceError
            If the gas path cannot be matched (e.g. speeds off the maps).
        """
        od, p = self.od, self.od.p
        extras = (p.customer_bleed_frac if customer_bleed_frac is None else customer_bleed_frac,
                  p.offtake_hp_W if offtake_hp_W is None else offtake_hp_W,
                  p.offtake_lp_W if offtake_lp_W is None else offtake_lp_W)
        hb = handling_bleed_frac
        cond = (alt_m, Mach, dT_isa_K)
        status = _REFUSED
        if self.compiled_iteration and isinstance(guess, TransientState) and distortion[0] is None and \
                distortion[1] is None and guess.distortion[0] is None and guess.distortion[1] is None:
            out = self._compiled(t_s, N1_rpm, N2_rpm, Wf_kg_s, cond, extras, hb, guess, tol)
            if isinstance(out, TransientState):
                return out
            status = out
        if isinstance(guess, TransientState) and \
                tuple(d is None for d in guess.distortion) == tuple(d is None for d in distortion):
            x_full, J_full = np.array(guess.x, dtype=float), guess          # Jacobian read only if needed
            J_base = guess._jbase
        else:
            x_full, J_full = od.start(distortion, guess.point if isinstance(guess, TransientState) else guess)
            J_base = J_full
        n = x_full.size
        free = list(_FREE) + list(range(9, n))
        rows = list(range(6)) + list(range(9, n))
        inputs = np.array([N1_rpm / p.N1_rpm, N2_rpm / p.N2_rpm, Wf_kg_s / od.ref["Wf"]])
        d_in = inputs - x_full[_INPUTS]
        x_full[_INPUTS] = inputs
        demand = ("Wf_kg_s", Wf_kg_s)
        last: dict[str, Any] = {}

        def full_x(xr: np.ndarray) -> np.ndarray:
            x = x_full.copy()
            x[free] = xr
            return x

        def resid(xr: np.ndarray) -> np.ndarray:
            r = od._residuals(full_x(xr), cond, demand, extras, distortion, hb)
            last["r"], last["xr"] = r, xr.copy()
            return r[rows]

        key = (tuple(d is None for d in distortion), n)
        res = None
        if isinstance(guess, TransientState):
            if status == _STALLED:                      # the Python iteration would stall too: rebuild
                self._cache = None
            else:                                       # not compiled, or refused: the Python iteration
                res = self._chord(resid, x_full[free], d_in, key, tol)
        if res is None:
            if isinstance(J_full, TransientState):
                J_full = J_full.jacobian
            J0 = None if J_full is None else np.asarray(J_full)[np.ix_(rows, free)]
            all_names = od.residual_names(distortion)
            names = all_names[:6] + all_names[9:]
            res = newton_solve(resid, x_full[free], names, tol=tol, jacobian=J0,
                               where=f"transient of {p.name!r} at t={t_s} s, N1={N1_rpm:.6g} rpm, "
                                     f"N2={N2_rpm:.6g} rpm, Wf={Wf_kg_s:.6g} kg/s")
            self._cache = None
        if self._cache is None or self._cache[0] != key:
            self._cache = (key, *self._fd_jacobian(od, full_x(res.x), cond, demand, extras, distortion, rows, free,
                                                   hb))
        if not np.array_equal(last["xr"], res.x):
            resid(res.x)
        r = last["r"]
        x_full[free] = res.x
        fast = od._evaluate(x_full, cond, demand, extras, distortion, hb, with_sm=True).o.copy()  # and SMs

        if isinstance(J_full, np.ndarray):              # a Newton solve here: its Jacobian is the new base
            J_base = J_full
        return self._make_state(t_s, N1_rpm, N2_rpm, x_full.copy(), r, fast, res, J_base, cond, demand, extras,
                                distortion, hb, rows, free)

    def _make_state(self, t_s: float, N1_rpm: float, N2_rpm: float, x_match: np.ndarray, r: np.ndarray,
                    fast: np.ndarray | None, res: NewtonResult | _LazyResult, J_base: np.ndarray | None,
                    cond: tuple[float, float, float], demand: tuple[str, float], extras: tuple[float, float, float],
                    distortion: tuple[Distortion | None, Distortion | None], hb: float | None, rows: list[int],
                    free: list[int]) -> TransientState:
        """The state at a match x_match (all unknowns) with residuals r (all); its point and full Jacobian
        are formed only when read."""
        od, p = self.od, self.od.p
        n = x_match.size

        def jacobian(src: np.ndarray | None = J_base, res: NewtonResult | _LazyResult = res) -> np.ndarray:
            J = np.eye(n) if src is None else np.array(src, dtype=float)
            J[np.ix_(rows, free)] = res.jacobian
            return J

        def point(x: np.ndarray = x_match) -> OffDesignPoint:
            info = od._cycle(x, cond, demand, extras, distortion, hb)[1]
            return od._result(NewtonResult(x, r, jacobian(), res.iterations, res.evaluations), info, cond,
                              distortion)

        net_hp, net_lp = float(r[6]) * od.ref["P_hp"], float(r[7]) * od.ref["P_lp"]
        return TransientState(t_s, point, spool_acceleration(net_lp, N1_rpm, self.I_lp),
                              spool_acceleration(net_hp, N2_rpm, self.I_hp), net_lp, net_hp,
                              tuple(x_match.tolist()), distortion, fast,
                              (p.N1_rpm, p.N2_rpm, od.ref["Wf"]), jacobian, J_base, x_match)

    def _compiled(self, t_s: float, N1_rpm: float, N2_rpm: float, Wf_kg_s: float, cond: tuple[float, float, float],
                  extras: tuple[float, float, float], hb: float | None, guess: TransientState,
                  tol: float) -> TransientState | int:
        """:meth:`_chord` as one call of the compiled :func:`.jit_solve.chord_solve` (no distortion, no booster):
        the state if it converged, else its status (:data:`.jit_solve.STALLED`: Python's iteration would stall
        as well; :data:`.jit_solve.REFUSED`: not compiled here, or an input the kernel leaves to Python)."""
        fc, c = self.od.fast, self._cache
        if fc is None or c is None or c[0] != _KEY_CLEAN:
            return _REFUSED
        od, p, u = self.od, self.od.p, self._u
        xf = guess._xa.copy() if guess._xa is not None else np.array(guess.x)
        u[:] = (N1_rpm / p.N1_rpm, N2_rpm / p.N2_rpm, Wf_kg_s / od.ref["Wf"], *cond, 0.0, Wf_kg_s, *extras,
                math.nan if hb is None else hb)
        H, r, o, sens = np.empty((6, 6)), np.empty(9), np.empty(len(fc.o)), np.empty(2)
        if len(c) > 5:                              # arrays of a compiled iteration: contiguous already
            J_in, Js_free, Js_in = c[2], c[3], c[4]
        else:                                       # the same numbers, the layout the kernel is compiled for
            J_in, Js_free, Js_in = np.ascontiguousarray(c[2]), np.ascontiguousarray(c[3]), np.ascontiguousarray(c[4])
        fcb = self.bundle(fc)                       # (imports jit_solve on first use)
        status, it = _chord_solve(xf, u, c[1], J_in, Js_free, Js_in, fcb, tol, H, r, o, sens)
        if status != _CONVERGED:
            return int(status)
        self._cache = (c[0], H, J_in, Js_free, Js_in, sens)
        res = _LazyResult(None, None, H, it, it + 1)     # x and r of the matched block are not read
        return self._make_state(t_s, N1_rpm, N2_rpm, xf, r, o, res, guess._jbase, cond, ("Wf_kg_s", Wf_kg_s),
                                extras, (None, None), hb, _ROWS9, _FREE_L)

    def bundle(self, fc: Any) -> tuple[Any, ...]:
        """The compiled cycle's arrays of `fc` (:func:`.jit_solve.bundle`), formed once per cycle; also imports
        :mod:`.jit_solve` (which needs numba) on first use."""
        b = self._bundle
        if b is None or b[0] is not fc:
            global _chord_solve
            from .jit_solve import bundle, chord_solve
            _chord_solve = chord_solve
            b = self._bundle = (fc, bundle(fc))
        return b[1]

    def _fd_jacobian(self, od: TurbofanOffDesign, x: np.ndarray, cond: tuple[float, float, float],
                     demand: tuple[str, float], extras: tuple[float, float, float],
                     distortion: tuple[Distortion | None, Distortion | None], rows: list[int], free: list[int],
                     hb: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Inverse of d r/d x_free and the matrix d r/d inputs (N1, N2, Wf), by forward differences;
        also the rows of the two shaft residuals (HP, LP): d r_shaft/d x_free and d r_shaft/d inputs."""
        rows_all = rows + [6, 7]
        r0 = od._residuals(x, cond, demand, extras, distortion, hb)[rows_all]
        cols = free + _INPUTS
        J = np.empty((len(rows_all), len(cols)))
        for j, c in enumerate(cols):
            xp = x.copy()
            h = 1e-6 * max(1.0, abs(x[c]))
            xp[c] += h
            J[:, j] = (od._residuals(xp, cond, demand, extras, distortion, hb)[rows_all] - r0) / h
        m, nf = len(rows), len(free)
        return np.linalg.inv(J[:m, :nf]), J[:m, nf:], J[m:, :nf], J[m:, nf:]

    def fuel_sensitivity(self, state: TransientState) -> tuple[float, float] | None:
        """d(dN1/dt)/dWf and d(dN2/dt)/dWf [rpm/s per kg/s] at fixed speeds, the gas path re-matched
        (linearised with the cached Jacobian); None if no Jacobian is cached.

        A co-simulation step whose fuel flow changes a little uses it to correct the spool
        accelerations at its start instead of matching the gas path there again.
        """
        if self._cache is None or len(self._cache) < 5:
            return None
        if len(self._cache) > 5:                     # formed by the compiled iteration at its match
            dr = self._cache[5].tolist()
        else:
            _, H, J_in, Js_free, Js_in = self._cache[:5]
            dx = -H @ J_in[:, 2]                     # re-matched free unknowns per unit of x_Wf
            dr = (Js_free @ dx + Js_in[:, 2]).tolist()   # shaft residuals (HP, LP) per unit of x_Wf
        od = self.od
        per = 1.0 / od.ref["Wf"]
        return (spool_acceleration(dr[1] * od.ref["P_lp"] * per, state.N1_rpm, self.I_lp),
                spool_acceleration(dr[0] * od.ref["P_hp"] * per, state.N2_rpm, self.I_hp))

    def _chord(self, resid: Callable[[np.ndarray], np.ndarray], x: np.ndarray, d_in: np.ndarray,
               key: tuple[Any, ...], tol: float) -> NewtonResult | None:
        """Predictor (first order in the change of N1, N2, Wf) and quasi-Newton iterations on the
        cached inverse Jacobian, kept up to date by Broyden's inverse update; None if there is no
        cache for this condition or the iteration stalls (the caller then rebuilds it)."""
        if self._cache is None or self._cache[0] != key:
            return None
        _, H, J_in, *shaft = self._cache[:5]         # (a compiled iteration's fuel sensitivity is left out)
        x = x - H @ (J_in @ d_in)
        try:
            r = resid(x)
        except ModelError:
            return None
        for it in range(8):
            norm = float(np.max(np.abs(r)))
            if norm < tol:
                self._cache = (key, H, J_in, *shaft)
                return _LazyResult(x, r, H, it, it + 1)
            dx = -H @ r
            try:
                r_new = resid(x + dx)
            except ModelError:
                break
            if float(np.max(np.abs(r_new))) > 0.5 * norm:
                break
            y = r_new - r
            Hy = H @ y
            H = H + np.outer(dx - Hy, dx @ H) / float(dx @ Hy)     # Broyden's good update of the inverse
            x, r = x + dx, r_new
        self._cache = None
        return None

    def simulate(self, start: OffDesignPoint, Wf_of_t: Callable[[float], float], t_end_s: float, dt_s: float,
                 alt_m: float = 0.0, Mach: float = 0.0, dT_isa_K: float = 0.0,
                 method: str = "heun", tol: float = 1e-9) -> list[TransientState]:
        """Integrate from a steady state `start` with fuel flow schedule `Wf_of_t` [kg/s] to `t_end_s` [s].

        Time is t_k = k dt_s (integer k), the house rule for time stepping.
        """
        if method not in ("euler", "heun"):
            raise ModelError(f"transient.simulate: method={method!r} must be 'euler' or 'heun'")
        if not (dt_s > 0.0 and t_end_s >= 0.0):
            raise OutOfRangeError(f"transient.simulate: dt_s={dt_s!r} must be > 0 and t_end_s={t_end_s!r} >= 0")
        cond = (alt_m, Mach, dT_isa_K)
        n_steps = int(math.floor(t_end_s / dt_s + 1e-9))
        N1, N2 = start.N1_rpm, start.N2_rpm
        s = self.state(0.0, N1, N2, Wf_of_t(0.0), *cond, guess=start, tol=tol)
        out = [s]
        for k in range(n_steps):
            t1 = (k + 1) * dt_s
            if method == "euler":
                N1, N2 = N1 + dt_s * s.dN1_dt_rpm_s, N2 + dt_s * s.dN2_dt_rpm_s
            else:
                p = self.state(t1, N1 + dt_s * s.dN1_dt_rpm_s, N2 + dt_s * s.dN2_dt_rpm_s, Wf_of_t(t1), *cond,
                               guess=s, tol=tol)
                N1 = N1 + 0.5 * dt_s * (s.dN1_dt_rpm_s + p.dN1_dt_rpm_s)
                N2 = N2 + 0.5 * dt_s * (s.dN2_dt_rpm_s + p.dN2_dt_rpm_s)
            s = self.state(t1, N1, N2, Wf_of_t(t1), *cond, guess=s, tol=tol)
            out.append(s)
        return out
