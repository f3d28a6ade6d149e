"""Airframe FMU: a JSBSim aircraft (parameter ``aircraft``, default UPERA), flying on engines computed outside
(each engine's thrust and fuel flow in: ``Fn_N``, ``Fn_N_2``... and ``Wf_kg_s``, ``Wf_kg_s_2``..., in the
order of the aircraft file's engines; :mod:`openemss.models.airframe.aircraft` says the convention).

A thin pythonfmu slave over :class:`openemss.models.airframe.adapter.Airframe`. Each
``doStep`` applies the inputs, advances JSBSim by the step (a whole number of internal
steps at ``rate_hz``, fitted at the first step to a step that is not a multiple of it) and caches
the outputs in one list, read by index.

Start: on a runway at rest (``start_on_runway``) or in the air at ``alt0_m`` and
``tas0_m_s``; with ``trim_at_start`` the air start is trimmed in level flight (angle of
attack from :func:`openemss.models.airframe.trim.trim_level`; the trim's elevator and
thrust are published as ``trim_elevator_norm`` and ``trim_Fn_N`` so the flight
control can start from them).

Weather: ``weather_file`` (String, empty by default: the steady ``wind_*_m_s`` and the
``turbulence_*`` parameters apply) names a mission file, or a file of only its ``wind`` and
``turbulence`` keys (:mod:`openemss.models.mission.weather`), absolute or relative to the FMU's
resources folder (the shipped ones: ``missions/weather/``). Its winds aloft replace the steady
wind and are applied at the aircraft's altitude every step; its turbulence (severity, wind at
20 ft, seed) replaces the turbulence parameters. The airframe owns the atmosphere: the flight
control reads its mission through its own ``mission_file`` and never passes the wind on.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from pythonfmu import Fmi2Causality, Fmi2Slave

from openemss.fmus.data import data_file
from openemss.fmus.fmu_state import FmuState, SlaveState, StateError, attrs_from_plain, plain_attrs
from openemss.fmus.initial_outputs import InitialOutputs
from openemss.fmus.signal_io import SignalIO
from openemss.models.airframe.adapter import Airframe as AirframeModel
from openemss.models.airframe.adapter import whole_frames
from openemss.models.airframe.aircraft import load_aircraft
from openemss.models.airframe.airframe_signals import (DEPARTURE_START, FUEL_FLOW_INPUTS, SIGNALS, STATE_FIELDS,
                                                      THRUST_INPUTS)
from openemss.models.airframe.errors import AirframeError
from openemss.models.airframe.loading import check_air_start, check_loading
from openemss.models.airframe.settings import PARAMETER_SETS, airframe_set
from openemss.models.airframe.trim import trim_level
from openemss.models.mission.errors import MissionError
from openemss.models.mission.mission import departure_runway, load_mission
from openemss.models.mission.weather import Weather, load_weather

REQUIREMENTS = ["jsbsim>=1.2", "numpy>=1.24", "scipy>=1.10", "pyyaml>=6.0"]
DATA_FILES = ["missions/weather/munich_wind_light_turbulence.yaml", "missions/munich.yaml"]
DEFAULT_MISSION = "missions/munich.yaml"  # the flight control's: the aircraft starts on its departure runway
_ON_GROUND = STATE_FIELDS.index("on_ground")
_TRIM = ("trim_elevator_norm", "trim_Fn_N")


class Airframe(FmuState, InitialOutputs, SignalIO, Fmi2Slave):
    """A JSBSim aircraft's six-degree-of-freedom airframe with external thrust and fuel burn.

    State (``fmi2GetFMUstate``, ``fmus/fmu_state.py``): JSBSim 1.3's Python API can neither copy an
    ``FGFDMExec`` nor set the history of its integrators, actuators and turbulence filters, so the airframe's
    state is its start (every parameter and input when :meth:`compute_start` ran) and the inputs and step of
    every ``doStep`` since: restoring builds the aircraft again from that start and flies those steps again
    (JSBSim is deterministic: the same result bit for bit). Saving costs nothing; restoring at time t costs
    flying the airframe alone to t again (about 0.3 ms per step of 0.05 s at 120 Hz). The log is plain data,
    so the state serializes.
    """

    author = "openEMSS"
    description = "JSBSim airframe (default UPERA): controls, each engine's thrust [N] and fuel flow [kg/s] in; SI state out"
    STATE_SKIP = frozenset({"_model", "_log", "_start", "_runway_defaults"})  # the last: constant, from __init__

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        rwy = departure_runway(load_mission(data_file(DEFAULT_MISSION, self.resources)))
        self._trim = [0.0, 0.0]
        self._model: AirframeModel | None = None
        self._engines = 1
        #: the runway start's parameters at their defaults (the default mission's departure runway)
        self._runway_defaults = {"lat0_deg": rwy.threshold.lat_deg, "lon0_deg": rwy.threshold.lon_deg,
                                 "heading0_deg": math.degrees(rwy.heading_rad), "alt0_m": rwy.elevation_m}
        departure = {d: self._runway_defaults[p] for d, p in DEPARTURE_START.items()}
        self.register_signals(SIGNALS, {"Real": (*STATE_FIELDS, *_TRIM), "Boolean": ("on_ground",)},
                              starts={**self._runway_defaults, **departure, "ground_elevation_m": rwy.elevation_m})
        self._y = [0.0] * (len(STATE_FIELDS) + len(_TRIM))
        self._yb = [True]
        #: the start (every parameter and input, by name) and (step, Real inputs, gear_down) of every step since
        self._start: dict[str, Any] = {}
        self._log: list[tuple[float, tuple[float, ...], bool]] = []
        #: the communication step the internal frames are fitted to (None: frames of 1/rate_hz), see do_step
        self._fit_step_s: float | None = None

    def _publish(self) -> None:
        v = self._model.values()  # type: ignore[union-attr]
        v.extend(self._trim)
        self._y = v
        self._yb = [v[_ON_GROUND] > 0.5]

    def _weather(self, weather_file: str) -> Weather | None:
        if not weather_file:
            return None
        p = Path(weather_file)
        if not p.is_absolute():
            p = Path(self.resources or ".") / p
        if not p.is_file():
            raise MissionError(f"airframe: weather_file '{weather_file}' not found (looked at {p}); give a "
                               f"path, absolute or relative to the FMU's resources folder (shipped: {DATA_FILES[0]})")
        return load_weather(p)

    def _settings(self) -> dict[str, Any]:
        """Every parameter and input by name, as the slave holds them now."""
        return {v.name: getattr(self, v.name) for v in self.vars.values() if v.causality != Fmi2Causality.output}

    def compute_start(self) -> None:
        self._start, self._log = {**self._settings(), "_fit_step_s": self._fit_step_s}, []
        # the parameter sets of data/airframe.yaml, from the parameters of their names, checked against its ranges
        sets = {section: airframe_set(cls, section).collect(lambda name: getattr(self, name), "", "airframe")
                for section, cls in PARAMETER_SETS.items()}
        st, env, ac_set = sets["start"], sets["environment"], sets["aircraft"]
        ac = load_aircraft(ac_set.aircraft, Path(self.resources) if self.resources else None)
        check_loading(st.fuel0_kg, self.added_mass_kg, ("fuel0_kg", "added_mass_kg"), engine_fed=True, aircraft=ac)
        if not st.start_on_runway:
            check_air_start(st.alt0_m, st.ground_elevation_m, ("alt0_m", "ground_elevation_m"), aircraft=ac)
        self._engines = len(ac.thrusters)
        w = self._weather(env.weather_file)
        turb = w.turbulence if w is not None else None
        sev, w20, seed = (env.turbulence_severity, env.turbulence_wind_20ft_m_s, env.turbulence_seed)
        if turb is not None:  # the file's turbulence replaces the parameters'
            sev, w20, seed = turb.severity, turb.wind_20ft_m_s, turb.seed
        m = AirframeModel(rate_hz=sets["simulation"].rate_hz, dT_isa_K=env.weather_dT_isa_K,
                          wind_ned_m_s=(env.wind_north_m_s, env.wind_east_m_s, env.wind_down_m_s),
                          turbulence_severity=sev, turbulence_wind_20ft_m_s=w20, seed=seed,
                          wind_profile=w.wind.ned_m_s if w is not None and w.wind is not None else None,
                          fit_step_s=self._fit_step_s, aircraft=ac)
        m.set_added_mass(self.added_mass_kg)
        m.set_payload(ac_set.payload_kg)
        self._trim = [0.0, 0.0]
        if st.start_on_runway:
            m.start_runway(*self._runway_start(st), fuel_kg=st.fuel0_kg, flaps=st.flaps0_norm)
        else:
            alpha, elevator, thrust = st.alpha0_rad, self.elevator_norm, self.Fn_N
            for name in THRUST_INPUTS[1:self._engines]:  # the engines' total
                thrust += getattr(self, name)
            if st.trim_at_start:
                m.start_air(st.alt0_m, 100.0, st.heading0_deg, fuel_kg=st.fuel0_kg,
                            ground_elevation_m=st.ground_elevation_m)
                mach = st.tas0_m_s / m.speed_of_sound_m_s()
                r = trim_level(st.alt0_m, mach, ac.empty_mass_kg + self.added_mass_kg + ac_set.payload_kg + st.fuel0_kg,
                               airframe=m,
                               flaps=st.flaps0_norm, gear_down=self.gear_down, heading_deg=st.heading0_deg,
                               lat_deg=st.lat0_deg, lon_deg=st.lon0_deg)
                alpha, elevator, thrust = r.alpha_rad, r.elevator, r.Fn_N
                self._trim = [elevator, thrust]
            m.start_air(st.alt0_m, st.tas0_m_s, st.heading0_deg, st.lat0_deg, st.lon0_deg,
                        alpha_rad=alpha, elevator=elevator, Fn_N=thrust, flaps=st.flaps0_norm,
                        gear_down=self.gear_down, fuel_kg=st.fuel0_kg, ground_elevation_m=st.ground_elevation_m)
        self._model = m
        self._publish()

    def _runway_start(self, st: Any) -> tuple[float, float, float, float]:
        """Latitude, longitude, heading [deg] and elevation [m] of a runway start: where the flight control's
        mission departs (the inputs ``departure_*``), unless the start's parameters were set away from their defaults
        (then theirs: a start that disagrees with the mission is the flight control's error, naming both)."""
        out = []
        for d, p in DEPARTURE_START.items():
            given, mission = getattr(st, p), getattr(self, d)
            out.append(mission if given == self._runway_defaults[p] and math.isfinite(mission) else given)
        return out[0], out[1], out[2], out[3]

    def do_step(self, current_time: float, step_size: float) -> bool:
        if not self._log and whole_frames(step_size, self._model.rate_hz) is None:  # type: ignore[union-attr]
            self._fit_frames(step_size)
        self._advance(step_size)
        self._log.append((step_size, tuple(self._u), self.gear_down))
        self._publish()
        return True

    def _fit_frames(self, step_size: float) -> None:
        """Build the aircraft again from its start with frames that divide ``step_size`` [s] (the host's first
        step, not a whole number of frames of ``1/rate_hz``: e.g. 100 Hz, or FMPy's default of a 500th of the
        stop time): JSBSim's actuators and kinematics take the frame length when the aircraft is built, so
        only then do they move at their rates in every step of that size. A later step of another size
        that is not whole frames ends with a shorter frame (the adapter's ``step``)."""
        self._fit_step_s = step_size
        self._restore_extra(({**self._start, "_fit_step_s": step_size}, [], 0))

    def _advance(self, step_size: float) -> None:
        """Fly one step of ``step_size`` [s] on the inputs held."""
        m = self._model
        m.set_surfaces(self.aileron_norm, self.elevator_norm, self.rudder_norm)
        m.set_flaps(self.flaps_norm)
        m.set_airbrake(self.airbrake_norm)
        m.set_gear(self.gear_down)
        m.set_brakes(self.brakes_norm, self.brakes_norm)
        m.set_steering(self.steering_norm)
        n = self._engines
        for k in range(n):
            m.set_thrust(getattr(self, THRUST_INPUTS[k]), k)
        wf = self.Wf_kg_s
        for name in FUEL_FLOW_INPUTS[1:n]:
            wf += getattr(self, name)
        for name in (*THRUST_INPUTS[n:], *FUEL_FLOW_INPUTS[n:]):
            if getattr(self, name) != 0.0:
                raise AirframeError(f"airframe: {name} = {getattr(self, name)}: the aircraft "
                                    f"{m.aircraft.name} has {n} engine(s) (inputs {', '.join(THRUST_INPUTS[:n])})")
        m.set_fuel_flow(wf)
        m.set_added_mass(self.added_mass_kg)
        m.step(step_size)

    # -- state: the start and the steps since (see the class) ------------------------------------------
    def _state_extra(self) -> tuple[dict[str, Any], list[tuple[float, tuple[float, ...], bool]], int]:
        return self._start, self._log, len(self._log)  # the log only grows: its first n entries stay

    def _restore_extra(self, extra: tuple[dict[str, Any], list[tuple[float, tuple[float, ...], bool]], int]) -> None:
        start, log, n = extra
        held = self._settings()  # the restored parameters and inputs, put back after the replay
        for name, value in start.items():
            setattr(self, name, value)
        self.compute_start()
        for h, u, gear in log[:n]:
            self._u[:] = u
            self.gear_down = gear
            self._advance(h)
        self._log = log[:n]
        for name, value in held.items():
            setattr(self, name, value)
        self._publish()  # the outputs of the state flown again (the start's were published by compute_start)

    @classmethod
    def _state_to_plain(cls, state: SlaveState) -> Any:
        start, log, n = state.extra
        return {"attrs": plain_attrs(state.attrs), "start": start, "log": [[h, list(u), g] for h, u, g in log[:n]]}

    def _state_from_plain(self, plain: Any) -> SlaveState:
        try:
            log = [(float(h), tuple(float(x) for x in u), bool(g)) for h, u, g in plain["log"]]
            return SlaveState(type(self).__name__, attrs_from_plain(self, plain["attrs"]), (plain["start"], log,
                                                                                              len(log)))
        except (KeyError, TypeError, ValueError) as exc:
            raise StateError(f"{type(self).__name__}: a serialized state that is not whole ({exc!r})") from None
