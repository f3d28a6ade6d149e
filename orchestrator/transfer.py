"""Transfers: copying connected outputs to inputs, with the connection's conversion applied."""
from __future__ import annotations

import numpy as np


class Transfer:
    """Copy a contiguous range of inputs of one type from their sources, converting on the way.

    A range of more than ``SMALL`` inputs is one ``take`` (a bound method, looked
    up once); Real connections with a transformation or unit conversion add one
    multiply and one add over the range. A small range (the usual case for one
    component in Gauss-Seidel) is copied element by element, which costs less than
    numpy's call overhead. Mapped Boolean/Integer/Enumeration connections are
    looked up one by one.
    """

    SMALL = 4
    __slots__ = ("_take", "_idx", "_inputs", "_scale", "_offset", "_mapped", "_pairs", "_outputs")

    def __init__(self, outputs: np.ndarray, idx: np.ndarray, inputs: np.ndarray, scale: np.ndarray,
                 offset: np.ndarray, mapped: list[tuple[int, dict[int, int]]]) -> None:
        self._outputs = outputs
        self._take = outputs.take
        self._idx = idx
        self._inputs = inputs
        identity = bool(np.all(scale == 1.0) and np.all(offset == 0.0))
        self._scale = None if identity else scale
        self._offset = None if identity else offset
        self._mapped = mapped
        self._pairs = None
        if len(idx) <= self.SMALL:
            self._pairs = [(j, int(src), float(scale[j]), float(offset[j])) for j, src in enumerate(idx)]

    def __call__(self) -> None:
        inputs = self._inputs
        if self._pairs is not None:
            outputs = self._outputs
            if self._scale is None:
                for j, src, _, _ in self._pairs:
                    inputs[j] = outputs[src]
            else:
                for j, src, a, b in self._pairs:
                    inputs[j] = outputs[src] * a + b
        else:
            self._take(self._idx, out=inputs)
            if self._scale is not None:
                np.multiply(inputs, self._scale, out=inputs)
                np.add(inputs, self._offset, out=inputs)
        for j, mapping in self._mapped:
            v = int(inputs[j])
            inputs[j] = mapping.get(v, v)
