"""Any engine file in time behind the engine FMU: the common outputs of :data:`.engine_signals.OUTPUTS` by role.

:class:`GraphEngineModel` is what :class:`.engine_model.EngineModel` is for the compiled turbofan, for an engine
file (:mod:`.engine_file`) scaled by ``thrust_scale`` (:func:`.engine_file.scale_engine`) and run by
:class:`.graph_transient.GraphTransient`: the same inputs (:class:`.engine_signals.EngineInputs`), the same
outputs and flags by name, the same fuel-system stops and shaft-port limits (:class:`.engine_signals.EngineLimits`,
fractions of the design, so they fit any engine). The outputs are found in the graph by role, not by
architecture:

=========================  ============================================================================
output                     where in the graph
=========================  ============================================================================
N1 (rpm, %, corrected)     the shaft of the first compressor (the fan's); percent of its design speed
N2                         the shaft of the last compressor before the main burner (N1's on one spool)
Tt4, FAR4                  the main burner's exit
Tt41                       the rotor inlet of the first turbine after the main burner (cooling mixed in)
Tt3, Pt3, OPR              the exit of the last compressor before the main burner; OPR over the first's inlet
Tt21, Tt17, Tt7            the stations of those names where the file has them, else NaN
BPR                        the first fan or splitter's; 0 without one
SM_fan, SM_hpc             surge margins of the first and of the last compressor (NaN for a map without
                           a surge line); ``*_clean`` the same (no distortion here)
Wf_kg_s, SFC               every burner's fuel (an afterburner's included)
offtake_hp/lp              the ports of N2's and N1's shafts (both on the one shaft of a single spool)
=========================  ============================================================================

Not carried for engine files (a step with them fails with one line, never a silently different engine): inlet
distortion, the customer bleed input (a file's customer bleed is one of its ``bleeds``), the health parameters
and the Larzac's handling bleed valve (a file's bleed ``schedule`` does that job). The shaft limits are the file's
``N_max_pct`` where given, else ``N1_max_pct`` and ``N2_max_pct``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .engine_file import EngineFileError, read_engine_file, scale_engine
from .engine_graph import EngineGraph
from .engine_signals import EO, FLAGS, N_FILE_OUTPUTS, OUTPUTS, EngineInputs, EngineLimits
from .errors import FlameoutError, ModelError, OutOfRangeError
from .graph_transient import GraphMatch, GraphTransient
from .health import HealthDeltas

__all__ = ["GraphEngineModel"]

_FLAG = {name: i for i, (name, _) in enumerate(FLAGS)}
_N_IN = len(EngineInputs.__dataclass_fields__)
_N_OUT = len(OUTPUTS)


class GraphEngineModel:
    """An engine file in time with the interface of :class:`.engine_model.EngineModel` the engine FMU uses.

    Parameters
    ----------
    engine_file : str or Path
        An engine file or a shipped name (:func:`.engine_file.read_engine_file`).
    thrust_scale : float
        Airflow, thrust, fuel flow and areas scaled at constant cycle (:func:`.engine_file.scale_engine`).
    limits : EngineLimits
        Fuel-system stops, shaft-port limits, flag limits.
    dt_internal_s, tol : float
        Largest internal Euler step [s]; matching tolerance [-].
    logger : callable, optional
        Receives one line per event or failure.

    Raises
    ------
    EngineFileError, ModelError
        An engine file that cannot be read, designed or run in time (one line: file, line, element).
    """

    def __init__(self, engine_file: str | Path, thrust_scale: float = 1.0, *, limits: EngineLimits | None = None,
                 dt_internal_s: float = 0.05, tol: float = 1e-9,
                 logger: Callable[[str], None] | None = None) -> None:
        self.g = EngineGraph(scale_engine(read_engine_file(engine_file), thrust_scale))
        self.dp = self.g.design()
        self.tr = GraphTransient(self.g, tol)
        eng, g = self.g.eng, self.g
        self.limits = limits if limits is not None else EngineLimits.from_file()
        self.dt_internal_s = dt_internal_s
        self.log: Callable[[str], None] = logger if logger is not None else (lambda msg: None)
        order = list(eng.order)
        main = order.index(g.main_burner)
        comps = g.compressors
        if not comps:
            raise ModelError(f"{eng.file}: an engine without a compressor has no N1 for the engine FMU")
        self.first, self.last = comps[0], ([c for c in comps if order.index(c) < main] or comps)[-1]
        self.lp, self.hp = (eng.elements[c].attrs["shaft"] for c in (self.first, self.last))
        self.turb41 = next((e for e in order[main:] if eng.elements[e].kind == "turbine"), None)
        self.bpr_el = next((e for e in order if eng.elements[e].kind in ("fan", "splitter")), None)
        self.N_d = {s: float(d.attrs["N_rpm"]) for s, d in eng.shafts.items()}
        self.N_max_pct = {s: d.attrs["N_max_pct"] for s, d in eng.shafts.items()}
        self._ix = {s: self.tr.shafts.index(s) if s in self.tr.shafts else None for s in (self.lp, self.hp)}
        self.Wf_d_kg_s = float(self.dp.elements[g.main_burner]["Wf_kg_s"])
        by_dst = {(lk.dst, lk.dst_port): lk.station for lk in eng.links}
        self._st2 = by_dst[(self.first, "in")]
        self.Wf_Pt3_min_kg_s_Pa = self.limits.Wf_Pt3_min_frac * self.Wf_d_kg_s / \
            float(self.dp.elements[self.last]["Pt_exit_Pa"])
        self.Wf_decel_max_kg_s2 = self.limits.Wf_decel_max_frac_s * self.Wf_d_kg_s
        self.match: GraphMatch | None = None
        #: The outputs (:data:`OUTPUTS`), then the file's own outputs (:attr:`extra_names`) in the engine FMU's
        #: slots (``file_out_1`` ...; 0 where the file declares fewer)
        self.values: list[float] = [math.nan] * len(OUTPUTS) + [0.0] * N_FILE_OUTPUTS
        self.flags: list[bool] = [False] * len(FLAGS)
        self.events = 0
        self.message = ""
        self.flamed_out = ""
        self.fuel_burned_kg = 0.0
        self.t_s = 0.0
        self.port_W = (0.0, 0.0)                # (HP, LP) shaft port powers applied [W], + taken from the shaft
        self._port_limited = False
        self._Wf_last = 0.0
        self._uin = np.zeros(_N_IN)
        #: The file's own outputs (its ``outputs:``), in its order: names, and values after each step
        self.extra_names: tuple[str, ...] = tuple(eng.outputs)
        if len(self.extra_names) > N_FILE_OUTPUTS:
            raise EngineFileError(f"{eng.file}:{eng.lines.get('outputs', 1)}: {len(self.extra_names)} outputs; the "
                                  f"engine FMU carries at most {N_FILE_OUTPUTS}")

    # ------------------------------------------------------------------ inputs
    @property
    def input_array(self) -> np.ndarray:
        """The model's input array (the fields of :class:`.engine_signals.EngineInputs`, in order)."""
        return self._uin

    def set_health(self, health: HealthDeltas) -> None:
        """Health parameters are not carried for engine files: all zero is accepted, any other refused."""
        if any(getattr(health, f) != 0.0 for f in health.__dataclass_fields__):
            raise OutOfRangeError(f"{self.g.eng.file}: the health parameters (health_*) are not carried for engine "
                                  "files; leave them 0")

    def _settings(self, u: EngineInputs) -> dict[str, Any]:
        if u.distortion_on or u.customer_bleed_frac != 0.0:
            raise ModelError(f"{self.g.eng.file}: inlet distortion and the customer_bleed_frac input are not carried "
                             "for engine files (declare a customer bleed among the file's bleeds)")
        lim = self.limits
        hp = min(max(u.offtake_hp_W, -lim.assist_hp_max_W), lim.offtake_hp_max_W) if u.offtake_hp_W == \
            u.offtake_hp_W else 0.0
        lp = min(max(u.offtake_lp_W, -lim.assist_lp_max_W), lim.offtake_lp_max_W) if u.offtake_lp_W == \
            u.offtake_lp_W else 0.0
        self.port_W, self._port_limited = (hp, lp), (hp != u.offtake_hp_W) or (lp != u.offtake_lp_W)
        off: dict[str, float] = {}
        for s, p in ((self.hp, hp), (self.lp, lp)):
            if p != 0.0:
                off[s] = off.get(s, self.g.eng.shafts[s].attrs["offtake_W"]) + p
        return {"offtake_W": off} if off else {}

    def _fuel_stops(self, Wf_cmd_kg_s: float) -> float:
        Pt3 = self.values[EO.Pt3_Pa] if self.match is not None else 0.0
        return max(Wf_cmd_kg_s, self.limits.Wf_min_frac * self.Wf_d_kg_s, self.Wf_Pt3_min_kg_s_Pa * Pt3)

    def metered_fuel_kg_s(self, Wf_cmd_kg_s: float, dt_s: float) -> float:
        """The fuel flow [kg/s] metered over the next step: raised to the stops, held to the deceleration limit."""
        return max(self._fuel_stops(Wf_cmd_kg_s), self._Wf_last - self.Wf_decel_max_kg_s2 * dt_s)

    # ------------------------------------------------------------------ start and step
    def start(self, u: EngineInputs, N1_pct: float | None = None) -> list[float]:
        """Steady state at the flight condition of `u` and its fuel flow, or at `N1_pct` [%] if given."""
        cond = (u.alt_m, u.mach, u.dT_isa_K)
        demand = ("N_rpm", N1_pct / 100.0 * self.N_d[self.lp], self.lp) if N1_pct is not None else \
            ("Wf_kg_s", self._fuel_stops(u.Wf_cmd_kg_s))
        self.match = self.tr.steady(cond, demand, self._settings(u))
        self.t_s, self.fuel_burned_kg, self.events, self.flamed_out = 0.0, 0.0, 0, ""
        self._Wf_last = self.match.Wf_kg_s
        self._publish(self.match, False, u.Wf_cmd_kg_s if N1_pct is None else self.match.Wf_kg_s)
        return self.values

    def step_array(self, dt_s: float, u: np.ndarray) -> list[float]:
        """Advance by `dt_s` [s] with the inputs (an array of :data:`.engine_model.INPUT_FIELDS`) held."""
        inputs = EngineInputs(*u.tolist())
        return self.step(dt_s, inputs)

    def step(self, dt_s: float, u: EngineInputs) -> list[float]:
        """Advance by `dt_s` [s] with the inputs `u` held; a step that cannot be matched holds the last state
        and sets ``solver_failed`` (:attr:`message` says why)."""
        if self.flamed_out:
            raise FlameoutError(self.flamed_out)
        m = self.match
        assert m is not None, "start() first"
        Wf = self.metered_fuel_kg_s(u.Wf_cmd_kg_s, dt_s)
        try:
            new = self.tr.step(m, dt_s, Wf, (u.alt_m, u.mach, u.dT_isa_K), self._settings(u), self.dt_internal_s)
        except ModelError as exc:
            self.message = f"engine: t={self.t_s + dt_s:.6g} s: {exc}"
            self.log(self.message)
            self.t_s += dt_s
            self._publish(m, True, u.Wf_cmd_kg_s)
            return self.values
        self.t_s += dt_s
        self.fuel_burned_kg += 0.5 * (self.values[EO.Wf_kg_s] + float(new.state.Wf)) * dt_s
        self.match, self._Wf_last = new, Wf
        self._publish(new, False, u.Wf_cmd_kg_s)
        return self.values

    def flame_out(self, dt_s: float, cause: str) -> list[float]:
        """The step in which the burner gets no fuel (e.g. the tanks are empty): no thrust, no fuel burned, the
        ``flameout`` flag up; the engine cannot be stepped on (no windmilling model)."""
        self.t_s += dt_s
        v = self.values
        v[EO.Fn_N] = v[EO.Fg_N] = v[EO.ram_drag_N] = v[EO.Wf_kg_s] = v[EO.dN1_dt_rpm_s] = v[EO.dN2_dt_rpm_s] = 0.0
        v[EO.SFC_kg_N_s] = math.inf
        self.flamed_out = self.message = (f"engine: flame-out at t = {self.t_s:.6g} s: {cause}; "
                                          f"{self.fuel_burned_kg:.6g} kg burned since the start")
        if not self.flags[_FLAG["flameout"]]:
            self.events += 1
        self.flags[_FLAG["flameout"]] = True
        self.log(self.message)
        return v

    # ------------------------------------------------------------------ outputs
    def _extra(self, m: GraphMatch) -> None:
        """The file's own outputs: an element's output, or a shaft's (``N_rpm``, ``turbine_W``, ``compressor_W``,
        ``offtake_W``, ``net_W``: on a fixed-speed shaft the power its load takes, ``mech_loss_W``; derived:
        ``N_pct``, ``torque_N_m`` = eta_mech sum P_T / omega, the turbines' torque on it)."""
        out = m.state.out
        for i, (kind, target, q, line) in enumerate(self.g.eng.outputs.values()):
            o = out["shaft " + target if kind == "shaft" else target] if (kind == "shaft" or target in out) else {}
            if kind == "shaft" and q in ("N_pct", "torque_N_m"):
                N = o["N_rpm"]
                val = 100.0 * N / self.N_d[target] if q == "N_pct" else \
                    self.g.eng.shafts[target].attrs["eta_mech"] * o["turbine_W"] / (N * math.pi / 30.0)
            elif q in o:
                val = o[q]
            else:
                have = sorted(o) + (["N_pct", "torque_N_m"] if kind == "shaft" else [])
                raise EngineFileError(f"{self.g.eng.file}:{line}: output {self.extra_names[i]!r}: {kind} {target!r} "
                                      f"has no quantity {q!r} (it has: {', '.join(have) or 'none'})")
            self.values[_N_OUT + i] = float(val)

    def _publish(self, m: GraphMatch, failed: bool, Wf_in: float) -> None:
        s, g, v = m.state, self.g, self.values
        if self.extra_names:
            self._extra(m)
        st = {lk.station: s.flows[(lk.src, lk.src_port)] for lk in g.eng.links}
        el = s.out
        N1, N2 = s.N(self.lp), s.N(self.hp)
        Fn = s.Fg - s.ram
        burner = el[g.main_burner]
        v[EO.Fn_N], v[EO.Fg_N], v[EO.ram_drag_N], v[EO.Wf_kg_s] = Fn, s.Fg, s.ram, s.Wf
        v[EO.N1_rpm], v[EO.N2_rpm] = N1, N2
        v[EO.N1_pct], v[EO.N2_pct] = 100.0 * N1 / self.N_d[self.lp], 100.0 * N2 / self.N_d[self.hp]
        v[EO.N1c_pct] = 100.0 * el[self.first]["Nc_rpm"] / g.ref[("Nc", self.first)]
        v[EO.Tt4_K], v[EO.FAR4] = burner["Tt_exit_K"], burner["FAR"]
        v[EO.Tt41_K] = el[self.turb41]["Tt_rotor_in_K"] if self.turb41 else burner["Tt_exit_K"]
        for name, station in ((EO.Tt21_K, "21"), (EO.Tt17_K, "17"), (EO.Tt7_K, "7")):
            v[name] = st[station][1] if station in st else math.nan
        v[EO.Pt3_Pa], v[EO.Tt3_K] = el[self.last]["Pt_exit_Pa"], el[self.last]["Tt_exit_K"]
        v[EO.OPR] = v[EO.Pt3_Pa] / st[self._st2][2]
        v[EO.BPR] = el[self.bpr_el]["BPR"] if self.bpr_el else 0.0
        for out, c in ((EO.SM_fan, self.first), (EO.SM_hpc, self.last)):
            v[out] = float(g.maps[c].surge_margin(el[c]["Nc_rpm"], el[c]["beta"]))
        v[EO.SM_fan_clean], v[EO.SM_hpc_clean] = v[EO.SM_fan], v[EO.SM_hpc]
        v[EO.SFC_kg_N_s] = s.Wf / Fn if Fn > 0.0 else math.inf
        v[EO.fuel_burned_kg] = self.fuel_burned_kg
        acc = m.dN_dt_rpm_s
        v[EO.dN1_dt_rpm_s], v[EO.dN2_dt_rpm_s] = (acc[i] if i is not None else 0.0
                                                  for i in (self._ix[self.lp], self._ix[self.hp]))
        v[EO.handling_bleed_frac] = 0.0
        v[EO.W2_kg_s] = el[g.inlet]["W_kg_s"]
        v[EO.offtake_hp_applied_W], v[EO.offtake_lp_applied_W] = self.port_W
        lim = self.limits
        over = any(100.0 * s.N(sh) / self.N_d[sh] > (self.N_max_pct[sh] or (lim.N1_max_pct if sh == self.lp else
                                                                               lim.N2_max_pct))
                   for sh in g.eng.shafts)
        new = dict(surge=bool(v[EO.SM_fan] < 0.0 or v[EO.SM_hpc] < 0.0),
                   flameout=bool(v[EO.FAR4] < lim.FAR_lean or Wf_in < lim.Wf_min_frac * self.Wf_d_kg_s),
                   overspeed=over, solver_failed=failed, fuel_limited=False,
                   shaft_power_limited=self._port_limited)
        for name, i in _FLAG.items():
            if new[name] and not self.flags[i] and name != "solver_failed":
                self.events += 1
                self.log(f"engine: t={self.t_s:.6g} s: {name} (N1 {v[EO.N1_pct]:.2f} %, N2 {v[EO.N2_pct]:.2f} %, "
                         f"FAR4 {v[EO.FAR4]:.5f})")
            self.flags[i] = new[name]

    def fcs_limits(self) -> dict[str, float]:
        """The fuel controller's limits of this engine (the FCS's ``Tt41_max_K`` and ``N1_max_pct``): the file's
        ``limits: Tt41_max_K``, else the design point's rotor inlet temperature (its Tt4 with the cooling air of
        the first turbine after the main burner); the N1 shaft's ``N_max_pct`` where the file gives it (else the
        controller keeps its own N1 limit, below the overspeed flag's)."""
        T = self.g.eng.limits.get("Tt41_max_K")
        if T is None:
            d = self.dp.elements
            T = d[self.turb41]["Tt_rotor_in_K"] if self.turb41 else d[self.g.main_burner]["Tt_exit_K"]
        N1 = self.N_max_pct[self.lp]
        return {"Tt41_max_K": float(T), **({"N1_max_pct": float(N1)} if N1 is not None else {})}

    def value(self, name: str) -> float:
        """One output by name (see :data:`.engine_signals.OUTPUTS`), or one of the file's own outputs."""
        if name in self.extra_names:
            return self.values[_N_OUT + self.extra_names.index(name)]
        return self.values[EO[name]]
