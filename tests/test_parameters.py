"""Parameter bindings (inline, .ssv on a component, .ssv on the system, --params) and input
start values reach the FMUs.

fmpy's own SSP runner (fmpy.ssp.simulation.simulate_ssp) ignores the SSD's parameter
bindings and sets every input to 0.0 before the first step; these tests would fail
under it. One test runs it on the same archive to show the difference.
"""
from __future__ import annotations

import zipfile
from pathlib import Path

import pytest

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import Comp, write_ssv, write_system
from thirdparty import run_isolated

PROBE = [("u_in", "input", "Real"), ("u_at_init", "output", "Real"), ("u_at_first_step", "output", "Real"),
         ("gain_at_init", "output", "Real"), ("count_at_init", "output", "Integer")]
RECORD = ["p.u_at_init", "p.u_at_first_step", "p.gain_at_init", "p.count_at_init"]


def run_probe(folder: Path, params: list[Path] | None = None) -> dict[str, float]:
    ex = Execution(bind_system(load_system(folder), params or []), rate_hz=10.0, record=RECORD)
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(0.2)
    return {k: float(v[-1]) for k, v in rec.result().items()}


def test_unconnected_input_keeps_its_start_value(tmp_path: Path, fmu_dir: Path) -> None:
    write_system(tmp_path, fmu_dir, [Comp("p", "StartProbe.fmu", PROBE)], [])
    out = run_probe(tmp_path)
    assert out["p.u_at_init"] == 3.5 and out["p.u_at_first_step"] == 3.5  # the FMU's declared start
    assert out["p.gain_at_init"] == 1.0 and out["p.count_at_init"] == 7


def test_inline_binding_sets_parameters_and_input_start(tmp_path: Path, fmu_dir: Path) -> None:
    write_system(tmp_path, fmu_dir, [Comp("p", "StartProbe.fmu", PROBE, {"gain": 2.5, "count": 11, "u_in": -4.0})],
                 [])
    out = run_probe(tmp_path)
    assert out == {"time_s": pytest.approx(0.2), "p.u_at_init": -4.0, "p.u_at_first_step": -4.0,
                   "p.gain_at_init": 2.5, "p.count_at_init": 11}


def test_component_ssv_then_system_ssv_then_command_line_override_in_that_order(
        tmp_path: Path, fmu_dir: Path) -> None:
    ssd = write_system(tmp_path, fmu_dir, [Comp("p", "StartProbe.fmu", PROBE)], [])
    write_ssv(tmp_path / "component.ssv", {"gain": 3.0, "count": 3, "u_in": 1.25})
    write_ssv(tmp_path / "system.ssv", {"p.count": 5})
    text = ssd.read_text()
    text = text.replace("        </ssd:Connectors>\n",
                        "        </ssd:Connectors>\n        <ssd:ParameterBindings><ssd:ParameterBinding "
                        'source="component.ssv"/></ssd:ParameterBindings>\n', 1)
    text = text.replace("    <ssd:Elements>", '    <ssd:ParameterBindings><ssd:ParameterBinding source="system.ssv"/>'
                                             "</ssd:ParameterBindings>\n    <ssd:Elements>")
    ssd.write_text(text)
    out = run_probe(tmp_path)
    assert (out["p.gain_at_init"], out["p.count_at_init"], out["p.u_at_init"]) == (3.0, 5, 1.25)
    cli = write_ssv(tmp_path / "cli.ssv", {"p.gain": 9.0})
    out = run_probe(tmp_path, [cli])
    assert (out["p.gain_at_init"], out["p.count_at_init"]) == (9.0, 5)


def test_prefixed_system_binding(tmp_path: Path, fmu_dir: Path) -> None:
    ssd = write_system(tmp_path, fmu_dir, [Comp("p", "StartProbe.fmu", PROBE)], [])
    write_ssv(tmp_path / "bare.ssv", {"gain": 4.0})
    ssd.write_text(ssd.read_text().replace(
        "    <ssd:Elements>", '    <ssd:ParameterBindings><ssd:ParameterBinding source="bare.ssv" prefix="p."/>'
                             "</ssd:ParameterBindings>\n    <ssd:Elements>"))
    assert run_probe(tmp_path)["p.gain_at_init"] == 4.0


def test_connected_input_takes_the_source_value_at_initialization(tmp_path: Path, fmu_dir: Path) -> None:
    from systems import GAIN_CONNECTORS

    write_system(tmp_path, fmu_dir, [Comp("g", "Gain.fmu", GAIN_CONNECTORS, {"k": 2.0, "u_real": 1.5}),
                                     Comp("p", "StartProbe.fmu", PROBE)], [("g.y_real", "p.u_in")])
    out = run_probe(tmp_path)
    assert out["p.u_at_init"] == 3.0  # k * u_real start, never 0.0


def test_fmpy_runner_loses_what_we_apply(tmp_path: Path, fmu_dir: Path) -> None:
    """The same archive under fmpy's runner: the binding is ignored and the input zeroed.

    (fmpy's runner also fails on an unconnected input, so the two probes feed each other.)
    """
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [Comp("p", "StartProbe.fmu", PROBE, {"gain": 2.5}),
                                   Comp("q", "StartProbe.fmu", PROBE)],
                 [("q.gain_at_init", "p.u_in"), ("p.gain_at_init", "q.u_in")])
    archive = tmp_path / "probe.ssp"
    with zipfile.ZipFile(archive, "w") as zf:
        for f in folder.rglob("*"):
            if f.is_file():
                zf.write(f, f.relative_to(folder).as_posix())
    theirs = run_isolated("fmpy_simulate_ssp", archive=str(archive), stop_time=0.2, step_size=0.1,
                          variables=["p.gain_at_init", "q.u_at_first_step"])
    ours = run_probe(folder)
    # ours: the binding reached p; q saw p's output (2.5) through the connection at its first step
    assert ours["p.gain_at_init"] == 2.5
    ex = Execution(bind_system(load_system(folder)), rate_hz=10.0, record=["q.u_at_first_step"])
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(0.2)
    assert rec.result()["q.u_at_first_step"][-1] == 2.5
    # fmpy: binding ignored, and the input held 0.0 at the first step
    assert theirs["p.gain_at_init"][-1] == 1.0
    assert theirs["q.u_at_first_step"][-1] == 0.0
