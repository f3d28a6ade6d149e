"""The orchestrator's parts (issue 20): the exchange and its probe, input modifiers honoured by any
algorithm, the registry, the Gauss-Seidel order without an execution, one reading of the SSD per command."""
from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError
from openemss.orchestrator.master import algorithm_registry
from openemss.orchestrator.master.algorithm import Algorithm, Coupling, step_order
from openemss.orchestrator.master.exchange import Exchange
from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.scenarios.manipulators import ScenarioManipulator, load_scenario
from openemss.orchestrator.ssp import read as ssp
from openemss.orchestrator.ssp import system as system_module
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import GAIN_CONNECTORS, Comp, write_system


@pytest.fixture()
def chain(tmp_path: Path, fmu_dir: Path) -> Path:
    """c -> a -> b, declared a, b, c: the Gauss-Seidel order is c, a, b; k of b is 3."""
    return write_system(tmp_path / "sys", fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS),
                                                    Comp("b", "Gain.fmu", GAIN_CONNECTORS, {"k": 3.0}),
                                                    Comp("c", "Gain.fmu", GAIN_CONNECTORS, {"u_real": 2.0})],
                        [("c.y_real", "a.u_real"), ("a.y_real", "b.u_real")], stop_time=1.0).parent


class OwnInputs(Algorithm):
    """An algorithm that writes its components' inputs itself (say, an extrapolation: here zeros) and
    knows nothing of scenarios: the overrides must reach the FMUs all the same."""

    name = "own-inputs"

    def step(self, coupling: Coupling, k: int) -> None:
        for i in range(len(self.multiples)):
            for v in coupling.inputs_of(i):
                v[:] = 0
            coupling.advance(i, k)
        coupling.transfer_all()


def test_an_algorithm_that_writes_inputs_itself_still_honours_the_scenario(chain: Path, tmp_path: Path) -> None:
    scenario = tmp_path / "s.yaml"
    scenario.write_text("events:\n  - at: 0.3\n    set: {b.u_real: 5.0}\n  - at: 0.6\n    release: [b.u_real]\n")
    bound = bind_system(load_system(chain))
    ex = Execution(bound, OwnInputs([1, 1, 1]), Exchange(bound, ["b.u_real", "b.y_real"]), rate_hz=10.0)
    ex.add_manipulator(ScenarioManipulator(load_scenario(scenario)))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(1.0)
    r = rec.result()
    t = r["time_s"]
    held = (t > 0.3 + 1e-9) & (t < 0.6 + 1e-9)  # steps that began while the override held
    assert np.all(r["b.y_real"][held] == 15.0)  # k_b * 5: the FMU got the override, not the algorithm's 0
    assert np.all(r["b.y_real"][(t > 0.1) & ~held] == 0.0)


def test_the_probe_reads_outputs_inputs_and_parameters(chain: Path) -> None:
    bound = bind_system(load_system(chain))
    exchange = Exchange(bound, ["b.u_real"])
    read_input, read_output = exchange.probe("b.u_real", "test"), exchange.probe("a.y_real", "test")
    exchange.vectors["Real"].inputs[exchange.signals[0].index] = 7.5
    assert read_input() == 7.5 and read_output() == 0.0
    with pytest.raises(ConfigurationError, match="test names no variable 'b.nope'"):
        exchange.probe("b.nope", "test")
    ex = Execution(bound, "jacobi", exchange, rate_hz=10.0)
    ex.initialize()
    try:
        assert exchange.probe("b.k", "test")() == 3.0  # a parameter: one FMI get, once the slaves are bound
        assert read_output() == 2.0  # a.y_real = k_a * c.y_real = 1 * 2 after the initial exchange
    finally:
        ex.run(0.0)  # terminates and frees the FMUs


def test_an_exchange_of_another_system_and_duplicate_names_are_refused(chain: Path) -> None:
    one, two = bind_system(load_system(chain)), bind_system(load_system(chain))
    with pytest.raises(ConfigurationError, match="another system"):
        Execution(one, "jacobi", Exchange(two))
    with pytest.raises(ConfigurationError, match="unknown algorithm 'newton'.*allowed: jacobi, gauss-seidel"):
        Execution(one, "newton")
    with pytest.raises(ValueError, match="registered twice"):
        algorithm_registry.register(algorithm_registry.REGISTRY["jacobi"])


def test_the_gauss_seidel_order_needs_no_execution(chain: Path, monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    bound = bind_system(load_system(chain))
    assert [bound.components[i].name for i in step_order(bound).order] == ["c", "a", "b"]

    def no_execution(*args: object, **kwargs: object) -> None:
        raise AssertionError("emss info built an Execution")

    monkeypatch.setattr(Execution, "__init__", no_execution)
    assert main(["info", str(chain)]) == 0
    assert "Gauss-Seidel order: c -> a -> b" in capsys.readouterr().out


@pytest.fixture()
def counted(monkeypatch: pytest.MonkeyPatch) -> Iterator[dict[str, list[str]]]:
    """Counts the readings of SSD files and of FMU model descriptions."""
    calls: dict[str, list[str]] = {"ssd": [], "fmu": []}
    read_ssd, read_md = ssp.read_ssd, system_module.read_model_description

    def counting_ssd(path: Path, *args: object, **kwargs: object) -> object:
        calls["ssd"].append(str(path))
        return read_ssd(path, *args, **kwargs)

    def counting_md(path: str, *args: object, **kwargs: object) -> object:
        calls["fmu"].append(path)
        return read_md(path, *args, **kwargs)

    monkeypatch.setattr(ssp, "read_ssd", counting_ssd)
    monkeypatch.setattr(system_module, "read_model_description", counting_md)
    yield calls


@pytest.mark.parametrize("command", [
    ["run", "--set", "a.k=2", "--stop-time", "0.2", "--rate", "10"],  # no --out: the folder is named from the SSD
    ["info", "--set", "a.k=2"],
    ["validate", "--set", "a.k=2"],
    ["export", "--container", "out.fmu"],
])
def test_a_command_reads_the_ssd_once_and_each_fmu_once(chain: Path, tmp_path: Path, counted: dict[str, list[str]],
                                                       monkeypatch: pytest.MonkeyPatch, command: list[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert main([command[0], str(chain), *command[1:]]) == 0
    assert len(counted["ssd"]) == 1, counted["ssd"]
    assert len(counted["fmu"]) == len(set(counted["fmu"])) == 1, counted["fmu"]  # three components, one FMU file
