"""Signals of the engine in time: inputs, outputs, flags, limits, the handling-bleed valve.

The names and descriptions (with units in brackets) of :data:`OUTPUTS` and :data:`FLAGS`
are those of the engine FMU's outputs; :class:`EngineInputs` holds its inputs for one step;
:func:`condition_from_ambient` turns an ambient static state into the flight condition of
the atmosphere model. Used by :mod:`.engine_model`.

References
----------
A. H. Lefebvre, D. R. Ballal, "Gas Turbine Combustion", 3rd ed., 2010, ch. 5 (weak
extinction: overall fuel-air ratios of about 0.002 to 0.005 at idle conditions).
ISO 2533:1975, Standard Atmosphere (pressure altitude).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import OutOfRangeError

__all__ = ["EngineInputs", "EngineLimits", "BleedValve", "OUTPUTS", "FLAGS", "condition_from_ambient"]

#: Real outputs of :attr:`EngineModel.values`, in order: (name, description with unit).
OUTPUTS: tuple[tuple[str, str], ...] = (
    ("thrust_N", "Net thrust [N]"), ("gross_thrust_N", "Gross thrust [N]"), ("ram_drag_N", "Ram drag [N]"),
    ("fuel_flow_kg_s", "Fuel flow burnt [kg/s]"), ("N1_rpm", "LP spool speed N1 [rpm]"),
    ("N2_rpm", "HP spool speed N2 [rpm]"), ("N1_pct", "LP spool speed N1, percent of design [%]"),
    ("N2_pct", "HP spool speed N2, percent of design [%]"),
    ("N1c_pct", "N1 corrected to the fan-face temperature, percent of design [%]"),
    ("Tt4_K", "Burner exit total temperature Tt4 [K]"), ("T41_K", "HPT rotor inlet total temperature T41 [K]"),
    ("Tt21_K", "Fan core exit total temperature Tt21 [K]"),
    ("Tt17_K", "Bypass nozzle inlet total temperature Tt17 [K]"),
    ("Tt7_K", "Core nozzle inlet total temperature Tt7 [K]"), ("Pt3_Pa", "HPC exit total pressure Pt3 [Pa]"),
    ("OPR", "Overall pressure ratio Pt3/Pt2 [-]"), ("BPR", "Bypass ratio [-]"),
    ("SM_fan", "Fan surge margin, worst (spoiled) sector [-]"),
    ("SM_hpc", "HPC surge margin, worst (spoiled) sector [-]"),
    ("SM_fan_clean", "Fan surge margin of the clean sector [-]"),
    ("SM_hpc_clean", "HPC surge margin of the clean sector [-]"),
    ("SFC_kg_N_s", "Specific fuel consumption, fuel flow over net thrust [kg/(N s)]"),
    ("fuel_burned_kg", "Fuel burned since the start [kg]"),
    ("dN1_dt_rpm_s", "LP spool acceleration [rpm/s]"), ("dN2_dt_rpm_s", "HP spool acceleration [rpm/s]"),
    ("handling_bleed_frac", "Handling bleed flow over HPC inlet flow [-]"),
    ("FAR4", "Burner exit fuel-air ratio [-]"), ("W2_kg_s", "Engine inlet mass flow [kg/s]"),
    ("offtake_hp_applied_W", "HP shaft port power applied after its limits, + taken from the spool, - delivered "
                             "to it [W]"),
    ("offtake_lp_applied_W", "LP shaft port power applied after its limits, + taken from the spool, - delivered "
                             "to it [W]"),
)
#: Boolean outputs of :attr:`EngineModel.flags`, in order: (name, description).
FLAGS: tuple[tuple[str, str], ...] = (
    ("surge", "A compressor sector is beyond its surge line (margin < 0) or the fuel is limited there [-]"),
    ("flameout", "Burner fuel-air ratio below the lean limit, or fuel flow below the minimum [-]"),
    ("overspeed", "N1 or N2 above its limit [-]"),
    ("solver_failed", "The last step could not be matched; the last good state is held [-]"),
    ("fuel_limited", "Fuel flow limited to the largest the gas path can match (surge side of the HPC map) [-]"),
    ("shaft_power_limited", "An HP or LP shaft port power (offtake or assist) was clipped to its limit [-]"),
)


@dataclass(frozen=True)
class EngineInputs:
    """Inputs held over one step.

    Attributes
    ----------
    Wf_kg_s : float
        Fuel flow [kg/s].
    alt_m, Mach, dT_isa_K : float
        Flight condition: geopotential altitude [m], Mach [-], ISA deviation [K].
    offtake_hp_W, offtake_lp_W : float
        Power at the HP and LP shaft ports [W], signed: positive is taken from the spool (accessories, a
        generator's load), negative is delivered to it (a motor's assist); clipped to the limits of
        :class:`EngineLimits` (``shaft_power_limited``).
    customer_bleed_frac : float
        Customer bleed from the HPC exit, W/W25 [-].
    distortion_on : bool
        Inlet distortion switched on.
    sector_deg, dPt_frac, dTt_K : float
        Spoiled sector angle [deg], its total-pressure deficit [-] and temperature excess [K].
    """

    Wf_kg_s: float
    alt_m: float = 0.0
    Mach: float = 0.0
    dT_isa_K: float = 0.0
    offtake_hp_W: float = 0.0
    offtake_lp_W: float = 0.0
    customer_bleed_frac: float = 0.0
    distortion_on: bool = False
    sector_deg: float = 90.0
    dPt_frac: float = 0.0
    dTt_K: float = 0.0


@dataclass(frozen=True)
class EngineLimits:
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

    N1_max_pct: float = 105.0
    N2_max_pct: float = 105.0
    FAR_lean: float = 0.003
    Wf_min_frac: float = 0.01
    Wf_Pt3_min_frac: float = 0.32
    Wf_decel_max_frac_s: float = 0.38
    offtake_hp_max_W: float = 200e3
    offtake_lp_max_W: float = 200e3
    assist_hp_max_W: float = 200e3
    assist_lp_max_W: float = 200e3

    def __post_init__(self) -> None:
        for name in ("offtake_hp_max_W", "offtake_lp_max_W", "assist_hp_max_W", "assist_lp_max_W"):
            v = getattr(self, name)
            if not (v >= 0.0 and math.isfinite(v)):
                raise OutOfRangeError(f"EngineLimits: {name}={v!r} must be finite and >= 0 [W]")


@dataclass(frozen=True)
class BleedValve:
    """Handling bleed valve with hysteresis.

    Attributes
    ----------
    threshold_N2_pct : float
        Centre of the switching band [% of design N2].
    band_pct : float
        Width of the hysteresis band [% of design N2].
    stroke_s : float
        Time for a full stroke [s].
    open_frac : float
        Bleed flow over HPC inlet flow when fully open [-].
    """

    threshold_N2_pct: float = 60.0
    band_pct: float = 2.0
    stroke_s: float = 0.5
    open_frac: float = 0.10


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
