"""The flight control system: mission state machine, TECS, pitch and lateral loops,
guidance and the fuel controller, stepped together.

:class:`FlightControlSystem` is what an FMU slave wraps: one :meth:`~FlightControlSystem.step`
per communication step takes the measured aircraft and engine states and returns
every command (:class:`FcsOutput`). All gains of all controllers are reachable by
one dotted name, ``"<controller>.<parameter>"``, e.g. ``"tecs.k_TP"`` or
``"fuel_control.stp_max_kg_s"`` (:meth:`~FlightControlSystem.get_parameter`,
:meth:`~FlightControlSystem.set_parameter`, :meth:`~FlightControlSystem.parameter_names`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..infra.jit import entry_point
from ..infra.params import ParamSet
from ..infra.records import fast_init
from ..mission.geo import wrap_pi
from ..mission.mission import Mission
from ..mission.sections import APPROACH, REGISTRY
from .approach import APPROACH_PHASES, ApproachParams
from .atmosphere import G0_M_S2, isa
from .clip import clip
from .errors import FcsError, ParameterError
from .estimation import AirspeedRateEstimator
from .fuel_control import FUEL_LIMITERS, FuelController
from .guidance import L1Guidance
from .inner_loops import PARAM_BLOCKS, STATE_BLOCKS, blocks, inner_step
from .lateral import LateralController
from .performance import Performance
from .pitch import PitchController
from .smoothing import TargetRamp
from .state import AircraftState, EngineState, Targets
from .state_machine import MissionRunner
from .tecs import Tecs, priority_code, speed_kind_code
from .tunable import Tunable
from .vertical import VNAV_MODES
from .vnav import Vnav

__all__ = ["FcsOutput", "FlightControlSystem", "FUEL_LIMITERS", "OUTPUT_SIGNALS"]

#: Flat output signals of :meth:`FcsOutput.signals`: name -> description with unit; the names are the FCS FMU's
#: outputs (:data:`.fcs_signals.SIGNALS`), one name from the model to the results.
OUTPUT_SIGNALS: dict[str, str] = {
    "elevator_norm": "Elevator command, normalised, > 0 trailing edge down (nose down) [-]",
    "aileron_norm": "Aileron command, normalised, > 0 rolls right [-]",
    "rudder_norm": "Rudder command, normalised, > 0 yaws the nose right [-]",
    "steering_norm": "Nose-wheel steering command, > 0 right [-]",
    "brakes_norm": "Wheel brake command [0-1]",
    "gear_down": "Landing gear command, 1 down [-]",
    "lever_norm": "Thrust lever command [0-1]",
    "Wf_cmd_kg_s": "Fuel-flow command [kg/s]",
    "theta_cmd_rad": "Pitch attitude command [rad]",
    "phi_cmd_rad": "Bank angle command [rad]",
    "section_index": "Active mission section index (number of sections when finished) [-]",
    "section_name": "Active mission section name [-]",
    "section_phase": "Phase within the active section [-]",
    "alt_cmd_m": "Commanded altitude above mean sea level (NaN when none) [m]",
    "tas_cmd_m_s": "Commanded true airspeed (NaN when none) [m/s]",
    "track_cmd_rad": "Commanded true track (NaN when none) [rad]",
    "xtk_m": "Cross-track error of the active path, right positive (NaN when none) [m]",
    "fuel_limiter": "Regulator the fuel controller selected: 0 the lever's N1c demand, 1 the Tt41 limit, "
                    "2 the N1 limit [-]",
    "airbrake_norm": "Airbrake command, 0 retracted to 1 fully out [-]",
    "vnav_mode": "Vertical mode: 0 none (ground), 1 ALT, 2 CLIMB, 3 PATH (managed descent), 4 DECEL, "
                 "5 HOLD (planned hold at a fix), 6 DESCENT (open), 7 APPROACH [-]",
    "ils_phase": "Phase of the automatic approach and landing: 0 none, 1 HOLD, 2 LOC_ARMED, 3 LOC, 4 GS, 5 FLARE, "
                 "6 DEROTATION, 7 ROLLOUT, 8 STOPPED [-]",
}
#: Period of the performance model's table look-ups in the energy-rate limits [s] (the polar and the
#: thrusts change slowly with altitude and Mach; the drag is recomputed every step).
PERF_REFRESH_S = 0.5


class _ParamHolder(Tunable[ApproachParams]):
    """Makes the approach parameters (shared by the runner) tunable by name."""

    tunable_name = "approach"

    def __init__(self, runner: MissionRunner) -> None:
        self._runner = runner
        self._params = runner.approach_params

    def _on_parameters_changed(self) -> None:
        self._runner.approach_params = self._params


_GROUND_PITCH_PHASES = frozenset({"ROLL", "ROTATE", "LIFTOFF"})


@fast_init
@dataclass(frozen=True, slots=True)
class FcsOutput:
    """Commands of one FCS step and the targets behind them (for recording and plots).

    Attributes
    ----------
    elevator_norm, aileron_norm, rudder_norm : float
        Normalised surfaces [-1, 1] (elevator > 0 nose down, aileron > 0 roll right, rudder > 0 nose right).
    steering_norm : float
        Nose-wheel steering [-1, 1] (> 0 right).
    brakes_norm : float
        Wheel brakes [0, 1].
    gear_down : bool
        Landing gear command.
    lever_norm : float
        Thrust lever [0, 1].
    Wf_cmd_kg_s : float
        Fuel-flow command [kg/s].
    theta_cmd_rad, phi_cmd_rad : float
        Pitch and bank commands [rad].
    targets : Targets
        The active section's targets (section index/name, phase, altitude, speed, track).
    tas_cmd_m_s : float
        Speed target as true airspeed [m/s] (NaN on the ground).
    fuel_limiter : int
        Regulator the fuel controller selected, an index of :data:`FUEL_LIMITERS` [-].
    airbrake_norm : float
        Airbrake command [0, 1].
    vnav_mode : int
        Vertical mode, an index of :data:`.vertical.VNAV_MODES` [-].
    ils_phase : int
        Approach phase, an index of :data:`.approach.APPROACH_PHASES` (0 outside a landing) [-].
    """

    elevator_norm: float
    aileron_norm: float
    rudder_norm: float
    steering_norm: float
    brakes_norm: float
    gear_down: bool
    lever_norm: float
    Wf_cmd_kg_s: float
    theta_cmd_rad: float
    phi_cmd_rad: float
    targets: Targets
    tas_cmd_m_s: float
    fuel_limiter: int = 0
    airbrake_norm: float = 0.0
    vnav_mode: int = 0
    ils_phase: int = 0

    def signals(self) -> dict[str, float | int | str | bool]:
        """The outputs as a flat mapping named as :data:`OUTPUT_SIGNALS` (the FMU's output names)."""
        tg = self.targets
        return {"elevator_norm": self.elevator_norm, "aileron_norm": self.aileron_norm,
                "rudder_norm": self.rudder_norm, "steering_norm": self.steering_norm, "brakes_norm": self.brakes_norm,
                "gear_down": self.gear_down, "lever_norm": self.lever_norm, "Wf_cmd_kg_s": self.Wf_cmd_kg_s,
                "theta_cmd_rad": self.theta_cmd_rad, "phi_cmd_rad": self.phi_cmd_rad,
                "section_index": tg.section_index, "section_name": tg.section_name, "section_phase": tg.phase,
                "alt_cmd_m": math.nan if tg.alt_cmd_m is None else tg.alt_cmd_m, "tas_cmd_m_s": self.tas_cmd_m_s,
                "track_cmd_rad": tg.track_cmd_rad, "xtk_m": tg.xtk_m, "fuel_limiter": self.fuel_limiter,
                "airbrake_norm": self.airbrake_norm, "vnav_mode": self.vnav_mode, "ils_phase": self.ils_phase}


class FlightControlSystem:
    """Mission, guidance, longitudinal, lateral and propulsion control of one aircraft.

    Parameters
    ----------
    mission : Mission
        The validated mission to fly.
    Wf0_kg_s : float
        Fuel flow at the start (engine running at idle) [kg/s].
    elevator0 : float
        Elevator at the start [-] (e.g. the trim of an air start): the pitch loop's
        integral starts from it, so the engagement is bumpless.
    """

    def __init__(self, mission: Mission, Wf0_kg_s: float | None = None, elevator0: float = 0.0,
                 performance: Performance | None = None) -> None:
        self.guidance = L1Guidance()
        self.tecs = Tecs()
        self.perf = performance if performance is not None else \
            Performance(n1c_idle=lambda: self.fuel.parameters.N1c_idle_pct)
        self.vnav = Vnav(self.perf)
        self.runner = MissionRunner(mission, self.guidance, vnav=self.vnav, tecs_params=self.tecs.parameters)
        self.pitch = PitchController()
        self.pitch.reset(elevator0)
        self.lateral = LateralController()
        self.fuel = FuelController(Wf0_kg_s=Wf0_kg_s)
        self._approach = _ParamHolder(self.runner)
        self.controllers: dict[str, Tunable] = {"tecs": self.tecs, "pitch": self.pitch, "lateral": self.lateral,
                                                "guidance": self.guidance, "approach": self._approach,
                                                "fuel_control": self.fuel, "vnav": self.vnav,
                                                "performance": self.perf}
        self._tecs_engaged = False
        self._lever: float | None = None
        self._estimator = AirspeedRateEstimator()
        self._ramp = TargetRamp()
        self.controllers["estimation"] = self._estimator
        self._perf_t = -math.inf  # time of the last look-up of the performance tables [s]
        # the inner loops' buffers (inner_loops.STATE_BLOCKS, PARAM_BLOCKS): each controller keeps its state in a
        # view of its block of the one state buffer; the parameter buffer holds copies of their values()
        self._state = np.zeros(sum(n for _, n in STATE_BLOCKS))
        self._tuned = {"estimation": self._estimator, "tecs": self.tecs, "pitch": self.pitch,
                       "lateral": self.lateral, "fuel_control": self.fuel}
        where = blocks(STATE_BLOCKS)
        for name, ctl in self._tuned.items():
            a, b = where[name]
            self._state[a:b] = ctl._s
            ctl._s = self._state[a:b]
        self._params = np.zeros(sum(n for _, n in PARAM_BLOCKS))
        self._params_of: tuple = ()  # the parameter sets the buffer holds
        self._inner = self._first_inner_step  # then inner_step's compiled entry point for the types of the call

    # -- parameters -----------------------------------------------------------------------
    def parameter_names(self) -> tuple[str, ...]:
        """Every tunable parameter, as ``"<controller>.<name>"``."""
        return tuple(f"{c}.{n}" for c, ctl in self.controllers.items() for n in ctl.parameter_names())

    def parameter_sets(self) -> dict[str, ParamSet[Any]]:
        """Each controller's parameters (value, unit, range, note, source), by the prefix of their names."""
        return {c: ctl.parameter_set() for c, ctl in self.controllers.items()}

    def _split(self, name: str) -> tuple[Tunable, str]:
        ctl, _, pname = name.partition(".")
        if ctl not in self.controllers or not pname:
            raise ParameterError(f"fcs: parameter '{name}' must be '<controller>.<name>' with controller one of "
                                 f"{', '.join(self.controllers)}")
        return self.controllers[ctl], pname

    def get_parameter(self, name: str) -> float:
        """Value of ``"<controller>.<name>"`` [its unit]."""
        ctl, p = self._split(name)
        return ctl.get_parameter(p)

    def set_parameter(self, name: str, value: float) -> None:
        """Set ``"<controller>.<name>"`` to ``value`` [its unit]."""
        ctl, p = self._split(name)
        ctl.set_parameter(p, value)
        self.runner.tecs_params = self.tecs.parameters
        self._perf_t = -math.inf

    # -- stepping -------------------------------------------------------------------------
    @property
    def finished(self) -> bool:
        """The mission is complete."""
        return self.runner.finished

    def step(self, t_s: float, dt_s: float, x: AircraftState, eng: EngineState) -> FcsOutput:
        """One FCS step at time ``t_s`` [s] of length ``dt_s`` [s].

        If ``x.Vdot_m_s2`` is NaN (an airframe that does not output it), the rate of the
        true airspeed and its rate are estimated from the ground velocity and the airspeed
        (:class:`~.estimation.AirspeedRateEstimator`, crossover ``estimation.tau_cross_s``), the rate
        low-passed with ``tecs.tau_Vdot_s``; the TECS flies the estimated airspeed.
        """
        runner = self.runner
        tg = runner.step(t_s, dt_s, x)
        tecs_on = tg.theta_cmd_rad is None
        # the outer loops' held targets ramped from one update to the next (smoothing.py)
        rt = self._ramp.step(t_s, tg, runner.targets_time_s, runner.held_for_s)
        alt_cmd, gamma_cmd = rt.alt_cmd_m, rt.gamma_cmd_rad
        if not tecs_on:
            self._tecs_engaged = False
        else:
            tecs = self.tecs
            if not self._tecs_engaged:
                # bumpless: from the last lever, or at the start the lever that demands the engine's N1c
                lever0 = self._lever if self._lever is not None else \
                    clip(eng.N1c_pct / max(self.fuel.parameters.k_delta_pct, 1e-6), 0.0, 1.0)
                tecs.reset(lever0 * tecs.available_thrust_N(x.alt_m, x.dT_isa_K), x.mass_kg * G0_M_S2, x.theta_rad)
                self._tecs_engaged = True
            if tg.speed is None:
                raise FcsError(f"fcs: section {tg.section_name!r} asks for energy control without a speed target")
            if gamma_cmd is None:
                if alt_cmd is None:
                    raise FcsError("tecs.step: give alt_cmd_m (altitude mode) or gamma_cmd_rad (path mode)")
            else:
                alt_cmd = None
            if not (x.on_ground or x.tas_m_s < 30.0) and (t_s - self._perf_t >= PERF_REFRESH_S or t_s < self._perf_t):
                # the performance model's table look-ups, every PERF_REFRESH_S (they change slowly)
                perf = self.perf
                self._params[_PERF_BLOCK] = (*perf.lookup(x.alt_m, perf.mach(x.alt_m, x.tas_m_s, x.dT_isa_K)),
                                             *perf.airbrake_values())
                self._perf_t = t_s
        tuned = (self._estimator._params, self.tecs._params, self.pitch._params, self.lateral._params,
                 self.fuel._params)
        if tuned != self._params_of:  # a parameter set was replaced (set_parameter)
            self._load_params(tuned)
        speed, lever_cmd, phi_cmd, heading_cmd = tg.speed, tg.lever, rt.phi_cmd_rad, rt.heading_cmd_rad
        o = self._inner(self._state, self._params, dt_s, x.alt_m, x.tas_m_s, x.Vdot_m_s2,
                       x.gamma_rad, x.vn_m_s, x.ve_m_s, x.psi_rad, x.phi_rad, x.theta_rad, x.p_rad_s, x.q_rad_s,
                       x.r_rad_s, x.beta_rad, x.qbar_Pa, x.mass_kg, x.dT_isa_K, x.on_ground, eng.N1c_pct, eng.N1_pct,
                       eng.Tt41_K, tecs_on, math.nan if tecs_on else tg.theta_cmd_rad,
                       math.nan if lever_cmd is None else lever_cmd, lever_cmd is not None,
                       math.nan if speed is None else rt.speed_value,
                       2 if speed is None else speed_kind_code(speed.kind),
                       math.nan if alt_cmd is None else alt_cmd, alt_cmd is not None,
                       math.nan if gamma_cmd is None else gamma_cmd, rt.hdot_ff_m_s, priority_code(tg.priority),
                       tg.gear_down, tg.airbrake, x.on_ground or tg.phase in _GROUND_PITCH_PHASES,
                       math.nan if phi_cmd is None else phi_cmd, phi_cmd is not None,
                       math.nan if heading_cmd is None else heading_cmd, heading_cmd is not None)
        if not o[10]:
            isa(x.alt_m, x.dT_isa_K)  # raises the atmosphere's error, which names the altitude
        lever = self._lever = o[3]
        rudder = o[2]
        if tg.align_heading_rad is not None:
            ap = runner.approach_params
            rudder = clip(-ap.k_psi_steer_1_rad * wrap_pi(x.psi_rad - tg.align_heading_rad), -1.0, 1.0)
        kind = REGISTRY.get(tg.section_type)  # None once the mission is finished
        ils = _PHASE_CODE.get(tg.phase, 0) if kind is not None and kind.conformance == APPROACH else 0
        return FcsOutput.make(o[0], o[1], rudder, tg.steer, tg.brake, tg.gear_down, lever, o[4], o[5], o[6], tg,
                              o[7], o[8], o[9], _MODE_CODE.get(tg.vnav_mode, 0), ils)

    def _first_inner_step(self, *args: object) -> tuple:
        """:func:`.inner_loops.inner_step` through its entry point for these arguments' types, kept for the next
        steps (:func:`..infra.jit.entry_point`)."""
        self._inner = entry_point(inner_step, args)
        return self._inner(*args)

    def _load_params(self, tuned: tuple) -> None:
        """Copy the controllers' parameters into the inner loops' parameter buffer; ``tuned`` their parameter
        sets, which the buffer then holds."""
        where = blocks(PARAM_BLOCKS)
        for name, ctl in self._tuned.items():
            a, b = where[name]
            self._params[a:b] = ctl.values()
        self._params_of = tuned


_PERF_BLOCK = slice(*blocks(PARAM_BLOCKS)["performance"])
_MODE_CODE = {m: i for i, m in enumerate(VNAV_MODES)}
_PHASE_CODE = {m: i for i, m in enumerate(APPROACH_PHASES)}
