"""SI adapter over ``jsbsim.FGFDMExec`` flying a JSBSim aircraft (default UPERA) on engines computed outside JSBSim.

The only place where the airframe converts between JSBSim's English units and SI.
Each engine's thrust enters as an external force (``external_reactions/thrust``, ``thrust_2``...: along
its thruster's axis, at the thruster, :mod:`.aircraft`'s convention); the fuel flow is integrated here and
written to the tanks each JSBSim step, so the mass falls exactly as the integral of the fuel flow.

Controls (normalised): elevator, aileron, rudder in [-1, 1] (elevator > 0 trailing
edge down, nose down; aileron > 0 rolls right; rudder > 0 yaws the nose right),
each through a rate-limited JSBSim actuator; flaps in [0, 1]; airbrake in [0, 1] (rate limited,
and blown back above its limiting dynamic pressure); gear 1 down, 0 up; brakes in [0, 1];
nose-wheel steering in [-1, 1] (> 0 turns right).

References
----------
.. [1] Berndt, J. S., and the JSBSim team, *JSBSim Reference Manual*, properties and
   external reactions, https://jsbsim-team.github.io/jsbsim-reference-manual/
"""
from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from .aircraft import COMMAND_PROPERTIES, DEFAULT_AIRCRAFT, Aircraft, load_aircraft
from .errors import AirframeError, FuelExhaustedError, LossOfAircraftError, OutOfEnvelopeError
from .geometry import load_geometry
from .loading import check_air_start, check_loading
from .settings import AirframeEnvironment, AirframeSimulation, AirframeStart, airframe_set

__all__ = ["Airframe", "AirframeState", "AeroForces", "JSBSIM_ROOT", "DEFAULT_RATE_HZ", "WindProfile",
           "FUEL_ROUNDOFF_KG"]

#: Winds aloft: altitude MSL [m] -> wind velocity (north, east, down) [m/s], e.g.
#: ``openemss.models.mission.weather.WindProfile.ned_m_s``.
WindProfile = Callable[[float], tuple[float, float, float]]

JSBSIM_ROOT = Path(__file__).resolve().parent / "jsbsim"
DEFAULT_RATE_HZ = 120.0
SETTLE_S = 2.0  # time the aircraft rests on its gear (brakes on) before time zero of a runway start

FT = 0.3048  # [m/ft]
LBF = 4.4482216152605  # [N/lbf]
LBM = 0.45359237  # [kg/lbm]
SLUG = 14.593902937206364  # [kg/slug]
PSF = 47.880258980335840  # [Pa/psf]
RANKINE = 5.0 / 9.0  # [K/R]
SLUG_FT3 = SLUG / FT ** 3  # [kg/m^3 per slug/ft^3]
KT = 1852.0 / 3600.0  # [m/s/kt]

# Read by state(): (property, factor to SI); order = AirframeState fields after time_s.
_STATE_PROPS: tuple[tuple[str, float], ...] = (
    ("position/lat-geod-deg", 1.0), ("position/long-gc-deg", 1.0),
    ("position/h-sl-ft", FT), ("position/h-agl-ft", FT),
    ("velocities/vtrue-fps", FT), ("velocities/vc-fps", FT), ("velocities/vg-fps", FT),
    ("velocities/mach", 1.0), ("aero/alpha-rad", 1.0), ("aero/beta-rad", 1.0),
    ("attitude/phi-rad", 1.0), ("attitude/theta-rad", 1.0), ("attitude/psi-rad", 1.0),
    ("velocities/p-rad_sec", 1.0), ("velocities/q-rad_sec", 1.0), ("velocities/r-rad_sec", 1.0),
    ("accelerations/Nz", 1.0), ("velocities/h-dot-fps", FT),
    ("atmosphere/P-psf", PSF), ("atmosphere/T-R", RANKINE), ("atmosphere/rho-slugs_ft3", SLUG_FT3),
    ("fcs/airbrake-pos-norm", 1.0),
)


#: Sink rate at touchdown beyond which the aircraft is lost [m/s]. The landing gear is designed for
#: 3.05 m/s (limit, CS/FAR 25.473) and must absorb 3.66 m/s without collapsing (reserve energy,
#: CS/FAR 25.723(b)); at twice the limit it is taken as destroyed.
CRASH_SINK_M_S = 6.0
#: Height of the centre of gravity above ground below which the fuselage touches it [m]: on its
#: wheels the CG of UPERA stands 0.92 m high, the fuselage radius is about 0.4 m.
CRASH_CG_AGL_M = 0.4
#: Fuel [kg] a step may ask of the tank beyond what it holds, as round-off (the engine burns over a step the
#: flow it publishes times the step; the tank takes it off in internal steps).
FUEL_ROUNDOFF_KG = 1e-9
#: Height within which a wingtip below the ground (semi-span x sin|bank| above the CG height) is a
#: wingtip strike [m].
WINGTIP_CHECK_AGL_M = 5.0


@dataclass(frozen=True)
class AirframeState:
    """The aircraft's state in SI units.

    Attributes
    ----------
    time_s : simulation time [s]
    lat_deg, lon_deg : geodetic latitude, longitude [deg]
    alt_m, alt_agl_m : altitude above mean sea level, above ground [m]
    tas_m_s, cas_m_s, gs_m_s : true, calibrated airspeed, ground speed [m/s]
    mach : Mach number [-]
    alpha_rad, beta_rad : angle of attack, sideslip [rad]
    phi_rad, theta_rad, psi_rad : roll, pitch, heading (true) [rad]
    p_rad_s, q_rad_s, r_rad_s : body roll, pitch, yaw rates [rad/s]
    load_factor : normal load factor Nz [-] (1 in level flight)
    vs_m_s : vertical speed, positive up [m/s]
    p_amb_Pa, T_amb_K, rho_amb_kg_m3 : ambient static pressure [Pa], temperature [K], density [kg/m^3]
    airbrake_pos_norm : airbrake position, 0 retracted to 1 fully out [-]
    on_ground : any wheel carries weight
    mass_kg, fuel_kg : total mass, fuel mass [kg]
    dT_isa_K : ISA temperature deviation of the atmosphere [K] (:meth:`Airframe.set_atmosphere`), the one
        value of the system: the engine and the flight control take it from here
    """

    time_s: float
    lat_deg: float
    lon_deg: float
    alt_m: float
    alt_agl_m: float
    tas_m_s: float
    cas_m_s: float
    gs_m_s: float
    mach: float
    alpha_rad: float
    beta_rad: float
    phi_rad: float
    theta_rad: float
    psi_rad: float
    p_rad_s: float
    q_rad_s: float
    r_rad_s: float
    load_factor: float
    vs_m_s: float
    p_amb_Pa: float
    T_amb_K: float
    rho_amb_kg_m3: float
    airbrake_pos_norm: float
    on_ground: bool
    mass_kg: float
    fuel_kg: float
    dT_isa_K: float


def _bounds(cls: type, section: str, name: str) -> tuple[float, float]:
    """The range of parameter ``name`` of ``section`` of ``data/airframe.yaml`` (the one place it is written)."""
    p = airframe_set(cls, section).param(name)
    return p.min, p.max


@dataclass(frozen=True)
class AeroForces:
    """JSBSim's aerodynamic forces at one instant, in SI (:meth:`Airframe.aero_forces`).

    Attributes
    ----------
    qbar_Pa : dynamic pressure [Pa]
    lift_N, drag_N : wind-axis lift and drag [N], positive as named
    wing_area_m2 : JSBSim's reference wing area [m^2]
    re_mac : Reynolds number on the mean aerodynamic chord [-]
    CL, CD : lift and drag coefficients on JSBSim's reference area [-]
    """

    qbar_Pa: float
    lift_N: float
    drag_N: float
    wing_area_m2: float
    re_mac: float
    CL: float
    CD: float


def _check(name: str, value: float, lo: float, hi: float, unit: str = "") -> float:
    v = float(value)
    if not (lo <= v <= hi) or math.isnan(v):
        raise OutOfEnvelopeError(f"{name} = {value}{unit} is outside the valid range [{lo}, {hi}]{unit}")
    return v


def whole_frames(step_s: float, rate_hz: float) -> int | None:
    """The number of frames of ``1/rate_hz`` [Hz] in ``step_s`` [s] when it is a whole number of them (to 1e-9
    relative, the rounding of a decimal step), else None."""
    n = round(step_s * rate_hz)
    return n if n >= 1 and abs(n / rate_hz - step_s) <= 1e-9 * max(1.0, step_s) else None


def frame_for_step(rate_hz: float, step_s: float) -> float:
    """The internal frame [s] for communication steps of ``step_s`` [s]: ``1/rate_hz`` when the step is a whole
    number of them, else the longest frame that divides the step and is no longer than ``1/rate_hz``
    (``step_s / ceil(step_s * rate_hz)``: 0.005 s for 100 Hz at 120 Hz).

    >>> frame_for_step(120.0, 0.05) == 1 / 120, frame_for_step(120.0, 0.01), frame_for_step(120.0, 0.002)
    (True, 0.005, 0.002)
    """
    if not step_s > 0.0 or math.isinf(step_s):
        raise AirframeError(f"a communication step of {step_s} s: it must be positive and finite")
    if whole_frames(step_s, rate_hz) is not None:
        return 1.0 / rate_hz
    return step_s / math.ceil(step_s * rate_hz)


class Airframe:
    """A JSBSim aircraft (default UPERA) with SI inputs and outputs, its engines replaced by thrust forces.

    Parameters
    ----------
    aircraft : str or Aircraft
        The aircraft (:func:`.aircraft.load_aircraft`: a name of this package's or the jsbsim package's
        aircraft, or a folder); default UPERA.
    rate_hz : float
        Internal JSBSim rate [Hz] (default 120).
    dT_isa_K : float
        ISA temperature deviation [K].
    wind_ned_m_s : tuple of float
        Steady wind towards north, east, down [m/s].
    turbulence_severity : int
        MIL-F-8785C turbulence probability-of-exceedance index 0 (off) to 7.
    turbulence_wind_20ft_m_s : float
        Wind speed at 20 ft for low-altitude turbulence [m/s].
    seed : int
        Random seed of the turbulence model.
    fit_step_s : float, optional
        A communication step [s] the frames must divide: when it is not a whole number of frames of
        ``1/rate_hz``, the frame is the longest that divides it and is no longer than ``1/rate_hz``
        (:func:`frame_for_step`), so that every step of that size is whole frames (JSBSim's flight-control
        components take the frame length when the aircraft is built; see :meth:`step`).

    Examples
    --------
    >>> af = Airframe()
    >>> af.start_runway(48.3539, 11.7860, 263.0, 453.0)
    >>> af.set_thrust(13000.0); af.step(0.05); af.state().gs_m_s  # doctest: +SKIP
    """

    def __init__(self, rate_hz: float = DEFAULT_RATE_HZ, dT_isa_K: float = 0.0,
                 wind_ned_m_s: tuple[float, float, float] = (0.0, 0.0, 0.0), turbulence_severity: int = 0,
                 turbulence_wind_20ft_m_s: float = 0.0, seed: int = 0,
                 wind_profile: WindProfile | None = None, fit_step_s: float | None = None,
                 aircraft: str | Aircraft = DEFAULT_AIRCRAFT) -> None:
        rate_hz = _check("rate_hz", rate_hz, *_bounds(AirframeSimulation, "simulation", "rate_hz"), " Hz")
        self.dt_s = frame_for_step(rate_hz, fit_step_s) if fit_step_s is not None else 1.0 / rate_hz
        self.rate_hz = rate_hz if self.dt_s == 1.0 / rate_hz else 1.0 / self.dt_s
        os.environ.setdefault("JSBSIM_DEBUG", "0")
        import jsbsim  # imported here so the model package loads without JSBSim for table work

        ac = aircraft if isinstance(aircraft, Aircraft) else load_aircraft(aircraft)
        self.aircraft = ac
        fdm = jsbsim.FGFDMExec(str(ac.root), None)
        fdm.set_debug_level(0)
        fdm["simulation/randomseed"] = int(seed)
        # the frame length before loading: JSBSim's flight-control components (actuators' rate limits, kinematics,
        # filters) take it once, when the aircraft is built (set after, they moved at 120 Hz's rate per frame)
        fdm.set_dt(self.dt_s)
        if not fdm.load_model_with_paths(ac.name, str(ac.root / "aircraft"), str(ac.engine_path), str(ac.systems_path)):
            raise AirframeError(f"JSBSim could not load the aircraft {ac.source}")
        self._fdm = fdm
        #: UPERA's design data (its aerodynamic model: the trim's), None for another aircraft
        self.geometry = load_geometry() if ac.source == (JSBSIM_ROOT / "aircraft" / DEFAULT_AIRCRAFT /
                                                         f"{DEFAULT_AIRCRAFT}.xml").resolve() else None
        self._fuel_kg = ac.fuel_capacity_kg
        self._wf_kg_s = 0.0
        self._steps = 0  # JSBSim steps of dt_s since time zero
        self._short_s = 0.0  # the shorter last frames of steps that were not whole multiples of dt_s, summed
        self._t0_s = 0.0
        pm = fdm.get_property_manager()
        self._nodes = tuple((pm.get_node(p, True), k) for p, k in _STATE_PROPS)  # made (0) where missing: airbrake
        self._wow = pm.get_node("gear/wow")
        self._hdot = pm.get_node("velocities/h-dot-fps")
        self._agl = pm.get_node("position/h-agl-ft")
        self._phi = pm.get_node("attitude/phi-rad")
        self._gear_cmd = pm.get_node("gear/gear-cmd-norm")
        self._mass = pm.get_node("inertia/mass-slugs")
        self._added = pm.get_node(f"inertia/pointmass-weight-lbs[{ac.payload_index}]")  # the payload point mass
        self._added_kg = 0.0
        self._payload_kg = 0.0
        self._tanks = tuple((pm.get_node(f"propulsion/tank[{i}]/contents-lbs"), share)
                            for i, share in zip(ac.fuel_tank_indices, ac.fuel_shares, strict=True))
        self._thrusts = tuple(pm.get_node(f"external_reactions/{t.force}/magnitude") for t in ac.thrusters)
        self._time = pm.get_node("simulation/sim-time-sec")
        self._h_sl = pm.get_node("position/h-sl-ft")
        self._wind_nodes = tuple(pm.get_node(f"atmosphere/wind-{c}-fps") for c in ("north", "east", "down"))
        # the commands set every step, as nodes: a string key costs a look-up in the property tree per call (made
        # where the aircraft has none, as a string key's assignment makes it)
        (self._ail, self._ele, self._rud, self._flap, self._abrk, self._brk_l, self._brk_r, self._steer) = (
            pm.get_node(p, True) for p in COMMAND_PROPERTIES)
        self._wind_profile: WindProfile | None = None
        self._started = False
        self.set_atmosphere(dT_isa_K, wind_ned_m_s, turbulence_severity, turbulence_wind_20ft_m_s)
        self.set_wind_profile(wind_profile)

    # -- environment --------------------------------------------------------
    def set_atmosphere(self, dT_isa_K: float = 0.0, wind_ned_m_s: tuple[float, float, float] = (0.0, 0.0, 0.0),
                       turbulence_severity: int = 0, turbulence_wind_20ft_m_s: float = 0.0) -> None:
        """ISA deviation [K], steady wind north/east/down [m/s], MIL-F-8785C turbulence (0 = off)."""
        f = self._fdm
        self._dT_isa_K = _check("dT_isa_K", dT_isa_K,
                                *_bounds(AirframeEnvironment, "environment", "weather_dT_isa_K"), " K")
        f["atmosphere/delta-T"] = self._dT_isa_K * 1.8  # [R per K]
        n, e, d = (float(v) for v in wind_ned_m_s)
        self._wind_fps = (n / FT, e / FT, d / FT)
        f["atmosphere/wind-north-fps"], f["atmosphere/wind-east-fps"], f["atmosphere/wind-down-fps"] = self._wind_fps
        sev = int(_check("turbulence_severity", turbulence_severity,
                         *_bounds(AirframeEnvironment, "environment", "turbulence_severity")))
        f["atmosphere/turb-type"] = 3 if sev > 0 else 0  # 3: MIL-F-8785C / Tustin
        f["atmosphere/turbulence/milspec/severity"] = sev
        f["atmosphere/turbulence/milspec/windspeed_at_20ft_AGL-fps"] = float(turbulence_wind_20ft_m_s) / FT

    def set_wind_profile(self, profile: WindProfile | None) -> None:
        """Winds aloft, replacing the steady wind: ``profile(alt_m)`` gives the wind (north, east, down)
        [m/s] at an altitude MSL [m]. It is applied at the start (at the initial altitude) and at the
        beginning of every :meth:`step` at the altitude then, so a step of 0.05 s at 20 m/s of climb
        flies the wind of its first metre. None keeps the steady wind of :meth:`set_atmosphere`."""
        self._wind_profile = profile
        if profile is not None and self._started:
            self._apply_wind(self._h_sl.get_double_value() * FT)

    def _apply_wind(self, alt_m: float) -> None:
        n, e, d = self._wind_profile(alt_m)  # type: ignore[misc]
        self._wind_fps = (n / FT, e / FT, d / FT)
        for node, v in zip(self._wind_nodes, self._wind_fps, strict=True):
            node.set_double_value(v)

    # -- initial conditions -------------------------------------------------
    def _begin(self, fuel_kg: float | None) -> None:
        cap = self.aircraft.fuel_capacity_kg
        if fuel_kg is not None:
            check_loading(fuel_kg, 0.0, aircraft=self.aircraft)
        self._fuel_kg = cap if fuel_kg is None else float(fuel_kg)
        self._fill_tanks(self._fuel_kg)
        self._wf_kg_s = 0.0
        for node in self._thrusts:
            node.set_double_value(0.0)

    def _fill_tanks(self, fuel_kg: float) -> None:
        """Spread ``fuel_kg`` over the fuel tanks in proportion to their capacities (:mod:`.aircraft`)."""
        for node, share in self._tanks:
            node.set_double_value(fuel_kg * share / LBM)

    def _run_ic(self) -> None:
        # Trim status on: actuators and kinematic components start at their commands.
        f = self._fdm
        f.set_trim_status(True)
        ok = f.run_ic()
        f.set_trim_status(False)
        if not ok:
            raise AirframeError("JSBSim rejected the initial condition")
        # JSBSim's initialization copies the initial condition's wind (kept zero, see start_air)
        # into the wind model; the wind goes in afterwards, and one frame without integration
        # (time and state frozen) makes the outputs at time zero see it.
        f["atmosphere/wind-north-fps"], f["atmosphere/wind-east-fps"], f["atmosphere/wind-down-fps"] = \
            self._wind_fps
        if any(self._wind_fps):
            f.suspend_integration()
            f.run()
            f.resume_integration()

    def start_runway(self, lat_deg: float, lon_deg: float, heading_deg: float, elevation_m: float,
                     fuel_kg: float | None = None, flaps: float = 0.0) -> AirframeState:
        """Place the aircraft at rest on a runway, gear down, flaps set [0, 1], brakes released
        at time zero, thrust zero.

        It rests on its gear for ``SETTLE_S`` seconds before time zero, so the
        struts start compressed under the aircraft's weight.
        """
        f = self._fdm
        self._begin(fuel_kg)
        f["ic/lat-geod-deg"] = _check("lat_deg", lat_deg, *_bounds(AirframeStart, "start", "lat0_deg"), " deg")
        f["ic/long-gc-deg"] = _check("lon_deg", lon_deg, *_bounds(AirframeStart, "start", "lon0_deg"), " deg")
        elev = _check("elevation_m", elevation_m, *_bounds(AirframeStart, "start", "ground_elevation_m"), " m")
        f["ic/terrain-elevation-ft"] = elev / FT
        if self._wind_profile is not None:
            self._apply_wind(float(elevation_m))
        f["ic/h-agl-ft"] = self.aircraft.rest_cg_height_m / FT
        f["ic/psi-true-deg"] = float(heading_deg) % 360.0
        f["ic/vw-mag-fps"] = 0.0
        for p in ("ic/phi-deg", "ic/theta-deg", "ic/u-fps", "ic/v-fps", "ic/w-fps", "ic/p-rad_sec",
                  "ic/q-rad_sec", "ic/r-rad_sec"):
            f[p] = 0.0
        self._set_controls_at_rest(gear_down=True)
        self.set_flaps(flaps)
        self.set_brakes(1.0, 1.0)
        self._run_ic()
        for _ in range(int(round(SETTLE_S * self.rate_hz))):
            self._fdm.run()
        self.set_brakes(0.0, 0.0)
        return self._zero_time()

    def start_air(self, alt_m: float, tas_m_s: float, heading_deg: float, lat_deg: float = 48.3539,
                  lon_deg: float = 11.7860, alpha_rad: float = 0.0, elevator: float = 0.0, Fn_N: float = 0.0,
                  flaps: float = 0.0, gear_down: bool = False, fuel_kg: float | None = None,
                  ground_elevation_m: float = 0.0, flight_path_rad: float = 0.0,
                  airbrake: float = 0.0) -> AirframeState:
        """Start in wings-level flight at altitude ``alt_m`` [m] MSL and true airspeed ``tas_m_s`` [m/s]
        (no sideslip, the given angle of attack [rad] and flight-path angle [rad], airbrake [0, 1]), the total
        thrust ``Fn_N`` [N] shared equally by the engines."""
        f = self._fdm
        check_air_start(alt_m, ground_elevation_m, aircraft=self.aircraft)
        self._begin(fuel_kg)
        f["ic/lat-geod-deg"] = _check("lat_deg", lat_deg, *_bounds(AirframeStart, "start", "lat0_deg"), " deg")
        f["ic/long-gc-deg"] = _check("lon_deg", lon_deg, *_bounds(AirframeStart, "start", "lon0_deg"), " deg")
        f["ic/terrain-elevation-ft"] = float(ground_elevation_m) / FT
        f["ic/h-sl-ft"] = _check("alt_m", alt_m, *_bounds(AirframeStart, "start", "alt0_m"), " m") / FT
        if self._wind_profile is not None:
            self._apply_wind(float(alt_m))
        # The initial condition is given as attitude and body-axis velocity over the ground, with
        # the initial condition's own wind zero. (With jsbsim 1.3.3, a 10 m/s tailwind set through
        # ic/vw-mag-fps and ic/vw-dir-deg gave an initial-condition airspeed of ground speed + 10 m/s,
        # but the flown airspeed was ground speed - 10 m/s, so the initial condition's wind is not used.)
        # Ground velocity = air velocity + wind.
        tas = _check("tas_m_s", tas_m_s, 0.0, 400.0, " m/s")
        alpha = _check("alpha_rad", alpha_rad, -0.5, 0.8, " rad")
        theta = alpha + float(flight_path_rad)
        psi = math.radians(float(heading_deg) % 360.0)
        n, e, d = (w * FT for w in self._wind_fps)
        ct, st, cp, sp = math.cos(theta), math.sin(theta), math.cos(psi), math.sin(psi)
        wind_body = (ct * (cp * n + sp * e) - st * d, -sp * n + cp * e, st * (cp * n + sp * e) + ct * d)
        f["ic/vw-mag-fps"] = 0.0
        f["ic/phi-rad"] = 0.0
        f["ic/theta-rad"] = theta
        f["ic/psi-true-rad"] = psi
        f["ic/u-fps"] = (tas * math.cos(alpha) + wind_body[0]) / FT
        f["ic/v-fps"] = wind_body[1] / FT
        f["ic/w-fps"] = (tas * math.sin(alpha) + wind_body[2]) / FT
        for p in ("ic/p-rad_sec", "ic/q-rad_sec", "ic/r-rad_sec"):
            f[p] = 0.0
        self._set_controls_at_rest(gear_down=gear_down)
        self.set_surfaces(elevator=elevator)
        self.set_flaps(flaps)
        self.set_airbrake(airbrake)
        for k in range(self.engines):  # the total thrust, shared equally by the engines
            self.set_thrust(Fn_N / self.engines, k)
        self._run_ic()
        return self._zero_time()

    def _set_controls_at_rest(self, gear_down: bool) -> None:
        self.set_surfaces(0.0, 0.0, 0.0)
        self.set_flaps(0.0)
        self.set_airbrake(0.0)
        self.set_gear(gear_down)
        self.set_brakes(0.0, 0.0)
        self.set_steering(0.0)

    def _zero_time(self) -> AirframeState:
        self._fdm.set_sim_time(0.0)
        self._steps = 0
        self._short_s = 0.0
        self._started = True
        return self.state()

    # -- inputs -------------------------------------------------------------
    def set_surfaces(self, aileron: float | None = None, elevator: float | None = None,
                     rudder: float | None = None) -> None:
        """Command the control surfaces, normalised to [-1, 1] (values beyond are clipped)."""
        if aileron is not None:
            self._ail.set_double_value(min(max(float(aileron), -1.0), 1.0))
        if elevator is not None:
            self._ele.set_double_value(min(max(float(elevator), -1.0), 1.0))
        if rudder is not None:
            self._rud.set_double_value(min(max(float(rudder), -1.0), 1.0))

    def set_flaps(self, flaps: float) -> None:
        """Flap command [0, 1] (1 = fully down)."""
        self._flap.set_double_value(min(max(float(flaps), 0.0), 1.0))

    def set_airbrake(self, airbrake: float) -> None:
        """Airbrake command [0, 1] (1 = fully out; the actuator limits the rate and blows back at high qbar)."""
        self._abrk.set_double_value(min(max(float(airbrake), 0.0), 1.0))

    def set_gear(self, down: bool | float) -> None:
        """Gear command: True/1 down, False/0 up."""
        self._gear_cmd.set_double_value(1.0 if float(down) >= 0.5 else 0.0)

    def set_brakes(self, left: float, right: float | None = None) -> None:
        """Wheel brakes [0, 1] on the left and right main wheels (right defaults to left)."""
        r = left if right is None else right
        self._brk_l.set_double_value(min(max(float(left), 0.0), 1.0))
        self._brk_r.set_double_value(min(max(float(r), 0.0), 1.0))

    def set_steering(self, steering: float) -> None:
        """Nose-wheel steering [-1, 1] (1 = full right)."""
        self._steer.set_double_value(min(max(float(steering), -1.0), 1.0))

    def set_thrust(self, Fn_N: float, engine: int = 0) -> None:
        """Net thrust [N] of engine ``engine`` (0-based, the file's order) along its axis (negative for reverse)."""
        self._thrusts[engine].set_double_value(float(Fn_N) / LBF)

    @property
    def engines(self) -> int:
        """The aircraft's number of engines (thrust forces)."""
        return len(self._thrusts)

    def set_fuel_flow(self, wf_kg_s: float) -> None:
        """Fuel flow of all engines [kg/s] (>= 0), burnt from the tanks during the following steps."""
        wf = float(wf_kg_s)
        if not wf >= 0.0:
            raise OutOfEnvelopeError(f"fuel flow = {wf_kg_s} kg/s is outside the valid range [0, inf) kg/s")
        self._wf_kg_s = wf

    def set_added_mass(self, mass_kg: float) -> None:
        """Mass [kg] (>= 0) added at the CG to the operating empty mass (e.g. an electrical system), from
        the next step on; JSBSim's total mass and inertia take it, with the payload, as the payload point mass."""
        m = float(mass_kg)
        if m != self._added_kg:
            check_loading(0.0, m, aircraft=self.aircraft)
            self._added_kg = m
            self._added.set_double_value((self._payload_kg + m) / LBM)

    def set_payload(self, mass_kg: float) -> None:
        """Payload [kg] (>= 0) at the empty aircraft's CG, from the next step on (with the added mass, the payload
        point mass of :mod:`.aircraft`)."""
        m = float(mass_kg)
        if m != self._payload_kg:
            check_loading(0.0, m, ("fuel_kg", "payload_kg"), aircraft=self.aircraft)
            self._payload_kg = m
            self._added.set_double_value((m + self._added_kg) / LBM)

    @property
    def payload_kg(self) -> float:
        """Payload [kg]."""
        return self._payload_kg

    @property
    def added_mass_kg(self) -> float:
        """Mass added at the CG [kg]."""
        return self._added_kg

    # -- stepping -----------------------------------------------------------
    def step(self, dt_s: float) -> None:
        """Advance by ``dt_s`` [s]: whole internal frames of ``1/rate_hz`` and, when ``dt_s`` is not a multiple of
        it, the remainder as one shorter last frame.

        JSBSim's flight-control components take the frame length when the aircraft is built, so in a shorter
        frame an actuator or kinematic moving at its rate limit moves a whole frame's worth (the integration of
        the motion itself takes the shorter frame). A host that steps at a size other than a multiple should give
        the airframe the internal rate that divides it (the FMU does so at its first step: ``fmus/airframe.py``).
        """
        if not dt_s > 0.0:
            raise AirframeError(f"step of {dt_s} s: a step must be positive")
        n = whole_frames(dt_s, self.rate_hz)
        short_s = 0.0
        if n is None:  # not a whole number of frames: the remainder as a shorter last frame
            n = math.floor(dt_s * self.rate_hz)
            short_s = dt_s - n * self.dt_s
        if not self._started:
            raise AirframeError("start the aircraft first (start_runway or start_air)")
        if self._wind_profile is not None:
            self._apply_wind(self._h_sl.get_double_value() * FT)
        run = self._fdm.run
        fill = self._fill_tanks
        burn = self._wf_kg_s * self.dt_s
        fuel = self._fuel_kg
        if burn * n + self._wf_kg_s * short_s > fuel + FUEL_ROUNDOFF_KG:
            raise FuelExhaustedError(
                f"tank empty at t = {self.time_s:.6g} s: the fuel flow input, {self._wf_kg_s:.6g} kg/s, burns "
                f"{burn * n + self._wf_kg_s * short_s:.6g} kg over the step of {dt_s:g} s, the tank holds "
                f"{fuel:.6g} kg (an engine burning from it must flame out: give it the tank's content, the "
                "airframe's fuel_kg)")
        airborne = self._wow.get_double_value() < 0.5
        sink_m_s = -self._hdot.get_double_value() * FT
        for _ in range(n):
            if burn > 0.0:
                fuel = fuel - burn if fuel > burn else 0.0
                fill(fuel)
            run()
        if short_s > 0.0:
            short_burn = self._wf_kg_s * short_s
            if short_burn > 0.0:
                fuel = fuel - short_burn if fuel > short_burn else 0.0
                fill(fuel)
            self._fdm.set_dt(short_s)
            try:
                run()
            finally:
                self._fdm.set_dt(self.dt_s)
            self._short_s += short_s
        self._fuel_kg = fuel
        self._steps += n
        agl_m = self._agl.get_double_value() * FT
        if agl_m < WINGTIP_CHECK_AGL_M:
            self._check_ground_contact(agl_m, sink_m_s if airborne and self._wow.get_double_value() > 0.5 else 0.0)

    def _check_ground_contact(self, agl_m: float, touchdown_sink_m_s: float) -> None:
        """Raise :class:`LossOfAircraftError` for a contact outside the landing envelope: a touchdown
        sinking faster than CRASH_SINK_M_S, the fuselage on the ground (gear up or collapsed), or a
        wingtip below it."""
        phi = self._phi.get_double_value()
        tip_m = agl_m - self.aircraft.wingspan_m / 2.0 * abs(math.sin(phi))
        what = ""
        if touchdown_sink_m_s > CRASH_SINK_M_S:
            what = f"touchdown sinking at {touchdown_sink_m_s:.1f} m/s (the gear holds {CRASH_SINK_M_S:g} m/s)"
        elif agl_m < CRASH_CG_AGL_M:
            what = (f"fuselage on the ground (centre of gravity {agl_m:.2f} m above it, gear "
                    f"{'down' if self._gear_cmd.get_double_value() > 0.5 else 'up'})")
        elif tip_m < 0.0:
            what = f"wingtip strike at {math.degrees(phi):.0f} deg of bank"
        if what:
            raise LossOfAircraftError(
                f"aircraft lost at t = {self.time_s:.2f} s: {what}, at {self._node('position/lat-geod-deg'):.5f} N "
                f"{self._node('position/long-gc-deg'):.5f} E, {self._node('velocities/vtrue-fps') * FT:.0f} m/s true "
                f"airspeed, sinking at {-self._hdot.get_double_value() * FT:.1f} m/s")

    def _node(self, prop: str) -> float:
        return float(self._fdm[prop])

    # -- outputs ------------------------------------------------------------
    @property
    def time_s(self) -> float:
        """Simulation time since the start [s] (whole frames x internal step, no accumulated rounding, plus the
        shorter frames of steps that were not multiples of it)."""
        return self._steps * self.dt_s + self._short_s

    @property
    def fuel_kg(self) -> float:
        """Fuel on board [kg]."""
        return self._fuel_kg

    @property
    def mass_kg(self) -> float:
        """Total mass [kg] as JSBSim uses it."""
        return self._mass.get_double_value() * SLUG

    def state(self) -> AirframeState:
        """The current state in SI units."""
        vals = [n.get_double_value() * k for n, k in self._nodes]
        return AirframeState(self.time_s, *vals, self._wow.get_double_value() > 0.5,
                             self._mass.get_double_value() * SLUG, self._fuel_kg, self._dT_isa_K)

    def values(self) -> list[float]:
        """The state as a flat list in AirframeState order (booleans as 0/1), for fast FMU output."""
        vals = [self.time_s]
        vals.extend(n.get_double_value() * k for n, k in self._nodes)
        vals.append(1.0 if self._wow.get_double_value() > 0.5 else 0.0)
        vals.append(self._mass.get_double_value() * SLUG)
        vals.append(self._fuel_kg)
        vals.append(self._dT_isa_K)
        return vals

    def speed_of_sound_m_s(self) -> float:
        """Speed of sound of JSBSim's atmosphere at the aircraft [m/s]."""
        return self._fdm["atmosphere/a-fps"] * FT

    def accelerations(self) -> tuple[float, float, float]:
        """Body-axis accelerations along x and z [m/s^2] and pitch acceleration [rad/s^2] (the trim's residuals)."""
        f = self._fdm
        return (f["accelerations/udot-ft_sec2"] * FT, f["accelerations/wdot-ft_sec2"] * FT,
                f["accelerations/qdot-rad_sec2"])

    def aero_forces(self) -> AeroForces:
        """The aerodynamic lift and drag JSBSim computes now (wind axes, positive as named), with the dynamic
        pressure, JSBSim's reference wing area and the Reynolds number on the mean chord."""
        f = self._fdm
        return AeroForces(f["aero/qbar-psf"] * PSF, f["forces/fwz-aero-lbs"] * LBF, f["forces/fwx-aero-lbs"] * LBF,
                          f["metrics/Sw-sqft"] * FT * FT, f["aero/Re"],
                          f["forces/fwz-aero-lbs"] / (f["aero/qbar-psf"] * f["metrics/Sw-sqft"]),
                          f["forces/fwx-aero-lbs"] / (f["aero/qbar-psf"] * f["metrics/Sw-sqft"]))

    def get_property(self, name: str) -> float:
        """Raw JSBSim property (English units), for diagnostics and tests."""
        return float(self._fdm[name])

    @property
    def fdm(self):  # noqa: ANN201
        """The underlying ``jsbsim.FGFDMExec`` (for diagnostics; SI conversion is the caller's then)."""
        return self._fdm

    def close(self) -> None:
        """Release JSBSim: the property nodes first, then the FDM.

        A JSBSim property node must not outlive the FDM whose property tree it points into: freed in the
        other order (as the attributes of a collected object can be, in a garbage-collected cycle), the
        node's release touches the freed tree and crashes the interpreter (JSBSim issue 201, PR 1000).
        Called by ``__del__``, so that the order holds however the adapter goes.
        """
        d = self.__dict__
        for k in [k for k, v in d.items() if _holds_node(v)]:
            d[k] = None
        d["_fdm"] = None

    def __del__(self) -> None:
        if self.__dict__.get("_fdm") is not None:
            self.close()


def _holds_node(v: object) -> bool:
    """True for a JSBSim property node or a tuple holding one (at any depth)."""
    if isinstance(v, tuple):
        return any(_holds_node(x) for x in v)
    return type(v).__name__ == "FGPropertyNode"
