"""Run third-party co-simulation tools (libcosim, fmpy's runners) in a child process.

libcosim and fmpy's ``simulate_fmu``/``simulate_ssp`` unload an FMU's shared
library when they are done with it. A pythonfmu FMU runs inside the calling
interpreter and leaves objects behind that refer to its library's code, so
unloading it in the test process corrupts the heap and the process may abort
at exit (seen as "corrupted double-linked list" in glibc's thread teardown, in
about one run in ten). Our own master never unloads a library (see
``orchestrator/master/slave.py``). The comparisons with other tools therefore run in
a child process that hands back its results as JSON and leaves with
``os._exit``, before any finalization.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent


def require_libcosim() -> None:
    """Skip the calling test when libcosimpy is not installed, without loading it in this process."""
    import importlib.util

    import pytest

    if importlib.util.find_spec("libcosimpy") is None:
        pytest.skip("libcosimpy is a test dependency (pip install -e '.[test]')")


def run_isolated(function: str, **kwargs: Any) -> Any:
    """Call ``thirdparty.<function>(**kwargs)`` in a child interpreter and return its JSON result."""
    code = ("import json, os, sys\n"
            f"sys.path.insert(0, {str(HERE)!r})\n"
            "import thirdparty\n"
            f"result = thirdparty.{function}(**json.loads(sys.argv[1]))\n"
            "sys.stdout.write('\\n@@RESULT@@' + json.dumps(result))\n"
            "sys.stdout.flush()\n"
            "os._exit(0)\n")
    proc = subprocess.run([sys.executable, "-c", code, json.dumps(kwargs)], capture_output=True, text=True)
    marker = proc.stdout.rfind("@@RESULT@@")
    if proc.returncode != 0 or marker < 0:
        raise RuntimeError(f"{function} failed in the child process (exit {proc.returncode}):\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout[marker + len("@@RESULT@@"):])


# -- what runs in the child ------------------------------------------------------------------------
def libcosim_run(system: str, variables: list[str], steps: int, step_ns: int | None = None,
                 history: bool = True) -> dict[str, Any]:
    """Run an SSP system in libcosim: values of ``component.variable`` after every step (or the last),
    and the final time [ns]."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    ex = CosimExecution.from_ssp_file(system, step_size=step_ns) if step_ns else CosimExecution.from_ssp_file(system)
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    refs = {}
    for name in variables:
        comp, var = name.split(".", 1)
        idx = ex.slave_index_from_instance_name(comp)
        refs[name] = (idx, next(v.reference for v in ex.slave_variables(idx) if v.name.decode() == var))
    out: dict[str, list[float]] = {n: [] for n in variables}
    for k in range(steps):
        ex.step(1)
        if history or k == steps - 1:
            for n, (idx, ref) in refs.items():
                out[n].append(observer.last_real_values(idx, [ref])[0])
    return {"values": out, "time_ns": ex.status().current_time}


def fmpy_simulate_ssp(archive: str, stop_time: float, step_size: float, variables: list[str]) -> dict[str, list]:
    """fmpy's SSP runner on an archive: the recorded columns asked for."""
    from fmpy.ssp.simulation import simulate_ssp

    result = simulate_ssp(archive, stop_time=stop_time, step_size=step_size)
    return {n: [float(v) for v in result[n]] for n in variables}


def fmpy_simulate_fmu(fmu: str, outputs: list[str], **kwargs: Any) -> dict[str, list]:
    """fmpy.simulate_fmu on one FMU: time and the outputs asked for."""
    from fmpy import simulate_fmu

    result = simulate_fmu(fmu, output=outputs, **kwargs)
    return {n: [float(v) for v in result[n]] for n in ("time", *outputs)}


def fmpy_bare_system(ssd: str, stop_time: float, step_size: float, variables: list[str]) -> dict[str, list]:
    """The SSD's FMUs on fmpy's ``FMU2Slave`` alone, applying none of the SSD's parameter bindings: every
    FMU at its start values, the connections copied output to input (same type, no unit conversion)
    after every step of all (Jacobi), five exchanges in initialization mode. Independent of our
    orchestrator: the SSD is read here with lxml. Returns time and ``component.variable`` per step."""
    import shutil
    import tempfile

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    from lxml import etree

    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    root = etree.parse(ssd).getroot()
    base = Path(ssd).parent
    comps: dict[str, Any] = {}
    refs: dict[str, dict[str, tuple[int, str]]] = {}
    tmp = tempfile.mkdtemp(prefix="fmpy_bare_")
    for c in root.iterfind(".//ssd:Component", ns):
        name, src = c.get("name"), str(base / c.get("source"))
        md = read_model_description(src)
        d = extract(src, unzipdir=f"{tmp}/{name}")
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                        instanceName=name)
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        comps[name] = fmu
        refs[name] = {v.name: (v.valueReference, v.type) for v in md.modelVariables}
    links = []
    for k in root.iterfind(".//ssd:Connection", ns):
        a, b = (k.get("startElement"), k.get("startConnector")), (k.get("endElement"), k.get("endConnector"))
        links.append((a, b, refs[a[0]][a[1]][1]))
    get = {"Real": "getReal", "Boolean": "getBoolean", "Integer": "getInteger", "String": "getString"}

    def value(comp: str, var: str) -> Any:
        vr, t = refs[comp][var]
        return getattr(comps[comp], get[t])([vr])[0]

    def exchange() -> None:
        vals = [(b, t, value(*a)) for a, b, t in links]
        for (comp, var), t, x in vals:
            getattr(comps[comp], "s" + get[t][1:])([refs[comp][var][0]], [x])

    for f in comps.values():
        f.enterInitializationMode()
    for _ in range(5):
        exchange()
    for f in comps.values():
        f.exitInitializationMode()
    out: dict[str, list] = {"time": [0.0], **{n: [float(value(*n.split(".", 1)))] for n in variables}}
    n = round(stop_time / step_size)
    for k in range(n):
        exchange()
        for f in comps.values():
            f.doStep(currentCommunicationPoint=k * step_size, communicationStepSize=step_size)
        out["time"].append((k + 1) * step_size)
        for v in variables:
            out[v].append(float(value(*v.split(".", 1))))
    shutil.rmtree(tmp, ignore_errors=True)
    return out


def fmpy_initialization_outputs(fmu: str, outputs: list[str], inputs: dict[str, float]) -> dict[str, list]:
    """One FMU on fmpy's FMU2Slave through Initialization Mode: the Real ``outputs`` read right after
    fmi2EnterInitializationMode, again after setting the Real ``inputs``, and after
    fmi2ExitInitializationMode (keys ``entered``, ``after_set``, ``exited``, in the order of ``outputs``)."""
    import shutil
    import tempfile

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    tmp = tempfile.mkdtemp(prefix="fmpy_init_")
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu, unzipdir=tmp),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="probe")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    refs = [vr[n] for n in outputs]
    out = {"entered": list(s.getReal(refs))}
    s.setReal([vr[n] for n in inputs], list(inputs.values()))
    out["after_set"] = list(s.getReal(refs))
    s.exitInitializationMode()
    out["exited"] = list(s.getReal(refs))
    shutil.rmtree(tmp, ignore_errors=True)
    return out
