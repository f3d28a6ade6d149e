"""Engine FMU: the two-spool turbofan in time (fuel flow and flight condition in, thrust and cycle out).

A thin pythonfmu slave over :class:`openemss.models.engine.engine_model.EngineModel`.
In initialisation the engine is put in a steady state at the initial
flight condition (inputs ``alt_m``, ``mach``, ``dT_isa_K``, or with
``use_ambient`` the ambient static ``p_amb_Pa`` and ``T_amb_K``, e.g. from the airframe): at the fuel flow
``start_Wf_kg_s`` if it is > 0, else at ``start_N1_pct``; computed when a master reads its outputs
in Initialization Mode and again for inputs set after that (``fmus/initial_outputs.py``), so that the
start is at the airframe's flight condition whatever the master's exchange. If the fuel flow
input is not set (<= 0) at that moment it takes the start point's fuel flow.

The engine is a preset (String parameter ``preset``: ``larzac04_sls``,
``reference_study``) or, with ``design_override``, the preset with every
``design_*`` parameter replacing its value, so a ``.ssv`` selects the engine; or any engine file (String
parameter ``engine_file``: a path or a shipped name, scaled by ``thrust_scale``), flown on its graph by
:class:`openemss.models.engine.graph_engine.GraphEngineModel` with the same inputs and outputs.
Surge, flameout, overspeed, fuel limiting and a failed match are Boolean outputs;
their rising edges go to the FMU logger. ``do_step`` never fails for valid but
extreme inputs: it holds the last good state and says so.
"""
from __future__ import annotations

import dataclasses
import math
from operator import itemgetter
from typing import Any

import numpy as np
from pythonfmu import Fmi2Slave
from pythonfmu.enums import Fmi2Status

from openemss.fmus.fmu_state import FmuState
from openemss.fmus.initial_outputs import InitialOutputs
from openemss.fmus.signal_io import SignalIO
from openemss.models.engine.design_params import TurbofanParams, load_params, preset_path, replace
from openemss.models.engine.engine_model import (
    FLAGS,
    INPUT_FIELDS,
    OUTPUTS,
    EngineInputs,
    EngineModel,
    condition_from_ambient,
)
from openemss.models.engine.engine_signals import (
    DESIGN_FIELDS,
    FLAMEOUT_STARVED,
    N_FILE_OUTPUTS,
    PARAMETER_SETS,
    SIGNALS,
)
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.fuel_supply import FuelSupply
from openemss.models.engine.graph_engine import GraphEngineModel
from openemss.models.engine.health import HealthDeltas, health_parameter_names
from openemss.models.engine.settings import engine_set

REQUIREMENTS = ["numpy>=1.24", "scipy>=1.10", "numba>=0.59"]
SOLVER_FAILED = [name for name, _ in FLAGS].index("solver_failed")
FLAMEOUT = [name for name, _ in FLAGS].index("flameout")
#: (field, description with unit) of the design parameters ``design_<field>``
DESIGN = tuple((f, f"{d} [{'-' if u == '1' else u}]") for f, u, d in DESIGN_FIELDS)
_INPUTS = tuple(s for s in SIGNALS if s.causality == "input")
_REAL_INPUTS = tuple(s.name for s in _INPUTS if s.type == "Real")
#: (FMU input, field of EngineInputs) of the inputs that go to the model as they are
_TO_MODEL = tuple((s.name, s.source) for s in _INPUTS if s.source in {f.name for f in dataclasses.fields(EngineInputs)})
_FIELD_INPUT = {field: name for name, field in _TO_MODEL}
#: Per field of EngineInputs (the model's input array), the slot of its FMU input among the Real inputs (the
#: slave's list ``_u``), or None for a Boolean input (read by name)
_SLOTS = tuple(_REAL_INPUTS.index(_FIELD_INPUT[f]) if _FIELD_INPUT[f] in _REAL_INPUTS else None for f in INPUT_FIELDS)
_BOOLS = tuple((i, _FIELD_INPUT[f]) for i, f in enumerate(INPUT_FIELDS) if _SLOTS[i] is None)
_ALT, _DT = INPUT_FIELDS.index("alt_m"), INPUT_FIELDS.index("dT_isa_K")
#: The health parameters (tunable): held in one list behind a setter that marks them changed, so that a step
#: costs one Boolean test, not eight attribute reads; applied to the model when they changed
_HEALTH = health_parameter_names()


class Engine(FmuState, InitialOutputs, SignalIO, Fmi2Slave):
    """Two-spool separate-flow turbofan with spool dynamics, bleeds, offtakes and inlet distortion."""

    author = "openEMSS"
    description = "Turbofan engine in time: fuel flow [kg/s] and flight condition in; thrust [N] and cycle out"

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        base = load_params(preset_path("larzac04_sls"))
        for f, _, _ in DESIGN_FIELDS:  # the design parameters start at the preset's values
            setattr(self, f"design_{f}", float(getattr(base, f)))
        self._model: EngineModel | GraphEngineModel | None = None
        self._filled_Wf_kg_s = math.nan  # the fuel flow input's value as compute_start filled it in [kg/s]
        self._hvals = [0.0] * len(_HEALTH)     # the health parameters' values, in the order of _HEALTH
        self._health_changed = False
        first, last = (i for i, s in enumerate(SIGNALS) if s.name in (_HEALTH[0], _HEALTH[-1]))
        self.register_signals(SIGNALS[:first])
        for i, row in enumerate(SIGNALS[first:last + 1]):
            self._hvals[i] = float(row.start)  # type: ignore[arg-type]
            self.register_signal(row, getter=lambda i=i: self._hvals[i], setter=lambda x, i=i: self._set_health(i, x))
        self.register_signals(SIGNALS[last + 1:])
        # the model's input array from the Real inputs (a Boolean's slot filled after): one itemgetter
        self._take = itemgetter(*(j if j is not None else 0 for j in _SLOTS))
        self._y = [0.0] * len(OUTPUTS)
        self._yb = [False] * len(FLAGS)
        self._yi = [0, 0]
        self._supply = FuelSupply()

    def _set_health(self, i: int, value: float) -> None:
        self._hvals[i] = float(value)
        self._health_changed = True

    def _inputs(self) -> EngineInputs:
        """The model's inputs, each from the FMU input the signal table names for it."""
        u = {field: getattr(self, name) for name, field in _TO_MODEL}
        if self.use_ambient:
            u["alt_m"], u["dT_isa_K"] = condition_from_ambient(self.p_amb_Pa, self.T_amb_K)
        u["distortion_on"] = bool(u["distortion_on"])
        return EngineInputs(**u)

    def _params(self) -> TurbofanParams:
        p = load_params(preset_path(self.preset))
        assert isinstance(p, TurbofanParams)
        if self.design_override:
            p = replace(p, Fn_target_N=None, **{n: float(getattr(self, f"design_{n}")) for n, _ in DESIGN})
        return p

    def _sets(self) -> dict[str, Any]:
        """The engine's parameter sets (limits, bleed valve, numerics, start) collected from the parameters that
        carry their names (``engine_signals.PARAMETER_SETS``), each checked against its range."""
        return {section: engine_set(cls, section).collect(lambda name: getattr(self, name), prefix, "engine")
                for section, (cls, prefix) in PARAMETER_SETS.items()}

    def compute_start(self) -> None:
        sets = self._sets()
        log = lambda msg: self.log(msg, Fmi2Status.warning, "logStatusWarning")  # noqa: E731
        m: EngineModel | GraphEngineModel
        if self.engine_file:        # an engine file, in time on its graph (models/engine/graph_engine.py)
            num = sets["numerics"]
            m = GraphEngineModel(self.engine_file, self.thrust_scale, limits=sets["limits"],
                                 dt_internal_s=num.dt_internal_s, tol=num.tol, logger=log)
        else:
            if self.thrust_scale != 1.0:
                raise OutOfRangeError(f"engine: thrust_scale={self.thrust_scale!r} applies to an engine_file; the "
                                      "preset's size is its design_W2_kg_s (with design_override)")
            m = EngineModel.from_sets(self._params(), sets["numerics"], sets["limits"], sets["bleed_valve"],
                                      logger=log)
        m.set_health(HealthDeltas(*self._hvals))        # the degraded engine's steady start
        self._health_changed = False
        u, start = self._inputs(), sets["start"]
        if start.start_Wf_kg_s > 0.0:
            u = dataclasses.replace(u, Wf_cmd_kg_s=start.start_Wf_kg_s)
            m.start(u)
        else:
            m.start(u, N1_pct=start.start_N1_pct)
        # the fuel flow input takes the start point's unless a master set it (a start computed again keeps
        # no fill-in of an earlier one: that was at the flight condition of then)
        if self.Wf_cmd_kg_s <= 0.0 or self.Wf_cmd_kg_s == self._filled_Wf_kg_s:
            self.Wf_cmd_kg_s = self._filled_Wf_kg_s = (m.match.Wf_kg_s if isinstance(m, GraphEngineModel) else
                                                       m.state.point.Wf_kg_s if m.state is not None else 0.0)
        if not isinstance(m, GraphEngineModel):     # a preset has no file outputs: their slots stay 0
            m.values.extend([0.0] * N_FILE_OUTPUTS)
        elif m.extra_names:
            self.log("engine: the engine file's outputs: " + ", ".join(
                f"file_out_{k + 1} = {n}" for k, n in enumerate(m.extra_names)), Fmi2Status.ok, "logAll")
        self._model = m
        self._supply = FuelSupply()
        self._y, self._yb, self._yi = m.values, m.flags, [m.events, int(m.flags[FLAMEOUT])]

    def model_inputs(self) -> np.ndarray:
        """The model's input array (:attr:`.EngineModel.input_array`) filled from the FMU's inputs."""
        uin = self._model.input_array  # type: ignore[union-attr]
        uin[:] = self._take(self._u)
        for i, name in _BOOLS:
            uin[i] = bool(getattr(self, name))
        if self.use_ambient:
            uin[_ALT], uin[_DT] = condition_from_ambient(self.p_amb_Pa, self.T_amb_K)
        return uin

    def do_step(self, current_time: float, step_size: float) -> bool:
        """One step; a step the engine cannot compute (an input not finite, or, unless
        ``accept_solver_failure``, a gas path that cannot be matched) fails with the cause logged.

        The inputs go to the model as one array (:meth:`.EngineModel.step_array`), no object per step."""
        ins = self._u
        total = sum(ins)
        if total - total != 0.0:             # an input not finite (or a sum that overflows: then checked one by one)
            bad = [f"{name}={getattr(self, name)}" for name in _REAL_INPUTS if not math.isfinite(getattr(self, name))]
            if bad:
                self.log(f"engine: t={current_time:.6g} s: input(s) not finite: {', '.join(bad)}; the engine "
                         "cannot compute its outputs", Fmi2Status.error, "logStatusError")
                return False
        m = self._model
        if self._health_changed:             # a tunable health parameter was set (a scenario's ramp)
            try:
                m.set_health(HealthDeltas(*self._hvals))  # type: ignore[union-attr]
            except OutOfRangeError as exc:
                self.log(f"engine: t={current_time:.6g} s: {exc}", Fmi2Status.error, "logStatusError")
                return False
            self._health_changed = False
        if m.flamed_out:  # type: ignore[union-attr]
            self.log(f"{m.flamed_out}: a flamed-out engine cannot be stepped on (there is no model of a "  # type: ignore[union-attr]
                     "windmilling engine)", Fmi2Status.error, "logStatusError")
            return False
        if self._supply.starves(m, self.fuel_kg, self.Wf_cmd_kg_s, step_size):  # type: ignore[arg-type]
            self._yi[0], self._yi[1] = m.events, FLAMEOUT_STARVED  # type: ignore[union-attr]
            return True
        m.step_array(step_size, self.model_inputs())  # type: ignore[union-attr]
        if m.flags[SOLVER_FAILED] and not self.accept_solver_failure:  # type: ignore[union-attr]
            self.log(f"{m.message} (outside the engine's envelope; set engine.accept_solver_failure=true "  # type: ignore[union-attr]
                     "to fly on with the state held)", Fmi2Status.error, "logStatusError")
            return False
        yi = self._yi
        yi[0], yi[1] = m.events, int(m.flags[FLAMEOUT])  # type: ignore[union-attr]
        return True
