"""Engine FMU: the two-spool turbofan in time (fuel flow and flight condition in, thrust and cycle out).

A thin pythonfmu slave over :class:`openemss.models.engine.engine_model.EngineModel`.
At the end of initialisation the engine is put in a steady state at the initial
flight condition (inputs ``alt_m``, ``mach``, ``isa_dev_K``, or with
``use_ambient`` the ambient static ``p_amb_Pa`` and ``T_amb_K``, e.g. from the airframe): at the fuel flow
``start_fuel_flow_kg_s`` if it is > 0, else at ``start_N1_pct``. If the fuel flow
input is not set (<= 0) at that moment it takes the start point's fuel flow.

The engine is a preset (String parameter ``preset``: ``larzac04_sls``,
``reference_study``) or, with ``design_override``, the preset with every
``design_*`` parameter replacing its value, so a ``.ssv`` selects the engine.
Surge, flameout, overspeed, fuel limiting and a failed match are Boolean outputs;
their rising edges go to the FMU logger. ``do_step`` never fails for valid but
extreme inputs: it holds the last good state and says so.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import fields

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Status

from openemss.models.engine.design_params import TurbofanParams, load_params, preset_path, replace
from openemss.models.engine.engine_model import (
    FLAGS,
    OUTPUTS,
    BleedValve,
    EngineInputs,
    EngineLimits,
    EngineModel,
    condition_from_ambient,
)

REQUIREMENTS = ["numpy>=1.24", "scipy>=1.10", "numba>=0.59"]
SOLVER_FAILED = [name for name, _ in FLAGS].index("solver_failed")

#: Design parameters exposed as ``design_<name>``: (field, description with unit).
DESIGN = (
    ("W2_kg_s", "Design inlet mass flow [kg/s]"), ("inlet_pi", "Design intake total-pressure recovery [-]"),
    ("BPR", "Design bypass ratio [-]"), ("PR_fan_outer", "Design fan outer (bypass) pressure ratio [-]"),
    ("eta_fan_outer", "Design fan outer isentropic efficiency [-]"),
    ("PR_fan_inner", "Design fan inner (core) pressure ratio [-]"),
    ("eta_fan_inner", "Design fan inner isentropic efficiency [-]"), ("PR_hpc", "Design HPC pressure ratio [-]"),
    ("eta_hpc", "Design HPC isentropic efficiency [-]"), ("Tt4_K", "Design burner exit temperature [K]"),
    ("eta_burner", "Burner efficiency [-]"), ("dPqP_burner", "Burner relative pressure loss [-]"),
    ("eta_hpt", "Design HPT isentropic efficiency [-]"), ("eta_lpt", "Design LPT isentropic efficiency [-]"),
    ("dPqP_21_24", "Fan-HPC duct relative pressure loss [-]"),
    ("dPqP_44_45", "HPT-LPT duct relative pressure loss [-]"),
    ("dPqP_5_7", "Jet pipe relative pressure loss [-]"), ("dPqP_13_17", "Bypass duct relative pressure loss [-]"),
    ("eta_mech_hp", "HP spool mechanical efficiency [-]"), ("eta_mech_lp", "LP spool mechanical efficiency [-]"),
    ("Cv_core", "Core nozzle velocity coefficient [-]"), ("Cd_core", "Core nozzle discharge coefficient [-]"),
    ("Cv_bypass", "Bypass nozzle velocity coefficient [-]"), ("Cd_bypass", "Bypass nozzle discharge coefficient [-]"),
    ("N1_rpm", "Design LP spool speed [rpm]"), ("N2_rpm", "Design HP spool speed [rpm]"),
)
_INPUTS = (
    ("fuel_flow_cmd_kg_s", "Fuel flow command [kg/s]"), ("alt_m", "Geopotential altitude [m]"),
    ("mach", "Flight Mach number [-]"), ("isa_dev_K", "ISA temperature deviation [K]"),
    ("offtake_hp_W", "HP shaft port power, + taken from the spool (offtake, generator), - delivered to it "
                     "(motor assist) [W]"),
    ("offtake_lp_W", "LP shaft port power, + taken from the spool (offtake, generator), - delivered to it "
                     "(motor assist) [W]"),
    ("customer_bleed_frac", "Customer bleed from the HPC exit over HPC inlet flow [-]"),
    ("distortion_sector_deg", "Spoiled inlet sector angle [deg]"),
    ("distortion_dPt_frac", "Total-pressure deficit of the spoiled sector over the clean value [-]"),
    ("distortion_dTt_K", "Total-temperature excess of the spoiled sector [K]"),
    ("p_amb_Pa", "Ambient static pressure, used with use_ambient [Pa]"),
    ("T_amb_K", "Ambient static temperature, used with use_ambient [K]"),
)


class Engine(Fmi2Slave):
    """Two-spool separate-flow turbofan with spool dynamics, bleeds, offtakes and inlet distortion."""

    author = "openEMSS"
    description = "Turbofan engine in time: fuel flow [kg/s] and flight condition in; thrust [N] and cycle out"

    def __init__(self, **kwargs) -> None:  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        fixed, discrete = Fmi2Variability.fixed, Fmi2Variability.discrete
        par, inp, out = Fmi2Causality.parameter, Fmi2Causality.input, Fmi2Causality.output
        base = load_params(preset_path("larzac04_sls"))
        self.preset = "larzac04_sls"
        self.design_override = False
        self.register_variable(String("preset", causality=par, variability=fixed,
                                      description="Engine preset: larzac04_sls or reference_study [-]"))
        self.register_variable(Boolean("design_override", causality=par, variability=fixed,
                                       description="Use the design_* parameters instead of the preset's values [-]"))
        for name, desc in DESIGN:
            setattr(self, f"design_{name}", float(getattr(base, name)))
            self.register_variable(Real(f"design_{name}", causality=par, variability=fixed, description=desc))
        self.I_lp_kg_m2 = 0.0
        self.I_hp_kg_m2 = 0.0
        self.dt_internal_s = 0.05
        self.tol = 1e-8
        self.start_N1_pct = 80.0
        self.start_fuel_flow_kg_s = 0.0
        lim, valve = EngineLimits(), BleedValve()
        self.N1_max_pct, self.N2_max_pct, self.FAR_lean = lim.N1_max_pct, lim.N2_max_pct, lim.FAR_lean
        self.Wf_Pt3_min_frac, self.Wf_decel_max_frac_s = lim.Wf_Pt3_min_frac, lim.Wf_decel_max_frac_s
        self.bleed_threshold_N2_pct, self.bleed_band_pct = valve.threshold_N2_pct, valve.band_pct
        self.bleed_stroke_s, self.bleed_open_frac = valve.stroke_s, valve.open_frac
        self.offtake_hp_max_W, self.offtake_lp_max_W = lim.offtake_hp_max_W, lim.offtake_lp_max_W
        self.assist_hp_max_W, self.assist_lp_max_W = lim.assist_hp_max_W, lim.assist_lp_max_W
        self.critical_angle_deg = 60.0
        self.linear_input_frac = 0.05
        for name, desc in (("I_lp_kg_m2", "LP spool polar inertia, 0 = the preset's [kg m2]"),
                           ("I_hp_kg_m2", "HP spool polar inertia, 0 = the preset's [kg m2]"),
                           ("dt_internal_s", "Largest internal integration step [s]"),
                           ("tol", "Gas-path matching tolerance, max residual [-]"),
                           ("start_N1_pct", "Initial steady N1 if no start fuel flow is given [%]"),
                           ("start_fuel_flow_kg_s", "Initial steady fuel flow, used if > 0 [kg/s]"),
                           ("N1_max_pct", "Overspeed limit of N1 [%]"), ("N2_max_pct", "Overspeed limit of N2 [%]"),
                           ("FAR_lean", "Lean flameout limit of the burner fuel-air ratio [-]"),
                           ("Wf_Pt3_min_frac", "Fuel system minimum-flow stop: burned Wf/Pt3 at least this "
                                               "fraction of the design point's, 0 = none [-]"),
                           ("Wf_decel_max_frac_s", "Fuel system decel limit: fastest decrease of the burned fuel "
                                                   "flow, fraction of the design fuel flow per second [1/s]"),
                           ("bleed_threshold_N2_pct", "Handling bleed switching speed, centre of the band [%]"),
                           ("bleed_band_pct", "Handling bleed hysteresis band width in N2 [%]"),
                           ("bleed_stroke_s", "Handling bleed valve full-stroke time [s]"),
                           ("bleed_open_frac", "Handling bleed flow over HPC inlet flow when open [-]"),
                           ("offtake_hp_max_W", "Largest power taken from the HP shaft port; beyond it the "
                                                "input is clipped and shaft_power_limited set [W]"),
                           ("offtake_lp_max_W", "Largest power taken from the LP shaft port; beyond it the "
                                                "input is clipped and shaft_power_limited set [W]"),
                           ("assist_hp_max_W", "Largest power delivered to the HP shaft port (motor assist, "
                                               "a positive number); beyond it clipped and flagged [W]"),
                           ("assist_lp_max_W", "Largest power delivered to the LP shaft port (motor assist, "
                                               "a positive number); beyond it clipped and flagged [W]"),
                           ("critical_angle_deg", "Critical sector angle of the distortion model [deg]"),
                           ("linear_input_frac", "Largest relative fuel change taken linearly at a step start, "
                                                 "0 = always matched [-]")):
            self.register_variable(Real(name, causality=par, variability=fixed, description=desc))
        self.integrator = 0
        self.distortion_target = 1
        self.register_variable(Integer("integrator", causality=par, variability=fixed,
                                       description="Integration method: 0 explicit Euler, 1 Heun [-]"))
        self.register_variable(Integer("distortion_target", causality=par, variability=fixed,
                                       description="Distorted compressor face: 1 fan, 2 HPC, 3 both [-]"))
        self.accept_solver_failure = False
        self.register_variable(Boolean("accept_solver_failure", causality=par, variability=fixed,
                                       description="Fly on with the last good state held where the gas path "
                                                   "cannot be matched (solver_failed set), instead of failing "
                                                   "the step [-]"))
        # inputs
        self.fuel_flow_cmd_kg_s = 0.0
        self.alt_m = 0.0
        self.mach = 0.0
        self.isa_dev_K = 0.0
        self.offtake_hp_W = 0.0
        self.offtake_lp_W = 0.0
        self.customer_bleed_frac = 0.0
        self.distortion_sector_deg = 90.0
        self.distortion_dPt_frac = 0.0
        self.distortion_dTt_K = 0.0
        self.distortion_on = False
        self.p_amb_Pa = 101325.0
        self.T_amb_K = 288.15
        self.use_ambient = False
        self.register_variable(Boolean("use_ambient", causality=par, variability=fixed,
                                       description="Flight condition from p_amb_Pa and T_amb_K instead of alt_m "
                                                   "and isa_dev_K [-]"))
        for name, desc in _INPUTS:
            self.register_variable(Real(name, causality=inp, description=desc))
        self.register_variable(Boolean("distortion_on", causality=inp, variability=discrete,
                                       description="Inlet distortion switched on [-]"))
        # outputs, read from the model's lists by index
        self._model: EngineModel | None = None
        self._vals = [0.0] * len(OUTPUTS)
        self._flags = [False] * len(FLAGS)
        self._out0 = len(self.vars)  # value reference of output i is _out0 + i
        for i, (name, desc) in enumerate(OUTPUTS):
            self.register_variable(Real(name, causality=out, description=desc, getter=lambda i=i: self._vals[i]))
        for i, (name, desc) in enumerate(FLAGS):
            self.register_variable(Boolean(name, causality=out, variability=discrete, description=desc,
                                           getter=lambda i=i: self._flags[i]))
        self.register_variable(Integer("events", causality=out, variability=discrete,
                                       description="Rising edges of surge, flameout, overspeed, fuel limiting, shaft "
                                                   "power limiting [-]",
                                       getter=lambda: 0 if self._model is None else self._model.events))

    def get_real(self, vrs: list[int]) -> list[float]:
        """The outputs straight from the model's list; pythonfmu's own calls one getter per variable."""
        vals, base, n = self._vals, self._out0, len(OUTPUTS)
        return [vals[vr - base] if 0 <= vr - base < n else Fmi2Slave.get_real(self, [vr])[0] for vr in vrs]

    def _inputs(self) -> EngineInputs:
        alt, dT = condition_from_ambient(self.p_amb_Pa, self.T_amb_K) if self.use_ambient else \
            (self.alt_m, self.isa_dev_K)
        return EngineInputs(self.fuel_flow_cmd_kg_s, alt, self.mach, dT, self.offtake_hp_W,
                            self.offtake_lp_W, self.customer_bleed_frac, bool(self.distortion_on),
                            self.distortion_sector_deg, self.distortion_dPt_frac, self.distortion_dTt_K)

    def _params(self) -> TurbofanParams:
        p = load_params(preset_path(self.preset))
        assert isinstance(p, TurbofanParams)
        if self.design_override:
            p = replace(p, Fn_target_N=None, **{n: float(getattr(self, f"design_{n}")) for n, _ in DESIGN})
        return p

    def exit_initialization_mode(self) -> None:
        known = {f.name for f in fields(TurbofanParams)}
        assert all(n in known for n, _ in DESIGN)
        m = EngineModel(self._params(), I_lp_kg_m2=self.I_lp_kg_m2 or None, I_hp_kg_m2=self.I_hp_kg_m2 or None,
                        dt_internal_s=self.dt_internal_s, method="heun" if self.integrator == 1 else "euler",
                        tol=self.tol, limits=EngineLimits(self.N1_max_pct, self.N2_max_pct, self.FAR_lean,
                                            Wf_Pt3_min_frac=self.Wf_Pt3_min_frac,
                                            Wf_decel_max_frac_s=self.Wf_decel_max_frac_s,
                                            offtake_hp_max_W=self.offtake_hp_max_W,
                                            offtake_lp_max_W=self.offtake_lp_max_W,
                                            assist_hp_max_W=self.assist_hp_max_W,
                                            assist_lp_max_W=self.assist_lp_max_W),
                        valve=BleedValve(self.bleed_threshold_N2_pct, self.bleed_band_pct, self.bleed_stroke_s,
                                         self.bleed_open_frac),
                        distortion_target=self.distortion_target, critical_angle_deg=self.critical_angle_deg,
                        linear_input_frac=self.linear_input_frac,
                        logger=lambda msg: self.log(msg, Fmi2Status.warning, "logStatusWarning"))
        u = self._inputs()
        if self.start_fuel_flow_kg_s > 0.0:
            u = dataclasses.replace(u, Wf_kg_s=self.start_fuel_flow_kg_s)
            m.start(u)
        else:
            m.start(u, N1_pct=self.start_N1_pct)
        if self.fuel_flow_cmd_kg_s <= 0.0:
            self.fuel_flow_cmd_kg_s = m.state.point.Wf_kg_s if m.state is not None else 0.0
        self._model = m
        self._vals, self._flags = m.values, m.flags

    def do_step(self, current_time: float, step_size: float) -> bool:
        """One step; a step the engine cannot compute (an input not finite, or, unless
        ``accept_solver_failure``, a gas path that cannot be matched) fails with the cause logged."""
        bad = [f"{name}={getattr(self, name)}" for name, _ in _INPUTS if not math.isfinite(getattr(self, name))]
        if bad:
            self.log(f"engine: t={current_time:.6g} s: input(s) not finite: {', '.join(bad)}; the engine cannot "
                     "compute its outputs", Fmi2Status.error, "logStatusError")
            return False
        u = self._inputs()
        m = self._model
        m.step(step_size, u)  # type: ignore[union-attr]
        if m.flags[SOLVER_FAILED] and not self.accept_solver_failure:  # type: ignore[union-attr]
            self.log(f"{m.message} (outside the engine's envelope; set engine.accept_solver_failure=true "  # type: ignore[union-attr]
                     "to fly on with the state held)", Fmi2Status.error, "logStatusError")
            return False
        return True
