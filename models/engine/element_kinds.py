"""The element kinds of an engine file: their ports and attributes, declared once (the registry).

An engine file (:mod:`.engine_file`) names elements of these kinds; the reader checks every attribute
against this table (type, unit, range, default), the graph solver (:mod:`.engine_graph`) evaluates them
(:mod:`.element_eval`), and the engine README's table of element kinds is this table. Adding an element
kind is one entry here and one function in :mod:`.element_eval` (``EVAL``).

Units are SI and carried by the attribute names where not dimensionless (``Tt_K``, ``N_rpm``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..infra import values
from .maps import DEFAULT_EXTRAPOLATION

__all__ = ["Attr", "Kind", "KINDS", "SHAFT_ATTRS", "BLEED_ATTRS", "SCHEDULE_ATTRS", "DESIGN_ATTRS", "FUEL_ATTRS", "LIMIT_ATTRS",
           "check_attr"]


@dataclass(frozen=True)
class Attr:
    """One attribute: its type (``number``, ``int``, ``text``, ``flag`` or a tuple of choices), unit, range,
    default (``None``: optional, no default; ``REQUIRED``: must be given) and meaning."""

    type: Any
    default: Any
    doc: str
    unit: str = "-"
    lo: float = -math.inf
    hi: float = math.inf


REQUIRED = object()
_FRAC = dict(lo=0.0, hi=1.0)
_MAP = Attr("text", REQUIRED, "map: a shipped map name (models/engine/maps), or a file: our JSON, an NPSS map "
                              "(.map, .npss) or a pyCycle map module (.py) (relative to the engine file)")
_MAP_OPT = {
    "map_Nc_rel": Attr("number", None, "the map's corrected speed placed on the design point (default the map's "
                                       "own design speed)", lo=0.05, hi=3.0),
    "map_line": Attr("number", None, "the map's R-line (compressor) or pressure ratio (turbine) placed on the "
                                     "design point (default the map's own)", lo=0.0, hi=100.0),
    "map_extended": Attr("flag", True, "extend the map below its lowest speed line (sub-idle, map_extension.py)"),
    "map_extrapolation": Attr("number", DEFAULT_EXTRAPOLATION, "linear extrapolation allowed beyond the map's grid, as a fraction of "
                                             "each axis' span (pyCycle's map_extrap=True extrapolates without a "
                                             "limit)", lo=0.0, hi=10.0),
}


@dataclass(frozen=True)
class Kind:
    """An element kind: its flow ports (inlets, outlets), its attributes, what it connects to."""

    doc: str
    inlets: tuple[str, ...]
    outlets: tuple[str, ...]
    attrs: Mapping[str, Attr] = field(default_factory=dict)
    shaft: bool = False           #: sits on a shaft (attribute ``shaft``)
    bleed_source: bool = False    #: bleeds may be taken from it
    bleed_sink: bool = False      #: bleeds may be returned into it


_COMPRESSOR = {
    "shaft": Attr("text", REQUIRED, "the shaft it is on"),
    "map": _MAP,
    "PR": Attr("number", REQUIRED, "design total pressure ratio", lo=1.0, hi=100.0),
    "eta": Attr("number", REQUIRED, "design isentropic efficiency", lo=1e-3, hi=1.0),
    "stages": Attr("int", 1, "number of stages (for interstage bleeds given by stage)", lo=1, hi=30),
    "held_Rline": Attr("number", None, "off-design: the map's R-line held by a variable-area nozzle (the "
                                       "nozzle's area is then free)", lo=0.0, hi=100.0),
    **_MAP_OPT,
}

KINDS: dict[str, Kind] = {
    "inlet": Kind("free stream to the engine face: ram recovery and ram drag", (), ("out",), {
        "pi": Attr("number", 1.0, "total-pressure recovery without shocks Pt2/Pt0", lo=1e-3, hi=1.0),
        "recovery": Attr(("mil_e_5008b", "none"), "mil_e_5008b",
                         "shock loss above Mach 1: MIL-E-5008B's ram recovery, or none"),
    }),
    "compressor": Kind("compressor on a map; bleeds by fractions of flow, pressure rise and work", ("in",),
                       ("out",), _COMPRESSOR, shaft=True, bleed_source=True),
    "fan": Kind("fan with a splitter: one map, the core (inner) stream at its own pressure ratio and efficiency",
                ("in",), ("core", "bypass"), {
                    **_COMPRESSOR,
                    "BPR": Attr("number", REQUIRED, "design bypass ratio W_bypass/W_core", lo=0.0, hi=100.0),
                    "PR_inner": Attr("number", None, "design pressure ratio of the core stream (default PR); "
                                                     "off-design (PR_inner - 1)/(PR - 1) is kept", lo=1.0, hi=100.0),
                    "eta_inner": Attr("number", None, "design efficiency of the core stream (default eta); "
                                                      "off-design eta_inner/eta is kept", lo=1e-3, hi=1.0),
                }, shaft=True),
    "splitter": Kind("splits a stream into core and bypass at a bypass ratio (an off-design unknown)", ("in",),
                     ("core", "bypass"), {
                         "BPR": Attr("number", REQUIRED, "design bypass ratio W_bypass/W_core", lo=0.0, hi=100.0)}),
    "duct": Kind("pressure loss; bleeds may leave (at its inlet state) or return (mixed in before the loss)",
                 ("in",), ("out",), {"dPqP": Attr("number", 0.0, "total-pressure loss dPt/Pt", lo=0.0, hi=0.99)},
                 bleed_source=True, bleed_sink=True),
    "burner": Kind("combustor or afterburner: energy balance with fuel", ("in",), ("out",), {
        "Tt_K": Attr("number", None, "design exit temperature (the main burner's, or an afterburner lit at design)",
                     "K", 300.0, 2500.0),
        "FAR": Attr("number", None, "fuel added per unit of entering air (an afterburner's setting; off-design "
                                    "it may be set per point)", lo=0.0, hi=0.07),
        "eta": Attr("number", 1.0, "combustion efficiency", lo=1e-3, hi=1.0),
        "dPqP": Attr("number", 0.0, "total-pressure loss dPt/Pt", lo=0.0, hi=0.99),
        "main": Attr("flag", None, "the burner the power setting acts on (default: the first burner in flow order)"),
    }),
    "turbine": Kind("turbine on a map; cooling flows enter at a fraction of its pressure drop", ("in",), ("out",), {
        "shaft": Attr("text", REQUIRED, "the shaft it drives"),
        "map": _MAP,
        "eta": Attr("number", REQUIRED, "design isentropic efficiency", lo=1e-3, hi=1.0),
        "PR": Attr("number", None, "design pressure ratio Pt_in/Pt_out; without it (one turbine per shaft) the "
                                   "design balances the shaft's power", lo=1.0, hi=100.0),
        **_MAP_OPT,
    }, shaft=True, bleed_sink=True),
    "nozzle": Kind("exhaust to ambient pressure: convergent (choked or not) or convergent-divergent (ideally "
                   "expanded)", ("in",), (), {
        "type": Attr(("convergent", "cd"), "convergent", "convergent, or convergent-divergent ideally expanded"),
        "Cv": Attr("number", 1.0, "velocity (thrust) coefficient", lo=1e-3, hi=1.0),
        "Cd": Attr("number", 1.0, "discharge coefficient (geometric area = effective / Cd)", lo=1e-3, hi=1.0),
        "PR_design": Attr("number", None, "design nozzle pressure ratio Pt/p_amb (sizes the mass flow, e.g. a "
                                          "turboshaft's exhaust)", lo=1.0, hi=100.0),
        "area": Attr(("fixed", "variable"), "fixed", "off-design throat area: the design's, or variable (scheduled "
                                                     "to hold a compressor's R-line)"),
    }),
}

SHAFT_ATTRS: dict[str, Attr] = {
    "N_rpm": Attr("number", REQUIRED, "design speed", "rpm", 1.0, 1e6),
    "eta_mech": Attr("number", 1.0, "mechanical efficiency (of the turbines' power)", lo=1e-3, hi=1.0),
    "I_kg_m2": Attr("number", 0.0, "polar moment of inertia (transients)", "kg m^2", 0.0, 1e6),
    "offtake_W": Attr("number", 0.0, "power port, signed: + taken from the shaft, - delivered to it", "W",
                      -1e9, 1e9),
    "load_W": Attr("number", None, "design power of a load (free power turbine): the design balances it", "W",
                   0.0, 1e10),
    "speed": Attr(("free", "fixed"), "free", "off-design: speed from the power balance, or held (a governed load; "
                                            "the load then takes the net power)"),
    "N_max_pct": Attr("number", None, "speed limit for the fuel controller [% of N_rpm]", "%", 1.0, 200.0),
}

SCHEDULE_ATTRS: dict[str, Attr] = {
    "of": Attr("text", REQUIRED, "the compressor whose corrected speed schedules the bleed"),
    "Nc_frac": Attr("number", REQUIRED, "corrected speed (fraction of its design) at the centre of the ramp",
                    lo=0.0, hi=2.0),
    "ramp_frac": Attr("number", 0.1, "width of the C1 ramp (fraction of design corrected speed)", lo=1e-6, hi=1.0),
    "open_frac": Attr("number", REQUIRED, "bleed W/W_in fully open (below the ramp)", lo=0.0, hi=0.5),
}

BLEED_ATTRS: dict[str, Attr] = {
    "from": Attr("text", REQUIRED, "the compressor or duct it is taken from"),
    "to": Attr("text", "overboard", "a turbine (cooling), a duct (returned) or overboard"),
    "frac_W": Attr("number", 0.0, "flow / source inlet flow", lo=0.0, hi=0.99),
    "frac_P": Attr("number", 1.0, "(Pt - Pt_in)/(Pt_out - Pt_in) of a compressor", **_FRAC),
    "frac_work": Attr("number", 1.0, "(ht - ht_in)/(ht_out - ht_in) of a compressor", **_FRAC),
    "stage": Attr("int", None, "taken behind this stage of the compressor's `stages` of equal work and pressure "
                               "ratio (instead of frac_P, frac_work)", lo=1, hi=30),
    "entry": Attr("number", 1.0, "into a turbine: where in its pressure drop it enters (1 inlet, 0 exit)", **_FRAC),
    "schedule": Attr("mapping", None, "opens below a corrected speed (keys: " + ", ".join(SCHEDULE_ATTRS) + ")"),
}

DESIGN_ATTRS: dict[str, Attr] = {
    "alt_m": Attr("number", 0.0, "altitude", "m", -5000.0, 47000.0),
    "Mach": Attr("number", 0.0, "flight Mach number", lo=0.0, hi=3.0),
    "dT_isa_K": Attr("number", 0.0, "ISA deviation", "K", -100.0, 100.0),
    "W_kg_s": Attr("number", None, "inlet mass flow (sizes the engine)", "kg/s", 1e-6, 1e4),
    "Fn_N": Attr("number", None, "net thrust the design meets by its mass flow", "N", 1e-3, 1e7),
}

#: The engine's limits for its fuel controller (top-level ``limits:``); the N1 limit is the N1 shaft's ``N_max_pct``.
LIMIT_ATTRS: dict[str, Attr] = {
    "Tt41_max_K": Attr("number", None, "HP turbine rotor inlet temperature limit for the fuel controller (default: "
                       "the design point's)", "K", 300.0, 3000.0),
}

FUEL_ATTRS: dict[str, Attr] = {
    "LHV_J_kg": Attr("number", None, "lower heating value (default Jet-A's of gas.py)", "J/kg", 1e6, 2e8),
    "hc_ratio": Attr("number", None, "hydrogen/carbon atom ratio (default Jet-A's)", lo=0.1, hi=4.0),
    "T_fuel_K": Attr("number", None, "fuel temperature (default 298.15 K)", "K", 220.0, 550.0),
}


def check_attr(a: Attr, v: Any) -> Any:
    """The value `v` of attribute `a`, checked (type and range); raises :class:`.values.ValueProblem` saying
    what is allowed."""
    if isinstance(a.type, tuple):
        return values.choice(v, a.type)
    if a.type == "number":
        return values.number(v, a.lo, a.hi, "" if a.unit == "-" else a.unit)
    if a.type == "int":
        return values.integer(v, int(a.lo), int(a.hi))
    if a.type == "flag":
        return values.flag(v)
    if a.type == "mapping":
        if not isinstance(v, dict):
            raise values.ValueProblem(f"expected a mapping, got {values.show(v)}")
        return v
    return values.name(v, "a name")
