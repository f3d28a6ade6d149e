"""Design and off-design of any engine file: the unknowns and residuals come from the element graph.

:class:`EngineGraph` runs the elements of an engine file (:mod:`.engine_file`) in flow order
(:mod:`.element_eval`) and forms its equations from the graph, as pyCycle's balances and NPSS's
independents and dependents do:

========================  ==============================================  ===========================================
element                   design unknown / residual                       off-design unknown / residual
========================  ==============================================  ===========================================
inlet                     mass flow, if the design gives Fn_N or sizes    mass flow
                          by a nozzle's PR_design / net thrust = Fn_N
compressor, fan           --                                              map beta (unless its R-line is held) /
                                                                          map flow = inflow
fan, splitter             --                                              bypass ratio
burner (main)             exit temperature given: fuel in closed form     fuel flow / the power setting
turbine                   pressure ratio if not given (one per shaft)     pressure ratio / map flow = inflow
nozzle                    PR_design given: nozzle PR = PR_design          fixed area: throat area = design's
shaft                     (with a turbine PR unknown) power balance,      speed (free) / power balance; a fixed
                          net = load_W                                    speed: the load takes the net power
========================  ==============================================  ===========================================

The design's values (corrected flows, pressure ratios, efficiencies, corrected speeds) scale each
turbomachine's map (:mod:`.map_scaled`), the nozzles keep the design's effective areas. A system whose
unknowns and residuals do not pair up is refused with one line naming the file and what is missing.
Newton with Broyden updates (:func:`.newton.newton_solve`) solves both.

References
----------
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (balances of design and off-design). P. P.
Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 7 (off-design matching).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from .atmosphere import free_stream
from .element_eval import EVAL, State
from .element_kinds import KINDS
from .engine_file import EngineDef, EngineFileError, read_engine_file
from .errors import ConvergenceError, ModelError
from .flow import FlowStation
from .gas import GasModel
from .inlet import ram_recovery_mil_e_5008b
from .newton import newton_solve

__all__ = ["EngineGraph", "GraphPoint", "DEMANDS"]

#: Power settings of an off-design point: (kind, value [SI], shaft for N_rpm, Nc_rpm and power_W).
DEMANDS = ("Wf_kg_s", "Tt_K", "Fn_N", "N_rpm", "Nc_rpm", "power_W")
_EXTENSIVE = ("Fn", "load")           # design residuals proportional to the mass flow


@dataclass(frozen=True)
class GraphPoint:
    """A design or off-design point of an engine graph (SI units).

    Attributes
    ----------
    alt_m, Mach, dT_isa_K : the flight condition
    Fn_N, Fg_N, ram_drag_N, Wf_kg_s, SFC_kg_N_s, W_kg_s, OPR : performance (Wf of every burner)
    stations : every station of the file's ``flow:`` as a :class:`.flow.FlowStation`
    elements : each element's outputs (PR, eta, power_W, Wc_kg_s, Nc_rpm, beta, Fg_N, A_eff_m2, Wf_kg_s...)
    shafts : each shaft's N_rpm, turbine and compressor powers, offtake and net (load) power [W]
    unknowns, x, jacobian, iterations, evaluations, residual_max : the solution
    """

    alt_m: float
    Mach: float
    dT_isa_K: float
    Fn_N: float
    Fg_N: float
    ram_drag_N: float
    Wf_kg_s: float
    SFC_kg_N_s: float
    W_kg_s: float
    OPR: float
    stations: Mapping[str, FlowStation]
    elements: Mapping[str, Mapping[str, float]]
    shafts: Mapping[str, Mapping[str, float]]
    unknowns: tuple[str, ...]
    x: tuple[float, ...]
    jacobian: Any
    iterations: int
    evaluations: int
    residual_max: float

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary, SI units in the key names (for JSON)."""
        return {"alt_m": self.alt_m, "Mach": self.Mach, "dT_isa_K": self.dT_isa_K, "Fn_N": self.Fn_N,
                "Fg_N": self.Fg_N, "ram_drag_N": self.ram_drag_N, "Wf_kg_s": self.Wf_kg_s,
                "SFC_kg_N_s": self.SFC_kg_N_s, "W_kg_s": self.W_kg_s, "OPR": self.OPR,
                "stations": {k: {"W_kg_s": s.W_kg_s, "Tt_K": s.Tt_K, "Pt_Pa": s.Pt_Pa, "FAR": s.FAR}
                             for k, s in self.stations.items()},
                "elements": {k: dict(v) for k, v in self.elements.items()},
                "shafts": {k: dict(v) for k, v in self.shafts.items()},
                "iterations": self.iterations, "evaluations": self.evaluations, "residual_max": self.residual_max}


class EngineGraph:
    """An engine file's graph, ready to design and to solve off-design points.

    Parameters
    ----------
    engine : EngineDef, or an engine file's path or shipped name (:func:`.engine_file.read_engine_file`)
    """

    def __init__(self, engine: EngineDef | str | Path) -> None:
        from .combustion import h_fuel_liquid
        from .thermo import T_REF_K
        eng = engine if isinstance(engine, EngineDef) else read_engine_file(engine)
        self.eng = eng
        fu = {k: v for k, v in eng.fuel.items() if v is not None and k != "T_fuel_K"}
        self.gas = GasModel(**fu)
        self.gc, gs0 = self.gas.kernel_arrays()
        self.gs = np.append(gs0, h_fuel_liquid(eng.fuel["T_fuel_K"] or T_REF_K, self.gas))
        self.src = {(lk.dst, lk.dst_port): lk for lk in eng.links}
        self.bleeds_from = {e: [b for b in eng.bleeds if b.src == e] for e in eng.elements}
        self.bleeds_to = {e: [b for b in eng.bleeds if b.dst == e] for e in eng.elements}
        self.inlet = next(e for e in eng.order if eng.elements[e].kind == "inlet")
        burners = [e for e in eng.order if eng.elements[e].kind == "burner"]
        mains = [e for e in burners if eng.elements[e].attrs["main"]]
        if len(mains) > 1:
            raise EngineFileError(f"{eng.where(mains[1], 'main')}a second main burner (the first: {mains[0]!r})")
        self.main_burner = mains[0] if mains else next((e for e in burners if eng.elements[e].attrs["main"] is not
                                                        False), None)
        self.k_inner: dict[str, float] = {}
        self.eff_ratio: dict[str, float] = {}
        for e in eng.elements.values():
            if e.kind == "fan":
                a = e.attrs
                pi, ei = a["PR_inner"] or a["PR"], a["eta_inner"] or a["eta"]
                self.k_inner[e.name] = (pi - 1.0) / (a["PR"] - 1.0) if a["PR"] > 1.0 else 1.0
                self.eff_ratio[e.name] = ei / a["eta"]
        self.compressors = [e for e in eng.order if eng.elements[e].kind in ("compressor", "fan")]
        self.maps: dict[str, Any] = {}
        self.held_beta: dict[str, float] = {}
        self.ref: dict[tuple[str, str], float] = {}
        self._design: GraphPoint | None = None

    # ------------------------------------------------------------------ evaluation
    def T_guess(self, burner: str, T_in: float) -> float:
        """Starting temperature of a burner's exit iteration [K]: its design exit temperature."""
        return self.ref.get(("Tt", burner), T_in + 1000.0)

    def _fs(self, cond: tuple[float, float, float]) -> tuple[float, ...]:
        fr = free_stream(*cond, self.gas)
        return (fr.Tt0_K, fr.Pt0_Pa, fr.V0_m_s, fr.amb.P_Pa, cond[1], ram_recovery_mil_e_5008b(cond[1]))

    def run(self, design: bool, fs: tuple[float, ...], vals: dict[tuple[str, str], float],
            settings: dict[str, Any]) -> State:
        """Every element in flow order at the unknowns' values `vals`; the shafts' balances."""
        s = State(self, design, fs, vals, settings)
        eng = self.eng
        for name in eng.order:
            e = eng.elements[name]
            fin = {p: s.flows[(lk.src, lk.src_port)] for p in KINDS[e.kind].inlets
                   for lk in (self.src[(name, p)],)}
            for port, flow in EVAL[e.kind](s, e, fin).items():
                s.flows[(name, port)] = flow
        for sh in eng.shafts.values():
            a = sh.attrs
            off = settings.get("offtake_W", {}).get(sh.name, a["offtake_W"])
            net = a["eta_mech"] * s.turb_W[sh.name] - s.comp_W[sh.name] - off
            s.out["shaft " + sh.name] = dict(N_rpm=s.N(sh.name), turbine_W=s.turb_W[sh.name],
                                             compressor_W=s.comp_W[sh.name], offtake_W=off, net_W=net,
                                             mech_loss_W=(1.0 - a["eta_mech"]) * s.turb_W[sh.name])
            if design and sh.name in self._balanced:
                s.resid[f"shaft {sh.name}.{'load' if a['load_W'] is not None else 'power'}"] = \
                    (net - (a["load_W"] or 0.0)) / self._P_ref(s, sh.name)
            elif not design and a["speed"] == "free":
                s.resid[f"shaft {sh.name}.power"] = net / self.ref[("P", sh.name)]
        return s

    def _P_ref(self, s: State, shaft: str) -> float:
        if ("P", shaft) not in self.ref:
            self.ref[("P", shaft)] = max(s.comp_W[shaft], s.turb_W[shaft], abs(self.eng.shafts[shaft].attrs["load_W"]
                                                                                or 0.0), 1.0)
        return self.ref[("P", shaft)]

    def _point(self, s: State, cond: tuple[float, float, float], names: tuple[str, ...], res: Any) -> GraphPoint:
        eng = self.eng
        st = {lk.station: FlowStation(*s.flows[(lk.src, lk.src_port)]) for lk in eng.links}
        Fn = s.Fg - s.ram
        by_dst = {(lk.dst, lk.dst_port): lk.station for lk in eng.links}
        P2 = st[by_dst[(self.compressors[0], "in")]].Pt_Pa if self.compressors else 1.0
        P3 = st[by_dst[(self.main_burner, "in")]].Pt_Pa if self.main_burner and self.compressors else P2
        elements = {k: MappingProxyType(v) for k, v in s.out.items() if not k.startswith("shaft ")}
        shafts = {k[6:]: MappingProxyType(v) for k, v in s.out.items() if k.startswith("shaft ")}
        W = s.out[self.inlet]["W_kg_s"]
        return GraphPoint(*cond, Fn, s.Fg, s.ram, s.Wf, s.Wf / Fn if Fn > 0.0 else math.inf, W, P3 / P2,
                          MappingProxyType(st), MappingProxyType(elements), MappingProxyType(shafts), names,
                          tuple(float(v) for v in res.x), res.jacobian, res.iterations, res.evaluations,
                          float(np.max(np.abs(res.r))) if len(res.r) else 0.0)

    def _residuals(self, s: State, names: tuple[str, ...]) -> np.ndarray:
        return np.array([s.resid[n] for n in names])

    # ------------------------------------------------------------------ design
    def _design_system(self) -> tuple[list[tuple[str, str]], list[str]]:
        eng = self.eng
        unknowns: list[tuple[str, str]] = []
        resid: list[str] = []
        d = eng.design
        if d["W_kg_s"] is None:
            unknowns.append(("W", self.inlet))
        if d["Fn_N"] is not None:
            resid.append("Fn")
        self._balanced = set()
        for sh in eng.shafts.values():
            free = [e for e in eng.order if eng.elements[e].kind == "turbine"
                    and eng.elements[e].attrs["shaft"] == sh.name and eng.elements[e].attrs["PR"] is None]
            if len(free) > 1:
                raise EngineFileError(f"{eng.where(free[1], 'PR')}a balance cannot be formed: shaft {sh.name!r} has "
                                      f"two turbines without a design PR ({', '.join(free)}); give all but one a PR")
            if free:
                unknowns.append(("PR", free[0]))
                self._balanced.add(sh.name)
                resid.append(f"shaft {sh.name}.{'load' if sh.attrs['load_W'] is not None else 'power'}")
            elif sh.attrs["load_W"] is not None or any(
                    eng.elements[e].kind in ("compressor", "fan") and eng.elements[e].attrs["shaft"] == sh.name
                    for e in eng.order):
                raise EngineFileError(f"{eng.file}:{sh.line}: a balance cannot be formed: shaft {sh.name!r} has no "
                                      "turbine without a design PR to balance its power")
        for e in eng.order:
            el = eng.elements[e]
            if el.kind == "nozzle" and el.attrs["PR_design"] is not None:
                resid.append(f"{e}.PR")
        if self.main_burner is None:
            raise EngineFileError(f"{eng.file}:{eng.lines.get('elements', 1)}: the engine has no burner")
        if len(unknowns) != len(resid):
            raise EngineFileError(
                f"{eng.file}:{eng.lines.get('design', 1)}: a balance cannot be formed at design: unknowns "
                f"{', '.join(f'{k} of {n}' for k, n in unknowns) or 'none'} against equations "
                f"{', '.join(resid) or 'none'} (give W_kg_s, or Fn_N, or a nozzle's PR_design, or a turbine's PR)")
        return unknowns, resid

    def design(self) -> GraphPoint:
        """The design point (cached): the file's design values, its balances solved; scales the maps."""
        if self._design is not None:
            return self._design
        eng = self.eng
        d = eng.design
        cond = (d["alt_m"], d["Mach"], d["dT_isa_K"])
        fs = self._fs(cond)
        unknowns, resid = self._design_system()
        W0 = d["W_kg_s"] or 100.0
        x = {u: (W0 if u[0] == "W" else 2.5) for u in unknowns}

        def solve(us: list[tuple[str, str]], rs: list[str], tol: float) -> Any:
            scale = {u: (W0 if u[0] == "W" else 1.0) for u in us}

            def f(xx: np.ndarray) -> np.ndarray:
                vals = dict(x)
                vals.update({u: v * scale[u] for u, v in zip(us, xx, strict=True)})
                s = self.run(True, fs, vals, {})
                if "Fn" in rs:
                    s.resid["Fn"] = (s.Fg - s.ram) / d["Fn_N"] - 1.0
                return np.array([s.resid[n] for n in rs])

            res = newton_solve(f, [x[u] / scale[u] for u in us], rs, tol=tol, where=f"design of {eng.file}")
            x.update({u: v * scale[u] for u, v in zip(us, res.x, strict=True)})
            return res

        ext = [r for r in resid if r == "Fn" or r.endswith(".load")]
        if ("W", self.inlet) in x and len(ext) == 1:      # the rest at a guessed flow, then the flow scales
            inner = [r for r in resid if r not in ext]
            solve([u for u in unknowns if u[0] != "W"], inner, 1e-10)
            s = self.run(True, fs, x, {})
            now = (s.Fg - s.ram) if ext[0] == "Fn" else s.out["shaft " + ext[0][6:-5]]["net_W"]
            target = d["Fn_N"] if ext[0] == "Fn" else eng.shafts[ext[0][6:-5]].attrs["load_W"]
            if now > 0.0:
                W0 = x[("W", self.inlet)] = W0 * target / now
        res = solve(unknowns, resid, 1e-13)
        s = self.run(True, fs, x, {})
        self._scale_maps(s)
        self._design = self._point(s, cond, tuple(resid), res)
        return self._design

    def _scale_maps(self, s: State) -> None:
        """Each turbomachine's map scaled to the design's values; the design's references."""
        from .map_files import scaled_map
        eng = self.eng
        for e in eng.order:
            el, o = eng.elements[e], s.out.get(e, {})
            if el.kind in ("compressor", "fan", "turbine"):
                self.maps[e] = scaled_map(eng, el, o)
                self.ref[("Wc", e)], self.ref[("Nc", e)], self.ref[("PR", e)] = o["Wc_kg_s"], o["Nc_rpm"], o["PR"]
                if el.kind != "turbine" and el.attrs["held_Rline"] is not None:
                    self.held_beta[e] = self.maps[e].map.beta_of_rline(el.attrs["held_Rline"])
            if el.kind in ("fan", "splitter"):
                self.ref[("BPR", e)] = el.attrs["BPR"] if el.attrs["BPR"] > 0.0 else 1.0
            if el.kind == "nozzle":
                self.ref[("A", e)] = o["A_eff_m2"]
            if el.kind == "burner":
                self.ref[("Tt", e)] = o["Tt_exit_K"]
        for sh in eng.shafts:
            o = s.out["shaft " + sh]
            self.ref[("P", sh)] = max(o["compressor_W"], o["turbine_W"], 1.0)
            self.ref[("N", sh)] = o["N_rpm"]
        self.ref[("W", self.inlet)] = s.out[self.inlet]["W_kg_s"]
        self.ref[("Wf", self.main_burner)] = max(s.out[self.main_burner]["Wf_kg_s"], 1e-9)
        self.ref[("Fn", "")] = max(abs(s.Fg - s.ram), 1.0)
        self.ref[("face", "")] = s.flows[(self.inlet, "out")][1:3]

    # ------------------------------------------------------------------ off-design
    def offdesign_system(self, demand: tuple[str, float, str | None]) -> tuple[list[tuple[str, str]], list[str]]:
        """Unknowns and residual names of an off-design point with power setting `demand`."""
        eng = self.eng
        self.design()
        unknowns: list[tuple[str, str]] = [("W", self.inlet)]
        resid: list[str] = []
        for e in eng.order:
            el = eng.elements[e]
            if el.kind in ("compressor", "fan"):
                if e not in self.held_beta:
                    unknowns.append(("beta", e))
                resid.append(f"{e}.flow")
            if el.kind in ("fan", "splitter"):
                unknowns.append(("BPR", e))
            if el.kind == "turbine":
                unknowns.append(("PR", e))
                resid.append(f"{e}.flow")
            if el.kind == "nozzle" and el.attrs["area"] == "fixed":
                resid.append(f"{e}.area")
        for sh in eng.shafts.values():
            if sh.attrs["speed"] == "free":
                unknowns.append(("N", sh.name))
                resid.append(f"shaft {sh.name}.power")
        unknowns.append(("Wf", self.main_burner))
        resid.append("demand")
        if len(unknowns) != len(resid):
            raise EngineFileError(
                f"{eng.file}:{eng.lines.get('elements', 1)}: a balance cannot be formed off-design: "
                f"{len(unknowns)} unknowns ({', '.join(f'{k} of {n}' for k, n in unknowns)}) against {len(resid)} "
                f"equations ({', '.join(resid)}); a variable-area nozzle needs a compressor's held_Rline, a fixed "
                "area nozzle needs none")
        return unknowns, resid

    def _demand_shaft(self, shaft: str | None) -> str:
        if shaft is not None:
            if shaft not in self.eng.shafts:
                raise ModelError(f"{self.eng.file}: no shaft {shaft!r} (shafts: {', '.join(self.eng.shafts)})")
            return shaft
        first = self.compressors[0] if self.compressors else None
        return self.eng.elements[first].attrs["shaft"] if first else next(iter(self.eng.shafts))

    def demand_value(self, s: State, kind: str, shaft: str) -> float:
        """The quantity a power setting of kind `kind` sets, in an evaluation (SI)."""
        if kind == "Wf_kg_s":
            return s.out[self.main_burner]["Wf_kg_s"]
        if kind == "Tt_K":
            return s.out[self.main_burner]["Tt_exit_K"]
        if kind == "Fn_N":
            return s.Fg - s.ram
        if kind == "N_rpm":
            return s.N(shaft)
        if kind == "Nc_rpm":
            c = next((e for e in self.compressors if self.eng.elements[e].attrs["shaft"] == shaft), None)
            if c is None:
                raise ModelError(f"{self.eng.file}: shaft {shaft!r} drives no compressor: no corrected speed")
            return s.out[c]["Nc_rpm"]
        return s.out["shaft " + shaft]["net_W"]

    def _demand_ref(self, kind: str, shaft: str) -> float:
        return {"Wf_kg_s": self.ref[("Wf", self.main_burner)], "Tt_K": self.ref[("Tt", self.main_burner)],
                "Fn_N": self.ref[("Fn", "")], "power_W": self.ref[("P", shaft)]}.get(kind, self.ref[("N", shaft)])

    def solve(self, alt_m: float = 0.0, Mach: float = 0.0, dT_isa_K: float = 0.0, *,
              demand: tuple[str, float] | tuple[str, float, str | None], settings: dict[str, Any] | None = None,
              guess: GraphPoint | None = None, tol: float = 1e-9) -> GraphPoint:
        """An off-design point at a flight condition and a power setting.

        Parameters
        ----------
        alt_m, Mach, dT_isa_K : float
            Flight condition [m], [-], [K].
        demand : (kind, value[, shaft])
            The power setting, kind one of :data:`DEMANDS` (``N_rpm``, ``Nc_rpm``, ``power_W`` of a shaft: default
            the shaft of the first compressor).
        settings : dict, optional
            ``offtake_W`` {shaft: W}, ``bleeds`` {name: frac_W}, ``burners`` {name: {"FAR" or "Tt_K": v}} (a
            secondary burner, e.g. an afterburner lit), ``N_rpm`` {shaft: rpm} (a fixed-speed shaft).
        guess : GraphPoint, optional
            A neighbouring solution (its unknowns and Jacobian start the iteration).
        tol : float
            Convergence on max |residual| [-].

        Raises
        ------
        ConvergenceError
            The matching does not converge (the message names every residual).
        """
        kind, value = demand[0], float(demand[1])
        if kind not in DEMANDS:
            raise ModelError(f"{self.eng.file}: power setting {kind!r}; allowed: {', '.join(DEMANDS)}")
        shaft = self._demand_shaft(demand[2] if len(demand) > 2 else None)  # type: ignore[misc]
        settings = dict(settings or {})
        cond = (alt_m, Mach, dT_isa_K)
        unknowns, resid = self.offdesign_system((kind, value, shaft))
        fs = self._fs(cond)
        try:
            return self._solve(cond, fs, kind, value, shaft, settings, unknowns, resid, guess, tol)
        except ConvergenceError as exc:
            if guess is not None or not self.compressors:
                raise
            first = exc
        try:     # continuation from the design's corrected speed at this flight condition
            c0 = self.compressors[0]
            sh0 = self.eng.elements[c0].attrs["shaft"]
            g = self._solve(cond, fs, "Nc_rpm", self.ref[("Nc", c0)], sh0, settings, unknowns, resid, None, tol)
            s = self.run(False, fs, self._vals(unknowns, g.x), settings)
            v0 = self.demand_value(s, kind, shaft)
            for fr in (0.25, 0.5, 0.75, 1.0):
                g = self._solve(cond, fs, kind, v0 + fr * (value - v0), shaft, settings, unknowns, resid, g, tol)
            return g
        except (ConvergenceError, ModelError):
            raise first from None

    def _vals(self, unknowns: list[tuple[str, str]], x: Any) -> dict[tuple[str, str], float]:
        return {u: (v if u[0] == "beta" else v * self.ref[u]) for u, v in zip(unknowns, x, strict=True)}

    def _start(self, unknowns: list[tuple[str, str]], fs: tuple[float, ...]) -> list[float]:
        """The design point moved to the flight condition by similarity at the engine face."""
        T_d, P_d = self.ref[("face", "")]
        el = self.eng.elements[self.inlet].attrs
        P = fs[1] * el["pi"] * (fs[5] if el["recovery"] == "mil_e_5008b" else 1.0)
        th, de = fs[0] / T_d, P / P_d
        x0 = []
        for u in unknowns:
            if u[0] == "beta":
                x0.append(self.maps[u[1]].beta_map)
            else:
                x0.append({"W": de / math.sqrt(th), "N": math.sqrt(th), "Wf": de * math.sqrt(th)}.get(u[0], 1.0))
        return x0

    def _solve(self, cond: tuple[float, float, float], fs: tuple[float, ...], kind: str, value: float, shaft: str,
               settings: dict[str, Any], unknowns: list[tuple[str, str]], resid: list[str],
               guess: GraphPoint | None, tol: float) -> GraphPoint:
        ref = self._demand_ref(kind, shaft)

        def f(x: np.ndarray) -> np.ndarray:
            s = self.run(False, fs, self._vals(unknowns, x), settings)
            s.resid["demand"] = (self.demand_value(s, kind, shaft) - value) / ref
            return self._residuals(s, tuple(resid))

        ok = guess is not None and len(guess.x) == len(unknowns)
        x0 = list(guess.x) if ok else self._start(unknowns, fs)  # type: ignore[union-attr]
        res = newton_solve(f, x0, resid, tol=tol, jacobian=guess.jacobian if ok else None,  # type: ignore[union-attr]
                           where=f"{self.eng.file} at alt {cond[0]} m, Mach {cond[1]}, {kind}={value:.6g}")
        s = self.run(False, fs, self._vals(unknowns, res.x), settings)
        return self._point(s, cond, tuple(f"{k} of {n}" for k, n in unknowns), res)

