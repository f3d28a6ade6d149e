"""The FCS FMU (fmus/fcs.py, built by build-fmus) against the Python FlightControlSystem.

The FMU is a thin adapter, so fed with the same measured states it must give the
Python controller's commands to floating-point round-off: 1e-12 (the same operations
in the same order; only the conversions of the inputs could differ). The input
sequence is a synthetic take-off from EDDM 26R (positions on the runway heading,
an airspeed ramp, lift-off, a climb, small attitude oscillations and an engine
spooling up), played into the FCS by a tiny player FMU in our orchestrator. The Python
side rebuilds the measured state from the same table as tests/fcs/upera_loop.py does
(ground velocity from successive positions), written independently of the FMU.

Also: every variable has a unit, every FCS gain is a tunable parameter that an .ssv
(or a scenario, during the run) reaches, a bad mission file or gain fails the
initialization with a clear one-line message, fmpy runs the FMU without openEMSS, and
coupled runs take off from EDDM and climb: airframe FMU + FCS FMU + a first-order engine
stand-in FMU (equal to the Python closed loop of upera_loop.py; also run in libcosim),
and airframe + FCS + the engine model's FMU.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from openemss.models.fcs.fcs import FlightControlSystem
from openemss.models.fcs.state import AircraftState, EngineState
from openemss.models.mission.geo import LatLon, from_local_ne, local_ne_m
from openemss.models.mission.mission import load_mission
from openemss.orchestrator.fmu.build import build_fmu, ensure_built
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.scenarios.manipulators import ScenarioManipulator, load_scenario
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import Comp, write_ssv, write_system

ROOT = Path(__file__).resolve().parents[2]
MUNICH = ROOT / "missions" / "munich.yaml"
H = 0.05  # communication step [s] (20 Hz, the default rate)

REAL_IN = ("lat_deg", "lon_deg", "alt_m", "tas_m_s", "gs_m_s", "vs_m_s", "phi_rad", "theta_rad", "psi_rad",
           "p_rad_s", "q_rad_s", "r_rad_s", "beta_rad", "rho_amb_kg_m3", "mass_kg", "N1_pct", "N1c_pct", "Tt41_K")
REAL_OUT = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "brakes_norm", "steering_norm",
            "lever_norm", "Wf_cmd_kg_s", "theta_cmd_rad", "phi_cmd_rad", "alt_cmd_m", "tas_cmd_m_s",
            "mach_cmd", "track_cmd_rad", "xtk_m")
# A player FMU: plays the rows of a JSON table (one per communication step) on outputs named as the FCS's
# inputs; after its k-th step it shows row k+1, so under Jacobi the FCS's k-th step sees row k.
PLAYER = '''"""Test player: outputs row k of a JSON table after k steps."""
import json

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Real, String

NAMES = {names!r}


class Player(Fmi2Slave):
    """Plays a table of recorded inputs."""

    author = "openEMSS tests"
    description = "Table player [-]"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.table_file = ""
        self.register_variable(String("table_file", causality=Fmi2Causality.parameter,
                                      variability=Fmi2Variability.fixed, description="JSON table [-]"))
        self._rows = [dict.fromkeys(NAMES, 0.0) | {{"on_ground": True}}]
        self._k = 0
        for n in NAMES:
            self.register_variable(Real(n, causality=Fmi2Causality.output, description=n + " [-]",
                                        getter=lambda n=n: float(self._rows[self._k][n])))
        self.register_variable(Boolean("on_ground", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete, description="on ground [-]",
                                       getter=lambda: bool(self._rows[self._k]["on_ground"])))

    def exit_initialization_mode(self):
        with open(self.table_file) as fh:
            self._rows = json.load(fh)
        self._k = 0

    def do_step(self, current_time, step_size):
        self._k = min(self._k + 1, len(self._rows) - 1)
        return True
'''

# A first-order engine stand-in (as tests/fcs/upera_loop.py): N1c follows 400 %/(kg/s) of corrected fuel flow
# with a 1 s lag (explicit Euler); thrust 13 kN (rho/rho0)^0.7 (N1c/100)^2; Tt41 = 700 K + 7 K/% N1c.
ENGINE = '''"""Test engine stand-in: first-order corrected fan speed, thrust from N1c and density."""
import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class EngineStandIn(Fmi2Slave):
    """First-order turbofan stand-in."""

    author = "openEMSS tests"
    description = "First-order engine stand-in [-]"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.N1c0_pct = 25.0
        self.register_variable(Real("N1c0_pct", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.fixed, description="initial N1c [%]"))
        self.Wf_cmd_kg_s = 0.012
        self.p_amb_Pa = 101325.0
        self.T_amb_K = 288.15
        self.rho_amb_kg_m3 = 1.225
        for n in ("Wf_cmd_kg_s", "p_amb_Pa", "T_amb_K", "rho_amb_kg_m3"):
            self.register_variable(Real(n, causality=Fmi2Causality.input, description=n + " [-]"))
        self.N1c_pct = 25.0
        self.N1_pct = 25.0
        self.Tt41_K = 875.0
        self.Fn_N = 0.0
        self.Wf_kg_s = 0.012
        for n in ("N1c_pct", "N1_pct", "Tt41_K", "Fn_N", "Wf_kg_s"):
            self.register_variable(Real(n, causality=Fmi2Causality.output, description=n + " [-]"))

    def _outputs(self):
        # in initialization mode the airframe's outputs (our inputs) are still 0: ISA sea level until then
        th = self.T_amb_K / 288.15 if self.T_amb_K > 0.0 else 1.0
        self.N1_pct = self.N1c_pct * math.sqrt(th)
        self.Tt41_K = 700.0 + 7.0 * self.N1c_pct
        self.Fn_N = 13000.0 * (self.rho_amb_kg_m3 / 1.225) ** 0.7 * (self.N1c_pct / 100.0) ** 2
        self.Wf_kg_s = self.Wf_cmd_kg_s

    def exit_initialization_mode(self):
        self.N1c_pct = self.N1c0_pct
        self._outputs()

    def do_step(self, current_time, step_size):
        th = self.T_amb_K / 288.15
        delta = self.p_amb_Pa / 101325.0
        target = min(400.0 * self.Wf_cmd_kg_s / (delta * math.sqrt(th)), 115.0)
        self.N1c_pct += (target - self.N1c_pct) * step_size  # explicit Euler, as upera_loop.py
        self._outputs()
        return True
'''


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The FCS FMU built by build-fmus, with the test player and engine stand-in FMUs beside it."""
    out = tmp_path_factory.mktemp("fcs_fmu")
    ensure_built(ROOT / "fmus", out, names=["fcs"], force=True)
    src = tmp_path_factory.mktemp("fcs_fmu_src")
    (src / "player.py").write_text(PLAYER.format(names=list(REAL_IN)))
    (src / "engine_stand_in.py").write_text(ENGINE)
    build_fmu(src / "player.py", out)
    build_fmu(src / "engine_stand_in.py", out)
    return out


# -- the input sequence ---------------------------------------------------------------------------
def synthetic_takeoff(n_steps: int) -> list[dict[str, float | bool]]:
    """A take-off from the EDDM 26R threshold: 2.5 m/s^2 to 75 m/s, lift-off at 28 s, 8 m/s climb;
    small roll, pitch and sideslip oscillations; the engine spools up with a 3 s lag."""
    thr = LatLon.from_deg(48.366887, 11.821173)
    hdg = math.radians(263.42)
    elev = 441.7
    rows = []
    for k in range(n_steps + 1):
        t = k * H
        V = 2.5 * t if t < 30.0 else 75.0 + 0.2 * (t - 30.0)
        s = 1.25 * t * t if t < 30.0 else 1125.0 + 75.0 * (t - 30.0) + 0.1 * (t - 30.0) ** 2
        climb = t >= 28.0
        vs = 8.0 if climb else 0.0
        alt = elev + (8.0 * (t - 28.0) if climb else 0.0)
        track = hdg + (0.02 * math.sin(0.1 * t) if climb else 0.0)
        p = from_local_ne(thr, s * math.cos(hdg) + 3.0 * math.sin(0.2 * t), s * math.sin(hdg))
        N1c = 60.0 + 35.0 * (1.0 - math.exp(-t / 3.0))
        rows.append({"lat_deg": p.lat_deg, "lon_deg": p.lon_deg, "alt_m": alt, "tas_m_s": V, "gs_m_s": V,
                     "vs_m_s": vs, "phi_rad": 0.05 * math.sin(0.7 * t) if climb else 0.0,
                     "theta_rad": (0.12 if climb else 0.0) + 0.01 * math.sin(1.3 * t),
                     "psi_rad": track + 0.01 * math.sin(0.5 * t),
                     "p_rad_s": 0.035 * math.cos(0.7 * t) if climb else 0.0,
                     "q_rad_s": 0.013 * math.cos(1.3 * t), "r_rad_s": 0.005 * math.cos(0.5 * t),
                     "beta_rad": 0.01 * math.sin(0.9 * t), "rho_amb_kg_m3": 1.17 * (1.0 - 9.5e-5 * (alt - elev)),
                     "mass_kg": 2100.0 - 0.2 * t, "N1_pct": 0.99 * N1c, "N1c_pct": N1c,
                     "Tt41_K": 700.0 + 6.0 * N1c, "on_ground": not climb})
    return rows


def python_reference(rows: list[dict[str, float | bool]], n_steps: int, gains: dict[str, float] | None = None,
                     changes: dict[int, dict[str, float]] | None = None) -> dict[str, list]:
    """The Python FlightControlSystem fed with the rows, the measured state built as upera_loop.py does;
    ``gains`` set before the start, ``changes[k]`` before step ``k``."""
    # the FMU's default first fuel-flow command (its parameter Wf0_kg_s: the shipped system's)
    from openemss.models.fcs.fcs_signals import GAIN_DEFAULTS, SIGNALS

    wf0 = next(float(s.start) for s in SIGNALS if s.name == "Wf0_kg_s")  # type: ignore[arg-type]
    fcs = FlightControlSystem(load_mission(MUNICH), Wf0_kg_s=wf0)
    for name, value in {**GAIN_DEFAULTS, **(gains or {})}.items():  # the FMU's defaults (its flight idle)
        fcs.set_parameter(name, value)
    out: dict[str, list] = {}
    prev = None
    for k in range(n_steps):
        for name, value in (changes or {}).get(k, {}).items():
            fcs.set_parameter(name, value)
        r = rows[k]
        pos = LatLon.from_deg(r["lat_deg"], r["lon_deg"])
        # the master's step sizes are differences of its integer-tick times, t_k = k H (so they differ
        # from H in the last bits, which the FCS's ground acceleration, a difference of differences, sees)
        if prev is None:
            vn, ve = r["gs_m_s"] * math.cos(r["psi_rad"]), r["gs_m_s"] * math.sin(r["psi_rad"])
        else:
            n, e = local_ne_m(prev, pos)
            vn, ve = n / (k * H - (k - 1) * H), e / (k * H - (k - 1) * H)
        prev = pos
        gamma = math.asin(max(-1.0, min(1.0, r["vs_m_s"] / max(r["tas_m_s"], 1.0))))
        x = AircraftState(pos, r["alt_m"], r["tas_m_s"], math.nan, gamma, vn, ve, r["psi_rad"], r["phi_rad"],
                          r["theta_rad"], r["p_rad_s"], r["q_rad_s"], r["r_rad_s"], r["beta_rad"],
                          0.5 * r["rho_amb_kg_m3"] * r["tas_m_s"] ** 2, r["mass_kg"], bool(r["on_ground"]))
        o = fcs.step(k * H, (k + 1) * H - k * H, x, EngineState(r["N1_pct"], r["N1c_pct"], r["Tt41_K"]))
        for name, v in o.signals().items():
            out.setdefault(name, []).append(v)
    return out


class Probe:
    """Observer reading variables of one component at every sample with single gets (the recorders take
    inputs and outputs of numeric types only: this reads String outputs and parameters)."""

    def __init__(self, component: str, names: tuple[str, ...]) -> None:
        self.component, self.names = component, names
        self.values: dict[str, list[object]] = {n: [] for n in names}

    def start(self, execution: Execution) -> None:
        i = [c.name for c in execution.system.components].index(self.component)
        self._slave = execution.slaves[i]
        self._vars = [execution.system.components[i].variables[n] for n in self.names]

    def sample(self, k: int, time_s: float) -> None:
        for n, v in zip(self.names, self._vars, strict=True):
            value = self._slave.get_value(v)
            self.values[n].append(value.decode() if isinstance(value, bytes) else value)

    def finish(self, execution: Execution, error: BaseException | None) -> None:
        pass


def fcs_connectors() -> list[tuple[str, str, str]]:
    return ([(n, "input", "Real") for n in REAL_IN] + [("on_ground", "input", "Boolean")]
            + [(n, "output", "Real") for n in REAL_OUT] + [("gear_down", "output", "Boolean"),
                                                            ("section_index", "output", "Integer"),
                                                            ("mission_completed", "output", "Boolean")])


def played_system(folder: Path, fmus: Path, rows: list[dict[str, float | bool]],
                  fcs_params: dict[str, float | int | bool] | None = None) -> Path:
    """Player -> FCS system in ``folder``; the table is written beside it."""
    table = folder / "table.json"
    folder.mkdir(parents=True, exist_ok=True)
    table.write_text(json.dumps(rows))
    player = [(n, "output", "Real") for n in REAL_IN] + [("on_ground", "output", "Boolean")]
    ssd = write_system(folder, fmus, [Comp("player", "Player.fmu", player), Comp("fcs", "Fcs.fmu", fcs_connectors(),
                                                                                   fcs_params or {})],
                       [(f"player.{n}", f"fcs.{n}") for n in (*REAL_IN, "on_ground")])
    # the table path is a String parameter: bind it inline (tests/systems.py writes numbers only)
    text = add_binding(ssd.read_text(), "player", _string_values("table_file", str(table)))
    ssd.write_text(text)
    return ssd


def run_played(folder: Path, n_steps: int, probe_names: tuple[str, ...] = ("section_name", "section_phase"),
               scenario: Path | None = None) -> tuple[dict, Probe]:
    ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="jacobi")
    rec = MemoryRecorder()
    probe = Probe("fcs", probe_names)
    if scenario is not None:
        ex.add_manipulator(ScenarioManipulator(load_scenario(scenario)))
    ex.add_observer(rec)
    ex.add_observer(probe)
    ex.run(n_steps * H)
    return rec.result(), probe


# -- tests ----------------------------------------------------------------------------------------------
def test_model_description_units_and_every_gain(fmus: Path) -> None:
    """build-fmus built and validated it (fmpy validate); every variable has a unit in brackets;
    Integer/Boolean variables are discrete; every FCS parameter is a tunable parameter with its default."""
    md = read_model_description(str(fmus / "Fcs.fmu"))
    v = {x.name: x for x in md.modelVariables}
    for x in md.modelVariables:
        assert x.description and x.description.rstrip().endswith("]"), x.name
        assert x.description.rstrip()[x.description.rstrip().rfind("[") + 1:-1].strip(), x.name  # non-empty unit
        if x.type in ("Integer", "Boolean", "String") and x.causality in ("input", "output"):
            assert x.variability == "discrete", x.name
    ref = FlightControlSystem(load_mission(MUNICH))
    names = ref.parameter_names()
    assert len(names) >= 70
    from openemss.models.fcs.fcs_signals import GAIN_DEFAULTS

    for name in names:
        assert v[name].causality == "parameter" and v[name].variability == "tunable", name
        default = GAIN_DEFAULTS.get(name, ref.get_parameter(name))  # the FMU's own: the shipped flight idle
        if isinstance(default, bool):
            assert v[name].type == "Boolean" and (v[name].start in ("true", True)) == default, name
        else:
            assert v[name].type == "Real" and float(v[name].start) == pytest.approx(default, rel=1e-15), name
    assert v["mission_file"].type == "String" and v["mission_file"].causality == "parameter"
    assert v["mission_file"].start == "missions/munich.yaml"
    for name in (*REAL_IN, "on_ground"):
        assert v[name].causality == "input", name
    for name in (*REAL_OUT, "gear_down", "section_index", "section_name", "mission_completed"):
        assert v[name].causality == "output", name
    assert v["section_index"].type == "Integer" and v["section_name"].type == "String"
    assert v["mission_completed"].type == "Boolean" and v["gear_down"].type == "Boolean"
    # the FCS's airframe-facing outputs and inputs carry the airframe FMU's names
    from openemss.models.airframe.airframe_signals import SIGNALS as AIRFRAME

    af = {s.name for s in AIRFRAME}
    for name in ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "brakes_norm", "steering_norm",
                 "gear_down", *REAL_IN[:15]):
        if name not in ("N1_pct", "N1c_pct", "Tt41_K"):
            assert name in af, name


#: outputs that are NaN in the Python FCS when the section has no target, and what the FMU gives then
NONE_IS_FLOWN: dict[str, str | float | None] = {"alt_cmd_m": "alt_m", "tas_cmd_m_s": "tas_m_s",
                                                "xtk_m": 0.0, "track_cmd_rad": None}
N_STEPS = 1600  # 80 s: roll, rotation, lift-off, climb to 300 m AGL, the first waypoint leg under TECS


def test_same_outputs_as_the_python_fcs(fmus: Path, tmp_path: Path) -> None:
    rows = synthetic_takeoff(N_STEPS)
    played_system(tmp_path / "sys", fmus, rows)
    got, probe = run_played(tmp_path / "sys", N_STEPS)
    ref = python_reference(rows, N_STEPS)
    # the sequence exercised the mission: rolling, take-off, then the first waypoint leg (TECS engaged)
    assert ref["section_index"][0] == 0 and ref["section_index"][-1] == 2
    assert np.isfinite(ref["alt_cmd_m"][-1]) and np.isfinite(ref["tas_cmd_m_s"][-1])
    assert np.ptp(ref["Wf_cmd_kg_s"]) > 0.05 and np.ptp(ref["elevator_norm"]) > 0.05
    assert np.ptp(ref["aileron_norm"]) > 0.01
    # sample k+1 holds the outputs of step k (sample 0: the outputs after initialization)
    for name in REAL_OUT:
        py = "tas_cmd_m_s" if name == "mach_cmd" else name  # FcsOutput.signals() names as the FMU's outputs
        if name == "flaps_norm":
            assert np.all(got[f"fcs.{name}"] == 0.0)
            continue
        if name == "mach_cmd":
            continue
        want, mine = np.array(ref[py], dtype=float), got[f"fcs.{name}"][1:]
        if name in NONE_IS_FLOWN:  # no target (NaN in the Python FCS): the FMU outputs the flown value
            none = np.isnan(want)
            assert np.all(np.isfinite(mine)), name
            flown = NONE_IS_FLOWN[name]
            if flown is not None:
                want = np.where(none, [float(r[flown]) if isinstance(flown, str) else flown for r in rows[:N_STEPS]],
                                want)
            else:  # the ground track: compared where a target exists
                want, mine = want[~none], mine[~none]
        np.testing.assert_allclose(mine, want, rtol=1e-12, atol=1e-12, err_msg=name)
    np.testing.assert_array_equal(got["fcs.section_index"][1:], ref["section_index"])
    np.testing.assert_array_equal(got["fcs.gear_down"][1:], np.array(ref["gear_down"], dtype=float))
    assert probe.values["section_name"][1:] == ref["section_name"]
    assert probe.values["section_phase"][1:] == ref["section_phase"]
    assert not got["fcs.mission_completed"].any()
    # Mach command: the TAS command over the ISA speed of sound at the flown altitude (independent formula)
    T = 288.15 - 0.0065 * np.array([r["alt_m"] for r in rows[:N_STEPS]])
    tas_cmd = np.array(ref["tas_cmd_m_s"], dtype=float)
    tas_cmd = np.where(np.isnan(tas_cmd), [r["tas_m_s"] for r in rows[:N_STEPS]], tas_cmd)  # none: the flown TAS
    mach = tas_cmd / np.sqrt(1.4 * 287.05287 * T)
    np.testing.assert_allclose(got["fcs.mach_cmd"][1:], mach, rtol=1e-9, equal_nan=True)


def test_gain_from_an_ssv_reaches_the_controller(fmus: Path, tmp_path: Path) -> None:
    """A component .ssv sets stp_max (dotted FMI name) and a system .ssv sets tecs.k_TP: the FMU reports the
    controller's values, its fuel-flow steps respect the new stp_max, and it matches the Python FCS with
    the same gains set by script."""
    n = 400
    rows = synthetic_takeoff(n)
    folder = tmp_path / "sys"
    ssd = played_system(folder, fmus, rows)
    gains = {"fuel_control.stp_max_kg_s": 2.0e-4, "tecs.k_TP": 3.0, "guidance.wp_fly_by": True}
    write_ssv(folder / "fcs_gains.ssv", {"fuel_control.stp_max_kg_s": gains["fuel_control.stp_max_kg_s"],
                                         "guidance.wp_fly_by": True})
    write_ssv(folder / "system.ssv", {"fcs.tecs.k_TP": gains["tecs.k_TP"]})
    text = add_binding(ssd.read_text(), "fcs", '<ssd:ParameterBinding source="fcs_gains.ssv"/>')
    text = text.replace("    <ssd:Elements>", '    <ssd:ParameterBindings><ssd:ParameterBinding source="system.ssv"/>'
                                             "</ssd:ParameterBindings>\n    <ssd:Elements>", 1)
    ssd.write_text(text)
    got, probe = run_played(folder, n, tuple(gains))
    for name, value in gains.items():  # read back from the controller at every step (the getter asks the FCS)
        assert set(probe.values[name]) == {value}, name
    wf = got["fcs.Wf_cmd_kg_s"][1:]
    assert np.max(np.abs(np.diff(wf))) <= 2.0e-4 * (1 + 1e-12)
    default = python_reference(rows, n)
    assert np.max(np.abs(np.diff(default["Wf_cmd_kg_s"]))) > 1.0e-3  # the default stp_max (1.5e-3) was used
    ref = python_reference(rows, n, gains)
    np.testing.assert_allclose(wf, ref["Wf_cmd_kg_s"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(got["fcs.elevator_norm"][1:], ref["elevator_norm"], rtol=1e-12, atol=1e-12)


def test_gain_changed_during_the_run_by_a_scenario(fmus: Path, tmp_path: Path) -> None:
    """The gains are tunable: a scenario sets stp_max and the TECS thrust gain at 12 s (in the take-off
    roll, the fuel still rising) and the FMU follows the Python FCS with the same change before that step."""
    n = 400
    rows = synthetic_takeoff(n)
    played_system(tmp_path / "sys", fmus, rows)
    scenario = tmp_path / "scenario.yaml"
    scenario.write_text("events:\n  - at: 12.0\n    set: {fcs.fuel_control.stp_max_kg_s: 3.0e-4, "
                        "fcs.tecs.k_TP: 2.5}\n")
    got, probe = run_played(tmp_path / "sys", n, ("fuel_control.stp_max_kg_s",), scenario)
    k = int(round(12.0 / H))
    assert probe.values["fuel_control.stp_max_kg_s"][k - 1] == 0.0015
    assert probe.values["fuel_control.stp_max_kg_s"][k] == 3.0e-4  # the controller's value after the event
    ref = python_reference(rows, n, changes={k: {"fuel_control.stp_max_kg_s": 3.0e-4, "tecs.k_TP": 2.5}})
    wf = got["fcs.Wf_cmd_kg_s"][1:]
    np.testing.assert_allclose(wf, ref["Wf_cmd_kg_s"], rtol=1e-12, atol=1e-12)
    steps = np.abs(np.diff(wf))
    assert steps[: k - 1].max() == pytest.approx(0.0015) and steps[k:].max() <= 3.0e-4 * (1 + 1e-12)


def test_fmu_is_self_contained(fmus: Path, tmp_path: Path) -> None:
    """fmpy's own simulate_fmu runs the FCS FMU where openemss cannot be imported (the FCS code and the
    Munich mission travel in the FMU); unconnected inputs keep their start values (at rest on 26R)."""
    import subprocess
    import sys
    import zipfile

    z = zipfile.ZipFile(fmus / "Fcs.fmu")
    assert z.read("resources/requirements.txt").decode().split() == ["pyyaml>=6.0", "numpy>=1.24", "numba>=0.59",
                                                                     "pythonfmu>=0.6.5"]
    assert "resources/missions/munich.yaml" in z.namelist()
    code = ("import os, sys\n"
            "sys.modules['openemss'] = None\n"
            "from fmpy import simulate_fmu\n"
            f"r = simulate_fmu({str(fmus / 'Fcs.fmu')!r}, stop_time=1.0, output_interval=0.05, "
            "output=['lever_norm', 'section_index', 'gear_down', 'Wf_cmd_kg_s'])\n"
            "print(r['lever_norm'][-1], r['section_index'][-1], r['gear_down'][-1], r['Wf_cmd_kg_s'][-1])\n"
            "sys.stdout.flush(); os._exit(0)  # see tests/thirdparty.py: no finalization after the unload\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    lever, section, gear, wf = proc.stdout.split()[-4:]
    assert float(lever) == 1.0 and int(section) == 0 and gear == "True"  # take-off roll, full lever
    assert float(wf) == pytest.approx(0.07 + 20 * 0.0015)  # fuel rising at stp_max from Wf0_kg_s (default 0.07)


def test_gain_outside_its_range_is_refused(fmus: Path, tmp_path: Path) -> None:
    """tecs.k_TP = 50 (allowed 0 to 10): the run stops at initialization naming the parameter and the range."""
    from openemss.orchestrator.errors import EmssError

    rows = synthetic_takeoff(10)
    played_system(tmp_path / "sys", fmus, rows, {"tecs.k_TP": 50.0})
    with pytest.raises(EmssError) as info:
        run_played(tmp_path / "sys", 10)
    msg = str(info.value)
    assert "fcs" in msg and "k_TP" in msg and "10" in msg, msg


def _cli_error(folder: Path, capsys: pytest.CaptureFixture[str]) -> str:
    from openemss.orchestrator.cli.main import main

    rc = main(["run", str(folder), "--out", str(folder / "out"), "--stop-time", "1"])
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert rc != 0 and len(err) == 1, err
    return err[0]


def test_missing_mission_file_fails_initialization_clearly(fmus: Path, tmp_path: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    ssd = played_system(folder, fmus, synthetic_takeoff(10))
    ssd.write_text(_bind_mission(ssd.read_text(), "missions/nowhere.yaml"))
    line = _cli_error(folder, capsys)
    assert "component 'fcs'" in line and "fmi2ExitInitializationMode" in line, line
    assert "mission_file 'missions/nowhere.yaml' not found" in line and "resources" in line, line


def test_invalid_mission_file_gives_the_mission_error(fmus: Path, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(MUNICH.read_text().replace("waypoints: [WP1, WP2]", "waypoints: [WP1, WP99]"))
    folder = tmp_path / "sys"
    ssd = played_system(folder, fmus, synthetic_takeoff(10))
    ssd.write_text(_bind_mission(ssd.read_text(), str(bad)))
    line = _cli_error(folder, capsys)
    assert "component 'fcs'" in line and "bad.yaml:" in line and "WP99" in line, line


def _string_values(name: str, value: str) -> str:
    return ('<ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet version="1.0" name="strings">'
            f'<ssv:Parameters><ssv:Parameter name="{name}"><ssv:String value="{value}"/></ssv:Parameter>'
            "</ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding>")


def add_binding(text: str, component: str, binding: str) -> str:
    """Add a ParameterBinding element to ``component`` of an SSD text (into its ParameterBindings)."""
    i = text.index(f'<ssd:Component name="{component}"')
    end = text.index("</ssd:Component>", i)
    j = text.find("<ssd:ParameterBindings>", i, end)
    if j >= 0:
        j += len("<ssd:ParameterBindings>")
        return text[:j] + binding + text[j:]
    j = text.index("        </ssd:Connectors>\n", i) + len("        </ssd:Connectors>\n")
    return text[:j] + f"        <ssd:ParameterBindings>{binding}</ssd:ParameterBindings>\n" + text[j:]


def _bind_mission(text: str, path: str) -> str:
    return add_binding(text, "fcs", _string_values("mission_file", path))


# -- coupled: airframe FMU + FCS FMU + engine stand-in FMU --------------------------------------------------
AF_TO_FCS = ("lat_deg", "lon_deg", "alt_m", "tas_m_s", "gs_m_s", "vs_m_s", "phi_rad", "theta_rad", "psi_rad",
             "p_rad_s", "q_rad_s", "r_rad_s", "beta_rad", "rho_amb_kg_m3", "mass_kg")
FCS_TO_AF = ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "brakes_norm", "steering_norm")
AMBIENT = ("p_amb_Pa", "T_amb_K", "rho_amb_kg_m3")


def coupled_system(fmus: Path, tmp_path: Path, engine_model: bool = False,  # type: ignore[no-untyped-def]
                   whole_mission: bool = False):
    """Airframe + FCS + engine system on a shortened Munich mission (roll, take-off, climb to WP 1; with
    ``whole_mission`` the shipped Munich mission, the FCS FMU's default), the airframe at rest 50 m beyond
    the 26R threshold; the engine is the first-order stand-in, or with ``engine_model`` the engine FMU
    (fmus/engine.py, Larzac 04 preset) started steady at 60 % N1. Returns (folder, mission, start, runway)."""
    ensure_built(ROOT / "fmus", fmus, names=["airframe", "engine"] if engine_model else ["airframe"])
    text = MUNICH.read_text()
    short = tmp_path / "short.yaml"
    short.write_text(text[:text.index("  - {type: WaypointFollowing, fly_by: true, name: Munich circuit")]
                     .replace("waypoints: [WP1, WP2]", "waypoints: [WP1]"))
    mission = load_mission(short)
    assert [s.type for s in mission.sections] == ["Rolling", "TakeOff", "WaypointFollowing"]
    rwy = mission.sections[0]["runway"]
    p0 = rwy.point(50.0)  # 50 m beyond the threshold, on the centre line
    af_conn = ([(n, "output", "Real") for n in (*AF_TO_FCS, "p_amb_Pa", "T_amb_K", "alt_agl_m", "mach")]
               + [("on_ground", "output", "Boolean")]
               + [(n, "input", "Real") for n in (*FCS_TO_AF, "Fn_N", "Wf_kg_s")]
               + [("gear_down", "input", "Boolean")])
    conns = ([(f"airframe.{n}", f"fcs.{n}") for n in (*AF_TO_FCS, "on_ground")]
             + [(f"fcs.{n}", f"airframe.{n}") for n in (*FCS_TO_AF, "gear_down")]
             + [("fcs.Wf_cmd_kg_s", "engine.Wf_cmd_kg_s")]
             + [(f"engine.{n}", f"airframe.{n}") for n in ("Fn_N", "Wf_kg_s")]
             + [("engine.N1_pct", "fcs.N1_pct"), ("engine.N1c_pct", "fcs.N1c_pct")])
    if engine_model:  # the engine model's inputs: altitude and Mach; its rotor inlet temperature is Tt41_K
        eng = Comp("engine", "Engine.fmu",
                   [(n, "input", "Real") for n in ("Wf_cmd_kg_s", "alt_m", "mach")]
                   + [(n, "output", "Real") for n in ("N1c_pct", "N1_pct", "Tt41_K", "Fn_N", "Wf_kg_s")],
                   {"start_N1_pct": 60.0})
        conns += [("airframe.alt_m", "engine.alt_m"), ("airframe.mach", "engine.mach"),
                  ("engine.Tt41_K", "fcs.Tt41_K")]
        wf0 = 0.07  # about the engine's fuel flow at 60 % N1, sea level static
        idle: dict[str, float] = {}  # the FCS's defaults: the Larzac 04's flight idle
    else:
        eng = Comp("engine", "EngineStandIn.fmu",
                   [(n, "input", "Real") for n in ("Wf_cmd_kg_s", *AMBIENT)]
                   + [(n, "output", "Real") for n in ("N1c_pct", "N1_pct", "Tt41_K", "Fn_N", "Wf_kg_s")],
                   {"N1c0_pct": 25.0})
        conns += [(f"airframe.{n}", f"engine.{n}") for n in AMBIENT] + [("engine.Tt41_K", "fcs.Tt41_K")]
        wf0 = 0.012
        idle = {"fuel_control.N1c_idle_pct": 0.0, "tecs.lever_min": 0.0}  # the stand-in has no flight idle
    folder = tmp_path / "sys"
    # one binding per component: libcosim applies only one of a component's ParameterBindings
    fcs_params: dict[str, float | str] = {"Wf0_kg_s": wf0, **idle}
    if not whole_mission:
        fcs_params["mission_file"] = str(short)
    write_system(folder, fmus, [
        Comp("fcs", "Fcs.fmu", fcs_connectors(), fcs_params), eng,
        Comp("airframe", "Airframe.fmu", af_conn, {"lat0_deg": p0.lat_deg, "lon0_deg": p0.lon_deg,
                                                    "heading0_deg": math.degrees(rwy.heading_rad),
                                                    "alt0_m": rwy.elevation_m})], conns)
    if whole_mission:
        return folder, load_mission(MUNICH), p0, rwy
    return folder, mission, p0, rwy


def test_coupled_airframe_fcs_engine_take_off_and_climb(fmus: Path, tmp_path: Path) -> None:
    """Airframe FMU (JSBSim UPERA), FCS FMU and the first-order engine stand-in FMU in our Gauss-Seidel master
    (order FCS, engine, airframe: the FCS samples the state at t, the engine and the airframe fly its commands
    over [t, t + h]) take off from EDDM 26R and climb to 1000 m on a shortened Munich mission (roll, take-off,
    climb to WP 1). It is the closed loop of tests/fcs/upera_loop.py, computed there in plain Python on the
    same models: the trajectories agree to 1e-9 (the same arithmetic, with the master's step sizes and the
    engine's N1 corrected with the temperature of its last step, as the FMUs see them)."""
    from upera_loop import fly_upera

    from openemss.models.airframe import adapter

    folder, mission, p0, rwy = coupled_system(fmus, tmp_path)
    t_end = 140.0
    ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="gauss-seidel")
    assert ex.order.order == (0, 1, 2)  # fcs, engine, airframe
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(t_end)
    r = {k: v[1:] for k, v in rec.result().items()}  # sample k+1: after step k
    # it took off and climbed
    t = r["time_s"]
    lift = int(np.argmax(r["airframe.on_ground"] < 0.5))
    assert 15.0 < t[lift] < 30.0 and not r["airframe.on_ground"][lift:].any()
    alt = r["airframe.alt_m"]
    at_100s = int(round(100.0 / H)) - 1
    assert alt[at_100s] == pytest.approx(1000.0, abs=5.0)  # WP 1 leg at 1000 m: captured
    assert np.all(np.diff(alt[lift:at_100s]) > -0.05)  # climbed without sinking back
    assert np.max(np.abs(r["airframe.phi_rad"][:at_100s])) < math.radians(5.0)  # straight out on 26R
    sec = r["fcs.section_index"]
    assert list(np.unique(sec)) == [0, 1, 2, 3] and np.all(np.diff(sec) >= 0)
    done = int(np.argmax(r["fcs.mission_completed"] > 0.5))
    assert r["fcs.mission_completed"][-1] and sec[done] == 3
    # the same closed loop in Python (tests/fcs/upera_loop.py)
    af = adapter.Airframe()
    s = af.start_runway(p0.lat_deg, p0.lon_deg, math.degrees(rwy.heading_rad), rwy.elevation_m)
    fcs = FlightControlSystem(mission, Wf0_kg_s=0.012)
    run = fly_upera(af, s, fcs, t_end, N1c0=25.0)
    assert fcs.finished and len(run.t) == done + 1  # both finish the mission in the same step
    n = len(run.t)
    np.testing.assert_array_equal(sec[:n], run.sec)
    np.testing.assert_allclose(alt[:n], run.alt, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(r["fcs.Wf_cmd_kg_s"][:n], run.wf, rtol=1e-9, atol=1e-12)
    lat = np.array([p.lat_deg for p in run.pos])
    np.testing.assert_allclose(r["airframe.lat_deg"][:n], lat, rtol=0, atol=1e-10)  # 1e-10 deg ~ 11 um: round-off carried by the loop


def test_coupled_system_in_libcosim(fmus: Path, tmp_path: Path) -> None:
    """libcosim (the reference third-party importer) runs the same three-FMU system, with the mission file
    bound as a String parameter, and gives our Jacobi master's trajectory for the first 30 s (roll, lift-off,
    climb). The same computation up to round-off: libcosim's times are integer nanoseconds, so the step size
    and time it passes differ from ours by an ulp in some steps (seen from step 5 on in the elevator and
    the engine's N1c, 1e-15 relative); the closed loop carries these along, to at most 5e-9 of the range each
    signal sweeps in 30 s (the elevator; 6e-11 the altitude). Tolerance: 1e-7 of the range (a difference
    of modelling would show at 1e-3 or more)."""
    pytest.importorskip("libcosimpy.CosimExecution", reason="libcosimpy is a test dependency")
    from thirdparty import run_isolated

    folder, *_ = coupled_system(fmus, tmp_path)
    steps = 600
    names = ["airframe.alt_m", "airframe.tas_m_s", "airframe.lat_deg", "fcs.Wf_cmd_kg_s",
             "fcs.elevator_norm", "engine.N1c_pct"]
    ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="jacobi")
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(steps * H)
    ours = rec.result()
    assert ours["airframe.alt_m"][-1] > 441.7 + 100.0  # airborne and climbing under Jacobi too (26R at 441.7 m)
    got = run_isolated("libcosim_run", system=str(folder), variables=names, steps=steps,
                       step_ns=int(round(H * 1e9)))["values"]
    for n in names:
        scale = float(np.ptp(ours[n]))  # the range the signal swept
        np.testing.assert_allclose(got[n], ours[n][1:], rtol=0, atol=1e-7 * scale, err_msg=n)


def test_coupled_with_the_engine_fmu_takes_off_and_climbs(fmus: Path, tmp_path: Path) -> None:
    """The three FMUs of the project, airframe, FCS and the engine model (Larzac 04, spool dynamics), in our
    Gauss-Seidel master: the take-off roll at full lever, lift-off, climb-out to 300 m above the runway and
    the capture of the 1000 m climb leg under TECS, with the fuel controller keeping N1 and T41 within
    their limits (fuel_control.N1_max_pct 103 %, Tt41_max_K 1400 K) on the real engine."""
    folder, *_ = coupled_system(fmus, tmp_path, engine_model=True)
    ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="gauss-seidel")
    assert ex.order.order == (0, 1, 2)
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(45.0)
    r = {k: v[1:] for k, v in rec.result().items()}
    lift = int(np.argmax(r["airframe.on_ground"] < 0.5))
    assert 15.0 < r["time_s"][lift] < 30.0 and not r["airframe.on_ground"][lift:].any()
    assert r["fcs.section_index"][-1] == 2  # climbing on the first waypoint leg, TECS engaged
    alt = r["airframe.alt_m"]
    assert alt[-1] > 850.0 and np.all(np.diff(alt[lift:]) > -0.05)
    assert np.max(np.abs(r["airframe.phi_rad"])) < math.radians(5.0)
    assert r["engine.N1_pct"].max() <= 103.0 + 0.5 and r["engine.Tt41_K"].max() <= 1400.0 + 10.0
    assert r["engine.N1_pct"].max() > 95.0  # the take-off was flown at high power


def test_munich_mission_through_the_fmus(fmus: Path, tmp_path: Path) -> None:
    """The whole demonstration mission, from the FCS FMU's shipped mission file, flown by the airframe, FCS
    and engine stand-in FMUs in our Gauss-Seidel master: every section in order, up to 7500 m, the ILS
    approach and a full stop on runway 26R near its centre line. (The Python closed loop of the same
    models, tests/fcs/test_upera_closed_loop.py, states the bounds of the flown profile.)"""
    folder, mission, _, rwy = coupled_system(fmus, tmp_path, whole_mission=True)
    ex = Execution(bind_system(load_system(folder)), rate_hz=1.0 / H, algorithm="gauss-seidel")
    rec = MemoryRecorder(every=20)  # 1 s
    ex.add_observer(rec)
    ex.run(4500.0)  # the mission takes about 3900 s
    r = rec.result()
    n = len(mission.sections)
    done = r["fcs.mission_completed"] > 0.5
    assert done[-1] and r["fcs.section_index"][-1] == n
    sec = r["fcs.section_index"]
    assert np.all(np.diff(sec) >= 0) and set(sec.astype(int)) == set(range(n + 1))  # each section, in order
    assert r["airframe.alt_m"].max() == pytest.approx(7500.0, abs=25.0)
    assert r["airframe.on_ground"][-1] and r["airframe.tas_m_s"][-1] < 1.0
    along, cross = rwy.local(LatLon.from_deg(r["airframe.lat_deg"][-1], r["airframe.lon_deg"][-1]))
    assert 0.0 < along < rwy.length_m and abs(cross) < rwy.width_m / 4
