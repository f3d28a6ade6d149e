"""Steady level (or straight climbing) flight of UPERA with an external thrust: angle of attack,
elevator and thrust.

JSBSim's own trim adjusts its engines' throttles, which UPERA does not have (the
thrust is an external force), so this module solves the steady equations itself:
wings level, no sideslip, a given flight-path angle (zero: level), pitch angle =
angle of attack + flight-path angle,
no rotation, and the three body-axis accelerations u', w', q' that JSBSim
computes at that state (aerodynamics, gravity, thrust at the engine's position)
set to zero with :func:`scipy.optimize.root`.

References
----------
.. [1] Stevens, B. L., Lewis, F. L., Johnson, E. N., *Aircraft Control and Simulation*,
   3rd ed., Wiley, 2016, sect. 3.6 (steady-state flight and trim).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import root

from .adapter import Airframe
from .aero import aero_model
from .errors import OutOfEnvelopeError, TrimError
from .geometry import G0

__all__ = ["TrimResult", "trim_level", "ALT_RANGE_M", "MACH_RANGE"]

ALT_RANGE_M = (0.0, 8000.0)
MACH_RANGE = (0.1, 0.85)
#: Another aircraft than UPERA (its envelope is its file's, unknown here): the range JSBSim's standard atmosphere
#: and a subsonic trim take.
ANY_ALT_RANGE_M = (-400.0, 20000.0)
ANY_MACH_RANGE = (0.05, 0.95)
#: First guess of the lift slope of another aircraft [1/rad] (a swept wing of aspect ratio 6 to 10)
GUESS_CL_ALPHA = 4.5
TOL_ACC = 1e-7  # [m/s^2] and [rad/s^2] residual accepted as converged


@dataclass(frozen=True)
class TrimResult:
    """A trimmed level-flight condition.

    Attributes
    ----------
    alt_m : altitude MSL [m]; mach [-]; mass_kg [kg]; tas_m_s : true airspeed [m/s]
    alpha_rad : angle of attack = pitch angle [rad]
    elevator : normalised elevator command [-] (> 0 trailing edge down)
    Fn_N : net thrust [N]
    lift_N, drag_N : aerodynamic lift and drag [N]
    CL, CD : lift and drag coefficients on the wing area [-]
    qbar_Pa : dynamic pressure [Pa]; re_mac : Reynolds number on the MAC [-]
    residual : largest remaining acceleration [m/s^2 or rad/s^2]
    """

    alt_m: float
    mach: float
    mass_kg: float
    tas_m_s: float
    alpha_rad: float
    elevator: float
    Fn_N: float
    lift_N: float
    drag_N: float
    CL: float
    CD: float
    qbar_Pa: float
    re_mac: float
    residual: float

    @property
    def alpha_deg(self) -> float:
        """Angle of attack [deg]."""
        return math.degrees(self.alpha_rad)

    def as_dict(self) -> dict[str, float]:
        """Fields plus ``alpha_deg``, for printing and JSON."""
        d = asdict(self)
        d["alpha_deg"] = self.alpha_deg
        return d


def _check_range(name: str, value: float, rng: tuple[float, float], unit: str) -> float:
    v = float(value)
    if not (rng[0] <= v <= rng[1]):
        raise OutOfEnvelopeError(f"{name} = {value:g}{unit} is outside the valid range "
                                 f"{rng[0]:g} to {rng[1]:g}{unit}")
    return v


def trim_level(alt_m: float, mach: float, mass_kg: float | None = None, airframe: Airframe | None = None,
               flaps: float = 0.0, gear_down: bool = False, heading_deg: float = 0.0, lat_deg: float = 48.3539,
               lon_deg: float = 11.7860, flight_path_rad: float = 0.0, airbrake: float = 0.0) -> TrimResult:
    """Trim the aircraft (default UPERA) in steady level flight, the thrust shared equally by its engines.

    UPERA is trimmed in its envelope (:data:`ALT_RANGE_M`, :data:`MACH_RANGE`) with its aerodynamic model's stall
    checks; another aircraft from a first guess, over :data:`ANY_ALT_RANGE_M` and :data:`ANY_MACH_RANGE`, its
    mass from empty to its maximum take-off mass (else full tanks; beyond full tanks the rest is payload).

    Parameters
    ----------
    alt_m : float
        Altitude above mean sea level [m], 0 to 8000 (UPERA).
    mach : float
        Mach number [-], 0.1 to 0.85 (UPERA).
    mass_kg : float, optional
        Aircraft mass [kg] between the operating empty mass and MTOM (the
        difference, less the payload and added mass the airframe holds, is fuel); default MTOM.
    airframe : Airframe, optional
        The adapter to trim (its atmosphere settings apply); a new one by default.
        On return it is initialised at the trimmed state.
    flaps : float
        Flap setting [0, 1]. gear_down : bool, gear extended.
    heading_deg, lat_deg, lon_deg : float
        True heading and position [deg]: JSBSim's Earth rotation and gravity model make the
        trim depend on them slightly (Coriolis: 0.05 % of the thrust at 190 m/s).
    flight_path_rad : float
        Flight-path angle [rad] of a steady straight climb (> 0) or descent, -0.2 to 0.3;
        0 (default) is level flight.
    airbrake : float
        Airbrake position [0, 1] (below its blow-back dynamic pressure the position is the command).

    Raises
    ------
    OutOfEnvelopeError
        Altitude, Mach or mass out of range.
    TrimError
        No solution, or one that needs more than full elevator or lies past the stall.
    """
    af = airframe or Airframe()
    g = af.geometry
    ac = af.aircraft
    a = aero_model() if g is not None else None  # UPERA's: its envelope, stall and first guess
    alt = _check_range("altitude", alt_m, ALT_RANGE_M if a is not None else ANY_ALT_RANGE_M, " m")
    m = _check_range("Mach", mach, MACH_RANGE if a is not None else ANY_MACH_RANGE, "")
    top = ac.mtom_kg or ac.empty_mass_kg + ac.fuel_capacity_kg  # the maximum take-off mass, else full tanks
    mass = top if mass_kg is None else _check_range("mass", mass_kg, (ac.empty_mass_kg, top), " kg")
    fuel = mass - ac.empty_mass_kg - (af.payload_kg + af.added_mass_kg)  # the masses the airframe holds stay
    if fuel < 0.0:
        raise OutOfEnvelopeError(f"mass = {mass:g} kg is below the empty aircraft's {ac.empty_mass_kg:g} kg with the "
                                 f"payload and added mass it holds, {af.payload_kg + af.added_mass_kg:g} kg")
    if fuel > ac.fuel_capacity_kg:  # above full tanks (UPERA's MTOM is its full tank): the rest is payload
        af.set_payload(af.payload_kg + fuel - ac.fuel_capacity_kg)
        fuel = ac.fuel_capacity_kg
    weight = mass * G0
    gamma = _check_range("flight-path angle", flight_path_rad, (-0.2, 0.3), " rad")
    # Speed of sound from JSBSim's own atmosphere at this altitude.
    af.start_air(alt, 100.0, heading_deg, lat_deg, lon_deg, fuel_kg=fuel, ground_elevation_m=min(0.0, alt - 1000.0))
    tas = m * af.speed_of_sound_m_s()
    q = 0.5 * af.state().rho_amb_kg_m3 * tas ** 2
    s = g.wing.area_m2 if g is not None else af.aero_forces().wing_area_m2
    cl_req = weight * math.cos(gamma) / (q * s)
    where = f"at {alt:g} m, Mach {m:g}, {mass:g} kg"
    if a is not None:
        cl_max = a.clmax(flaps)
        if cl_req > 0.95 * cl_max:
            raise TrimError(f"level flight {where} needs CL = {cl_req:.2f}, beyond 95 % of CL_max = {cl_max:.2f} "
                            "(stall); fly faster or lower")
        alpha0 = (cl_req - float(a.cl_linear(0.0, m))) / float(a.cl_alpha(m))
    else:  # another aircraft: thin-airfoil-like first guess; JSBSim's own tables decide
        alpha0 = cl_req / GUESS_CL_ALPHA
    x0 = np.array([alpha0, 0.0, 0.05 + math.sin(gamma)])

    ground = min(0.0, alt - 1000.0)  # terrain well below, so no contact point touches it

    def residual(x: np.ndarray) -> np.ndarray:
        x = np.clip(x, [-0.45, -3.0, -2.0], [0.75, 3.0, 5.0])  # inside the tables (alpha) and sane
        # Twice: JSBSim's alpha-dot comes from the accelerations of the previous frame; the
        # second evaluation makes the residual a function of x alone (alpha-dot = 0 at the solution).
        for _ in range(2):
            af.start_air(alt, tas, heading_deg, lat_deg, lon_deg, alpha_rad=float(x[0]), elevator=float(x[1]),
                         Fn_N=float(x[2]) * weight, flaps=flaps, gear_down=gear_down, fuel_kg=fuel,
                         ground_elevation_m=ground, flight_path_rad=gamma, airbrake=airbrake)
        udot, wdot, qdot = af.accelerations()
        return np.array([udot / G0, wdot / G0, qdot])

    sol = root(residual, x0, method="hybr", options={"xtol": 1e-12})
    res = residual(sol.x)
    worst = float(np.max(np.abs(res[:2])) * G0)
    worst = max(worst, float(abs(res[2])))
    if not sol.success and worst > TOL_ACC * 100:
        raise TrimError(f"trim did not converge {where}: {sol.message} (residual {worst:.3g})")
    alpha, elev, thrust = float(sol.x[0]), float(sol.x[1]), float(sol.x[2]) * weight
    if abs(elev) > 1.0:
        raise TrimError(f"trim {where} needs elevator {elev:+.2f}, beyond full deflection [-1, 1]")
    if a is not None and alpha > a.alpha_stall(m):
        raise TrimError(f"trim {where} needs angle of attack {math.degrees(alpha):.1f} deg, past the stall "
                        f"({math.degrees(a.alpha_stall(m)):.1f} deg); fly faster or lower")
    forces = af.aero_forces()
    qbar, lift, drag = forces.qbar_Pa, forces.lift_N, forces.drag_N
    return TrimResult(alt_m=alt, mach=m, mass_kg=mass, tas_m_s=tas, alpha_rad=alpha, elevator=elev,
                      Fn_N=thrust, lift_N=lift, drag_N=drag, CL=lift / (qbar * s), CD=drag / (qbar * s),
                      qbar_Pa=qbar, re_mac=forces.re_mac, residual=worst)
