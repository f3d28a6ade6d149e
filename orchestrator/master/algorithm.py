"""Master algorithms: fixed-step Jacobi and Gauss-Seidel, with per-component step multiples.

A component with step multiple ``n`` steps at macro steps ``k`` with ``k % n == 0``
over ``n`` macro steps, and its outputs are read when it reaches the end of that
interval (``(k + 1) % n == 0``), as libcosim does with its decimation factors.

Gauss-Seidel steps components one after the other in an order derived from the
connection graph: strongly connected components (Tarjan) in topological order;
inside a cycle, the component with the fewest inputs still waiting goes first,
ties broken by declaration order in the SSD. The connections that then carry
values of the previous step (the ones that break the cycles) are reported.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..ssp.system_model import BoundSystem


@dataclass(frozen=True)
class StepOrder:
    """A Gauss-Seidel order and the connections that lag one step in it.

    Attributes
    ----------
    order : tuple[int, ...]
        Component indices in stepping order.
    lagging : tuple[tuple[int, int], ...]
        (source, target) pairs whose values come from the previous macro step.
    cycles : tuple[tuple[int, ...], ...]
        The strongly connected sets of more than one component (the loops), each in stepping order.
    """

    order: tuple[int, ...]
    lagging: tuple[tuple[int, int], ...]
    cycles: tuple[tuple[int, ...], ...] = ()


def _strongly_connected(n: int, edges: dict[int, list[int]]) -> list[list[int]]:
    """Tarjan's algorithm; returns the components in reverse topological order."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[int] = []
    result: list[list[int]] = []
    counter = 0

    def visit(v: int) -> None:
        nonlocal counter
        index[v] = low[v] = counter
        counter += 1
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, []):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            scc: list[int] = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                scc.append(w)
                if w == v:
                    break
            result.append(sorted(scc))

    for v in range(n):
        if v not in index:
            visit(v)
    return result


def gauss_seidel_order(n: int, connections: Sequence[tuple[int, int]]) -> StepOrder:
    """Derive a deterministic stepping order from ``(source, target)`` component pairs."""
    edges: dict[int, list[int]] = {}
    preds: dict[int, set[int]] = {i: set() for i in range(n)}
    for s, t in connections:
        if s != t:
            edges.setdefault(s, []).append(t)
            preds[t].add(s)
    for v in edges.values():
        v.sort()
    # Topological order of the condensation, ties broken by the smallest member index.
    sccs = list(reversed(_strongly_connected(n, edges)))
    scc_of = {v: i for i, scc in enumerate(sccs) for v in scc}
    indeg = {i: 0 for i in range(len(sccs))}
    cedges: dict[int, set[int]] = {i: set() for i in range(len(sccs))}
    for s, targets in edges.items():
        for t in targets:
            a, b = scc_of[s], scc_of[t]
            if a != b and b not in cedges[a]:
                cedges[a].add(b)
                indeg[b] += 1
    ready = sorted((min(sccs[i]), i) for i in indeg if indeg[i] == 0)
    order: list[int] = []
    cycles: list[tuple[int, ...]] = []
    while ready:
        _, i = ready.pop(0)
        done: set[int] = set(order)
        members = set(sccs[i])
        first = len(order)
        while members:  # inside a cycle: fewest waiting inputs first, then declaration order
            nxt = min(members, key=lambda v: (len((preds[v] & members) - done), v))
            order.append(nxt)
            done.add(nxt)
            members.discard(nxt)
        if len(sccs[i]) > 1:
            cycles.append(tuple(order[first:]))
        for j in sorted(cedges[i]):
            indeg[j] -= 1
            if indeg[j] == 0:
                ready.append((min(sccs[j]), j))
                ready.sort()
    position = {v: p for p, v in enumerate(order)}
    lagging = tuple(sorted({(s, t) for s, t in connections if s != t and position[s] > position[t]}))
    return StepOrder(tuple(order), lagging, tuple(cycles))


def step_order(system: BoundSystem) -> StepOrder:
    """The Gauss-Seidel order of a bound system, from its connections alone (no FMU is loaded)."""
    return gauss_seidel_order(len(system.components), [(ln.source, ln.target) for ln in system.links])


class Coupling(Protocol):
    """What an algorithm needs from the execution: stepping, I/O and transfers per component.

    ``set_inputs`` and ``advance`` apply the input modifiers (scenarios) themselves, so an
    algorithm need not know about them. ``save_state``, ``restore_state`` and ``inputs_of``
    serve algorithms that repeat a step (FMI 2.0 ``fmi2GetFMUstate``/``fmi2SetFMUstate``).
    """

    def step_component(self, i: int, k: int) -> None: ...
    def get_outputs(self, i: int) -> None: ...
    def set_inputs(self, i: int) -> None: ...
    def transfer_to(self, i: int) -> None: ...
    def transfer_all(self) -> None: ...
    def advance(self, i: int, k: int) -> None: ...
    def save_state(self, i: int) -> None: ...
    def restore_state(self, i: int) -> None: ...
    def inputs_of(self, i: int) -> list[np.ndarray]: ...
    def time_at(self, k: int) -> float: ...
    @property
    def observed(self) -> bool: ...


class Algorithm:
    """Base class: one macro step ``k`` (from ``t0 + k h`` to ``t0 + (k + 1) h``).

    An algorithm owns stepping and transfer; the execution owns time. A new algorithm subclasses
    this, defines ``name`` and ``step``, and is registered in :mod:`.algorithm_registry`.
    """

    name = "base"

    def __init__(self, multiples: Sequence[int]) -> None:
        self.multiples = tuple(multiples)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(multiples={list(self.multiples)})"

    def step(self, coupling: Coupling, k: int) -> None:
        """Advance every component due at macro step ``k``; subclasses define the order."""
        raise NotImplementedError(f"{type(self).__name__} does not define a step")


class Jacobi(Algorithm):
    """All components step from the same input values, then all outputs are exchanged."""

    name = "jacobi"

    def step(self, coupling: Coupling, k: int) -> None:
        # Outputs are read only by the exchange at the end, so a component's outputs can be
        # got right after its own step.
        m = self.multiples
        for i, n in enumerate(m):
            if n == 1:
                coupling.advance(i, k)
                continue
            if k % n == 0:
                coupling.set_inputs(i)
                coupling.step_component(i, k)
            if (k + 1) % n == 0:
                coupling.get_outputs(i)
        coupling.transfer_all()


class GaussSeidel(Algorithm):
    """Components step in order, each taking the newest outputs of those before it."""

    name = "gauss-seidel"

    def __init__(self, multiples: Sequence[int], order: StepOrder) -> None:
        super().__init__(multiples)
        self.order = order

    def step(self, coupling: Coupling, k: int) -> None:
        self.sweep(coupling, k, self.order.order)
        # Inputs as seen at the new time, so observers record them consistently with the outputs
        # (each component takes its own inputs again before its next step).
        if coupling.observed:
            coupling.transfer_all()

    def sweep(self, coupling: Coupling, k: int, components: Sequence[int]) -> None:
        """Step ``components`` one after the other, each taking the newest outputs of those before it."""
        m = self.multiples
        for i in components:
            n = m[i]
            if n == 1:  # the usual case: take inputs, step, publish outputs in one go
                coupling.transfer_to(i)
                coupling.advance(i, k)
                continue
            if k % n == 0:
                coupling.transfer_to(i)
                coupling.set_inputs(i)
                coupling.step_component(i, k)
            if (k + 1) % n == 0:
                coupling.get_outputs(i)
