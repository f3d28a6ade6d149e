"""Fuel controller: thrust lever to fuel-flow command, with Tt41 and N1 limiting.

The law of SPEC.md, stated exactly:

1. Demand. The thrust lever delta in [0, 1] gives the corrected fan speed demand
   ``N1c_dem = k_delta * delta`` [%].
2. Limiting. The demand is limited by the turbine-temperature and fan-speed
   limits through a *min-select* of three N1c errors [%]::

       e_dem = N1c_dem - N1c
       e_T   = g_T * (Tt41_max - Tt41)
       e_N   = g_N * (N1_max - N1)
       e     = min(e_dem, e_T, e_N)

   i.e. the limited demand is ``N1c_lim = N1c + e = min(N1c_dem, N1c + g_T
   (Tt41_max - Tt41), N1c + g_N (N1_max - N1))``. Below the limits (with margin)
   e = e_dem and the demand is untouched; when Tt41 or N1 reaches its limit,
   that error becomes the smallest and the demand is reduced in proportion to
   the exceedance (limiter gains g_T, g_N); the loop then holds the limited
   quantity at its limit with zero steady error, since the PI below integrates
   the selected error.
3. Fuel-flow step. A PI in velocity (incremental) form turns the selected
   error into a fuel-flow increment, which is clipped to +-stp_max per
   controller step::

       dWf = clip(kp (e_k - e_{k-1}) + ki dt e_k, -stp_max, +stp_max)
       Wf_k = clip(Wf_{k-1} + dWf, Wf_min, Wf_max)

Why a rate-limited PI rather than ``Wf += stp_max * sign(e)``: the sign law
never settles -- it chatters +-stp_max around the demand at every step, which
shows in Tt4 and thrust traces and in fuel burn -- whereas the velocity-form PI
reaches zero error, and for large errors it *is* the sign law (the clip binds),
so SPEC.md's "steps of at most stp_max toward the demand" holds in every case.
The velocity form keeps its state in Wf itself: switching between the demand,
Tt41 and N1 errors is bumpless and there is no integrator to wind up against
Wf_min/Wf_max.

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

from .errors import ParameterError
from .tunable import Tunable, load_params

__all__ = ["FuelControlParams", "FuelControlOutput", "FuelController"]

PARAM_FILE = "fuel_control.yaml"


@dataclass(frozen=True, slots=True)
class FuelControlParams:
    """Gains and limits of the fuel controller (data/fuel_control.yaml).

    Attributes
    ----------
    k_delta_pct : float
        Corrected fan speed demand per unit thrust lever [%].
    Tt41_max_K : float
        HP turbine rotor inlet temperature limit [K].
    N1_max_pct : float
        Fan (LP spool) mechanical speed limit [%].
    g_Tt41_pct_K : float
        Limiter gain: N1c error per kelvin of Tt41 margin [%/K].
    g_N1_pct_pct : float
        Limiter gain: N1c error per percent of N1 margin [-].
    kp_kg_s_pct : float
        Proportional gain of the incremental PI [kg/s per %].
    ki_kg_s2_pct : float
        Integral gain of the incremental PI [kg/s^2 per %].
    stp_max_kg_s : float
        Largest fuel-flow change per controller step [kg/s].
    Wf_min_kg_s, Wf_max_kg_s : float
        Fuel-flow command bounds [kg/s].
    """

    k_delta_pct: float
    Tt41_max_K: float
    N1_max_pct: float
    g_Tt41_pct_K: float
    g_N1_pct_pct: float
    kp_kg_s_pct: float
    ki_kg_s2_pct: float
    stp_max_kg_s: float
    Wf_min_kg_s: float
    Wf_max_kg_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> FuelControlParams:
        """Parameter set of ``data/fuel_control.yaml`` with optional overrides."""
        return load_params(cls, PARAM_FILE, "fuel_control", **overrides)


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
        Demand from the lever, k_delta * delta [%].
    N1c_lim_pct : float
        Limited demand N1c + e [%].
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
        self._Wf = self._params.Wf_min_kg_s if Wf0_kg_s is None else float(Wf0_kg_s)
        self._e_prev: float | None = None

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
        return self._Wf

    def reset(self, Wf_kg_s: float) -> None:
        """Restart from fuel flow ``Wf_kg_s`` [kg/s] (e.g. the engine's trimmed value)."""
        self._Wf = float(Wf_kg_s)
        self._e_prev = None

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
        p = self._params
        d = min(max(delta, 0.0), 1.0)
        N1c_dem = p.k_delta_pct * d
        e_dem = N1c_dem - N1c_pct
        e_T = p.g_Tt41_pct_K * (p.Tt41_max_K - Tt41_K)
        e_N = p.g_N1_pct_pct * (p.N1_max_pct - N1_pct)
        e, limiter = e_dem, "demand"
        if e_T < e:
            e, limiter = e_T, "Tt41"
        if e_N < e:
            e, limiter = e_N, "N1"
        e_prev = e if self._e_prev is None else self._e_prev
        dWf = p.kp_kg_s_pct * (e - e_prev) + p.ki_kg_s2_pct * dt_s * e
        dWf = min(max(dWf, -p.stp_max_kg_s), p.stp_max_kg_s)
        # bounds, approached at the same limited rate if the command was outside them
        target = min(max(self._Wf + dWf, p.Wf_min_kg_s), p.Wf_max_kg_s)
        dWf = min(max(target - self._Wf, -p.stp_max_kg_s), p.stp_max_kg_s)
        Wf_new = self._Wf + dWf
        self._Wf = Wf_new
        self._e_prev = e
        return FuelControlOutput(Wf_new, dWf, N1c_dem, N1c_pct + e, limiter)
