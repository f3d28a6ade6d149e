"""The airframe FMU (built by build-fmus) against the Python adapter: same inputs, same trajectory.

Both run the same JSBSim model with the same internal rate, so the trajectories
must agree to floating-point round-off (1e-9 relative), not to a tolerance of
modelling. Also: every variable's description carries a unit, Integer/Boolean
variables are discrete, and fmpy's own simulate_fmu runs the FMU.
"""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import assert_house_style, open_slave
from openemss.models.airframe.adapter import Airframe
from openemss.models.airframe.trim import trim_level

ROOT = Path(__file__).resolve().parents[2]
H = 0.05  # communication step [s]: six JSBSim steps at 120 Hz
OUT = ("lat_deg", "lon_deg", "alt_m", "alt_agl_m", "tas_m_s", "cas_m_s", "gs_m_s", "mach", "alpha_rad",
       "beta_rad", "phi_rad", "theta_rad", "psi_rad", "p_rad_s", "q_rad_s", "r_rad_s", "load_factor", "vs_m_s",
       "p_amb_Pa", "T_amb_K", "rho_amb_kg_m3", "mass_kg", "fuel_kg")


@pytest.fixture(scope="module")
def fmu(project_fmus: dict[str, Path]) -> Path:
    return project_fmus["airframe"]


def test_model_description(fmu: Path) -> None:
    md = read_model_description(str(fmu))
    names = {v.name: v for v in md.modelVariables}
    assert_house_style(md)
    for name in ("aileron_norm", "elevator_norm", "rudder_norm", "flaps_norm", "gear_down", "brakes_norm",
                 "steering_norm", "Fn_N", "Wf_kg_s"):
        assert names[name].causality == "input"
    for name in (*OUT, "on_ground", "dT_isa_K"):
        assert names[name].causality == "output"
    for name in ("lat0_deg", "lon0_deg", "heading0_deg", "alt0_m", "tas0_m_s", "fuel0_kg", "weather_dT_isa_K",
                 "wind_north_m_s", "turbulence_severity", "rate_hz", "start_on_runway"):
        assert names[name].causality == "parameter"


def _inputs(k: int) -> dict[str, float]:
    """A manoeuvre: elevator doublet, aileron pulse, rudder step, thrust ramp, fuel flow."""
    t = k * H
    return {"elevator_norm": -0.05 + (-0.1 if 1.0 <= t < 2.0 else 0.1 if 2.0 <= t < 3.0 else 0.0),
            "aileron_norm": 0.2 if 4.0 <= t < 5.0 else 0.0,
            "rudder_norm": 0.1 if t >= 6.0 else 0.0,
            "Fn_N": 3000.0 + 200.0 * t,
            "Wf_kg_s": 0.12,
            "flaps_norm": 0.0, "brakes_norm": 0.0, "steering_norm": 0.0}


def test_fmu_and_adapter_identical(fmu: Path, tmp_path: Path) -> None:
    n_steps = 160  # 8 s
    # --- the adapter
    af = Airframe()
    af.start_air(3000.0, 160.0, 90.0, 48.3, 11.8, alpha_rad=0.03, elevator=-0.05, Fn_N=3000.0,
                 fuel_kg=500.0, ground_elevation_m=453.0)
    ref = []
    for k in range(n_steps):
        u = _inputs(k)
        af.set_surfaces(u["aileron_norm"], u["elevator_norm"], u["rudder_norm"])
        af.set_thrust(u["Fn_N"])
        af.set_fuel_flow(u["Wf_kg_s"])
        af.step(H)
        s = af.state()
        ref.append([getattr(s, n) for n in OUT])  # the FMU's outputs are the state's fields
    ref = np.array(ref)
    # --- the FMU, driven by fmpy's FMU2Slave
    slave, vr = open_slave(fmu, "airframe")
    slave.setBoolean([vr["start_on_runway"], vr["trim_at_start"], vr["gear_down"]], [False, False, False])
    params = {"alt0_m": 3000.0, "tas0_m_s": 160.0, "heading0_deg": 90.0, "lat0_deg": 48.3, "lon0_deg": 11.8,
              "alpha0_rad": 0.03, "fuel0_kg": 500.0, "ground_elevation_m": 453.0, **_inputs(0)}
    slave.setReal([vr[k] for k in params], list(params.values()))
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    out_vr = [vr[n] for n in OUT]
    got = []
    for k in range(n_steps):
        u = _inputs(k)
        slave.setReal([vr[n] for n in u], list(u.values()))
        slave.doStep(currentCommunicationPoint=k * H, communicationStepSize=H)
        got.append(slave.getReal(out_vr))
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)  # keep the library loaded: unloading pythonfmu is unsafe (thirdparty.py)
    got = np.array(got)
    # the manoeuvre did something
    assert np.ptp(ref[:, OUT.index("phi_rad")]) > math.radians(5)
    assert ref[-1, OUT.index("fuel_kg")] == pytest.approx(500.0 - 0.12 * n_steps * H, abs=1e-9)
    np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-9)


def _runway() -> dict[str, float]:
    """The airframe FMU's default start: the departure runway of missions/munich.yaml, read from the file."""
    import yaml

    doc = yaml.safe_load((Path(__file__).resolve().parents[2] / "missions" / "munich.yaml").read_text())
    return doc["places"]["runways"]["EDDM_26R"]


def _simulate(fmu: Path, outputs: list[str], **kwargs: object) -> dict[str, np.ndarray]:
    """fmpy.simulate_fmu, in a child process: it unloads the FMU's library afterwards (thirdparty.py)."""
    from thirdparty import run_isolated

    res = run_isolated("fmpy_simulate_fmu", fmu=str(fmu), outputs=outputs, **kwargs)
    return {k: np.array(v) for k, v in res.items()}


def test_trimmed_air_start_in_fmpy_simulate(fmu: Path) -> None:
    """fmpy.simulate_fmu runs the FMU from a trimmed air start; with the trim's elevator and thrust
    held (as start values of the inputs) the altitude stays within 5 m for 30 s."""
    rwy = _runway()  # the FMU's defaults
    r = trim_level(5000.0, 0.6, heading_deg=rwy["heading_deg"], lat_deg=rwy["threshold_lat_deg"],
                   lon_deg=rwy["threshold_lon_deg"])
    res = _simulate(fmu, start_time=0.0, stop_time=30.0, output_interval=H,
                    start_values={"start_on_runway": False, "trim_at_start": True, "alt0_m": 5000.0,
                                  "tas0_m_s": r.tas_m_s, "gear_down": False, "elevator_norm": r.elevator,
                                  "Fn_N": r.Fn_N},
                    outputs=["alt_m", "tas_m_s", "trim_elevator_norm", "trim_Fn_N", "on_ground"])
    assert res["trim_Fn_N"][-1] == pytest.approx(r.Fn_N, rel=1e-6)
    assert np.max(np.abs(res["alt_m"] - 5000.0)) < 5.0
    assert not res["on_ground"].any()


def test_runway_start_rolls(fmu: Path) -> None:
    res = _simulate(fmu, start_time=0.0, stop_time=10.0, output_interval=H,
                    start_values={"Fn_N": 13000.0}, outputs=["gs_m_s", "on_ground", "alt_agl_m"])
    assert res["on_ground"].all()
    # 13 kN on 2100 kg less drag and rolling friction: about 6 m/s^2 -> 55 to 65 m/s after 10 s
    assert 50.0 < res["gs_m_s"][-1] < 65.0


def test_runs_in_our_orchestrator_and_libcosim(fmu: Path, tmp_path: Path) -> None:
    """The FMU in a one-component SSP system, run by our Jacobi master and by libcosim, gives the
    adapter's trajectory (trimmed air start at 5000 m, 180 m/s, then elevator and thrust held at
    their start values 0: the aircraft pitches up and slows). 1e-9: the same computation."""
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.observers import MemoryRecorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system
    from systems import Comp, write_system

    outs = ["alt_m", "tas_m_s", "theta_rad", "q_rad_s", "mass_kg"]
    params = {"start_on_runway": False, "trim_at_start": True, "alt0_m": 5000.0, "tas0_m_s": 180.0}
    comp = Comp("airframe", fmu.name, [(n, "output", "Real") for n in outs], params)
    folder = tmp_path / "system"
    (folder / "resources").mkdir(parents=True)
    shutil.copy2(fmu, folder / "resources" / fmu.name)
    write_system(folder, fmu.parent, [comp], [], copy_fmus=False)
    steps, rate = 100, 1 / H
    # ours
    ex = Execution(bind_system(load_system(folder)), rate_hz=rate, algorithm="jacobi")
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(steps * H)
    ours = rec.result()
    # the adapter (FMU defaults: the 26R threshold of the mission file, its heading and elevation, gear
    # input true = down)
    rwy = _runway()
    af = Airframe()
    lat, lon, hdg, elev = rwy["threshold_lat_deg"], rwy["threshold_lon_deg"], rwy["heading_deg"], rwy["elevation_m"]
    af.start_air(5000.0, 100.0, hdg, lat, lon, ground_elevation_m=elev)
    mach = 180.0 / (af.get_property("atmosphere/a-fps") * 0.3048)
    r = trim_level(5000.0, mach, 2100.0, airframe=af, gear_down=True, heading_deg=hdg, lat_deg=lat, lon_deg=lon)
    # the FMU starts at the trim's elevator and thrust; its inputs (0) act from the first step
    af.start_air(5000.0, 180.0, hdg, lat, lon, alpha_rad=r.alpha_rad, elevator=r.elevator, Fn_N=r.Fn_N,
                 gear_down=True, fuel_kg=600.0, ground_elevation_m=elev)
    af.set_surfaces(elevator=0.0)
    af.set_thrust(0.0)
    ref = {n: [] for n in outs}
    for _ in range(steps):
        af.step(H)
        s = af.state()
        for n in outs:
            ref[n].append(getattr(s, n))
    for n in outs:
        np.testing.assert_allclose(ours[f"airframe.{n}"][1:], ref[n], rtol=1e-9, atol=1e-9, err_msg=n)
    assert ours["airframe.theta_rad"][-1] > r.alpha_rad + 0.02  # it did pitch up
    # libcosim
    from thirdparty import require_libcosim, run_isolated

    require_libcosim()

    got = run_isolated("libcosim_run", system=str(folder), variables=[f"airframe.{n}" for n in outs], steps=steps,
                       step_ns=int(round(H * 1e9)))["values"]
    theirs = np.array([got[f"airframe.{n}"] for n in outs]).T
    np.testing.assert_allclose(theirs, np.array([ref[n] for n in outs]).T, rtol=1e-9, atol=1e-9)


def test_fmu_is_self_contained(fmu: Path, tmp_path: Path) -> None:
    """The FMU runs where neither openEMSS nor anything beyond its requirements (and the host's fmpy)
    can be imported, and it says what it needs in resources/requirements.txt (pyyaml: it reads its
    default start, the departure runway, from the mission file it carries, and the weather files)."""
    import subprocess
    import sys
    import zipfile

    z = zipfile.ZipFile(fmu)
    assert z.read("resources/requirements.txt").decode().split() == ["jsbsim>=1.2", "numpy>=1.24", "scipy>=1.10",
                                                                   "pyyaml>=6.0", "pythonfmu>=0.6.5"]
    assert any(n.endswith("jsbsim/aircraft/UPERA/UPERA.xml") for n in z.namelist())
    code = ("import sys\n"
            "for m in ('openemss', 'matplotlib'): sys.modules[m] = None  # lxml: fmpy's own\n"
            "from fmpy import simulate_fmu\n"
            f"r = simulate_fmu({str(fmu)!r}, stop_time=1.0, output_interval=0.05, "
            "start_values={'Fn_N': 13000.0}, output=['gs_m_s'])\n"
            "print(r['gs_m_s'][-1])")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert 3.0 < float(proc.stdout.split()[-1]) < 8.0  # about 6 m/s^2 for 1 s
