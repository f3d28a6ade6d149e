"""Fuel controller: thrust lever to fuel-flow command, with Tt41 and N1 limiting.

The law of SPEC.md, stated exactly:

1. Demand. The thrust lever delta in [0, 1] gives the corrected fan speed demand
   ``N1c_dem = k_delta * delta`` [%], never below the flight-idle setting:
   ``N1c_dem = max(k_delta * delta, N1c_idle)``. Idle is a corrected speed (as the
   idle of a real FADEC is a scheduled speed, not a fuel flow), so the engine is
   held at the bottom of its running range at every altitude instead of being
   starved below it; Wf_min stays as the lean blow-out floor of the command.
2. Three regulators, each an incremental (velocity-form) PI computing a fuel-flow
   change per controller step from its own error::

       demand:  e_D = N1c_dem - N1c  [%]   dWf_D = kp   (e_D - e_D,prev) + ki   dt e_D
       Tt41:    e_T = Tt41_max - Tt41 [K]  dWf_T = kp_T (e_T - e_T,prev) + ki_T dt e_T
       N1:      e_N = N1_max - N1     [%]  dWf_N = kp_N (e_N - e_N,prev) + ki_N dt e_N

3. Limiting by min-select: ``dWf = min(dWf_D, dWf_T, dWf_N)``. Far below its limit
   a limiter asks for a large increase and is never the smallest; as Tt41 or N1
   approaches its limit its regulator's request falls below the demand's, it
   takes over, and it holds the limited quantity at the limit with zero steady
   error (integral action). So the N1c demand is limited to what the engine can
   run at Tt41_max or N1_max; the reported ``N1c_lim_pct`` is the measured N1c
   while a limiter is selected.
4. Fuel-flow step. The selected change is clipped to +-stp_max per controller
   step, and the command to [Wf_min, Wf_max]::

       Wf_k = clip(Wf_{k-1} + clip(dWf, -stp_max, +stp_max), Wf_min, Wf_max)

Why rate-limited PIs rather than ``Wf += stp_max * sign(e)``: the sign law never
settles -- it chatters +-stp_max around the demand at every step, which shows in
Tt4 and thrust traces and in fuel burn -- whereas the PIs reach zero error, and for
large errors the demand PI *is* the sign law (the clip binds), so SPEC.md's "steps
of at most stp_max toward the demand" holds in every case. Why a min-select of
increments: each limit gets a regulator tuned to its own dynamics (Tt41 answers a
fuel change at once, ~3600 K per kg/s at constant spool speeds on the Larzac-sized
engine: an integral-only regulator suits it; N1 follows the spool), switching is
bumpless because the state is Wf itself, and no integrator winds up against the
limits.

One call of :meth:`FuelController.step` is one controller step: stp_max is per
call, so the slew rate is stp_max/dt.

References
----------
H. Richter, "Advanced Control of Turbofan Engines", Springer, 2012, ch. 1 and 6
(min-max selection of limit regulators, incremental PI).
L. C. Jaw, J. D. Mattingly, "Aircraft Engine Controls", AIAA, 2009, ch. 5.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..infra.jit import jitable
from ..infra.records import fast_init
from .errors import ParameterError
from .tunable import Tunable, field_index, load_params

__all__ = ["FuelControlParams", "FuelControlOutput", "FuelController", "FUEL_LIMITERS", "fuel_law"]

PARAM_FILE = "fuel_control.yaml"


@dataclass(frozen=True, slots=True)
class FuelControlParams:
    """Gains and limits of the fuel controller (data/fuel_control.yaml).

    Attributes
    ----------
    k_delta_pct : float
        Corrected fan speed demand per unit thrust lever [%].
    N1c_idle_pct : float
        Flight idle: the lowest corrected fan speed demand [%].
    Tt41_max_K : float
        HP turbine rotor inlet temperature limit [K].
    N1_max_pct : float
        Fan (LP spool) mechanical speed limit [%].
    kp_kg_s_pct, ki_kg_s2_pct : float
        Demand (N1c) regulator: proportional [kg/s per %] and integral [kg/s^2 per %] gains.
    kp_T_kg_s_K, ki_T_kg_s2_K : float
        Tt41 limiter: proportional [kg/s per K] and integral [kg/s^2 per K] gains.
    kp_N1_kg_s_pct, ki_N1_kg_s2_pct : float
        N1 limiter: proportional [kg/s per %] and integral [kg/s^2 per %] gains.
    stp_max_kg_s : float
        Largest fuel-flow change per controller step [kg/s].
    Wf_min_kg_s, Wf_max_kg_s : float
        Fuel-flow command bounds [kg/s].
    """

    k_delta_pct: float
    N1c_idle_pct: float
    Tt41_max_K: float
    N1_max_pct: float
    kp_kg_s_pct: float
    ki_kg_s2_pct: float
    kp_T_kg_s_K: float
    ki_T_kg_s2_K: float
    kp_N1_kg_s_pct: float
    ki_N1_kg_s2_pct: float
    stp_max_kg_s: float
    Wf_min_kg_s: float
    Wf_max_kg_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> FuelControlParams:
        """Parameter set of ``data/fuel_control.yaml`` with optional overrides."""
        return load_params(cls, PARAM_FILE, "fuel_control", **overrides)


@fast_init
@dataclass(frozen=True, slots=True)
class FuelControlOutput:
    """Result of one fuel-controller step.

    Attributes
    ----------
    Wf_cmd_kg_s : float
        Fuel-flow command [kg/s].
    dWf_kg_s : float
        Change of the command in this step, |dWf| <= stp_max [kg/s].
    N1c_dem_pct : float
        Demand from the lever, max(k_delta * delta, N1c_idle) [%].
    N1c_lim_pct : float
        Limited demand: N1c_dem, or the measured N1c while a limiter is selected [%].
    limiter : str
        Which error was selected: ``"demand"``, ``"Tt41"`` or ``"N1"``.
    """

    Wf_cmd_kg_s: float
    dWf_kg_s: float
    N1c_dem_pct: float
    N1c_lim_pct: float
    limiter: str


class FuelController(Tunable[FuelControlParams]):
    """Thrust lever to fuel-flow command (see the module docstring for the law).

    Parameters
    ----------
    params : FuelControlParams, optional
        Parameter set; the file's values by default.
    Wf0_kg_s : float
        Initial fuel-flow command [kg/s] (bumpless start from a running engine).
    """

    tunable_name = "fuel_control"

    def __init__(self, params: FuelControlParams | None = None, Wf0_kg_s: float | None = None) -> None:
        self._params = params if params is not None else FuelControlParams.from_file()
        self._check_consistent()
        # the state of fuel_law: the command [kg/s], 1 once the errors of a step are held, those errors (N1c
        # demand [%], Tt41 [K], N1 [%])
        self._s = np.array([self._params.Wf_min_kg_s if Wf0_kg_s is None else float(Wf0_kg_s), 0.0, 0.0, 0.0, 0.0])

    def _on_parameters_changed(self) -> None:
        self._check_consistent()

    def _check_consistent(self) -> None:
        p = self._params
        if p.Wf_min_kg_s > p.Wf_max_kg_s:
            raise ParameterError(f"fuel_control: Wf_min_kg_s = {p.Wf_min_kg_s} exceeds Wf_max_kg_s = "
                                 f"{p.Wf_max_kg_s}; need Wf_min_kg_s <= Wf_max_kg_s")

    @property
    def Wf_cmd_kg_s(self) -> float:
        """Current fuel-flow command [kg/s]."""
        return float(self._s[0])

    def reset(self, Wf_kg_s: float) -> None:
        """Restart from fuel flow ``Wf_kg_s`` [kg/s] (e.g. the engine's trimmed value)."""
        self._s[:2] = (float(Wf_kg_s), 0.0)

    def step(self, dt_s: float, delta: float, N1c_pct: float, N1_pct: float, Tt41_K: float) -> FuelControlOutput:
        """One controller step.

        Parameters
        ----------
        dt_s : float
            Controller step [s].
        delta : float
            Thrust lever position [-], clipped to [0, 1].
        N1c_pct : float
            Corrected fan speed [% of design].
        N1_pct : float
            Mechanical fan speed [% of design].
        Tt41_K : float
            HP turbine rotor inlet total temperature [K].

        Returns
        -------
        FuelControlOutput
        """
        return FuelControlOutput(*self.step_values(dt_s, delta, N1c_pct, N1_pct, Tt41_K))

    def step_values(self, dt_s: float, delta: float, N1c_pct: float, N1_pct: float,
                    Tt41_K: float) -> tuple[float, float, float, float, str]:
        """:meth:`step` returning the fields of :class:`FuelControlOutput` in their order, as a tuple (the
        FCS's per-step path, which builds no records). The one implementation of the controller."""
        f = fuel_law(self.values(), self._s, dt_s, delta, N1c_pct, N1_pct, Tt41_K)
        return float(f[0]), float(f[1]), float(f[2]), float(f[3]), FUEL_LIMITERS[f[4]]


#: The regulators of :func:`fuel_law`, by its code.
FUEL_LIMITERS = ("demand", "Tt41", "N1")
#: Index of each field of FuelControlParams in :meth:`FuelController.values`.
FP = field_index(FuelControlParams)


@jitable
def fuel_law(p: np.ndarray, s: np.ndarray, dt_s: float, delta: float, N1c_pct: float, N1_pct: float,
             Tt41_K: float) -> tuple[float, float, float, float, int]:
    """One step of the controller on plain values (:meth:`FuelController.step`'s arguments): parameters ``p``
    (:meth:`FuelController.values`, indexed by :data:`FP`), the state ``s`` (updated in place: the command, the
    flag and the errors of the previous step); returns the fields of :class:`FuelControlOutput` in their order, the
    limiter as its index in :data:`FUEL_LIMITERS`. The one implementation of the controller."""
    # clip(v, lo, hi) written out as its two comparisons (as in pitch.py)
    d = 0.0 if 0.0 > delta else delta
    d = 1.0 if 1.0 < d else d
    N1c_dem = p[FP.k_delta_pct] * d
    if p[FP.N1c_idle_pct] > N1c_dem:  # max(k_delta d, N1c_idle)
        N1c_dem = p[FP.N1c_idle_pct]
    e0_, e1_, e2_ = N1c_dem - N1c_pct, p[FP.Tt41_max_K] - Tt41_K, p[FP.N1_max_pct] - N1_pct
    if s[1] == 0.0:  # the first step: no previous errors
        p0, p1, p2 = e0_, e1_, e2_
    else:
        p0, p1, p2 = s[2], s[3], s[4]
    dWf, limiter = p[FP.kp_kg_s_pct] * (e0_ - p0) + p[FP.ki_kg_s2_pct] * dt_s * e0_, 0
    d_T = p[FP.kp_T_kg_s_K] * (e1_ - p1) + p[FP.ki_T_kg_s2_K] * dt_s * e1_
    if d_T < dWf:
        dWf, limiter = d_T, 1
    d_N = p[FP.kp_N1_kg_s_pct] * (e2_ - p2) + p[FP.ki_N1_kg_s2_pct] * dt_s * e2_
    if d_N < dWf:
        dWf, limiter = d_N, 2
    stp = p[FP.stp_max_kg_s]
    dWf = -stp if -stp > dWf else dWf
    dWf = stp if stp < dWf else dWf
    # bounds, approached at the same limited rate if the command was outside them
    Wf = s[0]
    target = Wf + dWf
    target = p[FP.Wf_min_kg_s] if p[FP.Wf_min_kg_s] > target else target
    target = p[FP.Wf_max_kg_s] if p[FP.Wf_max_kg_s] < target else target
    dWf = target - Wf
    dWf = -stp if -stp > dWf else dWf
    dWf = stp if stp < dWf else dWf
    Wf_new = Wf + dWf
    s[0], s[1], s[2], s[3], s[4] = Wf_new, 1.0, e0_, e1_, e2_
    N1c_lim = N1c_dem if limiter == 0 else N1c_pct
    return Wf_new, dWf, N1c_dem, N1c_lim, limiter
