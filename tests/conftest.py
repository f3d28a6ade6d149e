"""Shared fixtures: the FMUs the tests need, built once per session with build-fmus."""
from __future__ import annotations

import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from openemss.orchestrator.fmu.build import ensure_built

ROOT = Path(__file__).resolve().parent.parent
OSCILLATOR = ROOT / "examples" / "oscillator"


def pytest_configure(config: pytest.Config) -> None:
    """SIGINT as an interactive shell gives it, whatever started the suite.

    A shell starts a background job (``pytest &``, ``nohup``, a CI runner's job control) with SIGINT ignored, and
    an ignored disposition is inherited across ``exec``: every child the interruption tests start would ignore
    the SIGINT they send (the programs keep an ignored SIGINT ignored on purpose,
    ``test_an_ignored_sigint_stays_ignored``) and those tests would wait for an exit that never comes. A Python
    handler, unlike ``SIG_IGN``, is reset to the default at ``exec``, so children start with SIGINT's default.
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Folder holding every test FMU and the oscillator example's FMUs, freshly built."""
    out = tmp_path_factory.mktemp("fmus")
    ensure_built(OSCILLATOR / "fmus", out, force=True)
    ensure_built(ROOT / "tests" / "fmus", out, force=True)
    return out


@pytest.fixture(scope="session")
def project_fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The project's own FMUs (every slave in fmus/), built once per session: slave name -> FMU path."""
    from openemss.orchestrator.fmu.build import discover

    out = tmp_path_factory.mktemp("project_fmus")
    names = sorted(discover(ROOT / "fmus"))
    paths = ensure_built(ROOT / "fmus", out, names=names, force=True)
    return dict(zip(names, paths, strict=True))


@pytest.fixture(scope="session")
def project_system(project_fmus: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The project's system (ssp/SystemStructure.ssd) with the FMUs built for this session."""
    folder = tmp_path_factory.mktemp("project_system")
    shutil.copy(ROOT / "ssp" / "SystemStructure.ssd", folder)
    (folder / "resources").mkdir()
    for name, fmu in (("fcs", "Fcs.fmu"), ("engine", "Engine.fmu"), ("airframe", "Airframe.fmu")):
        shutil.copy(project_fmus[name], folder / "resources" / fmu)
    return folder


@pytest.fixture(scope="session")
def state_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """LoopElement.fmu with canGetAndSetFMUstate="true" (pythonfmu saves and restores its variables)."""
    out = tmp_path_factory.mktemp("state_fmu")
    stage = out / "stage"
    stage.mkdir()
    script = ROOT / "tests" / "fmus" / "loop_element.py"
    shutil.copy2(script, stage / script.name)
    code = ("import sys; from pythonfmu.builder import FmuBuilder; "
            "print(FmuBuilder.build_FMU(sys.argv[1], dest=sys.argv[2], canGetAndSetFMUstate=True))")
    proc = subprocess.run([sys.executable, "-c", code, str(stage / script.name), str(out)], capture_output=True,
                          text=True, check=True, cwd=out)
    return Path(proc.stdout.strip().splitlines()[-1])


def assert_house_style(model_description: object) -> None:
    """Every variable describes itself with its unit in brackets; Integer and Boolean inputs and
    outputs are discrete (fmpy validate requires it)."""
    for v in model_description.modelVariables:  # type: ignore[attr-defined]
        assert v.description and v.description.rstrip().endswith("]"), v.name
        if v.type in ("Integer", "Boolean") and v.causality in ("input", "output"):
            assert v.variability == "discrete", v.name


def open_slave(fmu: Path, instance_name: str) -> tuple[object, dict[str, int]]:
    """An instantiated FMU2Slave (experiment set up at t = 0) and its value references by name.

    The FMU is extracted once per process, as the orchestrator does (one library per FMU file);
    free it with ``slave.fmi2FreeInstance(slave.component)``, never ``freeInstance()``, which
    unloads the library (see thirdparty.py).
    """
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave

    from openemss.orchestrator.master.slave import extracted

    md = read_model_description(str(fmu))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extracted(fmu), modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=instance_name)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    return slave, {v.name: v.valueReference for v in md.modelVariables}


@pytest.fixture()
def oscillator(tmp_path: Path, fmu_dir: Path) -> Path:
    """A private copy of the oscillator example system with freshly built FMUs."""
    folder = tmp_path / "oscillator"
    (folder / "resources").mkdir(parents=True)
    for f in ("SystemStructure.ssd", "mass2.ssv"):
        shutil.copy2(OSCILLATOR / f, folder / f)
    for f in ("ForceDrivenMass.fmu", "DisplacementDrivenMass.fmu"):
        shutil.copy2(fmu_dir / f, folder / "resources" / f)
    return folder


@pytest.fixture(scope="session")
def engine_system(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A system of the engine FMU alone (built from fmus/engine.py into a temporary folder): the studies' cycle
    sweep reads the engine's design_* parameters from it."""
    from systems import Comp, write_system

    build = tmp_path_factory.mktemp("engine_fmu")
    ensure_built(ROOT / "fmus", build, names=["engine"], force=True)
    folder = tmp_path_factory.mktemp("engine_system") / "engine_only"
    write_system(folder, build, [Comp("engine", "Engine.fmu", [("Fn_N", "output", "Real")])], [],
                 name="EngineOnly", stop_time=1.0)
    return folder


@pytest.fixture(scope="session")
def larzac_dp():  # noqa: ANN201
    """The Larzac 04 preset's design point (SLS, ISA), shared by the engine tests."""
    from openemss.models.engine.cycle_design import design
    from openemss.models.engine.design_params import load_params, preset_path
    return design(load_params(preset_path("larzac04_sls")))


@pytest.fixture(scope="session")
def larzac_od(larzac_dp):  # noqa: ANN001, ANN201
    """Its off-design model on the shipped (extended) maps."""
    from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps
    return TurbofanOffDesign(larzac_dp, scaled_maps(larzac_dp))


# Two test modules run in a process of their own (tests/airframe/test_isolated.py), unless asked here: the
# suite segfaulted in garbage collection after them (5 times in some 30 full runs; in the airframe and common
# tests alone, 1 run in 3 with test_airframe_weather.py, none in 4 without it). That module drives the
# airframe FMU in-process through a failing initialization; test_asb_estimate.py loads AeroSandbox/casadi.
import os as _os  # noqa: E402

ISOLATED = ("airframe/test_airframe_weather.py", "airframe/test_asb_estimate.py")
collect_ignore = [] if _os.environ.get("EMSS_IN_PROCESS") else list(ISOLATED)


def table(folder: Path) -> dict[str, object]:
    """The time series of a results folder (any format emss run writes), every column as float64."""
    from openemss.orchestrator.recording.timeseries import read_timeseries

    return read_timeseries(folder).floats()


def columns(folder: Path) -> list[str]:
    """The column names of a results folder's time series, in file order."""
    from openemss.orchestrator.recording.timeseries import read_timeseries

    return read_timeseries(folder).names


@pytest.fixture(scope="session")
def munich_run(project_system: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The whole Munich mission (the shipped system, its defaults) flown once per session with its summary:
    its results folder. Shared by the tests that compare the shipped run's figures (tests/test_docs_figures.py)
    and its fuel flow (tests/fcs/test_smooth_targets.py)."""
    import openemss

    out = tmp_path_factory.mktemp("munich") / "run"
    openemss.run(project_system, out=out, pre_run=False, warn=lambda line: None)
    return out
