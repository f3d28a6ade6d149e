"""Master algorithms with a mock coupling: step order, step multiples, time arithmetic."""
from __future__ import annotations

import pytest

from openemss.orchestrator.master.algorithm import GaussSeidel, Jacobi, gauss_seidel_order


def test_chain_is_ordered_source_first() -> None:
    order = gauss_seidel_order(3, [(2, 1), (1, 0)])
    assert order.order == (2, 1, 0) and order.lagging == ()


def test_two_component_cycle_is_broken_deterministically() -> None:
    a = gauss_seidel_order(2, [(0, 1), (1, 0)])
    b = gauss_seidel_order(2, [(1, 0), (0, 1)])
    assert a == b
    assert a.order == (0, 1) and a.lagging == ((1, 0),)


def test_cycle_member_with_fewest_waiting_inputs_goes_first() -> None:
    # 0 <-> 1 <-> 2 and 2 -> 0: component 1 has inputs from 0 and 2, 0 from 1 and 2, 2 only from 1
    order = gauss_seidel_order(3, [(0, 1), (1, 0), (1, 2), (2, 1), (2, 0)])
    assert order.order[0] == 2
    # every connection is either satisfied in the step or listed as lagging
    pos = {c: i for i, c in enumerate(order.order)}
    for s, t in [(0, 1), (1, 0), (1, 2), (2, 1), (2, 0)]:
        assert (pos[s] < pos[t]) != ((s, t) in order.lagging)


def test_independent_parts_and_feedthrough_into_a_cycle() -> None:
    # 3 feeds the cycle {0, 1}; 2 is on its own; 1 feeds 4
    order = gauss_seidel_order(5, [(3, 0), (0, 1), (1, 0), (1, 4)])
    pos = {c: i for i, c in enumerate(order.order)}
    assert pos[3] < pos[0] and pos[3] < pos[1] and pos[1] < pos[4]
    assert sorted(order.order) == [0, 1, 2, 3, 4]
    assert order.lagging == ((1, 0),)


class MockCoupling:
    """Records the calls an algorithm makes."""

    observed = True

    def __init__(self) -> None:
        self.calls: list[tuple[str, int | None]] = []

    def step_component(self, i: int, k: int) -> None:
        self.calls.append(("step", i))

    def get_outputs(self, i: int) -> None:
        self.calls.append(("get", i))

    def set_inputs(self, i: int) -> None:
        self.calls.append(("set", i))

    def transfer_to(self, i: int) -> None:
        self.calls.append(("transfer", i))

    def transfer_all(self) -> None:
        self.calls.append(("transfer_all", None))

    def advance(self, i: int, k: int) -> None:
        self.calls.extend([("set", i), ("step", i), ("get", i)])


def test_jacobi_steps_all_then_exchanges() -> None:
    c = MockCoupling()
    Jacobi([1, 1]).step(c, 0)
    # each component steps from the inputs of the last exchange; nothing is exchanged before all stepped
    assert c.calls == [("set", 0), ("step", 0), ("get", 0), ("set", 1), ("step", 1), ("get", 1),
                       ("transfer_all", None)]


def test_gauss_seidel_takes_new_outputs_in_order() -> None:
    c = MockCoupling()
    GaussSeidel([1, 1], gauss_seidel_order(2, [(1, 0), (0, 1)])).step(c, 0)
    assert c.calls[:8] == [("transfer", 0), ("set", 0), ("step", 0), ("get", 0),
                           ("transfer", 1), ("set", 1), ("step", 1), ("get", 1)]


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_step_multiple_steps_every_nth_and_publishes_at_the_end_of_its_step(algorithm: str) -> None:
    multiples = [1, 3]
    alg = Jacobi(multiples) if algorithm == "jacobi" else GaussSeidel(multiples, gauss_seidel_order(2, []))
    steps, gets = [], []
    for k in range(9):
        c = MockCoupling()
        alg.step(c, k)
        steps.append([i for kind, i in c.calls if kind == "step"])
        gets.append([i for kind, i in c.calls if kind == "get"])
    assert [1 in s for s in steps] == [True, False, False] * 3
    assert [1 in g for g in gets] == [False, False, True] * 3
    assert all(0 in s and 0 in g for s, g in zip(steps, gets, strict=False))
