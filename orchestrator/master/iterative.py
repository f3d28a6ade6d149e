"""Iterative Gauss-Seidel: every loop of the system stepped again until its coupling is consistent.

Plain Gauss-Seidel steps the components of a loop (a strongly connected set of the connection
graph) one after the other; the first of them takes the others' outputs of the previous macro
step, so a strongly coupled loop lags by a step, and an algebraic loop (outputs that depend
directly on inputs all around) is solved only over time, one substitution per step. This
algorithm repeats the step of every loop, from the FMUs' states saved at its start
(``fmi2GetFMUstate``/``fmi2SetFMUstate``), until the inputs each member stepped with equal (to a
tolerance) the inputs the members' new outputs give: a fixed-point (Picard) iteration of the
Gauss-Seidel sweep on the loop's inputs [1]_, the "iterative" scheme of the co-simulation
literature [2]_. Components outside loops step once, as in Gauss-Seidel.

Convergence test, on the vector ``u`` of the loop members' connected inputs (every type)::

    |u_new - u_used| <= atol + rtol * |u_new|      element by element

where ``u_used`` is what the members stepped with in this sweep and ``u_new`` is what a transfer
from their new outputs gives. A sweep that meets it ends the step; after ``max_iterations``
sweeps without it the run fails with :class:`~.errors.CouplingError`, naming the loop, the time and
the input furthest from the tolerance. The iteration converges when the loop gain of the sweep is
below 1 (a contraction); otherwise no tolerance is met and the error says so.

References
----------
.. [1] Kübler, R. and Schiehlen, W., "Two methods of simulator coupling", Mathematical and Computer
   Modelling of Dynamical Systems 6(2), 2000, pp. 93-113.
.. [2] Gomes, C. et al., "Co-simulation: a survey", ACM Computing Surveys 51(3), 2018, section 4.3.
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ConfigurationError, CouplingError
from .algorithm import Coupling, GaussSeidel, StepOrder

RTOL = 1e-8  #: default relative tolerance on the loop inputs [-]
ATOL = 1e-10  #: default absolute tolerance on the loop inputs, in the inputs' units
MAX_ITERATIONS = 50  #: default sweeps per macro step and loop


class IterativeGaussSeidel(GaussSeidel):
    """Gauss-Seidel with every loop iterated to a consistent coupling within each macro step.

    Parameters
    ----------
    multiples : Sequence[int]
        Step multiple per component; members of a loop must step every macro step (1).
    order : StepOrder
        The Gauss-Seidel order, with its loops (``order.cycles``).
    names : Sequence[str]
        Component names, for messages.
    input_names : Sequence[Sequence[str]]
        Per component, ``component.variable`` of each connected input, in the order of
        ``Coupling.inputs_of`` (Real, then Integer, then Boolean), for messages.
    rtol, atol : float
        Tolerances of the convergence test (see the module docstring).
    max_iterations : int
        Sweeps per macro step and loop before :class:`~.errors.CouplingError`.
    """

    name = "gauss-seidel-iterative"

    def __init__(self, multiples: Sequence[int], order: StepOrder, names: Sequence[str],
                 input_names: Sequence[Sequence[str]] = (), rtol: float = RTOL, atol: float = ATOL,
                 max_iterations: int = MAX_ITERATIONS) -> None:
        super().__init__(multiples, order)
        for cycle in order.cycles:
            stepped = [names[i] for i in cycle if self.multiples[i] != 1]
            if stepped:
                raise ConfigurationError(f"algorithm {self.name}: {', '.join(stepped)} in the loop "
                                         f"{' -> '.join(names[i] for i in cycle)} must step every macro step "
                                         "(step multiple 1) to be iterated")
        if not (rtol >= 0 and atol >= 0 and rtol + atol > 0 and max_iterations >= 1):
            raise ConfigurationError(f"algorithm {self.name}: tolerances must be >= 0, not both 0, and "
                                     f"max_iterations >= 1 (got rtol {rtol}, atol {atol}, {max_iterations})")
        self.names = tuple(names)
        self.input_names = tuple(tuple(x) for x in input_names)
        self.rtol, self.atol, self.max_iterations = rtol, atol, max_iterations
        in_cycle = {i: c for c in order.cycles for i in c}
        # The stepping plan: runs of components outside loops (swept once, as in Gauss-Seidel) and each
        # loop once, at the place of its first member.
        plan: list[tuple[bool, tuple[int, ...]]] = []  # (is a loop, components)
        for i in order.order:
            if i not in in_cycle:
                if plan and not plan[-1][0]:
                    plan[-1] = (False, plan[-1][1] + (i,))
                else:
                    plan.append((False, (i,)))
            elif in_cycle[i][0] == i:
                plan.append((True, in_cycle[i]))
        self.plan = tuple(plan)
        self.iterations: list[int] = []  # sweeps of the last macro step, per loop (for tests and reports)

    def step(self, coupling: Coupling, k: int) -> None:
        self.iterations = []
        for is_loop, components in self.plan:
            if is_loop:
                self.iterations.append(self._iterate(coupling, components, k))
            else:
                self.sweep(coupling, k, components)
        if coupling.observed:
            coupling.transfer_all()

    def _iterate(self, coupling: Coupling, cycle: tuple[int, ...], k: int) -> int:
        """Sweep the loop until its inputs are consistent; returns the number of sweeps."""
        for i in cycle:
            coupling.save_state(i)
        used = [np.empty(0)] * len(cycle)
        worst = (0.0, "")
        for sweep in range(1, self.max_iterations + 1):
            if sweep > 1:
                for i in cycle:
                    coupling.restore_state(i)
            for p, i in enumerate(cycle):
                coupling.transfer_to(i)
                used[p] = np.concatenate([v.astype(np.float64) for v in coupling.inputs_of(i)])
                coupling.advance(i, k)
            worst, worst_excess = (0.0, ""), 0.0
            for p, i in enumerate(cycle):
                coupling.transfer_to(i)
                new = np.concatenate([v.astype(np.float64) for v in coupling.inputs_of(i)])
                change = np.abs(new - used[p])
                excess = np.nan_to_num(change - (self.atol + self.rtol * np.abs(new)), nan=np.inf)  # NaN never agrees
                if excess.size and excess.max() > worst_excess:
                    j = int(excess.argmax())
                    label = self.input_names[i][j] if i < len(self.input_names) and j < len(
                        self.input_names[i]) else f"{self.names[i]} input {j}"
                    worst, worst_excess = (float(change[j]), label), float(excess[j])
            if not worst[1]:
                return sweep
        loop = " -> ".join(self.names[i] for i in cycle)
        raise CouplingError(f"algorithm {self.name}: the loop {loop} did not converge in {self.max_iterations} "
                            f"sweeps in the step from t = {coupling.time_at(k):g} s (largest change "
                            f"{worst[0]:.3g} at {worst[1]}; "
                            f"tolerance {self.atol:g} + {self.rtol:g} x |value|): the loop gain is 1 or more, "
                            "or the tolerance is tighter than the FMUs' own accuracy")
