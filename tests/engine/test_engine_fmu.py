"""The engine FMU (built by build-fmus, validated by fmpy there) against the Python model.

The FMU and :class:`~openemss.models.engine.engine_model.EngineModel` run the same
computation, so with the same inputs they agree to round-off (1e-9), not to a
modelling tolerance. Also: every variable's description ends with a unit in brackets,
Integer/Boolean inputs and outputs are discrete, and the FMU runs in fmpy's
``simulate_fmu``, in our orchestrator and in libcosim (those two third-party runners in
a child process, :mod:`thirdparty`).
"""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import assert_house_style, open_slave
from openemss.models.engine.engine_model import FLAGS, OUTPUTS, EngineInputs, EngineModel

ROOT = Path(__file__).resolve().parents[2]
H = 0.05
OUT = [n for n, _ in OUTPUTS]


@pytest.fixture(scope="module")
def fmu(project_fmus: dict[str, Path]) -> Path:
    return project_fmus["engine"]


def test_model_description(fmu: Path) -> None:
    md = read_model_description(str(fmu))
    names = {v.name: v for v in md.modelVariables}
    assert_house_style(md)
    for name in ("Wf_cmd_kg_s", "alt_m", "mach", "dT_isa_K", "offtake_hp_W", "offtake_lp_W",
                 "customer_bleed_frac", "distortion_on", "distortion_sector_deg", "distortion_dPt_frac",
                 "distortion_dTt_K"):
        assert names[name].causality == "input", name
    for name in (*OUT, *(n for n, _ in FLAGS), "events"):
        assert names[name].causality == "output", name
    for name in ("preset", "design_override", "design_BPR", "design_PR_hpc", "design_Tt4_K", "I_lp_kg_m2",
                 "I_hp_kg_m2", "dt_internal_s", "start_N1_pct", "start_Wf_kg_s", "integrator",
                 "offtake_hp_max_W", "offtake_lp_max_W", "assist_hp_max_W", "assist_lp_max_W"):
        assert names[name].causality == "parameter", name


def _inputs(k: int) -> EngineInputs:
    """A fuel ramp and a chop, an altitude/Mach drift, an HP offtake, an LP motor's assist, bleed and a
    distortion pulse."""
    t = k * H
    wf = 0.12 + 0.05 * min(t, 2.0) if t < 3.0 else 0.10
    return EngineInputs(wf, 3000.0 + 10.0 * t, 0.5 + 0.005 * t, 0.0, 20e3 if t > 1.0 else 0.0,
                        -30e3 if t > 2.0 else 0.0,
                        0.02 if t > 1.5 else 0.0, 1.0 <= t < 2.5, 120.0, 0.08, 0.0)


_FMU_IN = ("Wf_cmd_kg_s", "alt_m", "mach", "dT_isa_K", "offtake_hp_W", "offtake_lp_W", "customer_bleed_frac")


def _reals(u: EngineInputs) -> list[float]:
    return [u.Wf_cmd_kg_s, u.alt_m, u.mach, u.dT_isa_K, u.offtake_hp_W, u.offtake_lp_W, u.customer_bleed_frac,
            u.distortion_sector_deg, u.distortion_dPt_frac, u.distortion_dTt_K]


def test_fmu_and_model_identical(fmu: Path, tmp_path: Path) -> None:
    n_steps = 80
    m = EngineModel("larzac04_sls")
    m.start(_inputs(0), N1_pct=75.0)
    ref, ref_flags = [], []
    for k in range(n_steps):
        m.step(H, _inputs(k))
        ref.append(list(m.values))
        ref_flags.append(list(m.flags))
    slave, vr = open_slave(fmu, "engine")
    in_vr = [vr[n] for n in (*_FMU_IN, "distortion_sector_deg", "distortion_dPt_frac", "distortion_dTt_K")]
    slave.setReal([vr["start_N1_pct"]], [75.0])
    slave.setReal(in_vr, _reals(_inputs(0)))
    slave.setBoolean([vr["distortion_on"]], [_inputs(0).distortion_on])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    out_vr = [vr[n] for n in OUT]
    flag_vr = [vr[n] for n, _ in FLAGS]
    got, got_flags = [], []
    for k in range(n_steps):
        u = _inputs(k)
        slave.setReal(in_vr, _reals(u))
        slave.setBoolean([vr["distortion_on"]], [u.distortion_on])
        slave.doStep(currentCommunicationPoint=k * H, communicationStepSize=H)
        got.append(slave.getReal(out_vr))
        got_flags.append(list(slave.getBoolean(flag_vr)))
        # a recorder's batch, outputs and inputs mixed, served as the outputs and inputs read apart
        mixed = [*in_vr[:3], *out_vr[:5], *in_vr[3:], out_vr[-1]]
        assert list(slave.getReal(mixed)) == [*_reals(u)[:3], *got[-1][:5], *_reals(u)[3:], got[-1][-1]]
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)  # keep the library loaded (thirdparty.py)
    ref_a, got_a = np.array(ref), np.array(got)
    assert np.ptp(ref_a[:, OUT.index("SM_fan")]) > 0.05          # the distortion pulse was felt
    np.testing.assert_allclose(got_a, ref_a, rtol=1e-9, atol=1e-9)
    assert got_flags == ref_flags
    # burned fuel is the integral of the fuel flow burnt (rectangle rule over the held inputs)
    assert ref_a[-1, OUT.index("fuel_burned_kg")] == pytest.approx(
        sum(r[OUT.index("Wf_kg_s")] for r in ref) * H, rel=1e-12)


def test_runs_in_our_orchestrator_and_libcosim(fmu: Path, tmp_path: Path) -> None:
    """A one-component SSP system: start at N1 70 % at 3000 m, Mach 0.5, fuel flow input bound to a
    higher value: the spools accelerate. Ours and libcosim against the Python model, 1e-9."""
    from openemss.orchestrator.master.execution import Execution
    from openemss.orchestrator.recording.observers import MemoryRecorder
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system
    from systems import Comp, write_system
    from thirdparty import require_libcosim, run_isolated

    outs = ["Fn_N", "N1_rpm", "N2_rpm", "Tt4_K", "SM_hpc", "fuel_burned_kg"]
    params: dict[str, float | int | bool] = {"start_N1_pct": 70.0, "alt_m": 3000.0, "mach": 0.5,
                                             "Wf_cmd_kg_s": 0.15, "integrator": 1}
    comp = Comp("engine", fmu.name, [(n, "output", "Real") for n in outs], params)
    folder = tmp_path / "system"
    (folder / "resources").mkdir(parents=True)
    shutil.copy2(fmu, folder / "resources" / fmu.name)
    write_system(folder, fmu.parent, [comp], [], copy_fmus=False)
    steps = 40
    ex = Execution(bind_system(load_system(folder)), rate_hz=1 / H, algorithm="jacobi")
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(steps * H)
    ours = rec.result()

    def reference(step_sizes: list[float]) -> dict[str, list[float]]:
        m = EngineModel("larzac04_sls", method="heun")
        u = EngineInputs(0.15, 3000.0, 0.5)
        m.start(u, N1_pct=70.0)
        ref: dict[str, list[float]] = {n: [] for n in outs}
        for h in step_sizes:
            m.step(h, u)
            for n in outs:
                ref[n].append(m.value(n))
        return ref

    # ours forms steps as t = (k+1) h - k h (sizes vary by an ulp), libcosim from integer ns ticks; the
    # model rounds them to 1 ps, so both equal the reference with h
    ref = reference([H] * steps)
    assert ref["N1_rpm"][-1] > ref["N1_rpm"][0] + 500.0           # it accelerated
    for n in outs:
        np.testing.assert_allclose(ours[f"engine.{n}"][1:], ref[n], rtol=1e-9, atol=1e-9, err_msg=n)
    require_libcosim()
    got = run_isolated("libcosim_run", system=str(folder), variables=[f"engine.{n}" for n in outs], steps=steps,
                       step_ns=int(round(H * 1e9)))["values"]
    theirs = np.array([got[f"engine.{n}"] for n in outs]).T
    np.testing.assert_allclose(theirs, np.array([ref[n] for n in outs]).T, rtol=1e-9, atol=1e-9)


def test_fmpy_simulate_fmu(fmu: Path) -> None:
    """fmpy's own runner (child process): steady start at a given fuel flow stays there."""
    from thirdparty import run_isolated

    m = EngineModel("larzac04_sls")
    pt = m.od.solve(5000.0, 0.6, N1_pct=90.0)
    res = run_isolated("fmpy_simulate_fmu", fmu=str(fmu), outputs=["N1_pct", "Fn_N", "fuel_burned_kg"],
                       start_time=0.0, stop_time=1.0, output_interval=H,
                       start_values={"alt_m": 5000.0, "mach": 0.6, "start_Wf_kg_s": pt.Wf_kg_s})
    assert res["N1_pct"][-1] == pytest.approx(90.0, rel=1e-6)
    assert res["Fn_N"][-1] == pytest.approx(pt.Fn_N, rel=1e-6)
    assert res["fuel_burned_kg"][-1] == pytest.approx(pt.Wf_kg_s * 1.0, rel=1e-6)


def test_design_override_selects_the_engine(fmu: Path, tmp_path: Path) -> None:
    """design_override with the reference study's BPR and HPC PR gives that engine's start point."""
    from openemss.models.engine.design_params import load_params, preset_path, replace

    slave, vr = open_slave(fmu, "engine2")
    slave.setBoolean([vr["design_override"]], [True])
    slave.setReal([vr["design_BPR"], vr["design_PR_hpc"], vr["start_N1_pct"]], [1.16, 5.528455284552847, 90.0])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    fn = slave.getReal([vr["Fn_N"]])[0]
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)
    p = replace(load_params(preset_path("larzac04_sls")), BPR=1.16, PR_hpc=5.528455284552847)
    m = EngineModel(p)
    m.start(EngineInputs(0.1), N1_pct=90.0)
    m.step(H, EngineInputs(m.state.point.Wf_kg_s))               # type: ignore[union-attr]
    assert fn == pytest.approx(m.value("Fn_N"), rel=1e-9)
    base = EngineModel("larzac04_sls")
    base.start(EngineInputs(0.1), N1_pct=90.0)
    assert abs(fn / base.value("Fn_N") - 1.0) > 1e-3          # a different engine


def test_fmu_is_self_contained(fmu: Path, tmp_path: Path) -> None:
    """The FMU runs where neither openEMSS nor anything beyond its requirements (and the host's fmpy)
    can be imported: the engine package, its maps and presets travel inside; requirements.txt says
    what it needs."""
    import subprocess
    import sys
    import zipfile

    z = zipfile.ZipFile(fmu)
    assert z.read("resources/requirements.txt").decode().split() == ["numpy>=1.24", "scipy>=1.10", "numba>=0.59",
                                                                   "pythonfmu>=0.6.5"]
    names = z.namelist()
    assert any(n.endswith("presets/larzac04_sls.json") for n in names)
    assert any(n.endswith("maps/axi5.json") for n in names)
    code = ("import sys\n"
            "for m in ('openemss', 'matplotlib', 'yaml', 'jsbsim'): sys.modules[m] = None\n"
            "from fmpy import simulate_fmu\n"
            f"r = simulate_fmu({str(fmu)!r}, stop_time=0.5, output_interval=0.05, "
            "start_values={'start_N1_pct': 85.0}, output=['N1_pct'])\n"
            "print(r['N1_pct'][-1])")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert float(proc.stdout.split()[-1]) == pytest.approx(85.0, rel=1e-6)


def test_flight_condition_from_ambient_pressure_and_temperature(fmu: Path, tmp_path: Path) -> None:
    """use_ambient: (p, T) of ISA 4000 m + 10 K gives the engine of alt 4000 m, ISA + 10 K; the
    conversion inverts the atmosphere model (round trip to 1e-6 m and 1e-9 K)."""
    from openemss.models.engine.atmosphere import isa
    from openemss.models.engine.engine_model import condition_from_ambient

    for alt, dT in ((0.0, 0.0), (4000.0, 10.0), (11500.0, -5.0)):
        a = isa(alt, dT)
        got = condition_from_ambient(a.P_Pa, a.T_K)
        assert got[0] == pytest.approx(alt, abs=1e-6) and got[1] == pytest.approx(dT, abs=1e-9)
    a = isa(4000.0, 10.0)
    slave, vr = open_slave(fmu, "engine3")
    slave.setBoolean([vr["use_ambient"]], [True])
    slave.setReal([vr["p_amb_Pa"], vr["T_amb_K"], vr["mach"], vr["start_N1_pct"]], [a.P_Pa, a.T_K, 0.5, 88.0])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=H)
    fn = slave.getReal([vr["Fn_N"]])[0]
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(0.1, 4000.0, 0.5, 10.0), N1_pct=88.0)
    m.step(H, EngineInputs(m.state.point.Wf_kg_s, 4000.0, 0.5, 10.0))          # type: ignore[union-attr]
    assert fn == pytest.approx(m.value("Fn_N"), rel=1e-7)
