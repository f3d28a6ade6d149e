"""Newton solver for the engine's matching equations, with Broyden updates and Jacobian reuse.

The off-design engine is a small square system r(x) = 0 (8 to 10 unknowns,
dimensionless residuals of order 1 near the solution). Each iteration solves
J dx = -r; the Jacobian J is built by forward differences once, then kept up
to date with Broyden's rank-one update, and rebuilt only when a step fails
to reduce |r| by half. A warm start passes the Jacobian of a neighbouring
point, so a sweep costs few residual evaluations per point. A step that
leaves the valid range of a component (an :class:`~.errors.OutOfRangeError`
from a map or the gas tables) or does not reduce the Euclidean norm of r is
halved, up to 12 times; convergence is judged on max |r_i|.

References
----------
C. G. Broyden, "A class of methods for solving nonlinear simultaneous
equations", Math. Comp. 19 (1965) 577-593.
J. E. Dennis, R. B. Schnabel, "Numerical Methods for Unconstrained Optimization
and Nonlinear Equations", SIAM, 1996, ch. 6 and 8 (line search, secant updates).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError, ModelError

__all__ = ["NewtonResult", "newton_solve"]


@dataclass(frozen=True)
class NewtonResult:
    """Result of :func:`newton_solve`.

    Attributes
    ----------
    x : numpy.ndarray
        Solution.
    r : numpy.ndarray
        Residuals at the solution.
    jacobian : numpy.ndarray
        Last Jacobian estimate (for warm starts).
    iterations : int
        Newton iterations taken.
    evaluations : int
        Residual evaluations, finite differences included.
    """

    x: np.ndarray
    r: np.ndarray
    jacobian: np.ndarray
    iterations: int
    evaluations: int


def newton_solve(f: Callable[[np.ndarray], np.ndarray], x0: Sequence[float] | np.ndarray, names: Sequence[str],
                 tol: float = 1e-9, max_iter: int = 40, jacobian: np.ndarray | None = None,
                 fd_step: float = 1e-6, where: str = "newton", refresh_after: int = 6) -> NewtonResult:
    """Solve f(x) = 0 from x0.

    Parameters
    ----------
    f : callable
        Residual function of the (dimensionless, order-1) unknowns; may raise
        :class:`~.errors.ModelError` for an invalid x.
    x0 : sequence of float
        Starting point.
    names : sequence of str
        Names of the residuals, for the error message.
    tol : float
        Convergence when max |r_i| < tol.
    max_iter : int
        Iteration limit.
    jacobian : numpy.ndarray, optional
        Jacobian to start with (warm start); default finite differences at x0.
    fd_step : float
        Forward-difference step on each unknown.
    where : str
        Name of the caller for error messages.
    refresh_after : int
        If the returned Jacobian has absorbed more Broyden updates than this
        since it was last built by differences, it is rebuilt at the solution,
        so that the next warm start begins with an accurate one.

    Raises
    ------
    ConvergenceError
        If max |r| >= tol after `max_iter` iterations, or no step reduces |r|;
        the message names every residual and its value.
    """
    x = np.array(x0, dtype=float)
    n_eval = 0

    def F(xx: np.ndarray) -> np.ndarray:
        nonlocal n_eval
        n_eval += 1
        return np.asarray(f(xx), dtype=float)

    def fd(xx: np.ndarray, rr: np.ndarray) -> np.ndarray:
        J = np.empty((rr.size, xx.size))
        for j in range(xx.size):
            xp = xx.copy()
            h = fd_step * max(1.0, abs(xx[j]))
            xp[j] += h
            try:
                J[:, j] = (F(xp) - rr) / h
            except ModelError:
                xp[j] = xx[j] - h
                J[:, j] = (rr - F(xp)) / h
        return J

    try:
        r = F(x)
    except ModelError as exc:
        raise ConvergenceError(f"{where}: the starting point is invalid: {exc}") from None
    J = fd(x, r) if jacobian is None else np.array(jacobian, dtype=float)
    fresh = jacobian is None
    updates = 0
    rejected = ""
    for it in range(max_iter + 1):
        norm = float(np.max(np.abs(r)))
        if norm < tol:
            if updates > refresh_after:
                J = fd(x, r)
            return NewtonResult(x, r, J, it, n_eval)
        if it == max_iter:
            break
        try:
            dx = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            dx = np.linalg.lstsq(J, -r, rcond=None)[0]
        lam, accepted = 1.0, False
        norm2 = float(np.linalg.norm(r))
        for _ in range(12):
            xn = x + lam * dx
            try:
                rn = F(xn)
            except ModelError as exc:
                rejected = str(exc)
                lam *= 0.5
                continue
            if np.linalg.norm(rn) < (1.0 - 1e-4 * lam) * norm2 or np.max(np.abs(rn)) < tol:
                accepted = True
                break
            lam *= 0.5
        if not accepted:
            if fresh:
                break
            J, fresh, updates = fd(x, r), True, 0   # stale Jacobian: rebuild and retry
            continue
        s, y = xn - x, rn - r
        slow = np.linalg.norm(rn) > 0.5 * norm2
        x, r = xn, rn
        if slow and not fresh:
            J, fresh, updates = fd(x, r), True, 0
        else:
            J = J + np.outer(y - J @ s, s) / float(s @ s)   # Broyden's good update
            fresh, updates = False, updates + 1
    detail = ", ".join(f"{nm}={v:.3e}" for nm, v in zip(names, r, strict=True))
    why = f"; last rejected step: {rejected}" if rejected else ""
    raise ConvergenceError(f"{where}: no convergence in {it} iterations (tolerance {tol:g}); residuals: "
                           f"{detail}{why}")
