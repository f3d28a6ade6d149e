"""Sampled signals of a run as the report reads them: increments of a rate held before its sample, and the
statistics of a Boolean flag. Shared by :mod:`.summary` and :mod:`.electric` (see :mod:`.summary` for the
convention: the value recorded at ``t[k]`` held over ``(t[k-1], t[k]]``)."""
from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["held_increments", "flag_stats"]


def held_increments(time_s: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """Integral of ``rate`` over each interval ``(t[k], t[k+1]]``, the value at ``t[k+1]`` held over it.

    Returns
    -------
    numpy.ndarray
        ``len(time_s) - 1`` increments [unit of rate times s].
    """
    return rate[1:] * np.diff(time_s)


def flag_stats(time_s: np.ndarray, flag: np.ndarray) -> dict[str, Any]:
    """How often a Boolean signal rose, when first, and for how long it was true.

    Returns
    -------
    dict
        ``count`` (rising edges; true at the first sample counts as one), ``first_time_s`` [s]
        (None if never true), ``duration_s`` [s] (intervals whose closing sample is true).
    """
    on = np.asarray(flag) > 0.5
    rises = int(on[0]) + int(np.count_nonzero(on[1:] & ~on[:-1])) if len(on) else 0
    first = float(time_s[np.argmax(on)]) if on.any() else None
    duration = float(np.sum(np.diff(time_s)[on[1:]])) if len(on) > 1 else 0.0
    return {"count": rises, "first_time_s": first, "duration_s": duration}
