"""Transfers: copying connected outputs to inputs, with the connection's conversion applied."""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Segment:
    """A contiguous range of inputs of one FMI type and where each takes its value from.

    ``inputs[j] = outputs[source_index[j]] * scale[j] + offset[j]``, then, for every ``(j, mapping)``
    in ``mapped``, ``inputs[j] = mapping.get(inputs[j], inputs[j])`` (Boolean/Integer/Enumeration maps).
    """

    outputs: np.ndarray
    source_index: np.ndarray
    inputs: np.ndarray
    scale: np.ndarray
    offset: np.ndarray
    mapped: tuple[tuple[int, dict[int, int]], ...] = ()


class Transfer:
    """Copy one or more segments (one per FMI type) from their sources, converting on the way.

    Few plain inputs (at most ``SMALL``, none mapped: the usual case for one component in
    Gauss-Seidel) are copied element by element across all segments in one loop, which costs
    less than numpy's call overhead per type. Otherwise a segment of more than ``SMALL_RANGE``
    inputs is one ``take`` (a bound method, looked up once), plus one multiply and one add when a
    Real connection has a transformation or unit conversion; a shorter one is copied element by
    element. Mapped Boolean/Integer/Enumeration inputs are then looked up one by one.
    """

    SMALL = 8
    SMALL_RANGE = 4
    __slots__ = ("_pairs", "_ranges")

    def __init__(self, segments: Sequence[Segment]) -> None:
        segments = [s for s in segments if len(s.inputs)]
        pairs = [(s.inputs, j, s.outputs, int(src),
                  None if s.scale[j] == 1.0 and s.offset[j] == 0.0 else (float(s.scale[j]), float(s.offset[j])))
                 for s in segments for j, src in enumerate(s.source_index)]
        self._pairs: list[tuple[np.ndarray, int, np.ndarray, int, tuple[float, float] | None]] | None = None
        self._ranges: list[tuple[object, ...]] = []
        if len(pairs) <= self.SMALL and not any(s.mapped for s in segments):
            self._pairs = pairs
            return
        for s in segments:
            identity = bool(np.all(s.scale == 1.0) and np.all(s.offset == 0.0))
            small = None
            if len(s.source_index) <= self.SMALL_RANGE:
                small = [(j, int(src), float(s.scale[j]), float(s.offset[j])) for j, src in enumerate(s.source_index)]
            self._ranges.append((s.outputs.take, s.source_index, s.inputs, None if identity else s.scale,
                                 None if identity else s.offset, small, s.outputs, s.mapped))

    def __call__(self) -> None:
        pairs = self._pairs
        if pairs is not None:
            for inputs, j, outputs, src, linear in pairs:
                inputs[j] = outputs[src] if linear is None else outputs[src] * linear[0] + linear[1]
            return
        for take, idx, inputs, scale, offset, small, outputs, mapped in self._ranges:
            if small is not None:
                if scale is None:
                    for j, src, _, _ in small:
                        inputs[j] = outputs[src]
                else:
                    for j, src, a, b in small:
                        inputs[j] = outputs[src] * a + b
            else:
                take(idx, out=inputs)
                if scale is not None:
                    np.multiply(inputs, scale, out=inputs)
                    np.add(inputs, offset, out=inputs)
            for j, mapping in mapped:
                v = int(inputs[j])
                inputs[j] = mapping.get(v, v)
