"""Airframe FMU: UPERA in JSBSim, flying on an engine computed outside (thrust and fuel flow in).

A thin pythonfmu slave over :class:`openemss.models.airframe.adapter.Airframe`. Each
``doStep`` applies the inputs, advances JSBSim by the step (a whole number of internal
steps at ``rate_hz``) and caches the outputs in one list, read by index.

Start: on a runway at rest (``start_on_runway``) or in the air at ``alt0_m`` and
``tas0_m_s``; with ``trim_at_start`` the air start is trimmed in level flight (angle of
attack from :func:`openemss.models.airframe.trim.trim_level`; the trim's elevator and
thrust are published as ``trim_elevator_norm`` and ``trim_thrust_N`` so the flight
control can start from them).

Weather: ``weather_file`` (String, empty by default: the steady ``wind_*_m_s`` and the
``turbulence_*`` parameters apply) names a mission file, or a file of only its ``wind`` and
``turbulence`` keys (:mod:`openemss.models.fcs.weather`), absolute or relative to the FMU's
resources folder (the shipped ones: ``missions/weather/``). Its winds aloft replace the steady
wind and are applied at the aircraft's altitude every step; its turbulence (severity, wind at
20 ft, seed) replaces the turbulence parameters. The airframe owns the atmosphere: the flight
control reads its mission through its own ``mission_file`` and never passes the wind on.
"""
from __future__ import annotations

from pathlib import Path

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String

from openemss.models.airframe.adapter import FT
from openemss.models.airframe.adapter import Airframe as AirframeModel
from openemss.models.airframe.trim import trim_level
from openemss.models.fcs.errors import MissionError
from openemss.models.fcs.weather import Weather, load_weather

REQUIREMENTS = ["jsbsim>=1.2", "numpy>=1.24", "scipy>=1.10", "pyyaml>=6.0"]
DATA_FILES = ["missions/weather/munich_wind_light_turbulence.yaml"]

# (name, description) in the order of AirframeModel.values() after time_s (on_ground handled apart).
OUTPUTS = (
    ("lat_deg", "Geodetic latitude [deg]"), ("lon_deg", "Longitude [deg]"),
    ("alt_msl_m", "Altitude above mean sea level [m]"), ("alt_agl_m", "Altitude above ground [m]"),
    ("tas_m_s", "True airspeed [m/s]"), ("cas_m_s", "Calibrated airspeed [m/s]"),
    ("gs_m_s", "Ground speed [m/s]"), ("mach", "Mach number [-]"),
    ("alpha_rad", "Angle of attack [rad]"), ("beta_rad", "Sideslip angle [rad]"),
    ("phi_rad", "Roll angle [rad]"), ("theta_rad", "Pitch angle [rad]"), ("psi_rad", "True heading [rad]"),
    ("p_rad_s", "Body roll rate [rad/s]"), ("q_rad_s", "Body pitch rate [rad/s]"),
    ("r_rad_s", "Body yaw rate [rad/s]"), ("load_factor", "Normal load factor Nz [-]"),
    ("vs_m_s", "Vertical speed, positive up [m/s]"), ("p_amb_Pa", "Ambient static pressure [Pa]"),
    ("T_amb_K", "Ambient static temperature [K]"), ("rho_amb_kg_m3", "Ambient density [kg/m3]"),
    ("airbrake_pos_norm", "Airbrake position, 0 retracted to 1 fully out [-]"),
)
_ON_GROUND = len(OUTPUTS) + 1  # index in values(): time, outputs..., on_ground, mass, fuel


class Airframe(Fmi2Slave):
    """UPERA six-degree-of-freedom airframe (JSBSim) with external thrust and fuel burn."""

    author = "openEMSS"
    description = "UPERA airframe in JSBSim: controls, thrust [N] and fuel flow [kg/s] in; SI state out"

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        fixed, discrete = Fmi2Variability.fixed, Fmi2Variability.discrete
        par, inp, out = Fmi2Causality.parameter, Fmi2Causality.input, Fmi2Causality.output
        # parameters: initial condition, fuel, atmosphere, internal rate
        self.start_on_runway = True
        self.trim_at_start = True
        self.lat0_deg = 48.366886
        self.lon0_deg = 11.821172
        self.heading0_deg = 263.4
        # The EDDM 26R threshold elevation of missions/munich.yaml (1449 ft, AIP): the runway the FCS
        # takes off from and lands on lies at the ground the aircraft stands on.
        self.alt0_m = 441.7
        self.tas0_m_s = 150.0
        self.alpha0_rad = 0.0
        self.ground_elevation_m = 441.7
        self.flaps0_norm = 0.0
        self.fuel0_kg = 600.0
        self.isa_dev_K = 0.0
        self.wind_north_m_s = 0.0
        self.wind_east_m_s = 0.0
        self.wind_down_m_s = 0.0
        self.turbulence_severity = 0
        self.turbulence_wind_20ft_m_s = 0.0
        self.turbulence_seed = 0
        self.weather_file = ""
        self.rate_hz = 120.0
        self.register_variable(String("weather_file", causality=par, variability=fixed,
                                      description="Winds aloft and turbulence: a mission or weather file (YAML), "
                                                  "absolute or relative to the FMU's resources folder; empty: the "
                                                  "wind_* and turbulence_* parameters [-]"))
        self.register_variable(Boolean("start_on_runway", causality=par, variability=fixed,
                                       description="Start at rest on the runway (else in the air) [-]"))
        self.register_variable(Boolean("trim_at_start", causality=par, variability=fixed,
                                       description="Air start trimmed in level flight (alpha from the trim) [-]"))
        for name, desc in (("lat0_deg", "Initial geodetic latitude [deg]"), ("lon0_deg", "Initial longitude [deg]"),
                           ("heading0_deg", "Initial true heading [deg]"),
                           ("alt0_m", "Initial altitude MSL; runway elevation on a runway start [m]"),
                           ("tas0_m_s", "Initial true airspeed of an air start [m/s]"),
                           ("alpha0_rad", "Initial angle of attack of an untrimmed air start [rad]"),
                           ("ground_elevation_m", "Ground elevation under an air start [m]"),
                           ("flaps0_norm", "Initial flap position, 0 up to 1 full [-]"),
                           ("fuel0_kg", "Initial fuel mass, 0 to 600 [kg]"),
                           ("isa_dev_K", "ISA temperature deviation [K]"),
                           ("wind_north_m_s", "Steady wind towards north [m/s]"),
                           ("wind_east_m_s", "Steady wind towards east [m/s]"),
                           ("wind_down_m_s", "Steady wind downwards [m/s]"),
                           ("turbulence_wind_20ft_m_s", "Wind speed at 20 ft for MIL-F-8785C turbulence [m/s]"),
                           ("rate_hz", "Internal JSBSim rate [Hz]")):
            self.register_variable(Real(name, causality=par, variability=fixed, description=desc))
        self.register_variable(Integer("turbulence_severity", causality=par, variability=fixed,
                                       description="MIL-F-8785C turbulence severity 0 (off) to 7 [-]"))
        self.register_variable(Integer("turbulence_seed", causality=par, variability=fixed,
                                       description="Random seed of the turbulence [-]"))
        # inputs
        self.aileron_norm = 0.0
        self.elevator_norm = 0.0
        self.rudder_norm = 0.0
        self.flaps_norm = 0.0
        self.airbrake_norm = 0.0
        self.gear_down = True
        self.brakes_norm = 0.0
        self.steering_norm = 0.0
        self.thrust_N = 0.0
        self.fuel_flow_kg_s = 0.0
        self.added_mass_kg = 0.0
        for name, desc in (("aileron_norm", "Aileron command, -1 to 1, > 0 rolls right [-]"),
                           ("elevator_norm", "Elevator command, -1 to 1, > 0 trailing edge down (nose down) [-]"),
                           ("rudder_norm", "Rudder command, -1 to 1, > 0 yaws the nose right [-]"),
                           ("flaps_norm", "Flap command, 0 up to 1 full (30 deg) [-]"),
                           ("airbrake_norm", "Airbrake command, 0 retracted to 1 fully out (rate limited, blown "
                                             "back above its limiting dynamic pressure) [-]"),
                           ("brakes_norm", "Wheel brakes, 0 to 1 [-]"),
                           ("steering_norm", "Nose-wheel steering, -1 to 1, > 0 right [-]"),
                           ("thrust_N", "Net thrust along the engine axis [N]"),
                           ("fuel_flow_kg_s", "Fuel flow burnt from the tank [kg/s]"),
                           ("added_mass_kg", "Mass added at the CG to the operating empty mass (e.g. the "
                                             "electrical system's mass_kg), 0 to 10000 [kg]")):
            self.register_variable(Real(name, causality=inp, description=desc))
        self.register_variable(Boolean("gear_down", causality=inp, variability=discrete,
                                       description="Landing gear command, true = down [-]"))
        # outputs, read from one cached list
        self._vals = [0.0] * (len(OUTPUTS) + 4)
        self.trim_elevator_norm = 0.0
        self.trim_thrust_N = 0.0
        self._out0 = len(self.vars) - 1  # value reference of output i (1-based in _vals) is _out0 + i
        for i, (name, desc) in enumerate(OUTPUTS, start=1):
            self.register_variable(Real(name, causality=out, description=desc, getter=lambda i=i: self._vals[i]))
        self.register_variable(Boolean("on_ground", causality=out, variability=discrete,
                                       description="A wheel carries weight [-]",
                                       getter=lambda: self._vals[_ON_GROUND] > 0.5))
        self.register_variable(Real("mass_kg", causality=out, description="Aircraft mass [kg]",
                                    getter=lambda: self._vals[_ON_GROUND + 1]))
        self.register_variable(Real("fuel_kg", causality=out, description="Fuel mass [kg]",
                                    getter=lambda: self._vals[_ON_GROUND + 2]))
        self.register_variable(Real("trim_elevator_norm", causality=out,
                                    description="Elevator of the trimmed air start [-]"))
        self.register_variable(Real("trim_thrust_N", causality=out,
                                    description="Thrust of the trimmed air start [N]"))
        self._model: AirframeModel | None = None

    def get_real(self, vrs: list[int]) -> list[float]:
        """The state outputs straight from the cached list; pythonfmu's own calls one getter per variable
        (about 1 us each, a third of this FMU's I/O cost)."""
        vals, base, n = self._vals, self._out0, len(OUTPUTS)
        return [vals[vr - base] if 0 < vr - base <= n else Fmi2Slave.get_real(self, [vr])[0] for vr in vrs]

    def _weather(self) -> Weather | None:
        if not self.weather_file:
            return None
        p = Path(self.weather_file)
        if not p.is_absolute():
            p = Path(self.resources or ".") / p
        if not p.is_file():
            raise MissionError(f"airframe: weather_file '{self.weather_file}' not found (looked at {p}); give a "
                               f"path, absolute or relative to the FMU's resources folder (shipped: {DATA_FILES[0]})")
        return load_weather(p)

    def exit_initialization_mode(self) -> None:
        w = self._weather()
        turb = w.turbulence if w is not None else None
        sev, w20, seed = (self.turbulence_severity, self.turbulence_wind_20ft_m_s, self.turbulence_seed)
        if turb is not None:  # the file's turbulence replaces the parameters'
            sev, w20, seed = turb.severity, turb.wind_20ft_m_s, turb.seed
        m = AirframeModel(rate_hz=self.rate_hz, isa_dev_K=self.isa_dev_K,
                          wind_ned_m_s=(self.wind_north_m_s, self.wind_east_m_s, self.wind_down_m_s),
                          turbulence_severity=sev, turbulence_wind_20ft_m_s=w20, seed=seed,
                          wind_profile=w.wind.ned_m_s if w is not None and w.wind is not None else None)
        m.set_added_mass(self.added_mass_kg)
        if self.start_on_runway:
            m.start_runway(self.lat0_deg, self.lon0_deg, self.heading0_deg, self.alt0_m, fuel_kg=self.fuel0_kg,
                           flaps=self.flaps0_norm)
        else:
            alpha, elevator, thrust = self.alpha0_rad, self.elevator_norm, self.thrust_N
            if self.trim_at_start:
                m.start_air(self.alt0_m, 100.0, self.heading0_deg, fuel_kg=self.fuel0_kg,
                            ground_elevation_m=self.ground_elevation_m)
                mach = self.tas0_m_s / (m.get_property("atmosphere/a-fps") * FT)
                r = trim_level(self.alt0_m, mach, m.geometry.oem_kg + self.added_mass_kg + self.fuel0_kg, airframe=m,
                               flaps=self.flaps0_norm, gear_down=self.gear_down, heading_deg=self.heading0_deg,
                               lat_deg=self.lat0_deg, lon_deg=self.lon0_deg)
                alpha, elevator, thrust = r.alpha_rad, r.elevator, r.thrust_N
                self.trim_elevator_norm, self.trim_thrust_N = elevator, thrust
            m.start_air(self.alt0_m, self.tas0_m_s, self.heading0_deg, self.lat0_deg, self.lon0_deg,
                        alpha_rad=alpha, elevator=elevator, thrust_N=thrust, flaps=self.flaps0_norm,
                        gear_down=self.gear_down, fuel_kg=self.fuel0_kg, ground_elevation_m=self.ground_elevation_m)
        self._model = m
        self._vals = m.values()

    def do_step(self, current_time: float, step_size: float) -> bool:
        m = self._model
        m.set_surfaces(self.aileron_norm, self.elevator_norm, self.rudder_norm)
        m.set_flaps(self.flaps_norm)
        m.set_airbrake(self.airbrake_norm)
        m.set_gear(self.gear_down)
        m.set_brakes(self.brakes_norm, self.brakes_norm)
        m.set_steering(self.steering_norm)
        m.set_thrust(self.thrust_N)
        m.set_fuel_flow(self.fuel_flow_kg_s)
        m.set_added_mass(self.added_mass_kg)
        m.step(step_size)
        self._vals = m.values()
        return True
