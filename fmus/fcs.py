"""Flight control system FMU: mission state machine, TECS, pitch and lateral laws, guidance, fuel control.

A thin pythonfmu slave over :class:`openemss.models.fcs.fcs.FlightControlSystem`. Its
inputs carry the airframe FMU's output names (``fmus/airframe.py``) and the engine's
``N1_pct``, ``N1c_pct`` and ``Tt41_K``; its surface, airbrake, gear, brake, steering and flap outputs carry the airframe
FMU's input names and ``Wf_cmd_kg_s`` the engine FMU's, so they connect name to name.

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

from pythonfmu import Fmi2Slave

from openemss.fmus.data import data_file
from openemss.fmus.fmu_state import FmuState
from openemss.fmus.initial_outputs import InitialOutputs
from openemss.fmus.signal_io import SignalIO
from openemss.models.common.airspeed import mach_from_tas
from openemss.models.fcs.atmosphere import isa
from openemss.models.fcs.errors import FcsError
from openemss.models.fcs.fcs import FcsOutput, FlightControlSystem
from openemss.models.fcs.fcs_signals import GAIN_DEFAULTS, SIGNALS
from openemss.models.fcs.state import AircraftState, EngineState
from openemss.models.mission.geo import LatLon, local_ne_m
from openemss.models.mission.mission import Mission, departure_runway, load_mission

REQUIREMENTS = ["pyyaml>=6.0", "numpy>=1.24", "numba>=0.59"]
DATA_FILES = ["missions/munich.yaml", "missions/README.md"]

DEFAULT_MISSION = next(s.start for s in SIGNALS if s.name == "mission_file")
_OUTPUTS = {kind: tuple(s for s in SIGNALS if s.causality == "output" and s.type == kind)
            for kind in ("Real", "Boolean", "Integer", "String")}


def _puller():  # type: ignore[no-untyped-def]
    """A function of the slave that sets its output vectors (``_y``, ``_yb``, ``_yi``, ``_ys``) from the
    outputs' accessors (attribute paths on the slave), generated from the table: one attribute load per
    path segment, the first segments (``out``, ``cmd``) loaded once (``operator.attrgetter`` over the
    paths cost three times as much, the FMU's largest line)."""
    heads: dict[str, str] = {}
    vectors = []
    for kind, attr in (("Real", "_y"), ("Boolean", "_yb"), ("Integer", "_yi"), ("String", "_ys")):
        items = []
        for r in _OUTPUTS[kind]:
            head, dot, rest = r.source.partition(".")
            if not (head.isidentifier() and all(p.isidentifier() for p in rest.split(".") if dot)):
                raise ValueError(f"fmus/fcs.py: output {r.name}: accessor {r.source!r} is not an attribute path")
            items.append(f"{heads.setdefault(head, f'_{len(heads)}')}.{rest}" if dot else f"slave.{head}")
        vectors.append(f"    slave.{attr} = [{', '.join(items)}]")
    src = ("def pull(slave):\n" + "".join(f"    {v} = slave.{h}\n" for h, v in heads.items())
           + "\n".join(vectors) + "\n")
    ns: dict[str, object] = {}
    exec(src, ns)  # noqa: S102 - the source is built from the table's accessors, checked above
    return ns["pull"]


_PULL = _puller()
_radians = math.radians
#: (name, description with unit) of the Real inputs and outputs, in the order of registration
INPUTS = tuple((s.name, s.described()) for s in SIGNALS if s.causality == "input" and s.type == "Real")
OUTPUTS = tuple((s.name, s.described()) for s in _OUTPUTS["Real"])
#: The Real inputs in the order :meth:`Fcs.do_step` unpacks them from the slave's input list ``_u`` (one
#: unpacking instead of a property call per input, about 1.5 us a step); checked against the table here.
_UNPACKED = ("lat_deg", "lon_deg", "alt_m", "tas_m_s", "gs_m_s", "vs_m_s", "phi_rad", "theta_rad", "psi_rad",
             "p_rad_s", "q_rad_s", "r_rad_s", "beta_rad", "rho_amb_kg_m3", "dT_isa_K", "mass_kg", "N1_pct", "N1c_pct",
             "Tt41_K")
if tuple(name for name, _ in INPUTS) != _UNPACKED:
    raise ImportError("fmus/fcs.py: Fcs.do_step unpacks the Real inputs as " + ", ".join(_UNPACKED)
                      + "; models/fcs/fcs_signals.py lists " + ", ".join(name for name, _ in INPUTS))


class Commands:
    """The guidance targets as outputs: the flown value where the section has none (all finite)."""

    __slots__ = ("alt_m", "tas_m_s", "mach", "track_rad", "xtk_m", "completed")

    def __init__(self) -> None:
        self.alt_m = self.tas_m_s = self.mach = self.track_rad = self.xtk_m = 0.0
        self.completed = False


class Departure:
    """The mission's departure runway as outputs (NaN without one): the airframe starts on it."""

    __slots__ = ("lat_deg", "lon_deg", "heading_deg", "elevation_m")

    def __init__(self, mission: Mission) -> None:
        rwy = departure_runway(mission)
        nan = math.nan
        self.lat_deg = rwy.threshold.lat_deg if rwy is not None else nan
        self.lon_deg = rwy.threshold.lon_deg if rwy is not None else nan
        self.heading_deg = math.degrees(rwy.heading_rad) if rwy is not None else nan
        self.elevation_m = rwy.elevation_m if rwy is not None else nan

    def named(self) -> dict[str, float]:
        """The outputs by name."""
        return {f"departure_{q}": getattr(self, q) for q in self.__slots__}


def _defaults() -> FlightControlSystem:
    """An FCS without sections: the controllers with their parameter files' values."""
    return FlightControlSystem(Mission("defaults", "", (), (), (), "<defaults>"))


class Fcs(FmuState, InitialOutputs, SignalIO, Fmi2Slave):
    """UPERA flight and propulsion control: a mission of stacked sections flown by TECS and L1 guidance."""

    author = "openEMSS"
    description = ("Flight control system: airframe state and engine N1/N1c/Tt41 in; surface, gear, brake, "
                   "steering, thrust lever and fuel-flow commands and guidance targets out")

    START_INPUTS = ()  # the start (mission, gains, initial commands) reads parameters only

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        default = load_mission(data_file(DEFAULT_MISSION, self.resources))
        rwy = departure_runway(default)  # the inputs start on it
        self.departure = Departure(default)
        self.out: FcsOutput | None = None
        self.cmd = Commands()
        self.register_signals(SIGNALS, starts={"lat_deg": rwy.threshold.lat_deg, "lon_deg": rwy.threshold.lon_deg,
                                               "alt_m": rwy.elevation_m, "psi_rad": rwy.heading_rad})
        # -- gains: every tunable parameter of the FCS under its dotted name of the Python API (valid FMI
        #    names in pythonfmu's structured naming convention; nested=False: no attribute lookup by parts),
        #    generated from the parameter files (value, unit, range, note) with the shipped system's defaults
        # every gain set so far (from the shipped system's defaults on), applied at each start
        self._pending: dict[str, float | bool] = dict(GAIN_DEFAULTS)
        self._fcs: FlightControlSystem | None = None
        rows = [row for c, spec in _defaults().parameter_sets().items()
                for row in spec.signals(f"{c}.", starts=GAIN_DEFAULTS)]
        self.gain_names: tuple[str, ...] = tuple(row.name for row in rows)
        for row in rows:
            self.register_signal(row, getter=lambda p=row.name, v=row.start: self._get_gain(p, v),
                                 setter=lambda x, p=row.name: self._set_gain(p, x), nested=False)
        # Before the first step the targets are 0, not the flown values: a master's initial fixed-point
        # exchange (ours compares with numpy.isclose) then sees them settle at once.
        self._start_outputs()
        self._prev_pos: LatLon | None = None
        self._prev_h = 0.0

    def _start_outputs(self, **named: float | bool | int | str) -> None:
        """The outputs before the first step: ``named`` values, else 0 (gear down)."""
        named = {"gear_down": True, **self.departure.named(), **named}
        self._y = [float(named.get(r.name, 0.0)) for r in _OUTPUTS["Real"]]  # type: ignore[arg-type]
        self._yb = [bool(named.get(r.name, False)) for r in _OUTPUTS["Boolean"]]
        self._yi = [int(named.get(r.name, 0)) for r in _OUTPUTS["Integer"]]  # type: ignore[arg-type]
        self._ys = [str(named.get(r.name, "")) for r in _OUTPUTS["String"]]

    # -- gains ------------------------------------------------------------------------------
    def _get_gain(self, name: str, default: float | bool) -> float | bool:
        if self._fcs is not None:
            return self._fcs.get_parameter(name)
        return self._pending.get(name, default)

    def _set_gain(self, name: str, value: float | bool) -> None:
        if self._fcs is not None:
            self._fcs.set_parameter(name, value)  # checked against its range; raises a clear ParameterError
        self._pending[name] = value  # a start computed again (in Initialization Mode) keeps it

    # -- life cycle -------------------------------------------------------------------------
    def _mission_path(self):  # type: ignore[no-untyped-def]
        from pathlib import Path

        p = Path(self.mission_file)
        if not p.is_absolute():
            p = Path(self.resources or ".") / p
        if not p.is_file():
            raise FcsError(f"fcs: mission_file '{self.mission_file}' not found (looked at {p}); give a path, "
                           f"absolute or relative to the FMU's resources folder (shipped: {DEFAULT_MISSION})")
        return p

    def compute_start(self) -> None:
        mission = load_mission(self._mission_path())
        self.departure = Departure(mission)
        fcs = FlightControlSystem(mission, Wf0_kg_s=self.Wf0_kg_s if self.Wf0_kg_s >= 0.0 else None,
                                  elevator0=self.elevator0_norm)
        for name, value in self._pending.items():
            fcs.set_parameter(name, value)
        self._fcs = fcs
        self._start_outputs(elevator_norm=self.elevator0_norm, flaps_norm=self.flaps_cmd_norm,
                            Wf_cmd_kg_s=fcs.fuel.Wf_cmd_kg_s, section_index=fcs.runner.active_index,
                            section_name=fcs.runner.active_name, mission_completed=fcs.finished)

    def do_step(self, current_time: float, step_size: float) -> bool:
        (lat, lon, alt, tas, gs, vs, phi, theta, psi, p, q, r, beta, rho, dev, mass, N1, N1c, Tt41) = self._u
        if not mass > 0.0 or not rho > 0.0:
            # Not an aircraft's state (a master that starts every input at 0, as FMPy's SSP runner does):
            # the commands are held and the mission does not advance on it.
            self.log(f"fcs: t={current_time:.6g} s: inputs are not an aircraft state (mass_kg={mass}, "
                     f"rho_amb_kg_m3={rho}); commands held")
            return True
        pos = LatLon.make(_radians(lat), _radians(lon))  # LatLon.from_deg without its class call (~0.25 us)
        if self._prev_pos is None or self._prev_h <= 0.0:
            vn, ve = gs * math.cos(psi), gs * math.sin(psi)
        else:  # the previous step's length separates the previous position from this one
            n, e = local_ne_m(self._prev_pos, pos)
            vn, ve = n / self._prev_h, e / self._prev_h
        self._prev_pos, self._prev_h = pos, step_size
        sg = vs / (1.0 if 1.0 > tas else tas)  # max(-1, min(1, vs / max(tas, 1))), NaN as 1
        sg = sg if sg < 1.0 else 1.0
        gamma = math.asin(sg if sg > -1.0 else -1.0)
        x = AircraftState.make(pos, alt, tas, math.nan, gamma, vn, ve, psi, phi, theta, p, q, r, beta,
                               0.5 * rho * tas * tas, mass, bool(self.on_ground), dev)
        fcs = self._fcs
        o = fcs.step(current_time, step_size, x, EngineState.make(N1, N1c, Tt41))  # type: ignore[union-attr]
        tg, c = o.targets, self.cmd
        a = tg.alt_cmd_m
        c.alt_m = alt if a is None or a != a else a  # (a != a: NaN)
        v = o.tas_cmd_m_s
        v = c.tas_m_s = tas if v != v else v
        c.mach = mach_from_tas(v, isa(alt, dev))
        a = tg.track_cmd_rad
        c.track_rad = math.atan2(ve, vn) if a != a else a
        a = tg.xtk_m
        c.xtk_m = 0.0 if a != a else a
        c.completed = fcs.finished  # type: ignore[union-attr]
        self.out = o
        _PULL(self)
        return True
