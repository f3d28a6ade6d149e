"""Generate the openEMSS system files in this folder from the FMUs themselves.

    build-fmus --out ssp/resources && python ssp/generate.py

writes ``SystemStructure.ssd`` (engine, airframe and flight control wired
together name to name, every connector taken from its FMU's modelDescription.xml with its FMI
unit, the units defined as the FMUs' UnitDefinitions; no parameter bound: the FMUs' defaults are
the shipped configuration) and the parameter sets ``engine_larzac04.ssv``,
``engine_reference_study.ssv``, ``engine_redesigned.ssv`` (the lowest-SFC engine of the
cycle study; ``emss run --params ssp/engine_redesigned.ssv`` flies it),
``aircraft_mtow.ssv`` (2100 kg: full tank), ``aircraft_half_fuel.ssv`` (1800 kg) and
``munich_wind_turbulence.ssv`` (the airframe's weather: a 20 kt wind aloft, light turbulence),
``engine_degraded.ssv`` (the engine's health parameters of a mid-life deterioration, to combine with an engine's set);
and ``hybrid/`` the same system with the electrical power system (``fmus/electric.py``) on both spools,
with its parameter sets ``ems_off.ssv`` and ``no_boost.ssv``. ``emss run ssp/hybrid`` flies it.
``tests/test_system_files.py`` checks every connector of the result against the FMUs, so the
files cannot drift from them.
"""
from __future__ import annotations

import sys
from pathlib import Path

from openemss.models.infra.signals import DEPARTURE
from openemss.models.engine.health import MID_LIFE, health_parameters
from openemss.models.fcs.fcs_signals import GAIN_DEFAULTS
from openemss.orchestrator.ssp.write import ParameterSet, SystemBuilder, connectors_from_fmu

HERE = Path(__file__).resolve().parent
RESOURCES = HERE / "resources"
STEP_S = 0.05  # 20 Hz, the reference system's rate

DEPARTURE_NAMES = tuple(f"departure_{q}" for q, _, _ in DEPARTURE)
# What each component's inputs are connected to: every input takes the output of the same name (one
# name per quantity, from the models' signal tables), from the component named here.
SOURCES = {
    "fcs": {"airframe": ("lat_deg", "lon_deg", "alt_m", "tas_m_s", "gs_m_s", "vs_m_s", "phi_rad", "theta_rad",
                         "psi_rad", "p_rad_s", "q_rad_s", "r_rad_s", "beta_rad", "rho_amb_kg_m3", "dT_isa_K",
                         "mass_kg", "on_ground"),
            "engine": ("N1_pct", "N1c_pct", "Tt41_K")},
    # the departure runway: the airframe starts where the flight control's mission departs (one source)
    "airframe": {"fcs": ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "airbrake_norm",
                         "brakes_norm", "steering_norm", "gear_down", *DEPARTURE_NAMES),
                 "engine": ("Fn_N", "Wf_kg_s")},
    "engine": {"fcs": ("Wf_cmd_kg_s",), "airframe": ("fuel_kg", "alt_m", "dT_isa_K", "mach")},
}
# No input is declared as a connector without a connection: FMPy's SSP runner (fmpy 0.3) feeds such an input
# the value of the connector before it (ssp/hybrid failed there at t = 0.1 s: the engine's distortion inputs got
# the LP offtake's 403 W). An input a scenario sets (the engine's distortion, the electric pulse load) is
# recorded all the same: emss run records every input its scenario names.
ENGINE_OUT = ("Fn_N", "Fg_N", "Wf_kg_s", "N1_rpm", "N2_rpm", "N1_pct", "N2_pct", "N1c_pct",
              "Tt4_K", "Tt41_K", "Tt21_K", "Tt17_K", "Tt7_K", "Tt3_K", "Pt3_Pa", "OPR", "BPR", "SM_fan", "SM_hpc",
              "SFC_kg_N_s", "fuel_burned_kg", "surge", "flameout", "overspeed", "solver_failed", "flameout_cause")
AIRFRAME_OUT = ("lat_deg", "lon_deg", "alt_m", "alt_agl_m", "tas_m_s", "cas_m_s", "gs_m_s", "mach",
                "alpha_rad", "beta_rad", "phi_rad", "theta_rad", "psi_rad", "p_rad_s", "q_rad_s", "r_rad_s",
                "load_factor", "vs_m_s", "p_amb_Pa", "T_amb_K", "rho_amb_kg_m3", "airbrake_pos_norm", "on_ground",
                "mass_kg", "fuel_kg", "dT_isa_K")
FCS_OUT = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "airbrake_norm", "brakes_norm",
           "steering_norm", "gear_down", "lever_norm", "Wf_cmd_kg_s", "alt_cmd_m", "tas_cmd_m_s", "mach_cmd",
           "track_cmd_rad", "section_index", "mission_completed", "fuel_limiter", "vnav_mode", "ils_phase",
           *DEPARTURE_NAMES)
# The electrical power system of ssp/hybrid/ (fmus/electric.py): spool speeds, lever, vertical speed and
# on-ground in; the signed shaft powers to the engine's port inputs (> 0 taken from the spool, < 0
# delivered: boost) and its mass to the airframe. pulse_load_W is not connected: a scenario sets it.
HYBRID_SOURCES = {
    "electric": {"engine": ("N1_rpm", "N2_rpm"), "fcs": ("lever_norm",), "airframe": ("vs_m_s", "on_ground")},
    "engine": {"electric": ("offtake_hp_W", "offtake_lp_W")},
    "airframe": {"electric": ("added_mass_kg",)},
}
ELECTRIC_OUT = ("offtake_hp_W", "offtake_lp_W", "hp_elec_W", "lp_elec_W", "hp_loss_W", "lp_loss_W", "battery_W",
                "battery_V", "battery_A", "soc", "load_W", "pulse_W", "load_shed_W", "E_shaft_hp_J", "E_shaft_lp_J",
                "E_elec_hp_J", "E_elec_lp_J", "E_loss_J", "E_batt_J", "E_loads_J", "E_shed_J", "added_mass_kg",
                "hp_limited", "lp_limited", "battery_limited", "load_shed", "ems_mode")
# the engine's shaft ports as applied after its own limits (recorded in the hybrid system)
ENGINE_PORTS_OUT = ("offtake_hp_applied_W", "offtake_lp_applied_W", "shaft_power_limited")
OUTPUTS = {"fcs": FCS_OUT, "engine": ENGINE_OUT, "airframe": AIRFRAME_OUT, "electric": ELECTRIC_OUT}
FMUS = {"fcs": "Fcs.fmu", "engine": "Engine.fmu", "airframe": "Airframe.fmu", "electric": "Electric.fmu"}
# The flight idle of the Larzac-04-sized engines, which the FCS FMU starts with (models/fcs/fcs_signals.py);
# the engine parameter sets state it with their engine.
IDLE = {f"fcs.{k}": v for k, v in GAIN_DEFAULTS.items()}


def _add(sys_: SystemBuilder, name: str, sources: dict[str, dict[str, tuple[str, ...]]],
         outputs: tuple[str, ...]) -> None:
    fmu = RESOURCES / FMUS[name]
    comp = sys_.component(name, f"resources/{FMUS[name]}")
    inputs = [n for names in sources.get(name, {}).values() for n in names]
    for n, kind, type_name, unit in connectors_from_fmu(fmu, inputs + list(outputs)):
        comp.connector(n, kind, type_name, unit if type_name == "Real" else None)


def fmu_units() -> dict[str, dict[str, float]]:
    """The unit definitions of the FMUs (their UnitDefinitions, which the signal tables make)."""
    from fmpy import read_model_description

    units: dict[str, dict[str, float]] = {}
    for f in FMUS.values():
        if not (RESOURCES / f).is_file():
            continue
        for u in read_model_description(str(RESOURCES / f), validate=False).unitDefinitions:
            b = u.baseUnit
            exps = {k: getattr(b, k) for k in ("kg", "m", "s", "A", "K", "mol", "cd", "rad")} if b else {}
            units[u.name] = {**{k: float(v) for k, v in exps.items() if v}, "factor": float(b.factor if b else 1.0),
                             "offset": float(b.offset if b else 0.0)}
    return units


def _merged(a: dict[str, dict[str, tuple[str, ...]]],
            b: dict[str, dict[str, tuple[str, ...]]]) -> dict[str, dict[str, tuple[str, ...]]]:
    out = {end: dict(sources) for end, sources in a.items()}
    for end, sources in b.items():
        for start, names in sources.items():
            out.setdefault(end, {})[start] = out.get(end, {}).get(start, ()) + tuple(names)
    return out


def build_system(hybrid: bool = False) -> SystemBuilder:
    """The engine + airframe + flight-control system of the Munich mission; with ``hybrid`` the electrical
    power system too (``ssp/hybrid/``): its machines on both spools (:data:`HYBRID_SOURCES`).

    It binds no parameter: the FMUs' defaults are the shipped configuration (the Larzac 04 starting
    at 60 % N1, the flight idle, the aircraft on EDDM 26R with 600 kg of fuel), so that a tool that
    applies no bindings flies the same mission.
    """
    # the Munich mission takes about 4040 s; emss run ends when the FCS reports it completed
    sys_ = SystemBuilder("openEMSS_hybrid" if hybrid else "openEMSS").experiment(0.0, 5000.0, STEP_S)
    sources = _merged(SOURCES, HYBRID_SOURCES) if hybrid else SOURCES
    outputs = {**OUTPUTS, "engine": ENGINE_OUT + ENGINE_PORTS_OUT} if hybrid else OUTPUTS
    for name in ("fcs", "engine", "airframe", *(("electric",) if hybrid else ())):
        _add(sys_, name, sources, outputs[name])
    for end, by_start in sources.items():
        for start, names in by_start.items():
            for n in names:
                sys_.connect(f"{start}.{n}", f"{end}.{n}")
    used = {k[3] for c in sys_.components for k in c.connectors if k[3]}
    defs = fmu_units()
    for unit in sorted(used):
        sys_.units[unit] = defs[unit]
    return sys_


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


#: pyCycle's high-bypass turbofan (models/engine/engines/pycycle_hbtf.yaml) scaled to the UPERA's thrust: 94.0 kN at
#: sea level static at its T4_MAX (1587 K) times 0.14 = 13.2 kN, the Larzac 04's 13.0 kN.
HBTF_THRUST_SCALE = 0.14


def engine_file_set(engine_file: str, thrust_scale: float) -> dict[str, bool | float | str]:
    """An engine file flown by the engine FMU, with the fuel controller's limits that engine's
    (:meth:`openemss.models.engine.graph_engine.GraphEngineModel.fcs_limits`) and the flight idle."""
    from openemss.models.engine.graph_engine import GraphEngineModel

    limits = GraphEngineModel(engine_file, thrust_scale).fcs_limits()
    return {"engine.engine_file": engine_file, "engine.thrust_scale": thrust_scale,
            **{f"fcs.fuel_control.{k}": v for k, v in limits.items()}, **IDLE}


def parameter_sets() -> dict[str, ParameterSet]:
    """System-level parameter sets: the engines (with their flight idle), the aircraft's loading."""
    return {"engine_larzac04.ssv": ParameterSet("engine_larzac04", {"engine.preset": "larzac04_sls", **IDLE}),
            "engine_reference_study.ssv": ParameterSet("engine_reference_study",
                                                       {"engine.preset": "reference_study", **IDLE}),
            "engine_redesigned.ssv": ParameterSet("engine_redesigned", {**redesigned_engine(), **IDLE}),
            "engine_pycycle_hbtf.ssv": ParameterSet("engine_pycycle_hbtf",
                                                    engine_file_set("pycycle_hbtf", HBTF_THRUST_SCALE)),
            # a mid-life deteriorated engine (models/engine/health.py MID_LIFE): combine with any engine's set
            "engine_degraded.ssv": ParameterSet("engine_degraded", {
                f"engine.{k}": v for k, v in health_parameters(MID_LIFE).items()}),
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
    missing = [f for f in FMUS.values() if not (RESOURCES / f).is_file()]
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
