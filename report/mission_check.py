"""``emss mission check MISSION [--system DIR]``: can the system's aircraft fly a mission as planned?

Per section, the required climb or descent gradient and turns against what the aircraft and its
engine can do there (:mod:`openemss.models.fcs.feasibility`, on the shipped models through
:mod:`.model_performance`), each infeasible or marginal section named with its numbers; ``--json`` for
machines. The same check runs before every ``emss run`` of a system that flies a mission (the
report plugin's ``pre_run`` hook), which prints its findings as warnings.

What the check takes from the system (its SSD, parameter sets and ``--set`` values, else each
FMU's start values, else the models' defaults), by role, never by component name (the roles of
:func:`.rundata.find_roles`):

* flight control: ``mission_file`` (for ``emss run``), every gain and limit (bank limit, climb
  and descent angle limits, idle, lever range, Tt41 and N1 limits, glide slope), ``flaps_cmd_norm``;
* engine: ``preset`` or ``design_override`` with its ``design_*`` values, its fuel-system stops;
* airframe: ``fuel0_kg`` and ``added_mass_kg`` (the take-off mass, warned about above the maximum),
  ``weather_dT_isa_K``, the weather it flies: ``weather_file`` (a mission's ``wind`` and ``turbulence``), else its
  steady ``wind_*_m_s``; an air start (``start_on_runway`` false) at ``lat0_deg``, ``lon0_deg``, ``alt0_m``,
  ``tas0_m_s``.

A mission that gives winds aloft or turbulence the airframe will not fly (its ``weather_file`` does
not name them) is reported: the flight control never passes the weather on, the airframe owns it.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

from openemss.models.airframe.loading import above_mtow
from openemss.models.fcs.errors import FcsError
from openemss.models.fcs.feasibility import MissionCheck, check_mission
from openemss.models.fcs.feasibility_perf import Limits, from_dotted
from openemss.models.mission.errors import GeometryError, MissionError
from openemss.models.mission.geo import LatLon
from openemss.models.mission.mission import Mission, load_mission, parse_mission_file
from openemss.models.mission.weather import Turbulence, Weather, WindLayer, WindProfile, parse_weather_text
from openemss.orchestrator.exit_codes import ExitCode

from .errors import ReportError
from .rundata import find_roles, read_fmu_file

__all__ = ["CheckSetup", "setup_from_system", "run_check", "format_check", "pre_run", "register"]

DEFAULT_ENGINE = "larzac04_sls"


@dataclass(frozen=True)
class CheckSetup:
    """What the check needs of a system (see the module docstring)."""

    system: str
    parameters: Mapping[str, float]      #: FCS gains and limits by dotted name
    engine: Any                          #: TurbofanParams
    engine_label: str
    engine_limits: Any                   #: EngineLimits
    mass_kg: float
    fuel_kg: float
    dT_isa_K: float
    flaps: float
    weather: Weather | None
    weather_origin: str
    mission_file: tuple[str, str] | None
    start: tuple[LatLon, float, float] | None

    @property
    def limits(self) -> Limits:
        return Limits.from_parameters(self.parameters.__getitem__)


def _fmu_variables(fmu: Path | None) -> dict[str, str | None]:
    """Every variable of an FMU with its start value as written (None: no start); {} if unreadable."""
    if fmu is None:
        return {}
    try:
        with zipfile.ZipFile(fmu) as z:
            root = ElementTree.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ElementTree.ParseError):
        return {}
    out: dict[str, str | None] = {}
    for sv in root.iter("ScalarVariable"):
        out[sv.attrib["name"]] = next((c.attrib["start"] for c in sv if "start" in c.attrib), None)
    return out


class _Values:
    """A component's parameter: bound value, else its FMU's start value, else a default."""

    def __init__(self, comp: str | None, fmu: Path | None, parameters: Mapping[str, Any]) -> None:
        self.comp, self.fmu, self.bound = comp, fmu, parameters
        self.starts = _fmu_variables(fmu)

    def get(self, name: str, default: Any = None) -> Any:
        if self.comp is not None and f"{self.comp}.{name}" in self.bound:
            return self.bound[f"{self.comp}.{name}"]
        return self.starts.get(name) if self.starts.get(name) is not None else default

    def number(self, name: str, default: float) -> float:
        v = self.get(name, default)
        try:
            return float(v)
        except (TypeError, ValueError):
            return default

    def flag(self, name: str, default: bool) -> bool:
        v = self.get(name, default)
        return v if isinstance(v, bool) else str(v).strip().lower() in ("true", "1")


def _engine(eng: _Values) -> tuple[Any, str, Any]:
    from openemss.models.engine.design_params import TurbofanParams, load_params, preset_path, replace
    from openemss.models.engine.engine_model import EngineLimits
    from openemss.models.engine.errors import OutOfRangeError
    from openemss.models.engine.settings import engine_set

    preset = str(eng.get("preset", DEFAULT_ENGINE))
    try:
        params = load_params(preset_path(preset))
    except Exception as e:  # an unknown preset: one line, as the engine FMU would say it
        raise ReportError(f"engine preset '{preset}': {e}") from None
    if not isinstance(params, TurbofanParams):
        raise ReportError(f"engine preset '{preset}' is not a turbofan")
    label = preset
    if eng.flag("design_override", False):
        from openemss.fmus.engine import DESIGN

        # as the engine FMU: each design_* value set, else its start value (the FMU starts them at the values of
        # DEFAULT_ENGINE, whatever the preset: a preset sized by thrust, as reference_study, has no W2_kg_s)
        base = params if preset == DEFAULT_ENGINE else load_params(preset_path(DEFAULT_ENGINE))
        params = replace(params, Fn_target_N=None, **{n: eng.number(f"design_{n}", float(getattr(base, n)))
                                                      for n, _ in DESIGN})
        label = f"{preset} with design_override"
    # as the engine FMU: the limits from its parameters of those names (PARAMETER_SETS), else the file's values
    spec = engine_set(EngineLimits, "limits")
    try:
        limits = spec.collect(lambda n: eng.number(n, float(spec.param(n).value)), "", eng.comp or "engine")
    except OutOfRangeError as e:
        raise ReportError(str(e)) from None
    return params, label, limits


def _weather(af: _Values) -> tuple[Weather | None, str]:
    value = af.get("weather_file", "")
    if value:
        found = read_fmu_file(str(value), af.fmu)
        if found is None:
            raise ReportError(f"airframe weather_file '{value}' not found (absolute, or relative to the airframe "
                              f"FMU's resources folder {af.fmu})")
        text, source = found
        return parse_weather_text(text, source), f"{af.comp}.weather_file = {value}"
    n, e = af.number("wind_north_m_s", 0.0), af.number("wind_east_m_s", 0.0)
    sev = int(af.number("turbulence_severity", 0))
    wind = None
    if math.hypot(n, e) > 0.0:
        wind = WindProfile((WindLayer(0.0, math.degrees(math.atan2(-e, -n)) % 360.0, math.hypot(n, e)),))
    turb = Turbulence(sev, af.number("turbulence_wind_20ft_m_s", 0.0), int(af.number("turbulence_seed", 0)),
                      str(sev)) if sev > 0 else None
    if wind is None and turb is None:
        return None, "still air"
    return Weather(wind, turb, f"{af.comp} parameters"), f"{af.comp}.wind_*_m_s and turbulence_* parameters"


def setup_from_system(components: Mapping[str, Path], parameters: Mapping[str, Any],
                      system: str = "") -> CheckSetup | None:
    """The check's view of a system: ``components`` (name -> FMU) and its bound ``parameters``
    (``component.variable`` -> value). None when no component flies a mission (no FCS role)."""
    from openemss.models.fcs.fcs import FlightControlSystem

    names = {c: _fmu_variables(Path(f)) for c, f in components.items()}
    roles = find_roles(f"{c}.{v}" for c, vs in names.items() for v in vs)
    if roles.fcs is None:
        return None

    def values(comp: str | None) -> _Values:
        return _Values(comp, Path(components[comp]) if comp is not None else None, parameters)

    fcs_v, eng_v, af_v = values(roles.fcs), values(roles.engine), values(roles.airframe)
    fcs = FlightControlSystem(Mission("defaults", "", (), (), (), "<defaults>"))
    for name in fcs.parameter_names():
        bound = parameters.get(f"{roles.fcs}.{name}")
        if bound is not None:
            fcs.set_parameter(name, bound)
    gains = {name: float(fcs.get_parameter(name)) for name in fcs.parameter_names()}
    engine, label, engine_limits = _engine(eng_v)
    from openemss.models.airframe.geometry import load_geometry

    g = load_geometry()
    fuel0 = min(max(af_v.number("fuel0_kg", g.fuel_capacity_kg), 0.0), g.fuel_capacity_kg)
    added = max(af_v.number("added_mass_kg", 0.0), 0.0)  # (the airframe refuses a negative one at its start)
    weather, origin = _weather(af_v)
    start = None
    if roles.airframe is not None and not af_v.flag("start_on_runway", True):
        start = (LatLon.from_deg(af_v.number("lat0_deg", 0.0), af_v.number("lon0_deg", 0.0)),
                 af_v.number("alt0_m", 0.0), af_v.number("tas0_m_s", 0.0))
    return CheckSetup(system, gains, engine, label, engine_limits, g.oem_kg + fuel0 + added, fuel0,
                      af_v.number("weather_dT_isa_K", 0.0), fcs_v.number("flaps_cmd_norm", 0.0),
                      weather, origin, read_fmu_file(str(fcs_v.get("mission_file", "")), fcs_v.fmu), start)


def weather_warnings(mission: Mission, setup: CheckSetup) -> list[str]:
    """Lines for a mission whose winds aloft or turbulence the airframe will not fly."""
    mw, aw = mission.weather, setup.weather
    if mw is None:
        return []
    lines = []
    for what, mine, flown in (("winds aloft", mw.wind, aw.wind if aw else None),
                              ("turbulence", mw.turbulence, aw.turbulence if aw else None)):
        if mine is not None and mine != flown:
            desc = (Weather(mine, None, "") if what == "winds aloft" else Weather(None, mine, "")).describe()  # type: ignore[arg-type]
            lines.append(f"{mission.source}: the mission gives {what} ({desc}) but the airframe flies "
                         f"{'none' if flown is None else 'others'} ({setup.weather_origin}): the airframe owns the "
                         "weather; set its weather_file to the mission file to fly them")
    return lines


def setup_warnings(mission: Mission, setup: CheckSetup) -> list[str]:
    """Lines for what the system flies against the mission and the aircraft's limits: weather the airframe will
    not fly (:func:`weather_warnings`), a take-off mass above the maximum."""
    heavy = above_mtow(setup.mass_kg)
    return weather_warnings(mission, setup) + ([heavy] if heavy else [])


def run_check(mission: Mission, setup: CheckSetup, margin: float = 0.2) -> MissionCheck:
    """The feasibility of ``mission`` on the system ``setup`` (performance from the shipped models)."""
    from .model_performance import FuelControlLimits, ModelPerformance

    fuel = from_dotted(FuelControlLimits, setup.parameters.__getitem__)
    perf = ModelPerformance(setup.engine, fuel, setup.engine_limits, setup.dT_isa_K, setup.flaps)
    wind = setup.weather.wind if setup.weather is not None else None
    return check_mission(mission, perf, setup.limits, setup.mass_kg, start=setup.start, wind=wind,
                         dT_isa_K=setup.dT_isa_K, margin=margin, fuel_kg=setup.fuel_kg)


def _f(x: float | None, scale: float = 1.0, fmt: str = "{:.1f}") -> str:
    return "" if x is None or not math.isfinite(x) else fmt.format(x * scale)


def format_check(check: MissionCheck, setup: CheckSetup, warnings: Sequence[str] = (), wall_s: float | None = None) \
        -> str:
    """The check as a table, its findings and a summary line."""
    w = setup.weather
    lines = [f"mission check: {check.mission} ({check.source})",
             f"system {setup.system}: engine {setup.engine_label}, {setup.mass_kg:.0f} kg at the start, ISA "
             f"{setup.dT_isa_K:+.0f} K, {w.describe() if w is not None else 'still air'}"
             f"{f' ({setup.weather_origin})' if w is not None else ''}; marginal: less than "
             f"{100 * check.margin:.0f} % of margin",
             f"  {'#':>2}  {'section':<34} {'type':<17} {'altitude m':<13} {'dist km':>7} {'need %':>7} "
             f"{'can %':>7} {'turn R km':>9} {'geom km':>7} {'T/D':>5} {'mass kg':>7}  verdict"]
    for s in check.sections:
        alt = (f"{s.alt_from_m:.0f}" if abs(s.alt_to_m - s.alt_from_m) < 1.0
               else f"{s.alt_from_m:.0f} -> {s.alt_to_m:.0f}")
        lines.append(f"  {s.index:>2}  {s.name[:34]:<34} {s.type:<17} {alt:<13} {_f(s.distance_m, 1e-3):>7} "
                     f"{_f(s.required_gradient, 100):>7} {_f(s.achievable_gradient, 100):>7} "
                     f"{_f(s.turn_radius_m, 1e-3):>9} {_f(s.geometry_radius_m, 1e-3):>7} "
                     f"{_f(s.thrust_ratio, fmt='{:.2f}'):>5} {s.mass_kg:>7.0f}  {s.verdict}")
    lines.append("  need/can: altitude change over the distance to the section's constraint / over the distance "
                 "it takes at full thrust (climb) or idle (descent); turn R: radius at the bank limit; geom: orbit "
                 "radius or shortest leg; T/D: maximum thrust over drag")
    found = [(s, f) for s, f in check.findings]
    if found:
        lines.append("findings:")
        lines.extend(f"  {s.index:>2} {s.name}: {f.text}" if f.verdict != "note" else f"  {s.index:>2} {s.name}: "
                     f"(note) {f.text}" for s, f in found)
    lines.extend(f"mission: {f.text}" for f in check.notes)
    lines.extend(f"warning: {w}" for w in warnings)
    n_inf, n_mar = check.count("infeasible"), check.count("marginal")
    lines.append(f"{n_inf} infeasible, {n_mar} marginal of {len(check.sections)} sections; rough estimates: fuel "
                 f"{check.fuel_estimate_kg:.0f} kg, {check.time_estimate_s / 60:.0f} min"
                 + (f"; checked in {wall_s:.2f} s" if wall_s is not None else ""))
    return "\n".join(lines)


def as_json(check: MissionCheck, setup: CheckSetup, warnings: Sequence[str], wall_s: float) -> dict[str, Any]:
    """The check as a JSON-able mapping (SI units in the key names)."""
    w = setup.weather
    return {"mission": check.mission, "source": check.source, "system": setup.system,
            "engine": setup.engine_label, "mass_kg": setup.mass_kg, "dT_isa_K": setup.dT_isa_K,
            "weather": None if w is None else {"description": w.describe(), "origin": setup.weather_origin},
            "margin": check.margin, "counts": {v: check.count(v) for v in ("ok", "marginal", "infeasible", "n/a")},
            "fuel_estimate_kg": check.fuel_estimate_kg, "time_estimate_s": check.time_estimate_s,
            "sections": [asdict(s) for s in check.sections], "warnings": list(warnings), "wall_time_s": wall_s}


# -- emss run: the pre-run hook ---------------------------------------------------------------
def pre_run(components: Mapping[str, Path], parameters: Mapping[str, Any]) -> list[str]:
    """Warnings before ``emss run``: the marginal and infeasible sections of the mission the system's flight
    control flies, and weather the airframe will not fly; nothing for a system without a mission."""
    t0 = time.perf_counter()
    setup = setup_from_system(components, parameters)
    if setup is None or setup.mission_file is None:
        return []
    text, source = setup.mission_file
    try:
        mission = parse_mission_file(text, source)
    except (FcsError, MissionError):
        return []  # the flight control refuses it at its start, with the file and line
    warnings = setup_warnings(mission, setup)
    check = run_check(mission, setup)
    lines = [f"mission check: section {s.index} ({s.type} '{s.name}'): {f.text}"
             for s, f in check.findings if f.verdict in ("marginal", "infeasible")]
    lines.extend(f"mission check: {f.text}" for f in check.notes)
    lines.extend(f"mission check: {w}" for w in warnings)
    if lines:
        lines.append(f"mission check: {check.count('infeasible')} infeasible, {check.count('marginal')} marginal of "
                     f"{len(check.sections)} sections ({time.perf_counter() - t0:.1f} s); the table: emss mission "
                     f"check {_repository_path(source)} (with this run's --params and --set)")
    return lines


def _repository_path(source: str) -> str:
    """A mission shipped in an FMU (``...Fcs.fmu!resources/missions/munich.yaml``) by the repository file it
    came from, when that exists; else the source as it is."""
    from openemss.orchestrator.fmu.build import PACKAGE_ROOT

    if "!" not in source:
        return source
    member = source.rpartition("!")[2].removeprefix("resources/")
    path = PACKAGE_ROOT / member
    if not path.is_file():
        return source
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


# -- emss mission check -----------------------------------------------------------------------
def _bind(system: Path, params: Sequence[Path], settings: Sequence[str]) -> tuple[dict[str, Path], dict[str, Any]]:
    """Components (name -> FMU) and bound parameters of a system with its parameter sets and ``--set`` values,
    the values read as ``emss run`` reads them (:func:`openemss.orchestrator.cli.api.load`: typed by their
    variables, finite, none twice)."""
    from openemss.orchestrator.cli.api import load
    from openemss.orchestrator.fmu.build import PACKAGE_ROOT, ensure_built

    project = PACKAGE_ROOT / "ssp"
    if system.is_dir() and project.is_dir() and system.resolve() == project.resolve():
        ensure_built(PACKAGE_ROOT / "fmus", project / "resources",
                     report=lambda m: None if m.startswith("up to date") else print(m, file=sys.stderr))
    bound = load(system, list(params), list(settings))
    components = {c.name: c.fmu_path for c in bound.components}
    values: dict[str, Any] = {f"{bound.components[p.component].name}.{p.variable.name}": p.value
                              for p in bound.parameters}
    return components, values


def cmd_check(args: argparse.Namespace) -> int:
    """``emss mission check``: exit code 0 when every section can be flown (marginal ones too), 1 (findings)
    when a section or a mission-level finding is infeasible (their number is in the table's last line, and in
    ``--json``); bad input exits with 2 and one line (:mod:`openemss.orchestrator.exit_codes`)."""
    t0 = time.perf_counter()
    if not 0.0 <= args.margin <= 1000.0:
        raise ReportError(f"--margin {args.margin}: a percentage from 0 to 1000")
    mission = load_mission(args.mission)
    from openemss.orchestrator.fmu.build import PACKAGE_ROOT

    system = args.system if args.system is not None else PACKAGE_ROOT / "ssp"
    components, values = _bind(system, args.params, args.set)
    setup = setup_from_system(components, values, str(system))
    if setup is None:
        raise ReportError(f"{system}: no component flies a mission (no flight control with a section_index)")
    warnings = setup_warnings(mission, setup)
    check = run_check(mission, setup, args.margin / 100.0)
    wall = time.perf_counter() - t0
    if args.json:
        print(json.dumps(as_json(check, setup, warnings, wall), indent=2, default=str))
    else:
        print(format_check(check, setup, warnings, wall))
    infeasible = check.count("infeasible") + sum(f.verdict == "infeasible" for f in check.notes)
    return ExitCode.FINDINGS if infeasible else ExitCode.OK  # the number is in the table's last line


def register(sub: argparse._SubParsersAction) -> tuple[type[Exception], ...]:  # type: ignore[type-arg]
    """Add ``emss mission check``."""
    m = sub.add_parser("mission", help="mission files: check a mission against what the aircraft can do",
                       description="Mission files (models/mission/mission.py, missions/README.md).")
    msub = m.add_subparsers(dest="mission_command", required=True, parser_class=type(m))
    c = msub.add_parser("check", help="predict per section whether the aircraft can fly it as planned",
                        description="Before flying: per section the required climb or descent gradient (altitude "
                                    "change over the distance to the section's constraint), the achievable one at "
                                    "full thrust or idle (engine and trimmed airframe of the system's parameter "
                                    "set), turn radius at the bank limit against orbit radius and legs, thrust "
                                    "against drag; names each infeasible or marginal section with its numbers. "
                                    f"Exit code {ExitCode.OK:d}: all can be flown; {ExitCode.FINDINGS:d}: "
                                    "infeasible sections (their number printed).")
    c.add_argument("mission", type=Path, metavar="MISSION", help="mission file (YAML or QGroundControl .plan)")
    c.add_argument("--system", type=Path, metavar="DIR",
                   help="system folder, .ssd or .ssp whose aircraft, engine and flight control fly it "
                        "(default: ssp/, the project's system)")
    c.add_argument("--params", type=Path, nargs="+", action="extend", default=[], metavar="FILE.ssv",
                   help="system-level parameter sets, as for emss run (e.g. ssp/engine_redesigned.ssv)")
    c.add_argument("--set", nargs="+", action="extend", default=[], metavar="COMPONENT.VARIABLE=VALUE",
                   help="parameter values, applied last (e.g. airframe.fuel0_kg=300)")
    c.add_argument("--margin", type=float, default=20.0, metavar="PCT",
                   help="a feasible section with less margin than this is marginal [%%] (default 20)")
    c.add_argument("--json", action="store_true", help="print the check as JSON")
    c.set_defaults(handler=cmd_check)
    return (FcsError, MissionError, GeometryError)
