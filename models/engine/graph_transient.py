"""Transient of any engine file: each free shaft's speed a state, the main burner's fuel flow the input.

At every instant the graph of :class:`.engine_graph.EngineGraph` is matched with the shaft speeds and the
fuel flow given: the unknowns of its off-design system less the free shafts' speeds and the fuel flow (the
mass flow, the compressors' betas, the bypass ratios, the turbines' pressure ratios) against its residuals less
the shafts' power balances and the power setting (the maps' flows, the fixed nozzle areas). What a shaft does
not balance accelerates it (:func:`.shaft.spool_acceleration`)::

    dN/dt = (eta_mech sum P_T - sum P_C - P_X) / (I omega) * 30/pi   [rpm/s],  I = the shaft's I_kg_m2.

A fixed-speed shaft (``speed: fixed``, a generator's) stays at its speed, its load takes the net power. Each
match starts from the last one (its unknowns and its Jacobian: :func:`.newton.newton_solve`'s Broyden updates
and Jacobian reuse, a Jacobian by differences only when the iteration stalls). Integration is explicit Euler
on steps of at most ``dt_internal_s``; the match at the end of a step is the next step's start when the input
has not changed, so a step at a constant input costs one match.

As :mod:`.transient` for the turbofan's compiled gas path: a quasi-steady gas path, no heat soakage or volume
dynamics.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 8 (the spool acceleration equation,
quasi-steady matching). E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (balances).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .element_eval import State
from .engine_file import EngineFileError
from .engine_graph import EngineGraph, GraphPoint
from .errors import ModelError
from .newton import NewtonResult, newton_solve
from .shaft import spool_acceleration

__all__ = ["GraphMatch", "GraphTransient"]

Condition = tuple[float, float, float]


@dataclass(frozen=True)
class GraphMatch:
    """The engine at one instant: the graph matched at given shaft speeds and fuel flow (SI units).

    Attributes
    ----------
    t_s : float
        Time [s].
    cond : (alt_m, Mach, dT_isa_K)
        Flight condition.
    N_rpm : tuple of float
        Speed of each free shaft (:attr:`GraphTransient.shafts`) [rpm].
    Wf_kg_s : float
        Fuel flow of the main burner [kg/s].
    settings : mapping
        The point's settings (:meth:`.EngineGraph.solve`).
    x, jacobian : the matched unknowns (scaled as the graph scales them) and the iteration's Jacobian
    state : the graph's evaluation (stations, element outputs, shaft powers)
    net_W : tuple of float
        Net power into each free shaft [W] (0 in a steady state).
    dN_dt_rpm_s : tuple of float
        Acceleration of each free shaft [rpm/s].
    evaluations : int
        Graph evaluations this match took.
    """

    t_s: float
    cond: Condition
    N_rpm: tuple[float, ...]
    Wf_kg_s: float
    settings: Mapping[str, Any]
    x: np.ndarray
    jacobian: np.ndarray
    state: State
    net_W: tuple[float, ...]
    dN_dt_rpm_s: tuple[float, ...]
    evaluations: int

    @property
    def Fn_N(self) -> float:
        """Net thrust [N]."""
        return self.state.Fg - self.state.ram


class GraphTransient:
    """An engine file's graph in time.

    Parameters
    ----------
    graph : EngineGraph
        The engine (designed on first use).
    tol : float
        Matching tolerance, max |residual| [-].

    Raises
    ------
    EngineFileError
        A free shaft without a positive ``I_kg_m2``: one line naming the file, the line and the shaft.
    """

    def __init__(self, graph: EngineGraph, tol: float = 1e-9) -> None:
        self.g = graph
        eng = graph.eng
        self.tol = tol
        #: The free shafts, whose speeds are the states, in the file's order.
        self.shafts: tuple[str, ...] = tuple(s for s, d in eng.shafts.items() if d.attrs["speed"] == "free")
        for s in self.shafts:
            if not eng.shafts[s].attrs["I_kg_m2"] > 0.0:
                raise EngineFileError(f"{eng.file}:{eng.shafts[s].line}: shaft {s!r}: I_kg_m2 is not given (or 0): "
                                      "a transient needs the polar moment of inertia of every free shaft [kg m^2], "
                                      "> 0")
        for e in eng.order:
            el = eng.elements[e]
            if el.kind == "nozzle" and el.attrs["area"] == "variable":
                raise EngineFileError(f"{eng.where(e, 'area')}a variable-area nozzle holding a compressor's R-line is "
                                      "not modelled in time (with the spool speed a state, nothing sets the turbine's "
                                      "pressure ratio; the area's schedule is not in the file): use area: fixed")
        self.I_kg_m2 = tuple(float(eng.shafts[s].attrs["I_kg_m2"]) for s in self.shafts)
        self.main = graph.main_burner
        full_u, full_r = graph.offdesign_system(("Wf_kg_s", 0.0, None))
        states = {("N", s) for s in self.shafts} | {("Wf", self.main)}
        self._cols = [i for i, u in enumerate(full_u) if u not in states]
        balances = {f"shaft {s}.power" for s in self.shafts} | {"demand"}
        self._rows = [i for i, r in enumerate(full_r) if r not in balances]
        self.unknowns = [full_u[i] for i in self._cols]
        self.residuals = tuple(full_r[i] for i in self._rows)
        self._full_u = full_u
        self._fs_cache: tuple[Condition | None, tuple[float, ...]] = (None, ())

    # ------------------------------------------------------------------ matching
    def _fs(self, cond: Condition) -> tuple[float, ...]:
        if self._fs_cache[0] != cond:
            self._fs_cache = (cond, self.g._fs(cond))
        return self._fs_cache[1]

    def _vals(self, x: np.ndarray, N: tuple[float, ...], Wf: float) -> dict[tuple[str, str], float]:
        vals = self.g._vals(self.unknowns, x)
        for s, n in zip(self.shafts, N, strict=True):
            vals[("N", s)] = n
        vals[("Wf", self.main)] = Wf
        return vals

    def _finish(self, t_s: float, cond: Condition, N: tuple[float, ...], Wf: float, settings: Mapping[str, Any],
                x: np.ndarray, J: np.ndarray, s: State, n_eval: int) -> GraphMatch:
        net = tuple(float(s.out["shaft " + sh]["net_W"]) for sh in self.shafts)
        acc = tuple(spool_acceleration(p, n, i) for p, n, i in zip(net, N, self.I_kg_m2, strict=True))
        return GraphMatch(t_s, cond, N, Wf, settings, x, J, s, net, acc, n_eval)

    def match(self, t_s: float, cond: Condition, N_rpm: tuple[float, ...], Wf_kg_s: float,
              settings: Mapping[str, Any], guess: GraphMatch) -> GraphMatch:
        """The graph matched at shaft speeds `N_rpm` [rpm] and fuel flow `Wf_kg_s` [kg/s], from `guess`.

        Raises
        ------
        ConvergenceError, ModelError
            The gas path cannot be matched there (the message names the residuals or the element).
        """
        fs = self._fs(cond)
        st = dict(settings)
        last: list[Any] = [None, None]           # (x, evaluation) of the last residual evaluation

        def f(x: np.ndarray) -> np.ndarray:
            s = self.g.run(False, fs, self._vals(x, N_rpm, Wf_kg_s), st)
            last[:] = [x.copy(), s]
            return np.array([s.resid[r] for r in self.residuals])

        res = newton_solve(f, guess.x, self.residuals, tol=self.tol, jacobian=guess.jacobian,
                           where=f"{self.g.eng.file} at t={t_s:.6g} s, N={', '.join(f'{n:.6g}' for n in N_rpm)} rpm, "
                                 f"Wf={Wf_kg_s:.6g} kg/s")
        s = last[1] if last[0] is not None and np.array_equal(res.x, last[0]) else \
            self.g.run(False, fs, self._vals(res.x, N_rpm, Wf_kg_s), st)
        return self._finish(t_s, cond, N_rpm, Wf_kg_s, settings, res.x, res.jacobian, s, res.evaluations)

    def steady(self, cond: Condition, demand: tuple[str, float] | tuple[str, float, str | None],
               settings: Mapping[str, Any] | None = None, guess: GraphPoint | None = None) -> GraphMatch:
        """The steady state at a power setting (:meth:`.EngineGraph.solve`) as the start of a transient."""
        st = dict(settings or {})
        pt = self.g.solve(*cond, demand=demand, settings=st, guess=guess, tol=self.tol)
        x = np.array(pt.x)[self._cols]
        J = np.asarray(pt.jacobian)[np.ix_(self._rows, self._cols)]
        N = tuple(float(pt.shafts[s]["N_rpm"]) for s in self.shafts)
        Wf = float(pt.elements[self.main]["Wf_kg_s"])
        s = self.g.run(False, self._fs(cond), self._vals(x, N, Wf), st)
        return self._finish(0.0, cond, N, Wf, st, x, J, s, pt.evaluations)

    def point(self, m: GraphMatch) -> GraphPoint:
        """The match as a :class:`.engine_graph.GraphPoint` (stations, elements, shafts; the shafts' power
        residuals are their imbalances)."""
        r = np.array([m.state.resid[n] for n in self.residuals])
        return self.g._point(m.state, m.cond, tuple(f"{k} of {n}" for k, n in self.unknowns),
                             NewtonResult(m.x, r, m.jacobian, 0, m.evaluations))

    # ------------------------------------------------------------------ integration
    def step(self, m: GraphMatch, dt_s: float, Wf_kg_s: float, cond: Condition | None = None,
             settings: Mapping[str, Any] | None = None, dt_internal_s: float = 0.05) -> GraphMatch:
        """The engine `dt_s` [s] after `m`, the fuel flow, flight condition and settings held over the step.

        Explicit Euler on ``ceil(dt_s / dt_internal_s)`` equal steps; the returned match is at the step's end."""
        cond = m.cond if cond is None else cond
        settings = m.settings if settings is None else settings
        n = max(1, math.ceil(dt_s / dt_internal_s - 1e-9))
        h = dt_s / n
        t0 = m.t_s
        for k in range(n):
            if Wf_kg_s != m.Wf_kg_s or cond != m.cond or settings != m.settings:
                m = self.match(m.t_s, cond, m.N_rpm, Wf_kg_s, settings, m)
            N = tuple(nn + h * a for nn, a in zip(m.N_rpm, m.dN_dt_rpm_s, strict=True))
            if not all(nn > 0.0 for nn in N):
                raise ModelError(f"{self.g.eng.file}: a shaft's speed falls to zero at t={m.t_s + h:.6g} s")
            m = self.match(t0 + (k + 1) * h, cond, N, Wf_kg_s, settings, m)
        return m

    def simulate(self, m: GraphMatch, Wf_of_t: Callable[[float], float], t_end_s: float, dt_s: float,
                 dt_internal_s: float = 0.05) -> list[GraphMatch]:
        """The history from `m` under the fuel schedule `Wf_of_t(t)` [kg/s] (held over each step of `dt_s`)."""
        hist = [m]
        for k in range(max(0, round(t_end_s / dt_s))):
            hist.append(self.step(hist[-1], dt_s, Wf_of_t(k * dt_s), dt_internal_s=dt_internal_s))
        return hist

