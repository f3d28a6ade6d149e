"""The engine FMU flying engine files (issue 31, point 6): parameters ``engine_file`` and ``thrust_scale``.

References: the steady graph (:meth:`.EngineGraph.solve`, shaft balances as equations) for the FMU's start
and the settled state after a fuel step; scaling at constant cycle (Walsh & Fletcher ch. 4) for
``thrust_scale``: thrust and fuel flow by the factor, temperatures, pressure ratios and SFC unchanged.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from conftest import open_slave
from openemss.models.engine.engine_file import read_engine_file, scale_engine
from openemss.models.engine.engine_graph import EngineGraph

H = 0.05


@pytest.fixture(scope="module")
def fmu(project_fmus: dict[str, Path]) -> Path:
    return project_fmus["engine"]


def _run(fmu: Path, name: str, engine_file: str, scale: float, steps: int, Wf_factor: float = 1.0,
         alt_m: float = 0.0, mach: float = 0.0) -> dict[str, float]:
    slave, vr = open_slave(fmu, name)
    slave.setString([vr["engine_file"]], [engine_file])
    slave.setReal([vr["thrust_scale"], vr["start_N1_pct"], vr["alt_m"], vr["mach"]], [scale, 85.0, alt_m, mach])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    out = ("Fn_N", "Wf_kg_s", "N1_pct", "N2_pct", "Tt41_K", "Tt4_K", "OPR", "SFC_kg_N_s", "N1_rpm", "Pt3_Pa")
    Wf0 = slave.getReal([vr["Wf_kg_s"]])[0]
    for k in range(steps):
        slave.setReal([vr["Wf_cmd_kg_s"]], [Wf0 * Wf_factor])
        slave.doStep(currentCommunicationPoint=k * H, communicationStepSize=H)
    vals = dict(zip(out, slave.getReal([vr[n] for n in out]), strict=True))
    vals["Wf0"] = Wf0
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)
    return vals


def test_fmu_flies_an_engine_file_to_its_steady_state(fmu: Path) -> None:
    cond = (3000.0, 0.5)
    v = _run(fmu, "hbtf1", "pycycle_hbtf", 1.0, 300, 1.05, *cond)       # 15 s after a 5 % fuel step
    g = EngineGraph("pycycle_hbtf")
    a = g.solve(*cond, demand=("N_rpm", 0.85 * 4666.1, "lp"))
    assert v["Wf0"] == pytest.approx(a.Wf_kg_s, rel=1e-7)               # the start: 85 % N1, steady
    b = g.solve(*cond, demand=("Wf_kg_s", 1.05 * a.Wf_kg_s), guess=a)
    assert v["Fn_N"] == pytest.approx(b.Fn_N, rel=1e-5)
    assert v["N1_pct"] == pytest.approx(100.0 * b.shafts["lp"]["N_rpm"] / 4666.1, rel=1e-5)
    assert v["N2_pct"] == pytest.approx(100.0 * b.shafts["hp"]["N_rpm"] / 14705.7, rel=1e-5)
    assert v["Tt4_K"] == pytest.approx(b.elements["burner"]["Tt_exit_K"], rel=1e-5)
    assert v["OPR"] == pytest.approx(b.OPR, rel=1e-5)


def test_thrust_scale_scales_thrust_and_fuel_at_constant_cycle(fmu: Path) -> None:
    one = _run(fmu, "hbtf_s1", "pycycle_hbtf", 1.0, 4, 1.02)
    s = 0.14
    small = _run(fmu, "hbtf_s2", "pycycle_hbtf", s, 4, 1.02)
    # the start is steady, so its thrust and fuel scale exactly; a transient's spools are slower by sqrt(s)
    assert small["Wf0"] == pytest.approx(s * one["Wf0"], rel=1e-8)
    eng = scale_engine(read_engine_file("pycycle_hbtf"), s)
    d1, d2 = EngineGraph("pycycle_hbtf").design(), EngineGraph(eng).design()
    assert d2.Fn_N == pytest.approx(s * d1.Fn_N, rel=1e-9)
    steady = [_run(fmu, f"hbtf_st{i}", "pycycle_hbtf", sc, 0) for i, sc in enumerate((1.0, s))]
    assert steady[1]["Fn_N"] == pytest.approx(s * steady[0]["Fn_N"], rel=1e-8)
    assert steady[1]["Wf_kg_s"] == pytest.approx(s * steady[0]["Wf_kg_s"], rel=1e-8)
    for k in ("Tt41_K", "Tt4_K", "OPR", "SFC_kg_N_s", "N1_pct", "N2_pct", "Pt3_Pa"):
        assert steady[1][k] == pytest.approx(steady[0][k], rel=1e-8), k
    assert steady[1]["N1_rpm"] == pytest.approx(steady[0]["N1_rpm"] / s ** 0.5, rel=1e-8)


@pytest.mark.parametrize(("engine_file", "scale", "message"), [
    ("no_such_engine", 1.0, "no engine 'no_such_engine'"),
    ("pycycle_hbtf", 0.0, "thrust_scale=0.0 must be a finite number > 0"),
    ("pycycle_hbtf", -2.0, "thrust_scale=-2.0 must be a finite number > 0"),
    ("pycycle_ab_turbojet", 1.0, "shaft 'hp': I_kg_m2 is not given"),
    ("", 2.0, "thrust_scale=2.0 applies to an engine_file"),
])
def test_bad_engine_file_or_scale_is_one_line(engine_file: str, scale: float, message: str) -> None:
    from openemss.fmus.engine import Engine
    from openemss.models.engine.errors import ModelError

    slave = Engine(instance_name="bad", resources=str(Path(__file__).resolve().parents[2]))
    slave.engine_file, slave.thrust_scale = engine_file, scale
    with pytest.raises(ModelError) as exc:            # what the FMU reports at initialisation, one line
        slave.compute_start()
    assert message in str(exc.value)
    assert "\n" not in str(exc.value)


def _with_inertia(tmp_path: Path, name: str, I_kg_m2: float) -> Path:
    """A shipped engine file with an inertia on its gas generator's shaft (``hp``), maps by absolute path."""
    src = Path(read_engine_file(name).file)
    f = tmp_path / f"{name}.yaml"
    f.write_text(src.read_text().replace("hp: {N_rpm: 8070.0}", f"hp: {{N_rpm: 8070.0, I_kg_m2: {I_kg_m2}}}")
                 .replace("../maps/", f"{src.parents[1] / 'maps'}/"))
    return f


def test_file_outputs_power_turbine(fmu: Path, tmp_path: Path) -> None:
    """The turboshaft's own outputs (its file's outputs:): the load's power against the steady graph's power
    setting, the torque against P = Q omega, through the FMU's file_out_* slots."""
    f = _with_inertia(tmp_path, "pycycle_turboshaft", 2.0)
    slave, vr = open_slave(fmu, "ts")
    slave.setString([vr["engine_file"]], [str(f)])
    slave.setReal([vr["start_N1_pct"]], [95.0])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    P, Q, N, Wf = slave.getReal([vr["file_out_1"], vr["file_out_2"], vr["file_out_3"], vr["Wf_kg_s"]])
    unused = slave.getReal([vr["file_out_4"]])[0]
    slave.terminate()
    slave.fmi2FreeInstance(slave.component)
    g = EngineGraph(str(f))
    p = g.solve(demand=("Wf_kg_s", Wf))
    assert P == pytest.approx(p.shafts["lp"]["net_W"], rel=1e-6)
    assert N == 5000.0
    assert Q == pytest.approx(p.shafts["lp"]["turbine_W"] / (5000.0 * 3.141592653589793 / 30.0), rel=1e-6)
    assert P > 1e6 and unused == 0.0


def test_file_output_naming_an_unknown_quantity_is_one_line(tmp_path: Path) -> None:
    from openemss.models.engine.engine_file import EngineFileError
    from openemss.models.engine.engine_signals import EngineInputs
    from openemss.models.engine.graph_engine import GraphEngineModel

    f = _with_inertia(tmp_path, "pycycle_turboshaft", 2.0)
    f.write_text(f.read_text().replace("shaft lp.torque_N_m", "shaft lp.torque_Nm"))
    m = GraphEngineModel(str(f))
    with pytest.raises(EngineFileError, match=r"pycycle_turboshaft.yaml:\d+: output 'Q_pt_N_m': shaft 'lp' has no "
                                              r"quantity 'torque_Nm' \(it has: .*torque_N_m\)"):
        m.start(EngineInputs(0.0), N1_pct=95.0)
    f.write_text(f.read_text().replace("shaft lp.torque_Nm", "shaft px.torque_N_m"))
    with pytest.raises(EngineFileError, match=r"output 'Q_pt_N_m': no shaft 'px'"):
        read_engine_file(str(f))
