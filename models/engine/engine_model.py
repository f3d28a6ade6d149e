"""The engine in time, as the engine FMU sees it: inputs, a fixed-step ``step(dt)`` and outputs.

:class:`EngineModel` wraps :class:`.transient.TurbofanTransient` for a co-simulation
slave. It owns the states (N1, N2 [rpm], the handling-bleed valve position [-], the
burned fuel [kg]) and turns every step into a number of internal steps of at most
``dt_internal_s`` (explicit Euler or Heun), with the inputs held over the step.

Robustness (what a mission needs from an engine that is driven by a controller):

* Surge (surge margin of the worst sector below zero), flameout (burner fuel-air
  ratio below a lean limit, or a fuel flow below the minimum the burner model
  takes) and overspeed (N1 or N2 above their limits) are flags, counted as events
  on their rising edge and reported through the logger; the model carries on.
* If the gas path cannot be matched in a step (a point beyond the maps, an input
  outside the atmosphere's range), the last good state is kept, ``solver_failed``
  is set and a message goes to the logger; :meth:`EngineModel.step` never raises a
  :class:`~.errors.ModelError` after :meth:`EngineModel.start`.
* Inputs are clipped to the ranges the components accept (distortion sector and
  deficits, bleed fraction, fuel flow >= 1 % of design); a clipped input is logged
  once per kind.
* The shaft ports (``offtake_hp_W``, ``offtake_lp_W``) are signed: + power taken from
  the spool (generator, accessories), - power delivered to it (motor assist). Each is
  clipped to ``[-assist_*_max_W, offtake_*_max_W]`` of :class:`EngineLimits`; a clipped
  port sets the ``shaft_power_limited`` flag (an event, logged on its rising edge), and
  the power the spool actually got is published as ``offtake_*_applied_W``.
* The handling bleed (HPC stage into the bypass) is a valve with hysteresis on the
  corrected fan speed N1c (:class:`BleedValve`): it is commanded open when N1c falls
  below ``threshold - band/2`` and closed when it rises above ``threshold + band/2``,
  and strokes at a finite rate, so it cannot chatter.

Inlet distortion (parallel compressor, :mod:`.distortion`) is switched by an input at
any step; it applies to the fan face, the HPC face or both (``distortion_target``).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 8 (transient
performance, handling bleed, surge and flameout as transient limits), sec. 5.2.6
(inlet distortion).
A. H. Lefebvre, D. R. Ballal, "Gas Turbine Combustion", 3rd ed., 2010, ch. 5 (weak
extinction: overall fuel-air ratios of about 0.002 to 0.005 at idle conditions).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .atmosphere import free_stream
from .cycle_design import design
from .design_params import TurbofanParams, load_params, preset_path
from .distortion import Distortion
from .engine_signals import EO, FLAGS, OUTPUTS, BleedValve, EngineInputs, EngineLimits, condition_from_ambient
from .errors import FlameoutError, ModelError, OutOfRangeError
from .flow import T_STD_K
from .gas_path import OX
from .health import HealthDeltas
from .jit_kernels import AVAILABLE
from .offdesign import OffDesignPoint, TurbofanMaps, TurbofanOffDesign, scaled_maps
from .settings import EngineNumerics
from .transient import _FREE_L, _KEY_CLEAN, _ROWS9, TransientState, TurbofanTransient, _LazyResult

__all__ = ["EngineInputs", "EngineLimits", "BleedValve", "EngineModel", "OUTPUTS", "FLAGS", "INPUT_FIELDS",
           "condition_from_ambient"]

#: Lowest map beta accepted in a transient, a tenth of the beta range inside the surge-side beta line
#: (beta 0, about on the surge line). Near and beyond it the speed lines are flat or extrapolated and the
#: match can jump to a non-physical branch on which less fuel moves the compressor further toward surge; a
#: fuel flow that needs more is limited there (``fuel_limited``, ``surge``).
_BETA_FLOOR = 0.1
#: Largest customer bleed W/W25 [-] taken; a larger input is clipped (and logged).
_CUSTOMER_BLEED_MAX = 0.3
_IDX = {name: i for i, (name, _) in enumerate(OUTPUTS)}
_N_OUT = len(OUTPUTS)
_SOLVER_FAILED = [name for name, _ in FLAGS].index("solver_failed")
_FLAMEOUT = [name for name, _ in FLAGS].index("flameout")
#: Fields of EngineInputs, in order: the layout of the input array of :meth:`EngineModel.step_array`.
INPUT_FIELDS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(EngineInputs))
# the slots of the state array (jit_step.ST), also where the Python step keeps its scalars
_ST_N1, _ST_N2, _ST_VPOS, _ST_VCMD, _ST_FUEL, _ST_T, _ST_A1, _ST_A2, _ST_WFS, _ST_N1S, _ST_N2S, _ST_PT3, _ST_KEYOK = \
    range(13)
_ST_KEY, _ST_FLAG, _N_ST = 13, 27, 33


def _slot(i: int, doc: str) -> property:
    """A float attribute held in the model's state array ``_st`` at slot i."""
    return property(lambda m: float(m._st[i]), lambda m, v: m._st.__setitem__(i, v), doc=doc)


@dataclass(frozen=True)
class _SpeedClampedTurbine:
    """A scaled turbine map read at its lowest (highest) corrected speed beyond its speed range.

    In a slam acceleration the LP turbine's corrected speed N1/sqrt(Tt45) falls below
    the lowest speed line of the shipped map (0.6 of design, extrapolated to 0.54).
    A turbine's flow capacity hardly depends on speed once its nozzle guide vanes
    choke, so the flow of the lowest speed line is a fair value; its efficiency
    there is optimistic (efficiency falls with the blade-speed ratio). Used only by
    :class:`EngineModel`; steady points inside the map are unchanged.
    """

    inner: Any
    Nc_min: float
    Nc_max: float

    def evaluate(self, Nc: float, PR: float) -> Any:
        return self.inner.evaluate(Nc if Nc > self.Nc_min else (self.Nc_min if Nc < self.Nc_max else self.Nc_max)
                                   if Nc < self.Nc_max else self.Nc_max, PR)

    def kernel_tuple(self) -> Any:
        """The inner map as the compiled gas path reads it, with the clamp of :meth:`evaluate` (below only: the
        conditional expression there returns Nc unchanged above Nc_min)."""
        return self.inner.kernel_tuple(self.Nc_min)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)


def _robust_maps(maps: TurbofanMaps) -> TurbofanMaps:
    clamp = [_SpeedClampedTurbine(t, t.map.nc_rel_range[0] * t.s_Nc, t.map.nc_rel_range[1] * t.s_Nc)
             if hasattr(t, "map") else t
             for t in (maps.hpt, maps.lpt)]
    return dataclasses.replace(maps, hpt=clamp[0], lpt=clamp[1])


def _params(preset: str | TurbofanParams) -> TurbofanParams:
    p = load_params(preset_path(preset)) if isinstance(preset, str) else preset
    if not isinstance(p, TurbofanParams):
        raise ModelError(f"EngineModel needs turbofan parameters, got {type(p).__name__}")
    return p


class EngineModel:
    """Two-spool turbofan in time for a co-simulation slave.

    Every setting not given (None) takes its value in ``data/engine.json`` (:mod:`.settings`).

    Parameters
    ----------
    params : str or TurbofanParams
        A preset name (``larzac04_sls``, ``reference_study``) or design parameters.
    I_lp_kg_m2, I_hp_kg_m2 : float, optional
        Spool inertias [kg m^2]; default the parameters'.
    dt_internal_s : float
        Largest internal step [s].
    method : str
        ``"euler"`` or ``"heun"``.
    tol : float
        Tolerance of the gas-path matching, max |residual| [-].
    limits : EngineLimits
        Flag limits.
    valve : BleedValve
        Handling bleed valve.
    distortion_target : int
        Where the inlet distortion acts: 1 fan face, 2 HPC face, 3 both.
    critical_angle_deg : float
        Critical sector angle of the distortion model [deg].
    linear_input_frac : float
        With Euler steps: when only the fuel flow changed since the last match, by at most this
        fraction [-], the spool accelerations at the step start are corrected linearly (the cached
        Jacobian's fuel sensitivity) instead of matching the gas path there again; 0 disables it.
    logger : callable, optional
        Receives one line per event or failure.
    """

    @classmethod
    def from_sets(cls, params: str | TurbofanParams, numerics: EngineNumerics, limits: EngineLimits,
                  valve: BleedValve, logger: Callable[[str], None] | None = None) -> EngineModel:
        """The model of the parameter sets of ``data/engine.json`` (:mod:`.settings`), e.g. as an FMU collected
        them from its parameters."""
        return cls(params, limits=limits, valve=valve, logger=logger, **numerics.model_options())

    def __init__(self, params: str | TurbofanParams = "larzac04_sls", *, I_lp_kg_m2: float | None = None,
                 I_hp_kg_m2: float | None = None, dt_internal_s: float | None = None, method: str | None = None,
                 tol: float | None = None, limits: EngineLimits | None = None, valve: BleedValve | None = None,
                 distortion_target: int | None = None, critical_angle_deg: float | None = None,
                 linear_input_frac: float | None = None, logger: Callable[[str], None] | None = None) -> None:
        # what is not given: the values of data/engine.json (settings.py)
        file = EngineNumerics.from_file().model_options()
        dt_internal_s = file["dt_internal_s"] if dt_internal_s is None else dt_internal_s
        method = file["method"] if method is None else method
        tol = file["tol"] if tol is None else tol
        distortion_target = file["distortion_target"] if distortion_target is None else distortion_target
        critical_angle_deg = file["critical_angle_deg"] if critical_angle_deg is None else critical_angle_deg
        linear_input_frac = file["linear_input_frac"] if linear_input_frac is None else linear_input_frac
        limits = EngineLimits.from_file() if limits is None else limits
        valve = BleedValve.from_file() if valve is None else valve
        if method not in ("euler", "heun"):
            raise ModelError(f"EngineModel: method={method!r} must be 'euler' or 'heun'")
        if not dt_internal_s > 0.0:
            raise OutOfRangeError(f"EngineModel: dt_internal_s={dt_internal_s!r} must be > 0")
        if distortion_target not in (1, 2, 3):
            raise OutOfRangeError(f"EngineModel: distortion_target={distortion_target!r} must be 1 (fan), "
                                  "2 (HPC) or 3 (both)")
        if not (valve.band_pct >= 0.0 and valve.stroke_s > 0.0 and 0.0 <= valve.open_frac < 0.5):
            raise OutOfRangeError(f"EngineModel: bleed valve {valve} needs band_pct >= 0, stroke_s > 0, "
                                  "open_frac in [0, 0.5)")
        p = _params(params)
        self.dp = design(p)
        # the maps extended to sub-idle (map_extension.py), so idle is where a real engine idles; a fast chop
        # on them would drive the fan to its surge line (N2 falling faster than N1) were it not for the fuel
        # system's minimum-flow stop on Pt3 (EngineLimits.Wf_Pt3_min_frac), applied in _kwargs
        maps = _robust_maps(scaled_maps(self.dp, extended=True))
        # the fuel system's stops in this design's units: minimum Wf/Pt3 [kg/(s Pa)], decel rate [kg/s^2]
        self.Wf_Pt3_min_kg_s_Pa = limits.Wf_Pt3_min_frac * self.dp.Wf_kg_s / self.dp.stations["3"].Pt_Pa
        self.Wf_decel_max_kg_s2 = limits.Wf_decel_max_frac_s * self.dp.Wf_kg_s
        self.od = TurbofanOffDesign(self.dp, maps, valve.open_frac, valve.threshold_N1c_pct)
        self.tr = TurbofanTransient(self.od, I_lp_kg_m2, I_hp_kg_m2)
        self.p, self.dt_internal_s, self.method, self.tol = p, dt_internal_s, method, tol
        self._Nc1_d = self.dp.components["fan_outer"].Nc_rpm
        self.limits, self.valve, self.target, self.crit = limits, valve, distortion_target, critical_angle_deg
        self.linear_input_frac = linear_input_frac
        self.log: Callable[[str], None] = logger if logger is not None else (lambda msg: None)
        # the scalars of the state, in one array the compiled step reads and writes (jit_step.ST)
        self._st = np.zeros(_N_ST)
        #: Step with the compiled step (:mod:`.jit_step`) where it applies; False: the Python step around the
        #: compiled match (the same numbers, slower; for benchmarks and tests). The compiled step reads the
        #: limits, the valve and ``linear_input_frac`` when it takes over from a Python step (after
        #: :meth:`start`, and after any step it leaves to Python): set them before :meth:`start`.
        self.compiled_step = True
        self._fast: tuple[Any, ...] | None = None   # (par, J_in, Js_free, Js_in, J_base, bundle) of the compiled step
        self._buf: np.ndarray | None = None         # the last match as jit_step.BUF, when the compiled step holds it
        self._bufs = np.zeros((2, 0))               # the compiled step's two match buffers: the last, the next
        self._k = 0                                 # the row of _bufs holding the last match
        self._rows = (self._bufs[0], self._bufs[1])
        # (step asked, rounded, internal step, dt_internal_s it was formed with)
        self._dt: tuple[float | None, float, float, float] = (None, 0.0, 0.0, dt_internal_s)
        self._cache_of_current = self._cache_of_buf
        self._lazy = False                          # the state is to be formed from _buf when read
        self._state: TransientState | None = None
        self._uin = np.empty(len(INPUT_FIELDS))
        self._vals = np.empty(len(OUTPUTS))
        self.t_s = 0.0
        self.N1_rpm = self.N2_rpm = 0.0
        self.valve_pos = 0.0
        self.valve_open_cmd = False
        self.fuel_burned_kg = 0.0
        #: The outputs (:data:`OUTPUTS`); a caller may append slots after them (the engine FMU: an engine file's own
        #: outputs, 0 for a preset), which the steps leave as they are
        self.values: list[float] = [0.0] * len(OUTPUTS)
        self.flags: list[bool] = [False] * len(FLAGS)
        self.events = 0
        self.failures = 0
        self.fuel_limited = False
        self.port_W = (0.0, 0.0)                # (HP, LP) shaft port powers applied [W], + taken from the spool
        self.port_limited = False
        self.message = ""
        #: The flame-out's message after :meth:`flame_out` (the engine cannot be stepped on), else "".
        self.flamed_out = ""
        self.state = None
        self._key = None
        self._clipped: set[str] = set()
        self._theta: tuple[object, float] = (None, 1.0)        # (flight condition, sqrt(Tt2 / 288.15 K))
        #: The health parameters applied (:meth:`set_health`); the clean scalars of the maps the gas path reads
        self.health = HealthDeltas()
        self._clean_scalars: tuple[np.ndarray, ...] | None = None

    def set_health(self, health: HealthDeltas) -> None:
        """Apply health parameters (:mod:`.health`) to the maps the gas path reads: the flow and efficiency
        scalars of fan, HPC, HPT and LPT times (1 + delta), from their clean values. Between steps (also before
        :meth:`start`, which then finds the degraded engine's steady state); the next step matches the gas path
        again at its start (no linearised shortcut across a change of the engine)."""
        fc = self.od.fast
        if self._clean_scalars is None:
            self._clean_scalars = tuple(m[6].copy() for m in fc.maps)
        for m, clean, (k_Wc, k_eta) in zip(fc.maps, self._clean_scalars, health.factors(), strict=True):
            m[6][0], m[6][2] = clean[0] * k_Wc, clean[2] * k_eta
        self.health = health
        self._key = None

    # ------------------------------------------------------------------ state
    N1_rpm = _slot(_ST_N1, "LP spool speed [rpm].")
    N2_rpm = _slot(_ST_N2, "HP spool speed [rpm].")
    valve_pos = _slot(_ST_VPOS, "Handling bleed valve position [-], 0 closed, 1 open.")
    fuel_burned_kg = _slot(_ST_FUEL, "Fuel burned since the start [kg].")
    t_s = _slot(_ST_T, "Time [s].")

    @property
    def valve_open_cmd(self) -> bool:
        """Whether the handling bleed valve is commanded open."""
        return bool(self._st[_ST_VCMD])

    @valve_open_cmd.setter
    def valve_open_cmd(self, v: bool) -> None:
        self._st[_ST_VCMD] = 1.0 if v else 0.0

    @property
    def _key(self) -> tuple[float, ...] | None:
        """The inputs of the last step that matched (:meth:`_make_key`), None after a failed or limited one."""
        return tuple(self._st[_ST_KEY:_ST_FLAG].tolist()) if self._st[_ST_KEYOK] else None

    @_key.setter
    def _key(self, key: tuple[float, ...] | None) -> None:
        self._st[_ST_KEYOK] = key is not None
        if key is not None:
            self._st[_ST_KEY:_ST_FLAG] = key

    @property
    def state(self) -> TransientState | None:
        """The engine at the last match (:class:`.transient.TransientState`), None before :meth:`start`."""
        if self._lazy:                          # held by the compiled step: formed now, as the Python step would
            self._lazy = False
            self._state = self._state_of(self._buf)  # type: ignore[arg-type]
        return self._state

    @state.setter
    def state(self, s: TransientState | None) -> None:
        self._lazy, self._state = False, s
        if s is not None:
            self._st[_ST_A1:_ST_N2S + 1] = (s.dN1_dt_rpm_s, s.dN2_dt_rpm_s, s.Wf_kg_s, s.N1_rpm, s.N2_rpm)

    def _state_of(self, b: np.ndarray) -> TransientState:
        """The TransientState of a match buffer (:data:`.jit_step.BUF`): the object the Python step forms there."""
        fast = self._fast
        assert fast is not None
        L = fast[8]
        t, Wf, hb, it, N1, N2, alt, Mach, dT, cust, hp, lp = b[L["t_s"]:L["size"]].tolist()
        res = _LazyResult(None, None, b[slice(*L["H"])].reshape(6, 6).copy(), int(it), int(it) + 1)
        return self.tr._make_state(t, N1, N2, b[0:9].copy(), b[9:18].copy(), b[slice(*L["o"])].copy(), res, fast[4],
                                   (alt, Mach, dT), ("Wf_kg_s", Wf), (cust, hp, lp), (None, None), hb, _ROWS9, _FREE_L)

    def _cache_of_buf(self) -> tuple[Any, ...]:
        """The transient's Jacobian cache at the match the compiled step holds (as its compiled iteration forms it)."""
        b, fast = self._buf, self._fast
        assert b is not None and fast is not None
        L = fast[8]
        return (_KEY_CLEAN, b[slice(*L["H"])].reshape(6, 6).copy(), fast[1], fast[2], fast[3],
                b[slice(*L["sens"])].copy())

    def _hold(self) -> None:
        """After a Python step: hand its match to the compiled step if that applies there (no distortion, the
        compiled iteration's cache), else leave the compiled step off until it does."""
        s, tr, self._buf = self._state, self.tr, None
        if not (self.compiled_step and AVAILABLE) or self.method != "euler" or s is None or s.fast is None or \
                s._xa is None:
            return
        c, fc = tr._cache, self.od.fast
        if c is None or len(c) != 6 or c[0] != _KEY_CLEAN or not fc or not tr.compiled_iteration or \
                s.distortion != (None, None):
            return
        fcb, f = tr.bundle(fc), self._fast
        if f is None or f[1] is not c[2] or f[2] is not c[3] or f[3] is not c[4] or f[4] is not s._jbase or \
                f[5] is not fcb:
            from .jit_step import buffer_layout, resolved, step_data  # (needs numba: imported where it runs)
            L = buffer_layout(len(fc.o))
            if self._bufs.shape[1] != L["size"]:
                self._bufs = np.zeros((2, L["size"]))
                self._rows = (self._bufs[0], self._bufs[1])
            par = self._par(len(fc.o)) if f is None else f[0]
            data = step_data(fcb, par, self._st, self._uin, self._vals, c[2], c[3], c[4], self._bufs)
            self._fast = (par, c[2], c[3], c[4], s._jbase, fcb, data, resolved(data), L)
        else:                                   # the constants as they are now (shared with the StepData)
            f[0][:] = self._par(len(fc.o))
        L = self._fast[8]
        b = self._rows[self._k]
        b[0:9] = s._xa
        b[slice(*L["H"])] = c[1].ravel()
        b[slice(*L["sens"])] = c[5]
        self._buf = b

    def _par(self, n_out: int) -> np.ndarray:
        """The constants of the compiled step (:data:`.jit_step.PAR`), from this model's; `n_out` the length of
        the compiled cycle's output array."""
        from .jit_step import PAR
        lim, v, p, od = self.limits, self.valve, self.p, self.od
        val = dict(Wf_min_kg_s=lim.Wf_min_frac * self.dp.Wf_kg_s, Wf_Pt3_min_kg_s_Pa=self.Wf_Pt3_min_kg_s_Pa,
                   Wf_decel_max_kg_s2=self.Wf_decel_max_kg_s2, assist_hp_max_W=lim.assist_hp_max_W,
                   offtake_hp_max_W=lim.offtake_hp_max_W, assist_lp_max_W=lim.assist_lp_max_W,
                   offtake_lp_max_W=lim.offtake_lp_max_W, linear_input_frac=self.linear_input_frac,
                   N1_design_rpm=p.N1_rpm, N2_design_rpm=p.N2_rpm, Wf_ref_kg_s=od.ref["Wf"], P_hp_ref_W=od.ref["P_hp"],
                   P_lp_ref_W=od.ref["P_lp"], I_lp_kg_m2=self.tr.I_lp, I_hp_kg_m2=self.tr.I_hp,
                   threshold_N1c_pct=v.threshold_N1c_pct, band_pct=v.band_pct, stroke_s=v.stroke_s,
                   open_frac=v.open_frac, Nc1_design_rpm=self._Nc1_d, BPR_design=p.BPR, FAR_lean=lim.FAR_lean,
                   N1_max_pct=lim.N1_max_pct, N2_max_pct=lim.N2_max_pct, beta_floor=_BETA_FLOOR, T_std_K=T_STD_K,
                   customer_bleed_max=_CUSTOMER_BLEED_MAX, n_out=n_out)
        return np.array([float(val[n]) for n in PAR])

    # ------------------------------------------------------------------ inputs
    def _clip(self, kind: str, v: float, lo: float, hi: float) -> float:
        if lo <= v <= hi:
            return v
        if kind not in self._clipped:
            self._clipped.add(kind)
            self.log(f"engine: input {kind}={v!r} clipped to [{lo}, {hi}] at t={self.t_s:.6g} s")
        return min(hi, max(lo, v)) if v == v else lo

    def _port(self, v: float, assist_max_W: float, offtake_max_W: float) -> tuple[float, bool]:
        """A shaft port's power [W] clipped to [-assist_max_W, offtake_max_W] (not a number: 0), and whether
        it was clipped."""
        if -assist_max_W <= v <= offtake_max_W:
            return v, False
        return (offtake_max_W if v > offtake_max_W else -assist_max_W) if v == v else 0.0, True

    def _fuel_stops(self, Wf_cmd_kg_s: float) -> float:
        """The commanded fuel flow [kg/s] raised to the fuel system's stops: a fixed minimum flow and the
        minimum-flow stop scheduled on the compressor delivery pressure of the last step (what the burner gets
        below a commanded chop; flagged, not clipped-logged)."""
        Wf_min = max(self.limits.Wf_min_frac * self.dp.Wf_kg_s,
                     self.Wf_Pt3_min_kg_s_Pa * self.values[_IDX["Pt3_Pa"]])
        return Wf_cmd_kg_s if Wf_cmd_kg_s >= Wf_min else Wf_min

    def metered_fuel_kg_s(self, Wf_cmd_kg_s: float, dt_s: float) -> float:
        """The fuel flow [kg/s] the fuel system meters over the next step of `dt_s` [s] for the command: raised
        to its stops (:meth:`_fuel_stops`) and held to its deceleration limit, as :meth:`step` applies them."""
        Wf = self._fuel_stops(Wf_cmd_kg_s)
        Wf_slew = self._st[_ST_WFS] - self.Wf_decel_max_kg_s2 * round(dt_s, 12)
        return Wf if Wf >= Wf_slew else Wf_slew

    def flame_out(self, dt_s: float, cause: str) -> list[float]:
        """The step of `dt_s` [s] in which the burner gets no fuel (`cause`, e.g. the tanks are empty): it burns
        nothing, makes no thrust, the ``flameout`` flag rises (an event, logged) and :attr:`flamed_out` holds the
        message; the spools' speeds, temperatures and pressures are those of the last step, held (there is no
        model of a windmilling engine): :meth:`step` raises :class:`~.errors.FlameoutError` from now on."""
        if self.state is not None:              # (formed from the compiled step's buffer, which goes now)
            self._buf = None                    # no compiled step after this
        self.t_s = self.t_s + dt_s
        v = self.values
        v[EO.Fn_N] = v[EO.Fg_N] = v[EO.ram_drag_N] = v[EO.Wf_kg_s] = 0.0
        v[EO.dN1_dt_rpm_s] = v[EO.dN2_dt_rpm_s] = 0.0
        v[EO.SFC_kg_N_s] = math.inf
        self.flamed_out = self.message = (f"engine: flame-out at t = {self.t_s:.6g} s: {cause}; "
                                          f"{self.fuel_burned_kg:.6g} kg burned since the start")
        if not self.flags[_FLAMEOUT]:
            self.events += 1
        self.flags[_FLAMEOUT] = True
        self._st[_ST_FLAG + _FLAMEOUT] = 1.0
        self.log(self.message)
        return v

    def _kwargs(self, u: EngineInputs) -> tuple[float, dict[str, object]]:
        """Fuel flow [kg/s] and keyword arguments of :meth:`.transient.TurbofanTransient.state`."""
        Wf = self._fuel_stops(u.Wf_cmd_kg_s)
        dist: tuple[Distortion | None, Distortion | None] = (None, None)
        if u.distortion_on:
            d = Distortion(self._clip("distortion_sector_deg", u.distortion_sector_deg, 1.0, 359.0) / 360.0,
                           self._clip("distortion_dPt_frac", u.distortion_dPt_frac, 0.0, 0.45),
                           self._clip("distortion_dTt_K", u.distortion_dTt_K, 0.0, 300.0), self.crit)
            dist = (d if self.target & 1 else None, d if self.target & 2 else None)
        lim = self.limits
        hp, hp_cut = self._port(u.offtake_hp_W, lim.assist_hp_max_W, lim.offtake_hp_max_W)
        lp, lp_cut = self._port(u.offtake_lp_W, lim.assist_lp_max_W, lim.offtake_lp_max_W)
        self.port_W, self.port_limited = (hp, lp), hp_cut or lp_cut
        kw: dict[str, object] = dict(
            alt_m=u.alt_m, Mach=u.mach, dT_isa_K=u.dT_isa_K, distortion=dist, tol=self.tol,
            customer_bleed_frac=self._clip("customer_bleed_frac", u.customer_bleed_frac, 0.0, _CUSTOMER_BLEED_MAX),
            offtake_hp_W=hp, offtake_lp_W=lp)
        return Wf, kw

    # ------------------------------------------------------------------ start
    def start(self, u: EngineInputs, N1_pct: float | None = None) -> list[float]:
        """Steady state at the flight condition of `u` and its fuel flow, or at `N1_pct` [%] if given.

        Raises
        ------
        ModelError
            If no steady state exists there (the only place this model raises).
        """
        Wf, kw = self._kwargs(u)
        dist = kw["distortion"]
        assert isinstance(dist, tuple)
        setting = {"N1_pct": N1_pct} if N1_pct is not None else {"Wf_kg_s": Wf}
        pt: OffDesignPoint = self.od.solve(u.alt_m, u.mach, u.dT_isa_K, customer_bleed_frac=kw["customer_bleed_frac"],
                                           offtake_hp_W=kw["offtake_hp_W"], offtake_lp_W=kw["offtake_lp_W"],
                                           distortion_fan=dist[0], distortion_hpc=dist[1], **setting)
        self.valve_open_cmd = pt.N1c_pct < self.valve.threshold_N1c_pct
        self.valve_pos = 1.0 if self.valve_open_cmd else 0.0
        hb = self.valve_pos * self.valve.open_frac
        if pt.handling_bleed_frac != hb:        # inside the steady schedule's ramp: steady with the on/off valve
            pt = self.od.solve(u.alt_m, u.mach, u.dT_isa_K, customer_bleed_frac=kw["customer_bleed_frac"],
                               offtake_hp_W=kw["offtake_hp_W"], offtake_lp_W=kw["offtake_lp_W"],
                               distortion_fan=dist[0], distortion_hpc=dist[1], guess=pt, handling_bleed_frac=hb,
                               **setting)
        self.N1_rpm, self.N2_rpm = pt.N1_rpm, pt.N2_rpm
        self.t_s, self.fuel_burned_kg, self.events, self.failures = 0.0, 0.0, 0, 0
        self.flamed_out = ""
        self.state, self._key = None, None
        self.tr._cache = None
        self.state = self.tr.state(0.0, self.N1_rpm, self.N2_rpm, pt.Wf_kg_s, guess=pt,
                                   handling_bleed_frac=self.valve_pos * self.valve.open_frac, **kw)  # type: ignore[arg-type]
        self._key = self._make_key(pt.Wf_kg_s, u)
        # started at a speed: its input is the fuel it burns there (not a fuel cut)
        self._publish(pt.Wf_kg_s, u.Wf_cmd_kg_s if N1_pct is None else pt.Wf_kg_s)
        self._hold()
        return self.values

    # ------------------------------------------------------------------ step
    def _make_key(self, Wf: float, u: EngineInputs) -> tuple[float, ...]:
        return (self.N1_rpm, self.N2_rpm, self.valve_pos, Wf, u.alt_m, u.mach, u.dT_isa_K, u.offtake_hp_W,
                u.offtake_lp_W, u.customer_bleed_frac, float(u.distortion_on), u.distortion_sector_deg,
                u.distortion_dPt_frac, u.distortion_dTt_K)

    def _evaluate(self, t_s: float, N1: float, N2: float, Wf: float, u: EngineInputs,
                  kw: dict[str, object]) -> TransientState | None:
        """The matched state at speeds N1, N2 [rpm]; None (and the failure logged) if it cannot be matched."""
        try:
            s = self.tr.state(t_s, N1, N2, Wf, guess=self.state,
                              handling_bleed_frac=self.valve_pos * self.valve.open_frac, **kw)  # type: ignore[arg-type]
            if s.beta_hpc < _BETA_FLOOR or s.beta_fan < _BETA_FLOOR:
                raise ModelError(f"beyond the surge side of a compressor map (beta fan {s.beta_fan:.4f}, "
                                 f"HPC {s.beta_hpc:.4f} < {_BETA_FLOOR})")
            return s
        except (ModelError, FloatingPointError, ZeroDivisionError, OverflowError, ValueError) as exc:
            self.failures += 1
            self.tr._cache = None
            self.message = (f"engine: t={t_s:.6g} s: gas path not matched at N1={N1:.6g} rpm, N2={N2:.6g} rpm, "
                            f"Wf={Wf:.6g} kg/s, alt={u.alt_m:.6g} m, Mach={u.mach:.4g}; last good state held: "
                            f"{exc}")
            return None

    def _evaluate_limited(self, t_s: float, N1: float, N2: float, Wf: float, u: EngineInputs,
                          kw: dict[str, object]) -> tuple[TransientState, float] | None:
        """As :meth:`_evaluate`; if the fuel flow cannot be matched (a slam beyond the compressor map's
        surge side), the largest fuel flow between the last matched one and `Wf` that can be
        (bisection, 6 halvings), with the ``fuel_limited`` flag."""
        s = self._evaluate(t_s, N1, N2, Wf, u, kw)
        self.fuel_limited = False
        if s is not None or self.state is None:
            return None if s is None else (s, Wf)
        lo, hi = self.state.Wf_kg_s, Wf
        same = abs(hi - lo) <= 1e-9 * abs(hi)                  # the held fuel flow itself no longer matches
        Wf_min = self.limits.Wf_min_frac * self.dp.Wf_kg_s
        good: tuple[TransientState, float] | None = None
        for f in ((0.95, 0.9, 0.8, 0.6, 0.4) if same else (1.0, 0.8, 0.6, 0.4, 0.2)):  # one the speeds match
            s = self._evaluate(t_s, N1, N2, max(Wf_min, f * lo), u, kw)
            if s is not None:
                good = (s, max(Wf_min, f * lo))
                break
        if good is None:
            return None
        lo = good[1]
        for _ in range(6):
            mid = 0.5 * (lo + hi)
            s = self._evaluate(t_s, N1, N2, mid, u, kw)
            if s is None:
                hi = mid
            else:
                good, lo = (s, mid), mid
        self.fuel_limited = True
        return good

    def _small_change(self, key: tuple[float, ...], Wf: float) -> tuple[float, float] | None:
        """Fuel sensitivities of the spool accelerations [rpm/s per kg/s] if, since the last match, only the
        fuel flow changed by at most ``linear_input_frac`` (and the flight condition by a little: 10 m,
        Mach 0.002, 0.1 K); None otherwise (then the start of the step is matched again)."""
        old = self._key
        if not self.linear_input_frac or old is None or self.state is None or self.method != "euler":
            return None
        if key[:3] != old[:3] or key[7:] != old[7:]:            # speeds, valve, offtakes, bleed, distortion
            return None
        if abs(key[4] - old[4]) > 10.0 or abs(key[5] - old[5]) > 0.002 or abs(key[6] - old[6]) > 0.1:
            return None
        Wf0 = self.state.Wf_kg_s
        if abs(Wf - Wf0) > self.linear_input_frac * Wf0:
            return None
        return self.tr.fuel_sensitivity(self.state)

    def _sqrt_theta2(self, kw: dict[str, object]) -> float | None:
        """sqrt(Tt2 / 288.15 K) at the flight condition of `kw` (cached), None outside the atmosphere's range."""
        cond = (kw["alt_m"], kw["Mach"], kw["dT_isa_K"])
        if self._theta[0] != cond:
            try:
                fc = self.od.fast
                Tt0 = float(fc.free_stream(cond)[0]) if fc is not None else \
                    free_stream(*cond, self.od.gas).Tt0_K  # type: ignore[arg-type]
            except ModelError:
                return None
            self._theta = (cond, math.sqrt(Tt0 / T_STD_K))
        return self._theta[1]

    def _valve(self, h: float, kw: dict[str, object]) -> None:
        v = self.valve
        sq = self._sqrt_theta2(kw)
        if sq is None:                          # no flight condition: the valve holds (the match will fail)
            return
        N1c_pct = 100.0 * self.N1_rpm / sq / self._Nc1_d
        if self.valve_open_cmd and N1c_pct > v.threshold_N1c_pct + 0.5 * v.band_pct:
            self.valve_open_cmd = False
        elif not self.valve_open_cmd and N1c_pct < v.threshold_N1c_pct - 0.5 * v.band_pct:
            self.valve_open_cmd = True
        target = 1.0 if self.valve_open_cmd else 0.0
        rate = h / v.stroke_s
        self.valve_pos = min(target, self.valve_pos + rate) if target > self.valve_pos else \
            max(target, self.valve_pos - rate)

    def step(self, dt_s: float, u: EngineInputs) -> list[float]:
        """Advance by `dt_s` [s] with the inputs `u` held; returns :attr:`values` (flags in :attr:`flags`)."""
        if self._buf is not None:
            self._uin[:] = (u.Wf_cmd_kg_s, u.alt_m, u.mach, u.dT_isa_K, u.offtake_hp_W, u.offtake_lp_W,
                            u.customer_bleed_frac, u.distortion_on, u.distortion_sector_deg, u.distortion_dPt_frac,
                            u.distortion_dTt_K)
            return self.step_array(dt_s, self._uin, u)
        return self._step(dt_s, u)

    def step_array(self, dt_s: float, u: np.ndarray, inputs: EngineInputs | None = None) -> list[float]:
        """:meth:`step` with the inputs as a float array in the order of :data:`INPUT_FIELDS` (the engine FMU's
        way: no object per step); `inputs`, if given, the same inputs as an :class:`EngineInputs`."""
        if self._buf is not None and self.method == "euler":  # the compiled step (jit_step.euler_step), if it takes it
            d = self._dt
            if d[0] != dt_s or d[3] != self.dt_internal_s:  # the step and its internal step as _step forms them
                r = round(dt_s, 12)
                d = self._dt = (dt_s, r, r / max(1, math.ceil(r / self.dt_internal_s - 1e-9)), self.dt_internal_s)
            if u is not self._uin:
                self._uin[:] = u
            fast = self._fast
            out = fast[7](d[1], d[2], fast[6], self._k, self.tol)  # type: ignore[index]
            if out >= 0:
                self._k = k = 1 - self._k
                self._buf, self._lazy = self._rows[k], True
                if self.tr.cache_source is None:
                    self.tr.cache_source = self._cache_of_current
                self.values[:_N_OUT] = self._vals.tolist()
                if self.fuel_limited:
                    self.fuel_limited = False
                if out:
                    self._flags_changed(out)
                return self.values
        if inputs is None:
            inputs = EngineInputs(*u.tolist())
            inputs = dataclasses.replace(inputs, distortion_on=bool(inputs.distortion_on))
        return self._step(dt_s, inputs)

    @property
    def input_array(self) -> np.ndarray:
        """The model's own input array (the fields of :class:`EngineInputs` in the order of :data:`INPUT_FIELDS`):
        filled by the caller and passed to :meth:`step_array`, it is not copied."""
        return self._uin

    def _flags_changed(self, out: int) -> None:
        """The flags after a compiled step; their rising edges (bits 0-5 of `out`) logged as :meth:`_publish` does."""
        st = self._st
        self.flags[:] = [bool(x) for x in st[_ST_FLAG:_ST_FLAG + len(FLAGS)].tolist()]
        v = self.values
        for i, (name, _) in enumerate(FLAGS):
            if out & (1 << i):
                self.events += 1
                self.log(f"engine: t={self.t_s:.6g} s: {name} (N1 {v[EO.N1_pct]:.2f} %, N2 {v[EO.N2_pct]:.2f} %, "
                         f"SM fan {v[EO.SM_fan]:.4f}, SM HPC {v[EO.SM_hpc]:.4f}, FAR4 {v[EO.FAR4]:.5f}, shaft ports "
                         f"HP {v[EO.offtake_hp_applied_W]:.6g} W, LP {v[EO.offtake_lp_applied_W]:.6g} W)")

    def _step(self, dt_s: float, u: EngineInputs) -> list[float]:
        """The step in Python around the compiled (or Python) match; hands over to the compiled step after it."""
        if self.state is None:
            raise ModelError("EngineModel.step before start()")
        if self.flamed_out:
            raise FlameoutError(f"{self.flamed_out}: a flamed-out engine cannot be stepped on (no windmilling model)")
        # to 1 ps: masters that form the same step differently (t = k h differences, integer ns ticks) then
        # give identical results, not results that differ by the matching tolerance
        dt_s = round(dt_s, 12)
        n = max(1, math.ceil(dt_s / self.dt_internal_s - 1e-9))
        h = dt_s / n
        if self.tr.cache_source is not None:    # the compiled step's cache, formed before its buffer is let go
            self.tr._cache = self.tr._cache
        self._buf = None
        Wf, kw = self._kwargs(u)
        Wf_slew = self.state.Wf_kg_s - self.Wf_decel_max_kg_s2 * dt_s   # the fuel system's decel limit
        if Wf < Wf_slew:
            Wf = Wf_slew
        t0 = self.t_s
        failed = False
        s = self.state
        key = self._make_key(Wf, u)
        Wf_used = self.state.Wf_kg_s
        a1, a2 = s.dN1_dt_rpm_s, s.dN2_dt_rpm_s
        if key != self._key:                                   # inputs changed: derivative at the step start
            sens = self._small_change(key, Wf)
            if sens is not None:                               # linearised: no extra match
                a1, a2 = a1 + sens[0] * (Wf - Wf_used), a2 + sens[1] * (Wf - Wf_used)
            else:
                res = self._evaluate_limited(t0, self.N1_rpm, self.N2_rpm, Wf, u, kw)
                if res is None:
                    failed = True
                else:
                    (self.state, Wf_used), s = res, res[0]
                    a1, a2 = s.dN1_dt_rpm_s, s.dN2_dt_rpm_s
        t, t_end = t0, t0 + dt_s
        while not failed and t < t_end - 1e-9 * dt_s:
            hh = min(h, t_end - t)
            for _ in range(4):                                  # halve the step where the match fails
                t1 = t + hh
                N1, N2 = self.N1_rpm + hh * a1, self.N2_rpm + hh * a2
                pred_ok = True
                if self.method == "heun":
                    pred = self._evaluate(t1, N1, N2, s.Wf_kg_s, u, kw)
                    if pred is None:
                        pred_ok = False
                    else:
                        N1 = self.N1_rpm + 0.5 * hh * (a1 + pred.dN1_dt_rpm_s)
                        N2 = self.N2_rpm + 0.5 * hh * (a2 + pred.dN2_dt_rpm_s)
                res = None
                if pred_ok and N1 > 0.0 and N2 > 0.0:
                    pos, N1_old, N2_old, cmd_old = self.valve_pos, self.N1_rpm, self.N2_rpm, self.valve_open_cmd
                    self.N1_rpm, self.N2_rpm = N1, N2
                    self._valve(hh, kw)
                    res = self._evaluate_limited(t1, N1, N2, Wf, u, kw)
                    if res is None:
                        self.N1_rpm, self.N2_rpm, self.valve_pos, self.valve_open_cmd = N1_old, N2_old, pos, cmd_old
                if res is not None:
                    break
                hh *= 0.5
            if res is None:
                failed = True
                break
            (self.state, Wf_used), s = res, res[0]
            a1, a2 = s.dN1_dt_rpm_s, s.dN2_dt_rpm_s
            t = t1
        self.t_s = t0 + dt_s
        Wf_used = self.state.Wf_kg_s
        self.fuel_burned_kg += Wf_used * dt_s
        self._key = self._make_key(Wf, u) if not (failed or self.fuel_limited) else None
        if failed and not self.flags[3]:
            self.log(self.message)
        self._publish(Wf_used, u.Wf_cmd_kg_s, failed)
        self._hold()
        return self.values

    # ------------------------------------------------------------------ outputs
    def _publish(self, Wf: float, Wf_in: float, failed: bool = False) -> None:
        s = self.state
        assert s is not None
        o = s.fast.tolist()                     # the gas path's outputs at the match (Python floats: the same
        v = self.values                         # operations as the compiled step's on numpy's)
        Wf = float(Wf)
        p = self.p
        N1, N2, Fn, Pt3 = s.N1_rpm, s.N2_rpm, o[OX.Fn], o[OX.Pt3]
        v[EO.Fn_N], v[EO.Fg_N], v[EO.ram_drag_N], v[EO.Wf_kg_s] = Fn, o[OX.Fg], o[OX.ram], Wf
        v[EO.N1_rpm], v[EO.N2_rpm] = N1, N2
        v[EO.N1_pct], v[EO.N2_pct] = 100.0 * N1 / p.N1_rpm, 100.0 * N2 / p.N2_rpm
        v[EO.N1c_pct] = 100.0 * o[OX.N1c] / self._Nc1_d
        v[EO.Tt4_K], v[EO.Tt41_K], v[EO.Tt21_K], v[EO.Tt17_K], v[EO.Tt7_K] = (o[OX.Tt4], o[OX.T41], o[OX.Tt21],
                                                                               o[OX.Tt17], o[OX.Tt7])
        v[EO.Pt3_Pa], v[EO.OPR], v[EO.BPR] = Pt3, Pt3 / o[OX.Pt2], float(s.x[7] * p.BPR)
        v[EO.SM_fan], v[EO.SM_hpc] = o[OX.SM_fan], o[OX.SM_hpc]
        v[EO.SM_fan_clean], v[EO.SM_hpc_clean] = o[OX.SM_fan_clean], o[OX.SM_hpc_clean]   # the clean sectors'
        v[EO.SFC_kg_N_s] = Wf / Fn if Fn > 0.0 else math.inf
        v[EO.fuel_burned_kg] = float(self.fuel_burned_kg)
        v[EO.dN1_dt_rpm_s], v[EO.dN2_dt_rpm_s] = float(s.dN1_dt_rpm_s), float(s.dN2_dt_rpm_s)
        v[EO.handling_bleed_frac], v[EO.FAR4], v[EO.W2_kg_s] = o[OX.hb], o[OX.FAR4], o[OX.W2]
        v[EO.offtake_hp_applied_W], v[EO.offtake_lp_applied_W] = self.port_W
        v[EO.Tt3_K] = o[OX.Tt3]
        FAR4 = v[EO.FAR4]
        lim = self.limits
        N1_pct, N2_pct, SM_fan, SM_hpc = v[EO.N1_pct], v[EO.N2_pct], v[EO.SM_fan], v[EO.SM_hpc]
        new = [bool(SM_fan < 0.0 or SM_hpc < 0.0 or self.fuel_limited),
               bool(FAR4 < lim.FAR_lean or Wf_in < lim.Wf_min_frac * self.dp.Wf_kg_s),
               bool(N1_pct > lim.N1_max_pct or N2_pct > lim.N2_max_pct), failed, self.fuel_limited,
               self.port_limited]
        self._st[_ST_PT3] = v[EO.Pt3_Pa]
        self._st[_ST_FLAG:_ST_FLAG + len(new)] = new
        for i, (name, _) in enumerate(FLAGS):
            if i != _SOLVER_FAILED and new[i] and not self.flags[i]:     # a failed match is logged by step()
                self.events += 1
                self.log(f"engine: t={self.t_s:.6g} s: {name} (N1 {N1_pct:.2f} %, N2 {N2_pct:.2f} %, "
                         f"SM fan {SM_fan:.4f}, SM HPC {SM_hpc:.4f}, FAR4 {FAR4:.5f}, shaft ports HP "
                         f"{self.port_W[0]:.6g} W, LP {self.port_W[1]:.6g} W)")
        self.flags[:] = new

    def value(self, name: str) -> float:
        """One output by name (see :data:`OUTPUTS`)."""
        return self.values[_IDX[name]]
