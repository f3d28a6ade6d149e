"""Splitter: divides the fan flow into core and bypass streams by the bypass ratio.

    W_core = W / (1 + BPR),   W_bypass = W BPR / (1 + BPR),

both with the total state of the entering flow (the fan's radial profile is
represented by compressing the two streams separately, :mod:`.cycle_design`).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.10.
"""

from __future__ import annotations

from .errors import OutOfRangeError
from .flow import FlowStation, split

__all__ = ["splitter"]


def splitter(fs: FlowStation, BPR: float) -> tuple[FlowStation, FlowStation]:
    """(core, bypass) streams for a bypass ratio `BPR` [-] >= 0; mass conserved exactly."""
    if not (BPR >= 0.0):
        raise OutOfRangeError(f"splitter: BPR={BPR!r} must be >= 0")
    return split(fs, 1.0 / (1.0 + BPR))
