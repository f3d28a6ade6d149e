"""Signals of the airframe: its parameters, inputs and outputs, one row each (the FMU's variables).

Outputs name the field of :class:`.adapter.AirframeState` they are read from (their accessor), i.e.
their slot of :meth:`.adapter.Airframe.values`. The parameters are the entries of ``data/airframe.yaml``
(:mod:`.settings`, with their ranges); those whose start is None are set by the FMU:
the start position and heading on the departure runway of the default mission (the EDDM runway
data are written once, in ``missions/munich.yaml``).
"""
from __future__ import annotations

from dataclasses import fields

from ..infra.signals import DEPARTURE, Signal, check_table
from .adapter import AirframeState
from .aircraft import MAX_ENGINES
from .settings import PARAMETER_SETS, airframe_set

__all__ = ["SIGNALS", "STATE_FIELDS", "THRUST_INPUTS", "FUEL_FLOW_INPUTS", "DEPARTURE_START"]

#: The start parameter each departure input stands for on a runway start.
DEPARTURE_START: dict[str, str] = {"departure_lat_deg": "lat0_deg", "departure_lon_deg": "lon0_deg",
                                   "departure_heading_deg": "heading0_deg", "departure_elevation_m": "alt0_m"}

#: The thrust and fuel-flow input of each engine, in the aircraft file's order (:mod:`.aircraft`).
THRUST_INPUTS: tuple[str, ...] = ("Fn_N", *(f"Fn_N_{k}" for k in range(2, MAX_ENGINES + 1)))
FUEL_FLOW_INPUTS: tuple[str, ...] = ("Wf_kg_s", *(f"Wf_kg_s_{k}" for k in range(2, MAX_ENGINES + 1)))

#: The slots of :meth:`.adapter.Airframe.values` (the fields of AirframeState, in order).
STATE_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(AirframeState))


def _in(name: str, unit: str, description: str, start: float | bool = 0.0, type_: str = "Real") -> Signal:
    return Signal(name, "input", unit, description, type_, start)


def _out(name: str, unit: str, description: str, accessor: str | None = None, type_: str = "Real") -> Signal:
    return Signal(name, "output", unit, description, type_, accessor=accessor)


SIGNALS: tuple[Signal, ...] = check_table((
    # start, environment, simulation: generated from data/airframe.yaml (value, unit, range, note)
    *(row for section, cls in PARAMETER_SETS.items() for row in airframe_set(cls, section).signals(variability=None)),
    _in("aileron_norm", "1", "Aileron command, -1 to 1, > 0 rolls right"),
    _in("elevator_norm", "1", "Elevator command, -1 to 1, > 0 trailing edge down (nose down)"),
    _in("rudder_norm", "1", "Rudder command, -1 to 1, > 0 yaws the nose right"),
    _in("flaps_norm", "1", "Flap command, 0 up to 1 full (30 deg)"),
    _in("airbrake_norm", "1", "Airbrake command, 0 retracted to 1 fully out (rate limited, blown back above its "
                              "limiting dynamic pressure)"),
    _in("brakes_norm", "1", "Wheel brakes, 0 to 1"),
    _in("steering_norm", "1", "Nose-wheel steering, -1 to 1, > 0 right"),
    *(_in(n, "N", f"Net thrust of engine {k + 1} along its axis") for k, n in enumerate(THRUST_INPUTS)),
    *(_in(n, "kg/s", f"Fuel flow of engine {k + 1}, burnt from the tanks") for k, n in enumerate(FUEL_FLOW_INPUTS)),
    _in("added_mass_kg", "kg", "Mass added at the CG to the operating empty mass (e.g. the electrical system's "
                               "mass_kg), 0 to 10000"),
    _in("gear_down", "1", "Landing gear command, true = down", True, "Boolean"),
    # the flight control's mission's departure runway (its outputs of the same names): a runway start whose
    # lat0_deg, lon0_deg, heading0_deg, alt0_m are left at their defaults starts there (start: the default mission's)
    *(_in(f"departure_{q}", u, f"{what} of the mission's departure runway, where a runway start is (NaN: none)")
      for q, u, what in DEPARTURE),
    _out("lat_deg", "deg", "Geodetic latitude"), _out("lon_deg", "deg", "Longitude"),
    _out("alt_m", "m", "Altitude above mean sea level"), _out("alt_agl_m", "m", "Altitude above ground"),
    _out("tas_m_s", "m/s", "True airspeed"), _out("cas_m_s", "m/s", "Calibrated airspeed"),
    _out("gs_m_s", "m/s", "Ground speed"), _out("mach", "1", "Mach number"),
    _out("alpha_rad", "rad", "Angle of attack"), _out("beta_rad", "rad", "Sideslip angle"),
    _out("phi_rad", "rad", "Roll angle"), _out("theta_rad", "rad", "Pitch angle"),
    _out("psi_rad", "rad", "True heading"),
    _out("p_rad_s", "rad/s", "Body roll rate"), _out("q_rad_s", "rad/s", "Body pitch rate"),
    _out("r_rad_s", "rad/s", "Body yaw rate"), _out("load_factor", "1", "Normal load factor Nz"),
    _out("vs_m_s", "m/s", "Vertical speed, positive up"),
    _out("p_amb_Pa", "Pa", "Ambient static pressure"),
    _out("T_amb_K", "K", "Ambient static temperature"),
    _out("rho_amb_kg_m3", "kg/m3", "Ambient density"),
    _out("airbrake_pos_norm", "1", "Airbrake position, 0 retracted to 1 fully out"),
    _out("on_ground", "1", "A wheel carries weight", type_="Boolean"),
    _out("mass_kg", "kg", "Aircraft mass"), _out("fuel_kg", "kg", "Fuel mass"),
    _out("dT_isa_K", "K", "ISA temperature deviation of the atmosphere flown (the parameter weather_dT_isa_K)"),
    # after the state: the trimmed air start (values() + these two)
    _out("trim_elevator_norm", "1", "Elevator of the trimmed air start"),
    _out("trim_Fn_N", "N", "Thrust of the trimmed air start, all engines together"),
), "models/airframe/airframe_signals.py")
