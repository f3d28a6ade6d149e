"""Duct: adiabatic total-pressure loss dPt/Pt.

    Pt_out = Pt_in (1 - dPqP),  Tt_out = Tt_in,  W_out = W_in.

At design the loss is a parameter; off-design it scales with the inlet
corrected flow squared (dPqP = dPqP_des (Wc/Wc_des)^2), the usual law for a
duct of fixed geometry at nearly constant loss coefficient.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.9
(duct pressure loss and its scaling with corrected flow squared).
"""

from __future__ import annotations

from .errors import OutOfRangeError
from .flow import FlowStation

__all__ = ["duct", "scaled_loss"]


def duct(fs: FlowStation, dPqP: float) -> FlowStation:
    """Exit station of a duct with relative total-pressure loss `dPqP` [-] in [0, 1)."""
    if not (0.0 <= dPqP < 1.0):
        raise OutOfRangeError(f"duct: dPqP={dPqP!r} is outside the valid range [0, 1)")
    return fs.with_Pt(fs.Pt_Pa * (1.0 - dPqP))


def scaled_loss(dPqP_design: float, Wc_kg_s: float, Wc_design_kg_s: float) -> float:
    """Off-design relative pressure loss [-]: dPqP_design (Wc/Wc_design)^2, capped below 0.5."""
    return min(dPqP_design * (Wc_kg_s / Wc_design_kg_s) ** 2, 0.5)
