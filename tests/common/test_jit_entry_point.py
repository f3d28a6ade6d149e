"""`infra.jit.entry_point`: the compiled entry point takes its types from the kernel's annotations, so that the
first call's values (an integer given for a float) do not fix the types of every later call."""
from __future__ import annotations

import numpy as np
import pytest

from openemss.models.infra.jit import AVAILABLE, entry_point, jit


@jit
def _affine(a: np.ndarray, x: float, n: int, flag: bool) -> float:
    return a[0] * x + n + (1.0 if flag else 0.0)


def _plain(a: np.ndarray, x: float, n: int, flag: bool) -> float:
    return a[0] * x + n + (1.0 if flag else 0.0)


def test_first_call_with_integers_does_not_truncate_later_floats() -> None:
    a = np.array([2.0])
    step = entry_point(_affine, (a, 1, 3, 1))  # an int for the float, an int for the bool
    for x, n, flag in ((1.7, 3, True), (-0.25, 0, False), (1e-3, -2, True), (5, 1, 0)):
        assert step(a, x, n, flag) == _plain(a, x, n, flag)  # exact: the same float operations


@pytest.mark.skipif(not AVAILABLE, reason="numba absent: entry_point returns the function itself")
def test_signature_from_annotations() -> None:
    from numba.core import types

    entry_point(_affine, (np.zeros(1), 1, 3, 1))
    assert (types.float64[::1], types.float64, types.int64, types.boolean) in _affine.overloads


def test_fcs_inner_step_parameters_are_all_annotated() -> None:
    """Every scalar parameter of the FCS's compiled step names its type, so entry_point types none of them from a
    value."""
    import inspect

    from openemss.models.fcs.inner_loops import inner_step

    fn = getattr(inner_step, "py_func", inner_step)
    for p in inspect.signature(fn).parameters.values():
        assert p.annotation in ("float", "int", "bool", "np.ndarray"), (p.name, p.annotation)


def test_wrong_number_of_arguments_is_refused() -> None:
    if not AVAILABLE:
        pytest.skip("numba absent")
    with pytest.raises(TypeError, match="positional parameters"):
        entry_point(_affine, (np.zeros(1), 1.0))


def test_not_a_kernel_is_returned_as_it_is() -> None:
    assert entry_point(_plain, (np.zeros(1), 1.0, 1, True)) is _plain
