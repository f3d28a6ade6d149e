"""The arguments of the one gas path (:func:`.gas_path.turbofan`) for one off-design model, packed once.

:class:`FastCycle` packs the design's reference values, the gas's arrays, the bleeds and the scaled
maps of a :class:`.offdesign.TurbofanOffDesign` into the arrays the gas path reads, caches the free
stream of the last flight condition, and evaluates the gas path into its own output arrays (stations,
bleeds, powers, residuals, outputs). :func:`cycle` is the gas path of an engine without booster or
distortion with the argument list of the transient's compiled iteration (:func:`.jit_solve.chord_solve`).

There is no second implementation of any component here: the Python API (:meth:`.offdesign.
TurbofanOffDesign.solve`, :class:`.offdesign_result.OffDesignPoint`) reads the same arrays.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import jit_kernels as K
from .gas_path import MAX_BLEEDS, OUT, SINK, STATIONS, pack_params, turbofan, work_arrays
from .jit_freestream import atm_array
from .jit_freestream import free_stream as compiled_free_stream
from .jit_kernels import jit_inline
from .shaft import TURBOFAN_SHAFTS

__all__ = ["OUT", "DEMAND", "FastCycle", "cycle"]

_NST, _NPW = len(STATIONS), len(TURBOFAN_SHAFTS) + 2
#: Demand kinds of :meth:`.offdesign.TurbofanOffDesign.solve` as the gas path's codes.
DEMAND = {"Wf_kg_s": 0, "N1_rpm": 1, "N1c_rpm": 2, "Tt4_K": 3, "Fn_N": 4}


def scratch() -> tuple[Any, ...]:
    """The arrays :func:`cycle` evaluates the gas path into and discards (stations, bleeds, powers, a face without
    distortion, error, with_sm flag, the gas path's work arrays), and the free stream and control vector of
    :func:`.jit_solve.chord_solve`, allocated once by the caller (:func:`.jit_solve.bundle`)."""
    return (np.empty((_NST, 5)), np.empty((MAX_BLEEDS, 6)), np.empty(_NPW), np.zeros((2, 4)),
            np.zeros(2, np.int64), np.zeros(1, np.bool_), work_arrays(), np.empty(6), np.empty(6))


@jit_inline
def cycle(x: np.ndarray, fs: np.ndarray, ctl: np.ndarray, e: np.ndarray, gc: np.ndarray, gs: np.ndarray,
          bl: np.ndarray, fan: Any, hpc: Any, hpt: Any, lpt: Any, scr: Any, r: np.ndarray, o: np.ndarray,
          with_sm: bool) -> int:
    """Residuals r (9) and outputs o (:data:`.gas_path.OUT`) of an engine without booster or distortion:
    :func:`.gas_path.turbofan` into the scratch arrays `scr` (:func:`scratch`); 0 or its error code."""
    S, B, PW, dist, err, flag, w = scr[:7]
    err[0] = err[1] = 0
    # a plain bool: the gas path then has the argument types FastCycle.evaluate calls it with (the caller passes
    # contiguous arrays), and numba compiles it once for both (a literal False, or a slice's layout, is another
    # type: a second compilation of the largest kernel, some 25 s)
    flag[0] = with_sm
    return turbofan(x, fs, ctl, e, gc, gs, bl, fan, hpc, hpt, lpt, fan, dist, S, B, PW, r, o, err, w, flag[0])


def _maps(od: Any) -> tuple[Any, ...]:
    """The scaled maps of `od` as the gas path reads them (each map's ``kernel_tuple()``); the fan's in place of
    an absent booster map (not read)."""
    m = od.maps
    out = []
    for name in ("fan", "hpc", "hpt", "lpt", "booster"):
        mp = getattr(m, name)
        if mp is None:
            out.append(out[0])
            continue
        kt = getattr(mp, "kernel_tuple", None)
        if kt is None:
            from .errors import ModelError
            raise ModelError(f"{od.p.name}: the {name} map ({type(mp).__name__}) has no table the gas path can read; "
                             "give a scaled map (offdesign.scaled_maps) or tabulate a map function with "
                             "map_scaled.tabulate_map")
        out.append(kt())
    return tuple(out)


class FastCycle:
    """The gas path's arguments for one :class:`.offdesign.TurbofanOffDesign`, and its output arrays.

    Attributes
    ----------
    e, gc, gs, bl : parameters (:data:`.gas_path.PARAMS`), gas arrays, design bleeds
    maps : (fan, hpc, hpt, lpt) scaled maps as the gas path reads them; ``boo`` the booster's (or the fan's)
    S, B, PW, r, o, err : the last evaluation's stations, bleeds, powers, residuals, outputs and error
    fsc, atm : the free-stream cache of :func:`.jit_solve.chord_solve` and the atmosphere's constants
    """

    def __init__(self, od: Any) -> None:
        from .combustion import h_fuel_liquid
        p, ref, g = od.p, od.ref, od.gas
        if len(p.bleeds) + 2 > MAX_BLEEDS:                  # the handling and customer bleeds come on top
            from .errors import ModelError
            raise ModelError(f"{p.name}: at most {MAX_BLEEDS - 2} bleeds, got {len(p.bleeds)}")
        self.e = pack_params(dict(
            mode=0.0, W2_ref=ref["W2"], PRh_ref=ref["PRh"], PRl_ref=ref["PRl"], Wf_ref=ref["Wf"],
            N1_design_rpm=p.N1_rpm, N2_design_rpm=p.N2_rpm, BPR_ref=p.BPR, Nc1_design_rpm=ref["Nc1"],
            inlet_pi=p.inlet_pi, k_inner=od.k_inner, eff_ratio_inner=od.eff_ratio_inner, booster=float(od.nb),
            dPqP_21_24=p.dPqP_21_24, dPqP_24_25=p.dPqP_24_25, dPqP_burner=p.dPqP_burner, dPqP_44_45=p.dPqP_44_45,
            dPqP_5_7=p.dPqP_5_7, dPqP_13_17=p.dPqP_13_17, handling_bleed_frac=p.handling_bleed_frac,
            hb_open_frac=od.hb_open, hb_N1c_frac=od.hb_N1c, hb_ramp_frac=od.hb_ramp,
            handling_bleed_stage=p.handling_bleed_stage, hpc_stages=p.hpc_stages,
            bypass_bleed_frac=p.bypass_bleed_frac, eta_burner=p.eta_burner, Tt4_guess_K=od.dp.Tt4_K,
            Cv_core=p.Cv_core, Cv_bypass=p.Cv_bypass, eta_mech_hp=p.eta_mech_hp, eta_mech_lp=p.eta_mech_lp,
            Wc21_ref=ref["Wc21"], Wc4_ref=ref["Wc4"], Wc45_ref=ref["Wc45"], A8_ref=ref["A8"], A18_ref=ref["A18"],
            P_hp_ref=ref["P_hp"], P_lp_ref=ref["P_lp"], Fn_ref=ref["Fn"], Tt4_ref=ref["Tt4"],
            PR_fan_outer=p.PR_fan_outer, eta_fan_outer=p.eta_fan_outer, PR_booster=p.PR_booster,
            eta_booster=p.eta_booster, PR_hpc=p.PR_hpc, eta_hpc=p.eta_hpc, eta_hpt=p.eta_hpt, eta_lpt=p.eta_lpt))
        self.gc, gs0 = g.kernel_arrays()            # the gas's own arrays: its properties are these kernels
        self.gs = np.append(gs0, h_fuel_liquid(p.T_fuel_K, g))
        self.bl = np.array([[b.frac_W, b.frac_P, b.frac_work, SINK[b.sink], b.sink_frac_P] for b in p.bleeds],
                           dtype=float).reshape(-1, 5)
        *self.maps, self.boo = _maps(od)
        self.maps = tuple(self.maps)
        self.gas = g
        self.S, self.B, self.PW = np.empty((_NST, 5)), np.empty((MAX_BLEEDS, 6)), np.empty(_NPW)
        self.r, self.o = np.empty(9 + 3), np.empty(len(OUT))
        self.err = np.zeros(2, np.int64)
        self.dist = np.zeros((2, 4))
        self._work = work_arrays()
        self._fs: tuple[tuple[float, float, float], np.ndarray] | None = None
        self._ctl = np.empty(6)
        self.atm = atm_array()                  # the ISA's constants, for the compiled free stream
        self.fsc = np.full(9, math.nan)         # (alt, Mach, dT) and the free stream of jit_solve.chord_solve

    @classmethod
    def build(cls, od: Any) -> FastCycle:
        """The packed arguments of `od` (raises :class:`~.errors.ModelError` for a map without a table)."""
        return cls(od)

    def free_stream(self, cond: tuple[float, float, float]) -> np.ndarray:
        """(Tt0, Pt0, V0, p_amb, Mach, ram recovery) of a flight condition, cached; raises as :func:`.free_stream`.

        Compiled (:func:`.jit_freestream.free_stream`); where that refuses, :func:`.atmosphere.free_stream` (which
        raises, or gives the values)."""
        if self._fs is not None and self._fs[0] == cond:
            return self._fs[1]
        fs = np.empty(6)
        if compiled_free_stream(self.gc, self.gs, self.atm, float(cond[0]), float(cond[1]), float(cond[2]), fs) != 0:
            from .atmosphere import free_stream
            from .inlet import ram_recovery_mil_e_5008b
            fr = free_stream(*cond, self.gas)              # raises with the full message
            fs = np.array([fr.Tt0_K, fr.Pt0_Pa, fr.V0_m_s, fr.amb.P_Pa, cond[1],
                           ram_recovery_mil_e_5008b(cond[1])])
        self._fs = (cond, fs)
        return fs

    def evaluate(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[int, float],
                 extras: tuple[float, float, float], hb_frac: float | None, dist: np.ndarray | None = None,
                 with_sm: bool = False) -> int:
        """The gas path at unknowns `x` into :attr:`S`, :attr:`B`, :attr:`PW`, :attr:`r`, :attr:`o`; returns 0 or
        the error code (:data:`.gas_path.ERRORS`, its stage in ``err[1]``). The free stream may raise first."""
        fs = self.free_stream(cond)
        c = self._ctl
        c[0], c[1] = demand
        c[2], c[3], c[4] = extras
        c[5] = math.nan if hb_frac is None else hb_frac
        self.err[:] = 0
        f, h, t, lp = self.maps
        return int(turbofan(x, fs, c, self.e, self.gc, self.gs, self.bl, f, h, t, lp, self.boo,
                            self.dist if dist is None else dist, self.S, self.B, self.PW, self.r, self.o, self.err,
                            self._work, with_sm))

    def __call__(self, x: np.ndarray, cond: tuple[float, float, float], demand: tuple[int, float],
                 extras: tuple[float, float, float], hb_frac: float | None, with_sm: bool = False) -> bool:
        """:meth:`evaluate` without distortion; True where it succeeded (:attr:`r` and :attr:`o` filled)."""
        return self.evaluate(x, cond, demand, extras, hb_frac, None, with_sm) == 0


#: Whether the gas path runs compiled here (numba importable).
COMPILED = K.AVAILABLE
