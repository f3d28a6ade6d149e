"""Battery pack: the Tremblay-Dessaint generic equivalent circuit, scaled from one cell to a pack.

Cell terminal voltage, with the extracted charge ``it`` [Ah], the current ``i`` [A] (> 0 discharging)
and the filtered current ``i*`` (first order, time constant ``tau``)::

    discharge (i* >= 0):  V = E0 - R i - K Q/(Q - it) (it + i*) + A exp(-B it)
    charge    (i* <  0):  V = E0 - R i - K Q/(Q - it) it - K Q/(it + 0.1 Q) i* + A exp(-B it)

(Tremblay & Dessaint 2009, eqs. 1-2, their Li-ion model). A pack of ``n_s`` cells in series and ``n_p``
strings in parallel has every voltage times ``n_s``, charge and current times ``n_p``; the model is
evaluated per cell with the pack current divided by ``n_p``.

A step of length ``dt`` holds the current constant; the power the pack delivers in the step is
``V i`` with ``V`` at the step's end state-independent part: given the requested power ``P`` [W] the
current solves ``P = (V0 - R_s i) i`` where ``V0`` (the voltage at zero current, with ``i*`` and ``it``
of the step's start) and ``R_s`` (the ohmic resistance) are known, so ``P = V i`` holds exactly and the
delivered energy is the sum of ``V i dt``.

Limits (battery management): discharge current at most ``I_discharge_max`` per cell, charge current at
most ``I_charge_max``; the terminal voltage never below ``V_cutoff`` or above ``V_full`` per cell; the
state of charge held in ``[soc_min, soc_max]``: in a step the current is cut so that the SOC at its end
lies exactly on the limit, never beyond (no overshoot).

References
----------
O. Tremblay, L.-A. Dessaint, "Experimental Validation of a Battery Dynamic Model for EV Applications",
World Electric Vehicle Journal 3 (2009) 289-298, doi:10.3390/wevj3020289.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .params import CELL_FILE, CellParams, PackParams, load_section

__all__ = ["BatteryState", "BatteryPack", "cell_voltage", "default_cell"]


def default_cell() -> CellParams:
    """The A123 ANR26650M1 cell with Tremblay & Dessaint's parameters (``data/a123_anr26650m1.yaml``)."""
    return load_section(CellParams, "cell", CELL_FILE)


def cell_voltage(c: CellParams, it_Ah: float, i_A: float, i_filt_A: float) -> float:
    """Terminal voltage of one cell [V] (Tremblay & Dessaint 2009, eqs. 1-2).

    Parameters
    ----------
    c : CellParams
        Cell parameters.
    it_Ah : float
        Extracted charge [Ah], 0 full.
    i_A, i_filt_A : float
        Current and filtered current [A], > 0 discharging.
    """
    Q = c.Q_Ah
    it = min(it_Ah, Q * (1.0 - 1e-9))
    pol = c.K_V_Ah * Q / (Q - it)
    v = c.E0_V - c.R_ohm * i_A - pol * it + c.A_V * math.exp(-c.B_1_Ah * it)
    if i_filt_A >= 0.0:
        return v - pol * i_filt_A
    return v - c.K_V_Ah * Q / (it + 0.1 * Q) * i_filt_A


@dataclass(frozen=True)
class BatteryState:
    """State of the pack after a step.

    Attributes
    ----------
    soc : float
        State of charge, 1 - it/Q [-].
    V_V, I_A, P_W : float
        Terminal voltage [V], current (> 0 discharging) [A], power delivered [W] over the last step.
    limited : bool
        The last step's request was cut by a current, voltage or SOC limit.
    """

    soc: float
    V_V: float
    I_A: float
    P_W: float
    limited: bool


class BatteryPack:
    """``n_series`` x ``n_parallel`` cells of the Tremblay-Dessaint model with battery-management limits.

    Parameters
    ----------
    pack : PackParams
        Layout, initial SOC and SOC limits.
    cell : CellParams, optional
        Cell data; default :func:`default_cell`.
    """

    def __init__(self, pack: PackParams, cell: CellParams | None = None) -> None:
        self.pack = pack
        self.cell = cell if cell is not None else default_cell()
        self.it_Ah = (1.0 - pack.soc0) * self.cell.Q_Ah  # per cell
        self.i_filt_A = 0.0  # per cell
        self.state = BatteryState(pack.soc0, self.V_oc_V, 0.0, 0.0, False)

    # -- pack figures
    @property
    def capacity_Ah(self) -> float:
        """Pack capacity [Ah]."""
        return self.cell.Q_Ah * self.pack.n_parallel

    @property
    def energy_nominal_J(self) -> float:
        """Nominal energy: capacity times nominal voltage [J]."""
        return self.capacity_Ah * 3600.0 * self.cell.V_nominal_V * self.pack.n_series

    @property
    def mass_kg(self) -> float:
        """Pack mass: cells times the pack mass factor [kg]."""
        return self.cell.mass_kg * self.pack.n_series * self.pack.n_parallel * self.pack.pack_mass_factor

    @property
    def soc(self) -> float:
        """State of charge [-]."""
        return 1.0 - self.it_Ah / self.cell.Q_Ah

    @property
    def V_oc_V(self) -> float:
        """Pack voltage at zero current with the present filtered current [V]."""
        return self.pack.n_series * cell_voltage(self.cell, self.it_Ah, 0.0, self.i_filt_A)

    # -- limits
    def current_limits_A(self, dt_s: float) -> tuple[float, float]:
        """Pack current range ``(lo, hi)`` [A] over a step of ``dt_s``: lo <= 0 charging, hi >= 0 discharging.

        From the cell's current limits, the SOC limits (the SOC at the step's end on the limit at most)
        and the voltage limits (terminal voltage at most ``V_full`` charging, at least ``V_cutoff``
        discharging, with the ohmic drop of the current itself).
        """
        c, p = self.cell, self.pack
        npar = p.n_parallel
        hi = c.I_discharge_max_A
        lo = -c.I_charge_max_A
        # SOC: it_end = it + i dt / 3600 must lie within [(1 - soc_max) Q, (1 - soc_min) Q]
        hi = min(hi, max(0.0, ((1.0 - p.soc_min) * c.Q_Ah - self.it_Ah) * 3600.0 / dt_s))
        lo = max(lo, min(0.0, ((1.0 - p.soc_max) * c.Q_Ah - self.it_Ah) * 3600.0 / dt_s))
        v0 = cell_voltage(c, self.it_Ah, 0.0, self.i_filt_A)
        if c.R_ohm > 0.0:
            hi = min(hi, max(0.0, (v0 - c.V_cutoff_V) / c.R_ohm))
            lo = max(lo, min(0.0, (v0 - c.V_full_V) / c.R_ohm))
        return lo * npar, hi * npar

    def power_limits_W(self, dt_s: float) -> tuple[float, float]:
        """Pack power range ``(lo, hi)`` [W] over a step: lo <= 0 charging, hi >= 0 discharging."""
        lo_A, hi_A = self.current_limits_A(dt_s)
        return self._power(lo_A), self._power(hi_A)

    def _power(self, I_A: float) -> float:
        """Pack power at pack current ``I_A`` with the present state [W]."""
        n = self.pack.n_parallel
        return self.pack.n_series * cell_voltage(self.cell, self.it_Ah, I_A / n, self.i_filt_A) * I_A

    def current_for_power_A(self, P_W: float) -> float:
        """Pack current delivering ``P_W`` (> 0 discharging) at the present state [A]; the smaller root of
        ``P = (V0 - R i) i``; ``nan`` where ``P`` exceeds the largest deliverable ``V0^2 / (4 R)``."""
        ns, npar = self.pack.n_series, self.pack.n_parallel
        V0 = self.V_oc_V
        R = self.cell.R_ohm * ns / npar
        if R == 0.0:
            return P_W / V0
        disc = V0 * V0 - 4.0 * R * P_W
        if disc < 0.0:
            return math.nan
        return 2.0 * P_W / (V0 + math.sqrt(disc))  # = (V0 - sqrt(disc)) / (2 R), without cancellation

    # -- step
    def step(self, P_W: float, dt_s: float) -> BatteryState:
        """Deliver ``P_W`` (> 0 discharging, < 0 charging) for ``dt_s``, cut to the limits.

        Returns the new state; ``state.P_W`` is the power delivered, ``V I`` exactly.
        """
        lo_P, hi_P = self.power_limits_W(dt_s)
        P = min(max(P_W, lo_P), hi_P)
        limited = abs(P - P_W) > 1e-9 * max(abs(P_W), 1.0)  # beyond the round-off of the bus balance
        I = self.current_for_power_A(P)
        lo_A, hi_A = self.current_limits_A(dt_s)
        if not math.isfinite(I) or I > hi_A or I < lo_A:  # round-off at a limit: take the limit's current
            I = min(max(I if math.isfinite(I) else hi_A, lo_A), hi_A)
        n = self.pack.n_parallel
        V = self.pack.n_series * cell_voltage(self.cell, self.it_Ah, I / n, self.i_filt_A)
        P = V * I
        # state update: coulomb counting (exact for a constant current) and the filtered current
        self.it_Ah += I / n * dt_s / 3600.0
        a = math.exp(-dt_s / self.cell.tau_s)
        self.i_filt_A = a * self.i_filt_A + (1.0 - a) * I / n
        self.state = BatteryState(self.soc, V, I, P, limited)
        return self.state
