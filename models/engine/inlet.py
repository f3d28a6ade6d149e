"""Inlet: total-pressure recovery from the free stream (0) to the fan face (2).

The inlet is adiabatic (Tt2 = Tt0) and loses total pressure:

    Pt2 = Pt0 * pi_d * eta_r(M0),

with pi_d the inlet's own (subsonic, friction and distortion) recovery at
design, a parameter, and eta_r the shock recovery of MIL-E-5008B:

    eta_r = 1                                for M0 <= 1,
    eta_r = 1 - 0.075 (M0 - 1)^1.35          for 1 < M0 <= 5.

The ram drag W0 V0 is booked by the engine (:mod:`.cycle_design`), not here.

References
----------
MIL-E-5008B, "Engines, Aircraft, Turbojet and Turbofan; Model Specification
for", U.S. Department of Defense, 1959 (ram recovery standard).
J. D. Mattingly, W. H. Heiser, D. T. Pratt, "Aircraft Engine Design", 2nd ed.,
AIAA, 2002, eq. (4.12a-b) (the same law, quoted as eta_R,spec).
"""

from __future__ import annotations

from .errors import OutOfRangeError
from .flow import FlowStation
from .jit_kernels import jit

__all__ = ["ram_recovery_mil_e_5008b", "ram_recovery", "inlet"]


@jit
def ram_recovery(Mach: float) -> float:
    """eta_r [-] of MIL-E-5008B at Mach [-] (no range check): the one implementation, compiled into the free
    stream (:mod:`.jit_freestream`) and called by :func:`ram_recovery_mil_e_5008b`."""
    return 1.0 if Mach <= 1.0 else 1.0 - 0.075 * (Mach - 1.0) ** 1.35


def ram_recovery_mil_e_5008b(Mach: float) -> float:
    """Shock total-pressure recovery eta_r [-] of MIL-E-5008B at flight Mach `Mach` [-], 0 to 5."""
    if not (0.0 <= Mach <= 5.0):
        raise OutOfRangeError(f"inlet.ram_recovery_mil_e_5008b: Mach={Mach!r} is outside the valid range 0 to 5")
    return float(ram_recovery(Mach))


def inlet(fs0: FlowStation, Mach: float, pi_design: float = 1.0) -> FlowStation:
    """Fan-face station 2 from the free stream 0.

    Parameters
    ----------
    fs0 : FlowStation
        Free-stream totals and the engine's air flow.
    Mach : float
        Flight Mach number [-].
    pi_design : float
        Inlet pressure recovery without shocks Pt2/Pt0 [-], in (0, 1].

    Returns
    -------
    FlowStation
        Station 2: same W, Tt, FAR; Pt2 = Pt0 pi_design eta_r(Mach).
    """
    if not (0.0 < pi_design <= 1.0):
        raise OutOfRangeError(f"inlet: pi_design={pi_design!r} is outside the valid range (0, 1]")
    return fs0.with_Pt(fs0.Pt_Pa * pi_design * ram_recovery_mil_e_5008b(Mach))
