"""Signals of the engine in time: inputs, outputs, flags, limits, the handling-bleed valve.

:data:`SIGNALS` is the engine's signal table (``models/infra/signals.py``): every variable of the
engine FMU (parameters, inputs, outputs, flags) with its unit and default, one row each; the FMU
(``fmus/engine.py``) registers its variables from it and ``ssp/generate.py`` takes the system's
connectors from the FMU. :data:`OUTPUTS` and :data:`FLAGS` (name, description with unit) are its
Real and Boolean outputs in the order the model fills :attr:`EngineModel.values` and ``flags``;
:class:`EngineInputs` holds the model's inputs for one step;
:func:`condition_from_ambient` turns an ambient static state into the flight condition of
the atmosphere model. Used by :mod:`.engine_model`.

References
----------
A. H. Lefebvre, D. R. Ballal, "Gas Turbine Combustion", 3rd ed., 2010, ch. 5 (weak
extinction: overall fuel-air ratios of about 0.002 to 0.005 at idle conditions).
ISO 2533:1975, Standard Atmosphere (pressure altitude).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, fields
from typing import ClassVar

from ..common.atmosphere import P0_PA, T0_K
from ..infra.signals import Signal, check_table
from .errors import OutOfRangeError
from .health import HEALTH_LIMIT, health_parameter_names
from .settings import EngineNumerics, EngineStart, FromEngineFile, engine_set

__all__ = ["EngineInputs", "EngineLimits", "BleedValve", "OUTPUTS", "FLAGS", "SIGNALS", "DESIGN_FIELDS",
           "PARAMETER_SETS", "condition_from_ambient", "N_FILE_OUTPUTS", "FUEL_UNLIMITED_KG", "FLAMEOUT_CAUSES",
           "FLAMEOUT_STARVED"]

#: The start value of the engine's ``fuel_kg`` input [kg]: no tank connected, the engine is not limited
#: (:mod:`.fuel_supply`).
FUEL_UNLIMITED_KG = 1e12
#: The engine's Integer output ``flameout_cause``: the text of each code (0: burning).
FLAMEOUT_CAUSES: tuple[str, ...] = (
    "",
    "burner fuel-air ratio below the lean limit or fuel flow below the minimum",
    "fuel starvation: the tanks could not deliver the metered fuel flow",
)
#: How many of an engine file's own outputs (its ``outputs:``) the engine FMU carries (``file_out_1`` ...).
N_FILE_OUTPUTS = 8
#: The code of a flame-out for want of fuel.
FLAMEOUT_STARVED = 2


def _out(name: str, unit: str, description: str) -> Signal:
    return Signal(name, "output", unit, description)


def _flag(name: str, description: str) -> Signal:
    return Signal(name, "output", "1", description, "Boolean")


def _in(name: str, unit: str, description: str, start: float, accessor: str | None) -> Signal:
    return Signal(name, "input", unit, description, start=start, accessor=accessor)


def _par(name: str, unit: str, description: str, start: float | None = None, accessor: str | None = None,
         type_: str = "Real") -> Signal:
    return Signal(name, "parameter", unit, description, type_, start, accessor)


#: Real outputs, in the order of :attr:`EngineModel.values` (filled by name, :data:`EO`).
_OUTPUT_ROWS: tuple[Signal, ...] = (
    _out("Fn_N", "N", "Net thrust"), _out("Fg_N", "N", "Gross thrust"),
    _out("ram_drag_N", "N", "Ram drag"), _out("Wf_kg_s", "kg/s", "Fuel flow burnt"),
    _out("N1_rpm", "rpm", "LP spool speed N1"), _out("N2_rpm", "rpm", "HP spool speed N2"),
    _out("N1_pct", "%", "LP spool speed N1, percent of design"),
    _out("N2_pct", "%", "HP spool speed N2, percent of design"),
    _out("N1c_pct", "%", "N1 corrected to the fan-face temperature, percent of design"),
    _out("Tt4_K", "K", "Burner exit total temperature Tt4"),
    _out("Tt41_K", "K", "HPT rotor inlet total temperature Tt41"),
    _out("Tt21_K", "K", "Fan core exit total temperature Tt21"),
    _out("Tt17_K", "K", "Bypass nozzle inlet total temperature Tt17"),
    _out("Tt7_K", "K", "Core nozzle inlet total temperature Tt7"), _out("Pt3_Pa", "Pa", "HPC exit total pressure Pt3"),
    _out("OPR", "1", "Overall pressure ratio Pt3/Pt2"), _out("BPR", "1", "Bypass ratio"),
    _out("SM_fan", "1", "Fan surge margin, worst (spoiled) sector"),
    _out("SM_hpc", "1", "HPC surge margin, worst (spoiled) sector"),
    _out("SM_fan_clean", "1", "Fan surge margin of the clean sector"),
    _out("SM_hpc_clean", "1", "HPC surge margin of the clean sector"),
    _out("SFC_kg_N_s", "kg/(N s)", "Specific fuel consumption, fuel flow over net thrust"),
    _out("fuel_burned_kg", "kg", "Fuel burned since the start"),
    _out("dN1_dt_rpm_s", "rpm/s", "LP spool acceleration"), _out("dN2_dt_rpm_s", "rpm/s", "HP spool acceleration"),
    _out("handling_bleed_frac", "1", "Handling bleed flow over HPC inlet flow"),
    _out("FAR4", "1", "Burner exit fuel-air ratio"), _out("W2_kg_s", "kg/s", "Engine inlet mass flow"),
    _out("offtake_hp_applied_W", "W", "HP shaft port power applied after its limits, + taken from the spool, "
                                      "- delivered to it"),
    _out("offtake_lp_applied_W", "W", "LP shaft port power applied after its limits, + taken from the spool, "
                                      "- delivered to it"),
    _out("Tt3_K", "K", "HPC exit total temperature Tt3 (the turbine's cooling air)"),
)
#: Boolean outputs, in the order of :attr:`EngineModel.flags`.
_FLAG_ROWS: tuple[Signal, ...] = (
    _flag("surge", "A compressor sector is beyond its surge line (margin < 0) or the fuel is limited there"),
    _flag("flameout", "Burner fuel-air ratio below the lean limit, or fuel flow below the minimum"),
    _flag("overspeed", "N1 or N2 above its limit"),
    _flag("solver_failed", "The last step could not be matched; the last good state is held"),
    _flag("fuel_limited", "Fuel flow limited to the largest the gas path can match (surge side of the HPC map)"),
    _flag("shaft_power_limited", "An HP or LP shaft port power (offtake or assist) was clipped to its limit"),
)
#: Real outputs of :attr:`EngineModel.values`, in order: (name, description with unit).
OUTPUTS: tuple[tuple[str, str], ...] = tuple((s.name, s.described()) for s in _OUTPUT_ROWS)
#: Boolean outputs of :attr:`EngineModel.flags`, in order: (name, description).
FLAGS: tuple[tuple[str, str], ...] = tuple((s.name, s.described()) for s in _FLAG_ROWS)
#: Index of each output in the model's value vector, by name (an IntEnum: the compiled step reads its members as
#: constants), so that both steps fill the outputs by name.
EO = enum.IntEnum("EO", [(name, i) for i, (name, _) in enumerate(OUTPUTS)])


@dataclass(frozen=True)
class EngineInputs:
    """Inputs held over one step.

    Attributes
    ----------
    Wf_cmd_kg_s : float
        Fuel flow command [kg/s] (the fuel system's stops limit what burns, the output ``Wf_kg_s``).
    alt_m, mach, dT_isa_K : float
        Flight condition: altitude above mean sea level, flown as the ISA geopotential altitude [m], Mach [-],
        ISA deviation [K].
    offtake_hp_W, offtake_lp_W : float
        Power at the HP and LP shaft ports [W], signed: positive is taken from the spool (accessories, a
        generator's load), negative is delivered to it (a motor's assist); clipped to the limits of
        :class:`EngineLimits` (``shaft_power_limited``).
    customer_bleed_frac : float
        Customer bleed from the HPC exit, W/W25 [-].
    distortion_on : bool
        Inlet distortion switched on.
    distortion_sector_deg, distortion_dPt_frac, distortion_dTt_K : float
        Spoiled sector angle [deg], its total-pressure deficit [-] and temperature excess [K].
    """

    Wf_cmd_kg_s: float
    alt_m: float = 0.0
    mach: float = 0.0
    dT_isa_K: float = 0.0
    offtake_hp_W: float = 0.0
    offtake_lp_W: float = 0.0
    customer_bleed_frac: float = 0.0
    distortion_on: bool = False
    distortion_sector_deg: float = 90.0
    distortion_dPt_frac: float = 0.0
    distortion_dTt_K: float = 0.0


@dataclass(frozen=True)
class EngineLimits(FromEngineFile):
    """Limits that raise flags.

    Attributes
    ----------
    N1_max_pct, N2_max_pct : float
        Overspeed limits [% of design speed].
    FAR_lean : float
        Lean (weak-extinction) limit of the burner fuel-air ratio [-]; Lefebvre & Ballal ch. 5.
    Wf_min_frac : float
        Smallest fuel flow the burner model takes, fraction of the design fuel flow [-]; lower
        inputs are clipped to it and flag a flameout.
    Wf_Pt3_min_frac : float
        Minimum-flow stop of the fuel metering unit, scheduled on the compressor delivery
        pressure, as a fraction of the design point's Wf/Pt3 [-]: the burner gets at least
        ``Wf_Pt3_min_frac * (Wf/Pt3)_design * Pt3``, whatever is commanded (the hydromechanical
        deceleration/minimum-flow stop of real fuel systems, which keeps a chop from blowing the
        burner out or stalling the fan while the HP spool runs down faster than the LP spool).
        As a fraction it fits any design: 0.32 is 8e-8 kg/(s Pa) on the Larzac 04, whose steady
        running line lies at 0.4 to 0.8 of its design ratio, and lets it run down from cruise to
        a steady sub-idle at 7500 m. 0 disables it.
    Wf_decel_max_frac_s : float
        Fastest decrease of the burned fuel flow, as a fraction of the design fuel flow per
        second [1/s], the fuel system's deceleration limit (0.38: 0.1 kg/s^2 on the Larzac 04,
        design fuel flow to zero in 2.6 s, of the order of a small turbofan's max-to-idle
        deceleration time). A chop commanded faster is followed at this rate: with an
        instantaneous chop (or at 2 per second) the HP spool of the model runs down so much faster
        than the LP spool that the fan is driven past its surge line within 0.2 to 0.5 s; at 0.38
        slam/chop cycles between idle and maximum run without a failed match from sea level to
        8000 m.
    offtake_hp_max_W, offtake_lp_max_W : float
        Largest power taken from the HP / LP shaft port (generator load, accessories) [W].
    assist_hp_max_W, assist_lp_max_W : float
        Largest power delivered to the HP / LP shaft port (motor assist) [W], as a positive number.
        A port input outside [-assist_max_W, offtake_max_W] is clipped to that range for the step,
        the clipped value is what the spool balance gets and what ``offtake_*_applied_W`` report, and the
        ``shaft_power_limited`` flag is set (its rising edge is an event, logged). Default 200 kW each,
        about 6 % of the Larzac 04's design HP spool power (3.5 MW) and 8 % of its LP spool power
        (2.4 MW): a machine rating for studies; set them to the electric machine's rating.

    References
    ----------
    L. C. Jaw, J. D. Mattingly, "Aircraft Engine Controls", AIAA, 2009, ch. 5 (Wf/P3 ratio-unit
    schedules, deceleration and minimum-flow limits).
    """

    SECTION: ClassVar[str] = "limits"

    N1_max_pct: float
    N2_max_pct: float
    FAR_lean: float
    Wf_min_frac: float
    Wf_Pt3_min_frac: float
    Wf_decel_max_frac_s: float
    offtake_hp_max_W: float
    offtake_lp_max_W: float
    assist_hp_max_W: float
    assist_lp_max_W: float

    def __post_init__(self) -> None:
        for name in ("offtake_hp_max_W", "offtake_lp_max_W", "assist_hp_max_W", "assist_lp_max_W"):
            v = getattr(self, name)
            if not (v >= 0.0 and math.isfinite(v)):
                raise OutOfRangeError(f"EngineLimits: {name}={v!r} must be finite and >= 0 [W]")


@dataclass(frozen=True)
class BleedValve(FromEngineFile):
    """Handling bleed valve with hysteresis, scheduled on the corrected fan speed.

    The valve is commanded open when N1c = N1 / sqrt(Tt2 / 288.15 K) falls below
    ``threshold_N1c_pct - band_pct / 2`` and closed when it rises above ``threshold_N1c_pct +
    band_pct / 2`` (percent of the design's corrected N1), as the reference engine's valve
    (the Larzac 04 blows air off behind its second HPC stage into the bypass "under a relative
    speed of 60 %" of the LP spool; its measured Tt7 departs from the reference study's model
    below about 11 000 rpm of N1, 64 % N1).

    Attributes
    ----------
    threshold_N1c_pct : float
        Centre of the switching band [% of design corrected N1].
    band_pct : float
        Width of the hysteresis band [% of design corrected N1].
    stroke_s : float
        Time for a full stroke [s].
    open_frac : float
        Bleed flow over HPC inlet flow when fully open [-].

    The values, units and ranges are those of ``data/engine.json``, section ``bleed_valve`` (:meth:`from_file`).
    """

    SECTION: ClassVar[str] = "bleed_valve"

    threshold_N1c_pct: float
    band_pct: float
    stroke_s: float
    open_frac: float



def condition_from_ambient(p_Pa: float, T_K: float) -> tuple[float, float]:
    """Flight condition (pressure altitude [m], ISA deviation [K]) of an ambient static state.

    The atmosphere model (:func:`.atmosphere.isa`) keeps the ISA pressure at an altitude and adds the
    deviation to the temperature, so (p, T) maps exactly to the altitude whose ISA pressure is p and
    to T minus that altitude's ISA temperature. p is clipped to the model's altitude range
    (-1000 m to 32000 m).
    """
    from scipy.optimize import brentq

    from .atmosphere import ALT_MAX_M, ALT_MIN_M, isa
    p_lo, p_hi = isa(ALT_MAX_M).P_Pa, isa(ALT_MIN_M).P_Pa
    p = min(p_hi, max(p_lo, p_Pa)) if p_Pa == p_Pa else p_hi
    alt = ALT_MIN_M if p >= p_hi else ALT_MAX_M if p <= p_lo else \
        float(brentq(lambda h: isa(h).P_Pa - p, ALT_MIN_M, ALT_MAX_M, xtol=1e-9, rtol=1e-15))
    return alt, T_K - isa(alt).T_K


#: Design parameters exposed as ``design_<field>`` (fields of ``TurbofanParams``): (field, unit, description).
DESIGN_FIELDS: tuple[tuple[str, str, str], ...] = (
    ("W2_kg_s", "kg/s", "Design inlet mass flow"), ("inlet_pi", "1", "Design intake total-pressure recovery"),
    ("BPR", "1", "Design bypass ratio"), ("PR_fan_outer", "1", "Design fan outer (bypass) pressure ratio"),
    ("eta_fan_outer", "1", "Design fan outer isentropic efficiency"),
    ("PR_fan_inner", "1", "Design fan inner (core) pressure ratio"),
    ("eta_fan_inner", "1", "Design fan inner isentropic efficiency"), ("PR_hpc", "1", "Design HPC pressure ratio"),
    ("eta_hpc", "1", "Design HPC isentropic efficiency"), ("Tt4_K", "K", "Design burner exit temperature"),
    ("eta_burner", "1", "Burner efficiency"), ("dPqP_burner", "1", "Burner relative pressure loss"),
    ("eta_hpt", "1", "Design HPT isentropic efficiency"), ("eta_lpt", "1", "Design LPT isentropic efficiency"),
    ("dPqP_21_24", "1", "Fan-HPC duct relative pressure loss"),
    ("dPqP_44_45", "1", "HPT-LPT duct relative pressure loss"),
    ("dPqP_5_7", "1", "Jet pipe relative pressure loss"), ("dPqP_13_17", "1", "Bypass duct relative pressure loss"),
    ("eta_mech_hp", "1", "HP spool mechanical efficiency"), ("eta_mech_lp", "1", "LP spool mechanical efficiency"),
    ("Cv_core", "1", "Core nozzle velocity coefficient"), ("Cd_core", "1", "Core nozzle discharge coefficient"),
    ("Cv_bypass", "1", "Bypass nozzle velocity coefficient"), ("Cd_bypass", "1", "Bypass nozzle discharge coefficient"),
    ("N1_rpm", "rpm", "Design LP spool speed"), ("N2_rpm", "rpm", "Design HP spool speed"),
)


def _defaults(cls: type) -> dict[str, float]:
    return {f.name: f.default for f in fields(cls)}


_IN = _defaults(EngineInputs)
#: The engine FMU's parameter sets: section of ``data/engine.json`` -> (its dataclass, the prefix of its
#: parameters' FMU names). The FMU's parameters are their entries, and it builds the model from them.
PARAMETER_SETS: dict[str, tuple[type, str]] = {"limits": (EngineLimits, ""), "bleed_valve": (BleedValve, "bleed_"),
                                               "numerics": (EngineNumerics, ""), "start": (EngineStart, "")}
_NAMES = {"fan": "Fan", "hpc": "HPC", "hpt": "HPT", "lpt": "LPT"}
#: The health parameters (:mod:`.health`): tunable, so a scenario can ramp them over a run.
_HEALTH_ROWS: tuple[Signal, ...] = tuple(
    Signal(name, "parameter", "1", f"{_NAMES[name.split('_')[1]]} health: relative change of its "
           + ("isentropic efficiency" if "_eta_" in name else "flow capacity")
           + f" against the clean map (e.g. -0.01), within +-{HEALTH_LIMIT:g}", start=0.0, variability="tunable")
    for name in health_parameter_names())

#: The engine's signal table: every variable of the engine FMU, in its order of registration. The
#: parameters' start values are the shipped configuration (the Larzac 04 at its flight idle start);
#: those of :data:`PARAMETER_SETS` come from ``data/engine.json`` with their ranges.
SIGNALS: tuple[Signal, ...] = check_table((
    _par("preset", "1", "Engine preset: larzac04_sls or reference_study", "larzac04_sls", type_="String"),
    _par("engine_file", "1", "Engine file (a path, or a shipped name: larzac04, pycycle_hbtf, ...) flown instead of "
         "the preset; empty: the preset", "", type_="String"),
    _par("thrust_scale", "1", "With engine_file: airflow, thrust, fuel flow and areas scaled at constant cycle, > 0",
         1.0),
    _par("design_override", "1", "Use the design_* parameters instead of the preset's values", False,
         type_="Boolean"),
    *(_par(f"design_{f}", u, d, None, f) for f, u, d in DESIGN_FIELDS),  # start: the preset's value
    # limits, bleed valve, numerics and start: generated from data/engine.json (value, unit, range, note)
    *(row for section, (cls, prefix) in PARAMETER_SETS.items()
      for row in engine_set(cls, section).signals(prefix, variability=None)),
    *_HEALTH_ROWS,
    # inputs: each the field of EngineInputs of its name (the flight condition, the fuel flow command, ...)
    _in("Wf_cmd_kg_s", "kg/s", "Fuel flow command; <= 0 at the start: the start point's", 0.0, None),
    _in("alt_m", "m", "Altitude above mean sea level, flown as the ISA geopotential altitude",
        _IN["alt_m"], None),
    _in("mach", "1", "Flight Mach number", _IN["mach"], None),
    _in("dT_isa_K", "K", "ISA temperature deviation of the atmosphere flown (the airframe's dT_isa_K)",
        _IN["dT_isa_K"], None),
    _in("offtake_hp_W", "W", "HP shaft port power, + taken from the spool (offtake, generator), - delivered to "
                             "it (motor assist)", _IN["offtake_hp_W"], None),
    _in("offtake_lp_W", "W", "LP shaft port power, + taken from the spool (offtake, generator), - delivered to "
                             "it (motor assist)", _IN["offtake_lp_W"], None),
    _in("customer_bleed_frac", "1", "Customer bleed from the HPC exit over HPC inlet flow",
        _IN["customer_bleed_frac"], None),
    _in("distortion_sector_deg", "deg", "Spoiled inlet sector angle", _IN["distortion_sector_deg"], None),
    _in("distortion_dPt_frac", "1", "Total-pressure deficit of the spoiled sector over the clean value",
        _IN["distortion_dPt_frac"], None),
    _in("distortion_dTt_K", "K", "Total-temperature excess of the spoiled sector", _IN["distortion_dTt_K"], None),
    # read by the FMU itself (use_ambient), not a field of EngineInputs
    _in("p_amb_Pa", "Pa", "Ambient static pressure, used with use_ambient", P0_PA, None),
    _in("T_amb_K", "K", "Ambient static temperature, used with use_ambient", T0_K, None),
    _in("fuel_kg", "kg", "Fuel the tanks feeding the engine hold (the airframe's fuel_kg): the burner flames out "
                         "when they cannot deliver the metered flow over a step; the start value, no tank "
                         "connected, does not limit", FUEL_UNLIMITED_KG, None),
    Signal("distortion_on", "input", "1", "Inlet distortion switched on", "Boolean", _IN["distortion_on"]),
    *_OUTPUT_ROWS,
    *_FLAG_ROWS,
    Signal("events", "output", "1", "Rising edges of surge, flameout, overspeed, fuel limiting, shaft power "
           "limiting", "Integer"),
    # the engine file's own outputs (its outputs: section, in its order); 0 where it declares fewer
    *(Signal(f"file_out_{k + 1}", "output", "1", f"Output {k + 1} of the engine file's outputs: section, in the "
             "unit its name says (the FMU logs the names at initialisation); 0 without one", "Real")
      for k in range(N_FILE_OUTPUTS)),
    Signal("flameout_cause", "output", "1", "Why the burner is out: "
           + "; ".join(f"{i} {c.partition(':')[0] or 'burning'}" for i, c in enumerate(FLAMEOUT_CAUSES)), "Integer"),
), "models/engine/engine_signals.py")
