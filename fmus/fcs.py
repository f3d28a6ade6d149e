"""Flight control system FMU: mission state machine, TECS, pitch and lateral laws, guidance, fuel control.

A thin pythonfmu slave over :class:`openemss.models.fcs.fcs.FlightControlSystem`. Its
inputs carry the airframe FMU's output names (``fmus/airframe.py``) and the engine's
``N1_pct``, ``N1c_pct`` and ``Tt41_K`` (the engine FMU, ``fmus/engine.py``, calls the
latter ``T41_K``); its surface, airbrake, gear, brake, steering and flap outputs carry the airframe
FMU's input names and ``fuel_flow_cmd_kg_s`` the engine FMU's, so they connect name to name.

Measured state. The FCS needs what the airframe does not output directly:

* ground velocity north/east (the ground track, wind included): from the change of
  position between successive steps (first step: ground speed along the heading), as
  the closed-loop tests (``tests/fcs/upera_loop.py``) do;
* the true airspeed rate: left to the FCS, which differentiates successive airspeeds;
* the air-relative flight-path angle ``asin(vs/max(tas, 1))``; the dynamic pressure
  ``rho tas^2 / 2``.

Parameters: ``mission_file`` (String, a path absolute or relative to the FMU's resources
folder; the Munich demonstration mission ships in it) and every gain, limit and time
constant of :meth:`FlightControlSystem.parameter_names`, under the same dotted names
(``tecs.k_TP``, ``fuel_control.stp_max_kg_s``, ...), tunable during the run. Their start
values, ranges and units come from the parameter files of ``openemss.models.fcs`` (data/).

Each ``doStep(t, h)`` samples the inputs at ``t``, runs one FCS step of length ``h`` and
holds the commands as outputs over the next step (a sampled-data controller: under
Gauss-Seidel with the FCS before the airframe the airframe flies them at once, under
Jacobi one step later). Before the first step the outputs are the start's: elevator
``elevator0_norm``, lever 0, fuel flow ``Wf0_kg_s``, gear down, the targets 0 (not NaN,
which a master's initial fixed-point iteration could not see settle).
"""
from __future__ import annotations

import math
from operator import itemgetter
from importlib import resources as _resources
from pathlib import Path

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String

from openemss.models.common import safe_yaml
from openemss.models.fcs.atmosphere import isa, mach_from_tas
from openemss.models.fcs.errors import FcsError
from openemss.models.fcs.fcs import OUTPUT_SIGNALS, FlightControlSystem
from openemss.models.fcs.geo import LatLon, local_ne_m
from openemss.models.fcs.mission import Mission, load_mission
from openemss.models.fcs.state import AircraftState, EngineState

REQUIREMENTS = ["pyyaml>=6.0"]
DATA_FILES = ["missions/munich.yaml", "missions/README.md"]

DEFAULT_MISSION = "missions/munich.yaml"

#: Real inputs: (name, description); all but on_ground, which is Boolean.
INPUTS: tuple[tuple[str, str], ...] = (
    ("lat_deg", "Geodetic latitude [deg]"), ("lon_deg", "Longitude [deg]"),
    ("alt_msl_m", "Altitude above mean sea level [m]"), ("tas_m_s", "True airspeed [m/s]"),
    ("gs_m_s", "Ground speed, used for the ground track of the first step only [m/s]"),
    ("vs_m_s", "Vertical speed, positive up [m/s]"),
    ("phi_rad", "Roll angle [rad]"), ("theta_rad", "Pitch angle [rad]"), ("psi_rad", "True heading [rad]"),
    ("p_rad_s", "Body roll rate [rad/s]"), ("q_rad_s", "Body pitch rate [rad/s]"),
    ("r_rad_s", "Body yaw rate [rad/s]"), ("beta_rad", "Sideslip angle [rad]"),
    ("rho_amb_kg_m3", "Ambient density, for the dynamic pressure [kg/m3]"), ("mass_kg", "Aircraft mass [kg]"),
    ("N1_pct", "Engine fan speed N1, percent of design [%]"),
    ("N1c_pct", "Engine corrected fan speed N1c, percent of design [%]"),
    ("Tt41_K", "HP turbine rotor inlet total temperature Tt41 [K]"),
)
#: Start values of the inputs (a level flight state, so an unconnected FCS computes something sane).
INPUT_START = {"alt_msl_m": 453.0, "mass_kg": 2100.0, "rho_amb_kg_m3": 1.17, "Tt41_K": 700.0,
               "lat_deg": 48.366886, "lon_deg": 11.821172, "psi_rad": math.radians(263.42)}

#: Real outputs, in the order of the cached value list: (name, description).
OUTPUTS: tuple[tuple[str, str], ...] = (
    ("aileron_norm", "Aileron command, -1 to 1, > 0 rolls right [-]"),
    ("elevator_norm", "Elevator command, -1 to 1, > 0 trailing edge down (nose down) [-]"),
    ("rudder_norm", "Rudder command, -1 to 1, > 0 yaws the nose right [-]"),
    ("flaps_norm", "Flap command, 0 up to 1 full (the parameter flaps_cmd_norm) [-]"),
    ("brakes_norm", "Wheel brake command, 0 to 1 [-]"),
    ("steering_norm", "Nose-wheel steering command, -1 to 1, > 0 right [-]"),
    ("lever_norm", "Thrust lever command, 0 to 1 [-]"),
    ("fuel_flow_cmd_kg_s", "Fuel-flow command to the engine [kg/s]"),
    ("theta_cmd_rad", "Pitch attitude command [rad]"), ("phi_cmd_rad", "Bank angle command [rad]"),
    ("alt_cmd_m", "Commanded altitude above mean sea level (NaN when none, 0 before the first step) [m]"),
    ("tas_cmd_m_s", "Commanded true airspeed (NaN when none, 0 before the first step) [m/s]"),
    ("mach_cmd", "Commanded true airspeed as Mach at the flown altitude (NaN when none, 0 before the first step) [-]"),
    ("track_cmd_rad", "Commanded true track (NaN when none, 0 before the first step) [rad]"),
    ("xtk_m", "Cross-track error of the active path, right positive (NaN when none, 0 before the first step) [m]"),
    ("airbrake_norm", "Airbrake command, 0 retracted to 1 fully out [-]"),
)
_N_REAL = len(OUTPUTS)
_N_IN = len(INPUTS)
_IDX = {name: i for i, (name, _) in enumerate(OUTPUTS)}


def _indices(vrs: list[int], base: int, n: int) -> list[int] | None:
    """Indices ``vr - base`` of value references in ``[base, base + n)``; None if any lies outside."""
    idx = [vr - base for vr in vrs]
    return idx if all(0 <= j < n for j in idx) else None


def _parameter_docs(package: str) -> dict[str, str]:
    """Description with unit of every ``<section>.<name>`` entry of the package's parameter files."""
    docs: dict[str, str] = {}
    folder = _resources.files(package).joinpath("data")
    for f in sorted(folder.iterdir(), key=lambda p: p.name):
        if not f.name.endswith(".yaml"):
            continue
        for section, entries in (safe_yaml.load(f.read_text(encoding="utf-8"), f.name) or {}).items():
            if not isinstance(entries, dict):
                continue
            for key, e in entries.items():
                if isinstance(e, dict) and "value" in e:
                    unit = str(e.get("unit", "-")).strip() or "-"
                    rng = ""
                    if "min" in e or "max" in e:
                        rng = f"; {e.get('min', '-inf')} to {e.get('max', 'inf')}"
                    docs[f"{section}.{key}"] = f"{e.get('note', key)}{rng} (data/{f.name}) [{unit}]"
    return docs


def _defaults() -> FlightControlSystem:
    """An FCS without sections: the controllers with their parameter files' values."""
    return FlightControlSystem(Mission("defaults", "", (), (), (), "<defaults>"))


class Fcs(Fmi2Slave):
    """UPERA flight and propulsion control: a mission of stacked sections flown by TECS and L1 guidance."""

    author = "openEMSS"
    description = ("Flight control system: airframe state and engine N1/N1c/Tt41 in; surface, gear, brake, "
                   "steering, thrust lever and fuel-flow commands and guidance targets out")

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        fixed, tunable, discrete = Fmi2Variability.fixed, Fmi2Variability.tunable, Fmi2Variability.discrete
        par, inp, out = Fmi2Causality.parameter, Fmi2Causality.input, Fmi2Causality.output
        # -- parameters of the FMU itself
        self.mission_file = DEFAULT_MISSION
        self.Wf0_kg_s = -1.0
        self.elevator0_norm = 0.0
        self.isa_dev_K = 0.0
        self.flaps_cmd_norm = 0.0
        self.register_variable(String("mission_file", causality=par, variability=fixed,
                                      description="Mission file (YAML or QGroundControl .plan), absolute or relative "
                                                  "to the FMU's resources folder [-]"))
        for name, desc, var in (
                ("Wf0_kg_s", "Fuel-flow command at the start; < 0: the minimum fuel_control.Wf_min_kg_s [kg/s]", fixed),
                ("elevator0_norm", "Elevator at the start (e.g. the airframe's trim_elevator_norm): the pitch "
                                   "integral starts from it [-]", fixed),
                ("isa_dev_K", "ISA temperature deviation the laws assume (as the airframe's isa_dev_K) [K]", fixed),
                ("flaps_cmd_norm", "Flap setting commanded throughout (the laws do not schedule flaps), "
                                   "0 to 1 [-]", tunable)):
            self.register_variable(Real(name, causality=par, variability=var, description=desc))
        # -- gains: every tunable parameter of the FCS under its dotted name of the Python API (valid FMI
        #    names in pythonfmu's structured naming convention; nested=False: no attribute lookup by parts)
        ref = _defaults()
        docs = _parameter_docs(FlightControlSystem.__module__.rpartition(".")[0])
        self._pending: dict[str, float | bool] = {}
        self._fcs: FlightControlSystem | None = None
        self.gain_names: tuple[str, ...] = ref.parameter_names()
        for pname in self.gain_names:
            value = ref.get_parameter(pname)
            desc = docs.get(pname, f"FCS parameter {pname} [-]")
            kind = Boolean if isinstance(value, bool) else Real
            self.register_variable(kind(pname, causality=par, variability=tunable, description=desc,
                                        getter=lambda p=pname, v=value: self._get_gain(p, v),
                                        setter=lambda x, p=pname: self._set_gain(p, x)), nested=False)
        # -- inputs, kept in one list in the order of INPUTS (consecutive value references from _in0)
        self._u = [float(INPUT_START.get(name, 0.0)) for name, _ in INPUTS]
        self._in0 = len(self.vars)
        for j, (name, desc) in enumerate(INPUTS):
            self.register_variable(Real(name, causality=inp, description=desc, getter=lambda j=j: self._u[j],
                                        setter=lambda x, j=j: self._u.__setitem__(j, float(x))))
        self.on_ground = True
        self._set_vrs: list[int] = []
        self._set_idx: list[int] | None = None
        self._set_all = False
        self._on_ground_vrs = [len(self.vars)]
        self.register_variable(Boolean("on_ground", causality=inp, variability=discrete,
                                       description="A wheel carries weight [-]"))
        # -- outputs, read from cached values
        # Before the first step the targets are 0, not NaN: a NaN output never settles in a master's
        # initial fixed-point exchange that compares with numpy.isclose (NaN != NaN), ours included.
        self._y = [0.0] * _N_REAL
        self._out0 = len(self.vars)
        for i, (name, desc) in enumerate(OUTPUTS):
            self.register_variable(Real(name, causality=out, description=desc, getter=lambda i=i: self._y[i]))
        self._get_vrs: list[int] = []
        self._get_pick = None
        vr_gear = len(self.vars)
        self._gear_down = True
        self._section_index = 0
        self._section_name = ""
        self._section_phase = ""
        self._completed = False
        self._fuel_limiter = 0
        self.register_variable(Boolean("gear_down", causality=out, variability=discrete,
                                       description="Landing gear command, true = down [-]",
                                       getter=lambda: self._gear_down))
        self.register_variable(Integer("section_index", causality=out, variability=discrete,
                                       description="Active mission section, 0-based (number of sections when the "
                                                   "mission is completed) [-]",
                                       getter=lambda: self._section_index))
        self.register_variable(String("section_name", causality=out, variability=discrete,
                                      description="Active mission section name ('finished' after the last) [-]",
                                      getter=lambda: self._section_name))
        self.register_variable(String("section_phase", causality=out, variability=discrete,
                                      description="Phase within the active section [-]",
                                      getter=lambda: self._section_phase))
        self.register_variable(Boolean("mission_completed", causality=out, variability=discrete,
                                       description="Every mission section is completed [-]",
                                       getter=lambda: self._completed))
        self.register_variable(Integer("fuel_limiter", causality=out, variability=discrete,
                                       description=OUTPUT_SIGNALS["fuel_limiter"],
                                       getter=lambda: self._fuel_limiter))
        self._vnav_mode = 0
        self._ils_phase = 0
        # the discrete outputs' value references in the order of registration (the batched gets' fast path)
        self._bool_out_vrs = [vr_gear, vr_gear + 4]  # gear_down, mission_completed
        self._int_out_vrs = [vr_gear + 1, vr_gear + 5, vr_gear + 6, vr_gear + 7]  # section_index, ..., ils_phase
        self.register_variable(Integer("vnav_mode", causality=out, variability=discrete,
                                       description=OUTPUT_SIGNALS["vnav_mode"], getter=lambda: self._vnav_mode))
        self.register_variable(Integer("ils_phase", causality=out, variability=discrete,
                                       description=OUTPUT_SIGNALS["ils_phase"], getter=lambda: self._ils_phase))
        assert [self.vars[vr].name for vr in self._bool_out_vrs + self._int_out_vrs + self._on_ground_vrs] == [
            "gear_down", "mission_completed", "section_index", "fuel_limiter", "vnav_mode", "ils_phase", "on_ground"]
        self._prev_pos: LatLon | None = None
        self._prev_h = 0.0

    # -- batched access: inputs and outputs by index, the rest through pythonfmu's variables --
    # pythonfmu's own get_/set_ methods look each variable up and call its getter or setter. A master asks
    # for the same value references every step: the batch's indices into the cached lists are resolved
    # when the references change (one list comparison per call otherwise), and served in one pass.
    def set_real(self, vrs: list[int], values: list[float]) -> None:
        if vrs != self._set_vrs:
            self._set_vrs, self._set_idx = list(vrs), _indices(vrs, self._in0, _N_IN)
            self._set_all = self._set_idx == list(range(_N_IN))
        idx, u = self._set_idx, self._u
        if idx is None:
            for vr, x in zip(vrs, values, strict=True):
                j = vr - self._in0
                if 0 <= j < _N_IN:
                    u[j] = x
                else:
                    super().set_real([vr], [x])
        elif self._set_all:
            u[:] = values
        else:
            for j, x in zip(idx, values, strict=True):
                u[j] = x

    def get_real(self, vrs: list[int]) -> list[float]:
        if vrs != self._get_vrs:
            self._get_vrs, idx = list(vrs), _indices(vrs, self._out0, _N_REAL)
            self._get_pick = None if idx is None else (itemgetter(*idx) if len(idx) > 1 else
                                                       (lambda y, j=idx[0]: (y[j],)))
        pick, y = self._get_pick, self._y
        if pick is not None:
            return list(pick(y))
        base, n = self._out0, _N_REAL
        return [y[vr - base] if 0 <= vr - base < n else super(Fcs, self).get_real([vr])[0] for vr in vrs]

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        if vrs == self._on_ground_vrs:
            self.on_ground = values[0]
        else:
            super().set_boolean(vrs, values)

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        if vrs == self._bool_out_vrs:
            return [self._gear_down, self._completed]
        return super().get_boolean(vrs)

    def get_integer(self, vrs: list[int]) -> list[int]:
        if vrs == self._int_out_vrs:
            return [self._section_index, self._fuel_limiter, self._vnav_mode, self._ils_phase]
        return super().get_integer(vrs)

    # -- gains ------------------------------------------------------------------------------
    def _get_gain(self, name: str, default: float | bool) -> float | bool:
        if self._fcs is not None:
            return self._fcs.get_parameter(name)
        return self._pending.get(name, default)

    def _set_gain(self, name: str, value: float | bool) -> None:
        if self._fcs is not None:
            self._fcs.set_parameter(name, value)  # checked against its range; raises a clear ParameterError
        else:
            self._pending[name] = value

    # -- life cycle -------------------------------------------------------------------------
    def _mission_path(self) -> Path:
        p = Path(self.mission_file)
        if not p.is_absolute():
            p = Path(self.resources or ".") / p
        if not p.is_file():
            raise FcsError(f"fcs: mission_file '{self.mission_file}' not found (looked at {p}); give a path, "
                           f"absolute or relative to the FMU's resources folder (shipped: {DEFAULT_MISSION})")
        return p

    def exit_initialization_mode(self) -> None:
        mission = load_mission(self._mission_path())
        fcs = FlightControlSystem(mission, Wf0_kg_s=self.Wf0_kg_s if self.Wf0_kg_s >= 0.0 else None,
                                  elevator0=self.elevator0_norm)
        for name, value in self._pending.items():
            fcs.set_parameter(name, value)
        self._pending.clear()
        self._fcs = fcs
        y = self._y
        y[_IDX["elevator_norm"]] = self.elevator0_norm
        y[_IDX["flaps_norm"]] = self.flaps_cmd_norm
        y[_IDX["fuel_flow_cmd_kg_s"]] = fcs.fuel.Wf_cmd_kg_s
        self._section_index = fcs.runner.active_index
        self._section_name = fcs.runner.active_name
        self._completed = fcs.finished

    def do_step(self, current_time: float, step_size: float) -> bool:
        (lat, lon, alt, tas, gs, vs, phi, theta, psi, p, q, r, beta, rho, mass, N1, N1c, Tt41) = self._u  # INPUTS
        pos = LatLon.from_deg(lat, lon)
        if self._prev_pos is None or self._prev_h <= 0.0:
            vn, ve = gs * math.cos(psi), gs * math.sin(psi)
        else:  # the previous step's length separates the previous position from this one
            n, e = local_ne_m(self._prev_pos, pos)
            vn, ve = n / self._prev_h, e / self._prev_h
        self._prev_pos, self._prev_h = pos, step_size
        gamma = math.asin(max(-1.0, min(1.0, vs / max(tas, 1.0))))
        x = AircraftState(pos, alt, tas, math.nan, gamma, vn, ve, psi, phi, theta, p, q, r, beta, 0.5 * rho * tas * tas,
                          mass, bool(self.on_ground), self.isa_dev_K)
        o = self._fcs.step(current_time, step_size, x, EngineState(N1, N1c, Tt41))
        tg = o.targets
        tas_cmd = o.tas_cmd_m_s
        mach_cmd = math.nan if math.isnan(tas_cmd) else mach_from_tas(tas_cmd, isa(alt, self.isa_dev_K))
        self._y[:] = (o.aileron, o.elevator, o.rudder, self.flaps_cmd_norm, o.brake, o.steer, o.lever,
                      o.Wf_cmd_kg_s, o.theta_cmd_rad, o.phi_cmd_rad,
                      math.nan if tg.alt_cmd_m is None else tg.alt_cmd_m, tas_cmd, mach_cmd, tg.track_cmd_rad,
                      tg.xtk_m, o.airbrake)
        self._gear_down = bool(o.gear_down)
        self._section_index = tg.section_index
        self._section_name = tg.section_name
        self._section_phase = tg.phase
        self._completed = self._fcs.finished
        self._fuel_limiter = o.fuel_limiter
        self._vnav_mode = o.vnav_mode
        self._ils_phase = o.ils_phase
        return True
