"""Generate the openEMSS system files in this folder from the FMUs themselves.

    build-fmus --out ssp/resources && python ssp/generate.py

writes ``SystemStructure.ssd`` (engine, airframe and flight control wired
together, every connector taken from its FMU's modelDescription.xml with the unit
its description states) and the parameter sets ``engine_larzac04.ssv``,
``engine_reference_study.ssv``, ``engine_redesigned.ssv`` (the lowest-SFC engine of the
cycle study; ``emss run --params ssp/engine_redesigned.ssv`` flies it),
``aircraft_mtow.ssv`` (2100 kg: full tank), ``aircraft_half_fuel.ssv`` (1800 kg) and
``munich_wind_turbulence.ssv`` (the airframe's weather: a 20 kt wind aloft, light turbulence);
and ``hybrid/`` the same system with the electrical power system (``fmus/electric.py``) on both spools,
with its parameter sets ``ems_off.ssv`` and ``no_boost.ssv``. ``emss run ssp/hybrid`` flies it.
``tests/test_system_files.py`` checks every connector of the result against the FMUs, so the
files cannot drift from them.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

from openemss.orchestrator.ssp_write import ParameterSet, SystemBuilder, connectors_from_fmu

HERE = Path(__file__).resolve().parent
RESOURCES = HERE / "resources"
STEP_S = 0.05  # 20 Hz, the reference system's rate

# airframe outputs the flight control reads, under the same names on both sides
AIRFRAME_TO_FCS = ("lat_deg", "lon_deg", "alt_msl_m", "tas_m_s", "gs_m_s", "vs_m_s", "phi_rad", "theta_rad",
                   "psi_rad", "p_rad_s", "q_rad_s", "r_rad_s", "beta_rad", "rho_amb_kg_m3", "mass_kg", "on_ground")
FCS_TO_AIRFRAME = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "airbrake_norm", "brakes_norm",
                   "steering_norm", "gear_down")
ENGINE_TO_AIRFRAME = ("thrust_N", "fuel_flow_kg_s")
# (start, end): names that differ between the two sides
RENAMED = (("airframe.alt_msl_m", "engine.alt_m"), ("airframe.mach", "engine.mach"),
           ("engine.N1_pct", "fcs.N1_pct"), ("engine.N1c_pct", "fcs.N1c_pct"),
           ("engine.T41_K", "fcs.Tt41_K"),  # the engine's rotor inlet temperature is the limit the FCS watches
           ("fcs.fuel_flow_cmd_kg_s", "engine.fuel_flow_cmd_kg_s"))
ENGINE_OUT = ("thrust_N", "gross_thrust_N", "fuel_flow_kg_s", "N1_rpm", "N2_rpm", "N1_pct", "N2_pct", "N1c_pct",
              "Tt4_K", "T41_K", "Tt21_K", "Tt17_K", "Tt7_K", "Pt3_Pa", "OPR", "BPR", "SM_fan", "SM_hpc",
              "SFC_kg_N_s", "fuel_burned_kg", "surge", "flameout", "overspeed", "solver_failed")
AIRFRAME_OUT = ("lat_deg", "lon_deg", "alt_msl_m", "alt_agl_m", "tas_m_s", "cas_m_s", "gs_m_s", "mach",
                "alpha_rad", "beta_rad", "phi_rad", "theta_rad", "psi_rad", "p_rad_s", "q_rad_s", "r_rad_s",
                "load_factor", "vs_m_s", "p_amb_Pa", "T_amb_K", "rho_amb_kg_m3", "airbrake_pos_norm", "on_ground",
                "mass_kg", "fuel_kg")
FCS_OUT = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "airbrake_norm", "brakes_norm",
           "steering_norm", "gear_down", "lever_norm", "fuel_flow_cmd_kg_s", "alt_cmd_m", "tas_cmd_m_s", "mach_cmd",
           "track_cmd_rad", "section_index", "mission_completed", "fuel_limiter", "vnav_mode", "ils_phase")
# The electrical power system of ssp/hybrid/ (fmus/electric.py): spool speeds, lever and on-ground in; the
# signed shaft powers to the engine's offtake inputs (> 0 taken from the spool, < 0 delivered: boost) and its
# mass to the airframe. pulse_load_W stays unconnected, for scenarios to set.
ELECTRIC_IN = ("N1_rpm", "N2_rpm", "lever_norm", "vs_m_s", "on_ground", "pulse_load_W")
ELECTRIC_OUT = ("offtake_hp_W", "offtake_lp_W", "hp_elec_W", "lp_elec_W", "hp_loss_W", "lp_loss_W", "battery_W",
                "battery_V", "battery_A", "soc", "load_W", "pulse_W", "load_shed_W", "E_shaft_hp_J", "E_shaft_lp_J",
                "E_elec_hp_J", "E_elec_lp_J", "E_loss_J", "E_batt_J", "E_loads_J", "E_shed_J", "mass_kg",
                "hp_limited", "lp_limited", "battery_limited", "load_shed", "ems_mode")
# the engine's shaft ports as applied after its own limits (recorded in the hybrid system)
ENGINE_PORTS_OUT = ("offtake_hp_applied_W", "offtake_lp_applied_W", "shaft_power_limited")
ELECTRIC_LINKS = (("engine.N1_rpm", "electric.N1_rpm"), ("engine.N2_rpm", "electric.N2_rpm"),
                  ("fcs.lever_norm", "electric.lever_norm"), ("airframe.vs_m_s", "electric.vs_m_s"),
                  ("airframe.on_ground", "electric.on_ground"),
                  ("electric.offtake_hp_W", "engine.offtake_hp_W"), ("electric.offtake_lp_W", "engine.offtake_lp_W"),
                  ("electric.mass_kg", "airframe.added_mass_kg"))
# Flight idle of the Larzac-04-sized engines (the fuel controller's lowest N1c demand, and the TECS lever
# that demands it, N1c_idle / k_delta): 40 % corrected fan speed runs steadily on the engine model from sea
# level to 7500 m (its lowest steady N1 there: 18 to 30 %) and gives 0.84 kN at 600 m, Mach 0.2 (a
# 3-degree glide slope needs about 0.9 kN) and -0.2 kN at 7500 m, Mach 0.75.
IDLE = {"fcs.fuel_control.N1c_idle_pct": 40.0, "fcs.tecs.lever_min": 0.40}
# the flight control's first fuel-flow command and the engine's start: steady at 60 % N1, sea level static
START = {"engine": {"start_N1_pct": 60.0, "preset": "larzac04_sls"},
         "fcs": {"Wf0_kg_s": 0.07, **{k.partition(".")[2]: v for k, v in IDLE.items()}}}


def _unit(fmu: Path, name: str, unit: str | None) -> str | None:
    """The unit of a variable: its unit attribute, else the one its description ends with ("[N]")."""
    if unit is not None:
        return unit
    from fmpy import read_model_description

    md = read_model_description(str(fmu), validate=False)
    v = next(v for v in md.modelVariables if v.name == name)
    m = re.search(r"\[([^\]]+)\]\s*$", v.description or "")
    return None if m is None or m.group(1) == "-" else m.group(1)


def _add(sys_: SystemBuilder, name: str, fmu_file: str, names: list[str]) -> None:
    fmu = RESOURCES / fmu_file
    comp = sys_.component(name, f"resources/{fmu_file}")
    for n, kind, type_name, unit in connectors_from_fmu(fmu, names):
        comp.connector(n, kind, type_name, _unit(fmu, n, unit) if type_name == "Real" else None)
    if name in START:
        comp.parameters(dict(START[name]))


def build_system(hybrid: bool = False) -> SystemBuilder:
    """The engine + airframe + flight-control system of the Munich mission; with ``hybrid`` the electrical
    power system too (``ssp/hybrid/``): its machines on both spools (:data:`ELECTRIC_LINKS`)."""
    # the Munich mission takes about 4040 s; emss run ends when the FCS reports it completed
    sys_ = SystemBuilder("openEMSS_hybrid" if hybrid else "openEMSS").experiment(0.0, 5000.0, STEP_S)
    # the distortion inputs are connectors too (unconnected), so a scenario that sets them is recorded
    engine_in = ["fuel_flow_cmd_kg_s", "alt_m", "mach", "distortion_on", "distortion_sector_deg",
                 "distortion_dPt_frac"] + (["offtake_hp_W", "offtake_lp_W"] if hybrid else [])
    fcs_in = [*AIRFRAME_TO_FCS, "N1_pct", "N1c_pct", "Tt41_K"]
    airframe_in = [*FCS_TO_AIRFRAME, *ENGINE_TO_AIRFRAME] + (["added_mass_kg"] if hybrid else [])
    _add(sys_, "fcs", "Fcs.fmu", fcs_in + list(FCS_OUT))
    _add(sys_, "engine", "Engine.fmu", engine_in + list(ENGINE_OUT) + (list(ENGINE_PORTS_OUT) if hybrid else []))
    _add(sys_, "airframe", "Airframe.fmu", airframe_in + list(AIRFRAME_OUT))
    names = ["fcs", "engine", "airframe"]
    if hybrid:
        _add(sys_, "electric", "Electric.fmu", list(ELECTRIC_IN) + list(ELECTRIC_OUT))
        for start, end in ELECTRIC_LINKS:
            sys_.connect(start, end)
        names.append("electric")
    for n in AIRFRAME_TO_FCS:
        sys_.connect(f"airframe.{n}", f"fcs.{n}")
    for n in FCS_TO_AIRFRAME:
        sys_.connect(f"fcs.{n}", f"airframe.{n}")
    for n in ENGINE_TO_AIRFRAME:
        sys_.connect(f"engine.{n}", f"airframe.{n}")
    for start, end in RENAMED:
        sys_.connect(start, end)
    for name in names:
        for unit in sorted({k[3] for c in sys_.components if c.name == name for k in c.connectors if k[3]}):
            if unit not in sys_.units:
                sys_.units[unit] = _SI.get(unit, {"factor": 1.0, "offset": 0.0})
    return sys_


# The units the connectors use, as SSP unit definitions (SI base exponents).
_SI: dict[str, dict[str, float]] = {
    "N": {"kg": 1, "m": 1, "s": -2, "factor": 1.0, "offset": 0.0},
    "kg/s": {"kg": 1, "s": -1, "factor": 1.0, "offset": 0.0},
    "kg": {"kg": 1, "factor": 1.0, "offset": 0.0},
    "m": {"m": 1, "factor": 1.0, "offset": 0.0},
    "m/s": {"m": 1, "s": -1, "factor": 1.0, "offset": 0.0},
    "rad": {"rad": 1, "factor": 1.0, "offset": 0.0},
    "rad/s": {"rad": 1, "s": -1, "factor": 1.0, "offset": 0.0},
    "deg": {"rad": 1, "factor": 0.017453292519943295, "offset": 0.0},
    "K": {"K": 1, "factor": 1.0, "offset": 0.0},
    "Pa": {"kg": 1, "m": -1, "s": -2, "factor": 1.0, "offset": 0.0},
    "kg/m3": {"kg": 1, "m": -3, "factor": 1.0, "offset": 0.0},
    "rpm": {"rad": 1, "s": -1, "factor": 0.10471975511965977, "offset": 0.0},
    "%": {"factor": 0.01, "offset": 0.0},
    "kg/(N s)": {"m": -1, "s": 1, "factor": 1.0, "offset": 0.0},
    "W": {"kg": 1, "m": 2, "s": -3, "factor": 1.0, "offset": 0.0},
    "J": {"kg": 1, "m": 2, "s": -2, "factor": 1.0, "offset": 0.0},
    "V": {"kg": 1, "m": 2, "s": -3, "A": -1, "factor": 1.0, "offset": 0.0},
    "A": {"A": 1, "factor": 1.0, "offset": 0.0},
}


def redesigned_engine() -> dict[str, bool | float | str]:
    """The engine of lowest SFC in SPEC.md's cycle study from the reference study's model (BPR 0.5 to 2,
    OPR 9 to 20, equal thrust, Tt4 and jet velocity ratio), as the engine FMU's design parameters."""
    from openemss.fmus.engine import DESIGN
    from openemss.models.engine.cycle_study import cycle_study, lowest_sfc_design
    from openemss.models.engine.design_params import load_params, preset_path

    ref = load_params(preset_path("reference_study"))
    bprs = [0.5 + 0.25 * i for i in range(7)]
    oprs = [9.0 + i for i in range(12)]
    chosen, _ = lowest_sfc_design(ref, cycle_study(ref, bprs, oprs))
    return {"engine.preset": "reference_study", "engine.design_override": True,
            **{f"engine.design_{n}": float(getattr(chosen, n)) for n, _ in DESIGN}}


def parameter_sets() -> dict[str, ParameterSet]:
    """System-level parameter sets: the engines (with their flight idle), the aircraft's loading."""
    return {"engine_larzac04.ssv": ParameterSet("engine_larzac04", {"engine.preset": "larzac04_sls", **IDLE}),
            "engine_reference_study.ssv": ParameterSet("engine_reference_study",
                                                       {"engine.preset": "reference_study", **IDLE}),
            "engine_redesigned.ssv": ParameterSet("engine_redesigned", {**redesigned_engine(), **IDLE}),
            # UPERA: operating empty mass 1500 kg, tank 600 kg (SPEC.md): take-off mass = 1500 kg + fuel
            "aircraft_mtow.ssv": ParameterSet("aircraft_mtow", {"airframe.fuel0_kg": 600.0}),
            "aircraft_half_fuel.ssv": ParameterSet("aircraft_half_fuel", {"airframe.fuel0_kg": 300.0}),
            # the Munich mission in a 20 kt wind aloft and light turbulence (the airframe owns the weather)
            "munich_wind_turbulence.ssv": ParameterSet("munich_wind_turbulence", {
                "airframe.weather_file": "missions/weather/munich_wind_light_turbulence.yaml"})}


def hybrid_parameter_sets() -> dict[str, ParameterSet]:
    """Parameter sets of ``ssp/hybrid/``: the electrical system without energy management (the HP generator
    supplies the bus, the LP machine idles: the reference for the hybrid figures) and without boost."""
    return {"ems_off.ssv": ParameterSet("ems_off", {"electric.ems.enabled": False}),
            "no_boost.ssv": ParameterSet("no_boost", {"electric.ems.boost_W": 0.0})}


def main() -> int:
    missing = [f for f in ("Fcs.fmu", "Engine.fmu", "Airframe.fmu", "Electric.fmu") if not (RESOURCES / f).is_file()]
    if missing:
        print(f"generate: build the FMUs first: build-fmus --out {RESOURCES} (missing {', '.join(missing)})",
              file=sys.stderr)
        return 1
    build_system().write(HERE)
    build_system(hybrid=True).write(HERE / "hybrid")
    from lxml import etree

    for folder, sets in ((HERE, parameter_sets()), (HERE / "hybrid", hybrid_parameter_sets())):
        for name, pset in sets.items():
            (folder / name).write_bytes(etree.tostring(pset.element(), xml_declaration=True, encoding="UTF-8",
                                                       pretty_print=True))
    print(f"wrote {HERE / 'SystemStructure.ssd'}, {', '.join(parameter_sets())}, "
          f"{HERE / 'hybrid' / 'SystemStructure.ssd'} and {', '.join(hybrid_parameter_sets())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
