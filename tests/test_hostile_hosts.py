"""The hostile corpus, hosts: the project's FMUs through every legal host sequence (issue 33 point 3).

Each case drives the built FMUs with fmpy's ``FMU2Slave`` (or ``openemss.run``) in a child interpreter, so that
a segmentation fault fails the case instead of killing pytest; the child ends with a garbage collection and
its normal exit, where the crashes of a double release showed. Sequences: a failed initialization, a failed
set, a failed get, a failed doStep, each followed by ``fmi2FreeInstance`` and repeated; then a fresh instance
that must work. Two instances at once, from one extraction and from two; an extraction folder removed
between instances; failed ``openemss.run`` calls (an FMU missing its data, an FMU whose code was altered
under the same module name) before and after runs of the intact system in one process.

What is asserted is independent of the code under test: the FMI status each call returns, the number of
instances of the slave class still alive after the frees (0: freed exactly once, nothing leaked), the class's
reference count before and after the failures (equal), the outputs of a fresh instance against those of an
instance in a process that saw no failure, and the child's exit code.
"""
from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Any

import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

#: Per shipped FMU: a value its start refuses (set before initialization; the failure comes at
#: fmi2ExitInitializationMode), a value its setter refuses at once (None: none), an input that makes its
#: doStep fail (with the step size), and the Real output compared between instances.
CASES: dict[str, dict[str, Any]] = {
    "engine": {"init": ("preset", "no_such_engine"), "set": None,
               "step": ("Wf_cmd_kg_s", math.nan, 0.05), "output": "Fn_N"},
    "fcs": {"init": ("mission_file", "{tmp}/no_such_mission.yaml"), "set": None,
            "step": ("alt_m", math.inf, 0.05), "output": "Wf_cmd_kg_s"},
    "airframe": {"init": ("weather_file", "{tmp}/no_such_weather.yaml"), "set": None,
                 "step": (None, None, math.nan), "output": "alt_m"},
    "electric": {"init": None, "set": ("hp_machine.P_max_W", -5.0),
                 "step": ("N1_rpm", math.nan, 0.05), "output": "battery_V"},
}
NAMES = sorted(CASES)
REPEAT = 6  # failures per case: the class lost one reference per failure, freed after a few


# -- the child ----------------------------------------------------------------------------------------------
def _open(fmu: str, unzip: str | None = None, name: str = "probe") -> tuple[Any, dict[str, Any], str]:
    import tempfile

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(fmu)
    folder = unzip or extract(fmu, unzipdir=tempfile.mkdtemp(prefix="hostile_hosts_"))
    s = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=name)
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    return s, {v.name: v for v in md.modelVariables}, str(folder)


def _set(s: Any, variables: dict[str, Any], name: str, value: Any) -> None:
    v = variables[name]
    getattr(s, f"set{v.type}")([v.valueReference], [value])


def _status(call: Any, *args: Any) -> int:
    """The FMI status of a call (0 when fmpy raised nothing)."""
    try:
        call(*args)
    except Exception as exc:  # fmpy's FMICallException carries the status
        return int(getattr(exc, "status", -1))
    return 0


def _run_good(s: Any, variables: dict[str, Any], output: str, steps: int = 3) -> list[float]:
    s.enterInitializationMode()
    s.exitInitializationMode()
    vr = variables[output].valueReference
    out = [s.getReal([vr])[0]]
    for k in range(steps):
        s.doStep(currentCommunicationPoint=k * 0.05, communicationStepSize=0.05)
        out.append(s.getReal([vr])[0])
    return out


def _slave_class(folder: str) -> type:
    module = sys.modules[Path(folder, "resources", "slavemodule.txt").read_text().strip()]
    from pythonfmu import Fmi2Slave

    return next(c for c in vars(module).values() if isinstance(c, type) and issubclass(c, Fmi2Slave)
                and c.__module__ == module.__name__)


def _live(cls: type) -> int:
    import gc

    gc.collect()
    return sum(1 for o in gc.get_objects() if type(o) is cls)


def child_fail_and_free(fmu: str, kind: str, var: str | None, value: Any, step_s: float, output: str,
                        repeat: int) -> dict[str, Any]:
    """A good instance freed (the baseline), then ``repeat`` instances failing by ``kind`` and freed, then a good
    one: statuses, live instances and the class's reference count, the good instances' outputs."""
    s, variables, folder = _open(fmu, name="first")
    first = _run_good(s, variables, output)
    s.fmi2FreeInstance(s.component)
    cls = _slave_class(folder)
    live0 = _live(cls)  # (garbage collected first: what refers to the class is alive)
    refs0 = sys.getrefcount(cls)
    statuses = []
    for i in range(repeat):
        s, variables, _ = _open(fmu, folder, name=f"failing{i}")
        if kind == "init":
            _set(s, variables, var, value)  # type: ignore[arg-type]
            status = _status(s.enterInitializationMode) or _status(s.exitInitializationMode)
        elif kind == "set":
            status = _status(_set, s, variables, var, value)
        elif kind == "set_in_init":  # through the functions the slave sets on itself in Initialization Mode
            s.enterInitializationMode()
            status = _status(_set, s, variables, var, value)
        elif kind == "get_unknown":
            status = _status(s.getReal, [987654])
        elif kind == "step":
            s.enterInitializationMode()
            s.exitInitializationMode()
            s.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.05)
            if var is not None:
                _set(s, variables, var, value)
            status = _status(s.doStep, 0.05, step_s)
        else:
            raise ValueError(kind)
        statuses.append(status)
        s.fmi2FreeInstance(s.component)
        _live(cls)
    s, variables, _ = _open(fmu, folder, name="last")
    last = _run_good(s, variables, output)
    s.fmi2FreeInstance(s.component)
    return {"statuses": statuses, "live": [live0, _live(cls)], "refs": [refs0, sys.getrefcount(cls)],
            "first": first, "last": last}


def child_two_at_once(fmu: str, output: str, separate: bool, remove_first: bool) -> dict[str, Any]:
    """Two instances alive at once (from one extraction, or from two), stepped alike; then, with
    ``remove_first``, both freed, the first extraction removed and a third instance from the second."""
    a, variables, folder_a = _open(fmu, name="a")
    b, _, folder_b = _open(fmu, None if separate else folder_a, name="b")
    out_a, out_b = _run_good(a, variables, output), _run_good(b, variables, output)
    a.fmi2FreeInstance(a.component)
    b.doStep(currentCommunicationPoint=0.15, communicationStepSize=0.05)  # b lives on without a
    b.fmi2FreeInstance(b.component)
    third = None
    if remove_first:
        shutil.rmtree(folder_a)
        c, variables, _ = _open(fmu, folder_b, name="c")
        third = _run_good(c, variables, output)
        c.fmi2FreeInstance(c.component)
    return {"a": out_a, "b": out_b, "third": third}


def child_simulate_twice(fmu: str, output: str) -> dict[str, Any]:
    """fmpy.simulate_fmu twice (it extracts into a temporary folder and removes it after each)."""
    from fmpy import simulate_fmu

    runs = []
    for _ in range(2):
        try:
            r = simulate_fmu(fmu, stop_time=0.2, step_size=0.05, output_interval=0.05, output=[output])
            runs.append([float(x) for x in r[output]])
        except Exception as exc:
            runs.append(str(exc))
    return {"runs": runs}


def child_runs(systems: list[str], out: str, settings: list[list[str]] | None = None) -> dict[str, Any]:
    """``openemss.run`` of each system in turn (with its ``settings``), in this one process: status and error of
    each, and per slave class loaded the number of its instances still alive after them all."""
    from pythonfmu import Fmi2Slave

    import openemss

    result = []
    for i, system in enumerate(systems):
        r = openemss.run(system, stop_time=0.5, out=f"{out}/run{i}", pre_run=False, post_run=False,
                         warn=lambda line: None, set=(settings or [[]] * len(systems))[i])
        result.append([r.status, r.error or ""])
    classes = {c for m in list(sys.modules.values()) for c in vars(m).values()
               if isinstance(c, type) and issubclass(c, Fmi2Slave) and c.__module__ == m.__name__
               and m.__name__.startswith("emss_")}
    return {"runs": result, "live": sorted(_live(c) for c in classes)}


def child_sequence(fmus: list[str], output: str) -> dict[str, Any]:
    """Each FMU in turn, each from its own extraction: instantiated, run three steps and freed; what failed."""
    result = []
    for fmu in fmus:
        try:
            s, variables, _ = _open(fmu)
        except Exception as exc:
            result.append(str(exc))
            continue
        result.append(_run_good(s, variables, output))
        s.fmi2FreeInstance(s.component)
    return {"runs": result}


def host(function: str, **kwargs: Any) -> dict[str, Any]:
    """``function(**kwargs)`` of this module in a child interpreter that collects its garbage and exits
    normally: its result, asserting the child did not crash."""
    code = ("import gc, json, sys\n"
            f"sys.path.insert(0, {str(HERE)!r})\n"
            "import test_hostile_hosts as t\n"
            f"r = t.{function}(**json.loads(sys.argv[1]))\n"
            "gc.collect()\n"
            "print('@@' + json.dumps(r), flush=True)\n")
    proc = subprocess.run([sys.executable, "-c", code, json.dumps(kwargs)], capture_output=True, text=True)
    assert proc.returncode == 0, f"the host crashed or failed (exit {proc.returncode}):\n{proc.stderr[-3000:]}"
    return json.loads(proc.stdout.split("@@")[-1])


# -- the cases ----------------------------------------------------------------------------------------------
def _assert_survived(r: dict[str, Any], kind: str) -> None:
    assert len(r["statuses"]) == REPEAT and all(s >= 2 for s in r["statuses"]), (kind, r["statuses"])
    assert r["live"] == [0, 0], f"{kind}: instances of the slave class alive after every free: {r['live']}"
    assert r["refs"][1] == r["refs"][0], f"{kind}: the slave class's references changed: {r['refs']}"
    assert r["last"] == r["first"], "a fresh instance after the failures differs from the first"
    assert all(math.isfinite(x) for x in r["last"])


@pytest.mark.parametrize("name", [n for n in NAMES if CASES[n]["init"]])
def test_free_after_a_failed_initialization(project_fmus: dict[str, Path], tmp_path: Path, name: str) -> None:
    var, value = CASES[name]["init"]
    r = host("child_fail_and_free", fmu=str(project_fmus[name]), kind="init", var=var,
             value=value.format(tmp=tmp_path), step_s=0.05, output=CASES[name]["output"], repeat=REPEAT)
    _assert_survived(r, "init")


@pytest.mark.parametrize("name", NAMES)
def test_free_after_a_failed_dostep(project_fmus: dict[str, Path], name: str) -> None:
    var, value, step_s = CASES[name]["step"]
    r = host("child_fail_and_free", fmu=str(project_fmus[name]), kind="step", var=var, value=value, step_s=step_s,
             output=CASES[name]["output"], repeat=REPEAT)
    _assert_survived(r, "step")


@pytest.mark.parametrize("name", NAMES)
def test_free_after_a_failed_get(project_fmus: dict[str, Path], name: str) -> None:
    """fmi2GetReal of a value reference the FMU does not have fails; the instance is freed after it."""
    r = host("child_fail_and_free", fmu=str(project_fmus[name]), kind="get_unknown", var=None, value=None,
             step_s=0.05, output=CASES[name]["output"], repeat=REPEAT)
    _assert_survived(r, "get")


def test_free_after_a_refused_set_before_and_in_initialization(project_fmus: dict[str, Path]) -> None:
    """The electrical system refuses a parameter out of its range at once, before Initialization Mode and in it
    (where the slave's checked setters stand in for the class's, fmus/initial_outputs.py)."""
    var, value = CASES["electric"]["set"]
    for kind in ("set", "set_in_init"):
        r = host("child_fail_and_free", fmu=str(project_fmus["electric"]), kind=kind, var=var, value=value,
                 step_s=0.05, output=CASES["electric"]["output"], repeat=REPEAT)
        _assert_survived(r, kind)


@pytest.mark.parametrize("separate", [False, True], ids=["one_extraction", "two_extractions"])
@pytest.mark.parametrize("name", NAMES)
def test_two_instances_at_once(project_fmus: dict[str, Path], name: str, separate: bool) -> None:
    r = host("child_two_at_once", fmu=str(project_fmus[name]), output=CASES[name]["output"], separate=separate,
             remove_first=separate)
    assert r["a"] == r["b"], "two instances with the same inputs differ"
    if separate:  # the first extraction removed: the second's instances read their own code and data
        assert r["third"] == r["a"]


@pytest.mark.parametrize("name", NAMES)
def test_simulate_fmu_twice_in_one_process(project_fmus: dict[str, Path], name: str) -> None:
    """Issue 34: a second fmpy.simulate_fmu failed with 'Failed to instantiate model' (the first extraction,
    removed by fmpy, was where the cached module looked for its data)."""
    r = host("child_simulate_twice", fmu=str(project_fmus[name]), output=CASES[name]["output"])
    first, second = r["runs"]
    assert isinstance(first, list) and second == first, r["runs"]


def _system(folder: Path, fmus: dict[str, Path]) -> Path:
    (folder / "resources").mkdir(parents=True)
    shutil.copy2(ROOT / "ssp" / "SystemStructure.ssd", folder / "SystemStructure.ssd")
    for name in ("engine", "fcs", "airframe"):
        shutil.copy2(fmus[name], folder / "resources" / fmus[name].name)
    return folder


def _rewrite(fmu: Path, change: Any) -> None:
    """Rewrite the FMU's zip with ``change(name, data)`` giving each entry's new bytes (None: left out)."""
    with zipfile.ZipFile(fmu) as z:
        entries = [(i, z.read(i.filename)) for i in z.infolist()]
    tmp = fmu.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for info, data in entries:
            new = change(info.filename, data)
            if new is not None:
                z.writestr(info, new)
    tmp.replace(fmu)


def test_failed_runs_do_not_poison_the_next_in_one_process(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    """openemss.run of systems whose FMU has the module names of the intact one but fails (its mission data
    missing; its code altered to fail), each followed by a run of the intact system in the same process."""
    good = _system(tmp_path / "good", project_fmus)
    no_data = _system(tmp_path / "no_data", project_fmus)
    _rewrite(no_data / "resources" / project_fmus["fcs"].name,
             lambda name, data: None if name == "resources/missions/munich.yaml" else data)
    altered = _system(tmp_path / "altered", project_fmus)
    marker = "altered by the hostile test"

    def alter(name: str, data: bytes) -> bytes:
        if name.startswith("resources/emss_engine_") and name.endswith(".py") and "/" not in name[10:]:
            head = b"    def do_step(self, current_time: float, step_size: float) -> bool:\n"
            assert head in data, "the engine slave's do_step is not where the test alters it"
            return data.replace(head, head + f"        raise RuntimeError({marker!r})\n".encode(), 1)
        return data
    _rewrite(altered / "resources" / project_fmus["engine"].name, alter)
    r = host("child_runs", systems=[str(no_data), str(good), str(altered), str(good)], out=str(tmp_path / "out"))
    (s1, e1), (s2, e2), (s3, e3), (s4, e4) = r["runs"]
    assert s1 == "failed" and "missions/munich.yaml" in e1, e1
    assert s2 == "completed", e2
    assert s3 == "failed" and marker in e3, e3
    assert s4 == "completed", e4


def test_data_file_is_the_instances_own(tmp_path: Path) -> None:
    """fmus/data.py reads the copy in the resources folder it is given, never the one beside its module; a copy
    missing there is named in the error."""
    from openemss.fmus.data import REPOSITORY, data_file

    (tmp_path / "missions").mkdir()
    (tmp_path / "missions" / "munich.yaml").write_text("planted\n")
    assert data_file("missions/munich.yaml", str(tmp_path)).read_text() == "planted\n"
    assert data_file("missions/munich.yaml", None) == REPOSITORY / "missions" / "munich.yaml"
    with pytest.raises(FileNotFoundError, match=str(tmp_path / "missions" / "README.md")):
        data_file("missions/README.md", tmp_path)


def test_the_master_frees_failed_instances(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    """Runs whose engine refuses its preset at initialization (fmi2Fatal, pythonfmu's status for every Python
    exception), then a good run, in one process: each failed instance is freed (none left alive, where the
    master used to leave every failed instance alone) and the process survives its garbage collection."""
    good = _system(tmp_path / "good", project_fmus)
    bad = [["engine.preset=no_such_engine"]] * 4
    r = host("child_runs", systems=[str(good)] * 5, out=str(tmp_path / "out"), settings=[*bad, []])
    assert [s for s, _ in r["runs"]] == ["failed"] * 4 + ["completed"], r["runs"]
    assert all("no_such_engine" in e for _, e in r["runs"][:4]), r["runs"]
    assert r["live"] and r["live"] == [0] * len(r["live"]), f"slave instances alive after the runs: {r['live']}"


def test_an_fmu_whose_code_fails_to_import_among_intact_ones(project_fmus: dict[str, Path], tmp_path: Path) -> None:
    """A copy of the electrical system FMU whose slave module raises on import (the module name of the intact
    one), before and after the intact one, in one process: it fails to instantiate (saying why on stderr), the
    intact one runs every time. pythonfmu runs the file again for a second instance and looks through what it
    defined with the exception still set: it crashed on the first class it met."""
    good = tmp_path / "Good.fmu"
    bad = tmp_path / "Bad.fmu"
    shutil.copy2(project_fmus["electric"], good)
    shutil.copy2(project_fmus["electric"], bad)

    def alter(name: str, data: bytes) -> bytes:
        if name.startswith("resources/emss_electric_") and name.endswith(".py") and "/" not in name[10:]:
            assert b"\nclass Electric(" in data
            return data.replace(b"\nclass Electric(", b"\nraise RuntimeError('altered')\nclass Electric(", 1)
        return data
    _rewrite(bad, alter)
    output = CASES["electric"]["output"]
    r = host("child_sequence", fmus=[str(bad), str(good), str(bad), str(good), str(bad), str(good)], output=output)
    runs = r["runs"]
    assert runs[0::2] == ["Failed to instantiate model"] * 3, runs
    assert runs[1] == runs[3] == runs[5] and all(math.isfinite(x) for x in runs[1]), runs
