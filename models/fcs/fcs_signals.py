"""Signals of the flight control system: the FMU's inputs and outputs, one row each.

The inputs carry the names of the airframe's and the engine's outputs they are connected to, the
outputs those of the inputs they drive (``models/airframe/airframe_signals.py``,
``models/engine/engine_signals.py``), so the system connects name to name. An output's accessor
is an attribute path on the FMU: ``out.<field>`` reads the step's :class:`.fcs.FcsOutput`, the
other paths values the FMU derives from it. The gains and limits are parameters of their own
table: the parameter files in ``data/`` (value, unit, range, note), read by :mod:`.tunable`.

Inputs whose start is None start at the default mission's departure runway (the FMU reads it),
so that the runway's data are written once, in ``missions/munich.yaml``.
"""
from __future__ import annotations

from ..infra.signals import DEPARTURE, Signal, check_table

__all__ = ["SIGNALS", "GAIN_DEFAULTS"]

#: The gains whose FMU default is the shipped system's rather than the model's own (``data/*.yaml``, where
#: the flight idle is 0: none, for a model used without an engine). Flight idle of the Larzac 04 (the
#: fuel controller's lowest N1c demand, and the TECS lever that demands it, N1c_idle / k_delta): 40 %
#: corrected fan speed runs steadily on the engine model from sea level to 7500 m (its lowest steady N1
#: there: 18 to 30 %) and gives 0.84 kN at 600 m, Mach 0.2 (a 3-degree glide slope needs about 0.9 kN)
#: and -0.2 kN at 7500 m, Mach 0.75. The engine parameter sets (ssp/*.ssv) state it with their engine.
GAIN_DEFAULTS: dict[str, float] = {"fuel_control.N1c_idle_pct": 40.0, "tecs.lever_min": 0.40}


def _par(name: str, unit: str, description: str, start: float | str, type_: str = "Real",
         variability: str | None = None) -> Signal:
    return Signal(name, "parameter", unit, description, type_, start, variability=variability)


def _in(name: str, unit: str, description: str, start: float | bool | None = 0.0, type_: str = "Real") -> Signal:
    return Signal(name, "input", unit, description, type_, start)


def _out(name: str, unit: str, description: str, accessor: str, type_: str = "Real") -> Signal:
    return Signal(name, "output", unit, description, type_, accessor=accessor)


_NONE = "; when there is none, the flown value"

SIGNALS: tuple[Signal, ...] = check_table((
    _par("mission_file", "1", "Mission file (YAML or QGroundControl .plan), absolute or relative to the FMU's "
                              "resources folder", "missions/munich.yaml", "String"),
    # the shipped system's first fuel-flow command (the engine's steady start at 60 % N1 burns about it)
    _par("Wf0_kg_s", "kg/s", "Fuel-flow command at the start; < 0: the minimum fuel_control.Wf_min_kg_s", 0.07),
    _par("elevator0_norm", "1", "Elevator at the start (e.g. the airframe's trim_elevator_norm): the pitch "
                                "integral starts from it", 0.0),
    _par("flaps_cmd_norm", "1", "Flap setting commanded throughout (the laws do not schedule flaps), 0 to 1",
         0.0, variability="tunable"),
    _in("lat_deg", "deg", "Geodetic latitude", None), _in("lon_deg", "deg", "Longitude", None),
    _in("alt_m", "m", "Altitude above mean sea level", None), _in("tas_m_s", "m/s", "True airspeed"),
    _in("gs_m_s", "m/s", "Ground speed, used for the ground track of the first step only"),
    _in("vs_m_s", "m/s", "Vertical speed, positive up"),
    _in("phi_rad", "rad", "Roll angle"), _in("theta_rad", "rad", "Pitch angle"),
    _in("psi_rad", "rad", "True heading", None),
    _in("p_rad_s", "rad/s", "Body roll rate"), _in("q_rad_s", "rad/s", "Body pitch rate"),
    _in("r_rad_s", "rad/s", "Body yaw rate"), _in("beta_rad", "rad", "Sideslip angle"),
    _in("rho_amb_kg_m3", "kg/m3", "Ambient density, for the dynamic pressure", 1.17),
    _in("dT_isa_K", "K", "ISA temperature deviation of the atmosphere flown (the airframe's), for the airspeed "
                         "conversions"),
    _in("mass_kg", "kg", "Aircraft mass", 2100.0),
    _in("N1_pct", "%", "Engine fan speed N1, percent of design"),
    _in("N1c_pct", "%", "Engine corrected fan speed N1c, percent of design"),
    _in("Tt41_K", "K", "HP turbine rotor inlet total temperature Tt41", 700.0),
    _in("on_ground", "1", "A wheel carries weight", True, "Boolean"),
    _out("aileron_norm", "1", "Aileron command, -1 to 1, > 0 rolls right", "out.aileron_norm"),
    _out("elevator_norm", "1", "Elevator command, -1 to 1, > 0 trailing edge down (nose down)", "out.elevator_norm"),
    _out("rudder_norm", "1", "Rudder command, -1 to 1, > 0 yaws the nose right", "out.rudder_norm"),
    _out("flaps_norm", "1", "Flap command, 0 up to 1 full (the parameter flaps_cmd_norm)", "flaps_cmd_norm"),
    _out("brakes_norm", "1", "Wheel brake command, 0 to 1", "out.brakes_norm"),
    _out("steering_norm", "1", "Nose-wheel steering command, -1 to 1, > 0 right", "out.steering_norm"),
    _out("lever_norm", "1", "Thrust lever command, 0 to 1", "out.lever_norm"),
    _out("Wf_cmd_kg_s", "kg/s", "Fuel-flow command to the engine", "out.Wf_cmd_kg_s"),
    _out("theta_cmd_rad", "rad", "Pitch attitude command", "out.theta_cmd_rad"),
    _out("phi_cmd_rad", "rad", "Bank angle command", "out.phi_cmd_rad"),
    _out("alt_cmd_m", "m", f"Commanded altitude above mean sea level{_NONE}", "cmd.alt_m"),
    _out("tas_cmd_m_s", "m/s", f"Commanded true airspeed{_NONE}", "cmd.tas_m_s"),
    _out("mach_cmd", "1", f"Commanded true airspeed as Mach at the flown altitude{_NONE}", "cmd.mach"),
    _out("track_cmd_rad", "rad", f"Commanded true track{_NONE} (the ground track)", "cmd.track_rad"),
    _out("xtk_m", "m", "Cross-track error of the active path, right positive; 0 when there is none", "cmd.xtk_m"),
    _out("airbrake_norm", "1", "Airbrake command, 0 retracted to 1 fully out", "out.airbrake_norm"),
    # the mission's departure runway (its first section that names one), where the airframe starts: one source
    *(_out(f"departure_{q}", u, f"{what} of the mission's departure runway, where the airframe starts (NaN: the "
                                "mission names none)", f"departure.{q}")
      for q, u, what in DEPARTURE),
    _out("gear_down", "1", "Landing gear command, true = down", "out.gear_down", "Boolean"),
    _out("mission_completed", "1", "Every mission section is completed", "cmd.completed", "Boolean"),
    _out("section_index", "1", "Active mission section, 0-based (number of sections when the mission is "
                               "completed)", "out.targets.section_index", "Integer"),
    _out("fuel_limiter", "1", "Regulator the fuel controller selected: 0 the lever's N1c demand, 1 the Tt41 "
                              "limit, 2 the N1 limit", "out.fuel_limiter", "Integer"),
    _out("vnav_mode", "1", "Vertical mode: 0 none (ground), 1 ALT, 2 CLIMB, 3 PATH (managed descent), 4 DECEL, "
                            "5 HOLD (planned hold at a fix), 6 DESCENT (open), 7 APPROACH", "out.vnav_mode",
         "Integer"),
    _out("ils_phase", "1", "Phase of the automatic approach and landing: 0 none, 1 HOLD, 2 LOC_ARMED, 3 LOC, "
                           "4 GS, 5 FLARE, 6 DEROTATION, 7 ROLLOUT, 8 STOPPED", "out.ils_phase", "Integer"),
    _out("section_name", "1", "Active mission section name ('finished' after the last)", "out.targets.section_name",
         "String"),
    _out("section_phase", "1", "Phase within the active section", "out.targets.phase", "String"),
), "models/fcs/fcs_signals.py")
