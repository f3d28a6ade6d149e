"""The single-spool turbojet's gas path, written once for its design point and its off-design.

Inlet, compressor with its bleeds, burner, turbine with its cooling flows, jet pipe and nozzle, on
the component functions of this package. The two uses differ only in what fixes each component:

* design (:mod:`.cycle_design`): the compressor at its design PR and efficiency, the burner to the
  design Tt4, the turbine delivering the power the compressor and the offtake need
  (:func:`.turbine.turbine_for_power`);
* off-design (:mod:`.offdesign_turbojet`): the compressor and the turbine on their maps
  (callables of the station at their inlet), the burner with a given fuel flow, the turbine at a
  given pressure ratio (an unknown of the matching).

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5-7.
E. S. Hendricks, J. S. Gray, "pyCycle", Aerospace 6(87), 2019 (``simple_turbojet``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .atmosphere import FreeStream
from .burner import BurnerResult, burner_to_temperature, burner_with_fuel
from .compressor import CompressorResult, compressor
from .design_params import TurbojetParams
from .duct import duct
from .errors import ModelError
from .flow import FlowStation
from .gas import GasModel
from .inlet import inlet
from .nozzle import NozzleResult, convergent_nozzle, ideal_nozzle
from .shaft import turbine_power_required
from .turbine import Cooling, TurbineResult, turbine, turbine_for_power

__all__ = ["TurbojetPath", "turbojet_path"]


@dataclass(frozen=True)
class TurbojetPath:
    """Every station and component result of one evaluation of the turbojet's gas path."""

    stations: dict[str, FlowStation]
    bleeds: dict[str, FlowStation]
    compressor: CompressorResult
    burner: BurnerResult
    turbine: TurbineResult
    nozzle: NozzleResult
    ram_drag_N: float
    Fn_N: float
    Wc_map_compressor_kg_s: float
    Wc_map_turbine_kg_s: float


def turbojet_path(p: TurbojetParams, gas: GasModel, fr: FreeStream, W2_kg_s: float,
                  compressor_point: Callable[[FlowStation], tuple[float, float, float]],
                  Wf_kg_s: float | None = None, PR_t: float | None = None,
                  turbine_point: Callable[[FlowStation], tuple[float, float]] | None = None) -> TurbojetPath:
    """The turbojet at a flight condition `fr` with inlet flow `W2_kg_s` [kg/s].

    Parameters
    ----------
    compressor_point : callable
        (PR [-], isentropic efficiency [-], the map's corrected flow [kg/s] or NaN) of the compressor given its
        inlet station (the design values, or its map at the corrected speed of that inlet).
    Wf_kg_s : float, optional
        Fuel flow [kg/s]; None: the burner heats to the design Tt4 (``p.Tt4_K``).
    PR_t : float, optional
        Turbine pressure ratio [-]; None: the turbine delivers the power the compressor and the offtake
        need (design).
    turbine_point : callable, optional
        (isentropic efficiency [-], the map's corrected flow [kg/s]) of the turbine given its inlet station (its
        map at `PR_t`); None: ``p.eta_t``.
    """
    st: dict[str, FlowStation] = {"0": fr.station(W2_kg_s, gas)}
    st["2"] = inlet(st["0"], fr.Mach, p.inlet_pi)
    PR_c, eta_c, Wc_c = compressor_point(st["2"])
    c = compressor(st["2"], PR_c, eta_c, p.bleeds, gas)
    bl = {b.name: s for b, s in zip(p.bleeds, c.bleeds, strict=True)}
    if len(bl) != len(p.bleeds):
        raise ModelError(f"{p.name}: bleed names must be unique, got {[b.name for b in p.bleeds]}")
    if any(b.sink == "bypass" for b in p.bleeds):
        raise ModelError(f"{p.name}: a turbojet has no bypass to return a bleed to")
    st["3"] = c.out
    st["31"] = c.out.with_W(c.out.W_kg_s - sum(bl[b.name].W_kg_s for b in p.bleeds if b.at_exit))
    if Wf_kg_s is None:
        bu = burner_to_temperature(st["31"], p.Tt4_K, p.eta_burner, p.dPqP_burner, p.T_fuel_K, gas)
    else:
        bu = burner_with_fuel(st["31"], Wf_kg_s, p.eta_burner, p.dPqP_burner, p.T_fuel_K, gas, p.Tt4_K)
    st["4"] = bu.out
    cool = [Cooling(bl[b.name], b.sink_frac_P) for b in p.bleeds if b.sink in ("hpt", "lpt")]
    eta_t, Wc_t = (p.eta_t, math.nan) if turbine_point is None else turbine_point(st["4"])
    if PR_t is None:
        t = turbine_for_power(st["4"], turbine_power_required([c.power_W], p.offtake_W, p.eta_mech), eta_t, cool,
                              gas)
    else:
        t = turbine(st["4"], PR_t, eta_t, cool, gas)
    st["41"], st["5"] = t.rotor_in, t.out
    st["7"] = st["8"] = duct(t.out, p.dPqP_jetpipe)
    n: Any
    if p.nozzle_type == "ideal":
        n = ideal_nozzle(st["7"], fr.amb.P_Pa, p.Cv, gas)
    else:
        n = convergent_nozzle(st["7"], fr.amb.P_Pa, p.Cv, p.Cd, gas)
    ram = W2_kg_s * fr.V0_m_s
    return TurbojetPath(st, bl, c, bu, t, n, ram, n.Fg_N - ram, Wc_c, Wc_t)
