"""The project's FMUs in hosts other than ours (issue 16 points 3 and 4).

* **Missing packages** (point 3): in a fresh venv that has nothing but fmpy (and fmpy's own
  requirements), an FMU fails to instantiate with one line naming every missing package and the
  ``pip install -r .../requirements.txt`` that installs them, on stderr and through the FMI logger.
* **Vendored** (point 3): the same FMU built with ``build-fmus --vendor`` runs there, and gives the
  outputs it gives in this environment.
* **A C host** (point 4): ``tests/chost/fmu_host.c``, compiled here against the FMI 2.0 headers fmpy
  ships, loads each FMU built with ``--link-libpython`` through ``dlopen`` (no LD_PRELOAD), steps it and
  frees it; its outputs equal fmpy's step by step.

The fresh venv is made without the network: ``python -m venv`` without pip, and a ``.pth`` file naming a
folder into which the installed files of fmpy and of what it requires are linked (symbolic links, with
the same code that vendors an FMU's packages), so nothing else of this environment can be imported.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from openemss.orchestrator.fmu.build import ensure_built
from openemss.orchestrator.fmu.fmu_deps import import_name, vendor_packages

ROOT = Path(__file__).resolve().parent.parent
HEADERS = Path(__import__("fmpy").__file__).parent / "c-code"


@pytest.fixture(scope="module")
def only_fmpy(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The python of a fresh venv where only fmpy and its requirements can be imported."""
    base = tmp_path_factory.mktemp("only_fmpy")
    venv.create(base / "venv", with_pip=False)
    py = base / "venv" / "bin" / "python"
    purelib = subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             check=True, capture_output=True, text=True).stdout.strip()
    vendor_packages(("fmpy",), base / "fmpy_only", also=(), copy=lambda s, d: os.symlink(s, d))
    Path(purelib, "fmpy_only.pth").write_text(str(base / "fmpy_only") + "\n")
    probe = "import fmpy, importlib.util as u; print([m for m in ('yaml', 'pythonfmu', 'scipy') if u.find_spec(m)])"
    assert subprocess.run([str(py), "-c", probe], check=True, capture_output=True, text=True).stdout.strip() == "[]"
    return py


_SIMULATE = """
import json, os, sys
from fmpy import simulate_fmu
log = []
try:
    r = simulate_fmu(sys.argv[1], stop_time=1.0, output_interval=0.05, step_size=0.05, debug_logging=True,
                     output=sys.argv[2:], logger=lambda c, n, s, cat, m: log.append(m.decode()))
    out = {"values": {k: [float(x) for x in r[k]] for k in sys.argv[2:]}}
except Exception as exc:
    out = {"error": str(exc)}
out["log"] = log
sys.stdout.write("@@" + json.dumps(out))
sys.stdout.flush()
os._exit(0)
"""


def _simulate(py: Path, fmu: Path, outputs: list[str]) -> tuple[dict, str]:  # type: ignore[type-arg]
    proc = subprocess.run([str(py), "-c", _SIMULATE, str(fmu), *outputs], capture_output=True, text=True,
                          cwd=fmu.parent)
    assert "@@" in proc.stdout, proc.stderr[-2000:]
    return json.loads(proc.stdout.split("@@", 1)[1]), proc.stderr


def test_missing_packages_fail_with_one_clear_line(only_fmpy: Path, tmp_path: Path) -> None:
    fmu = ensure_built(ROOT / "fmus", tmp_path, names=["fcs"])[0]
    result, stderr = _simulate(only_fmpy, fmu, ["lever_norm"])
    assert result.get("error") == "Failed to instantiate model"  # fmpy's own words
    lines = [ln for ln in stderr.splitlines() if ln.startswith("Fcs.fmu: cannot run")]
    assert len(lines) == 1, stderr
    line = lines[0]
    assert "pip install -r " in line and line.rstrip().endswith("(or use an FMU built with build-fmus --vendor)")
    req = Path(line.split("pip install -r ", 1)[1].split(" ", 1)[0])
    assert req.name == "requirements.txt"
    # the line names exactly those of the FMU's requirements its interpreter cannot find, found here by
    # asking that interpreter with the FMU's resources (which carry pythonfmu) on its path
    resources = tmp_path / "unzipped"
    with zipfile.ZipFile(fmu) as z:
        z.extractall(resources)
    wanted = (resources / "resources" / "requirements.txt").read_text().split()
    probe = ("import importlib.util as u, json, sys; sys.path.insert(0, sys.argv[1]); "
             "print(json.dumps([r for r, m in zip(sys.argv[2::2], sys.argv[3::2]) if u.find_spec(m) is None]))")
    args = [x for r in wanted for x in (r, import_name(r))]
    missing = json.loads(subprocess.run([str(only_fmpy), "-c", probe, str(resources / "resources"), *args],
                                        check=True, capture_output=True, text=True).stdout)
    assert "pyyaml>=6.0" in missing  # the fixture's interpreter has fmpy alone
    assert f"package(s) {', '.join(missing)} cannot be imported" in line, (missing, line)
    assert any(line in m for m in result["log"]), result["log"]  # the FMI logger got it too


def test_vendored_fmu_runs_where_only_fmpy_is(only_fmpy: Path, tmp_path: Path) -> None:
    """The FCS FMU with its packages inside (pyyaml, pythonfmu, numpy, numba) runs in the venv of fmpy alone and
    gives the outputs the plain FMU gives here; its size is stated in the README."""
    plain = ensure_built(ROOT / "fmus", tmp_path / "plain", names=["fcs"])[0]
    vendored = ensure_built(ROOT / "fmus", tmp_path / "vendored", names=["fcs"], vendor=True)[0]
    names = zipfile.ZipFile(vendored).namelist()
    assert any(n.startswith("resources/vendor/yaml/") for n in names)
    assert any(n.startswith("resources/vendor/pythonfmu/") for n in names)
    outs = ["lever_norm", "elevator_norm", "Wf_cmd_kg_s", "alt_cmd_m"]
    theirs, stderr = _simulate(only_fmpy, vendored, outs)
    assert "values" in theirs, (theirs, stderr[-2000:])
    ours, _ = _simulate(Path(sys.executable), plain, outs)
    for n in outs:
        np.testing.assert_array_equal(theirs["values"][n], ours["values"][n], err_msg=n)
    assert np.all(np.isfinite(theirs["values"]["alt_cmd_m"]))


# the output compared per FMU (run at their start values, no inputs set)
C_HOST_OUTPUT = {"engine": "Fn_N", "airframe": "alt_m", "fcs": "Wf_cmd_kg_s"}


@pytest.fixture(scope="module")
def c_host(tmp_path_factory: pytest.TempPathFactory) -> Path:
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler")
    exe = tmp_path_factory.mktemp("chost") / "fmu_host"
    subprocess.run([cc, "-O1", "-Wall", "-Werror", f"-I{HEADERS}", "-o", str(exe),
                    str(ROOT / "tests" / "chost" / "fmu_host.c"), "-ldl"], check=True, capture_output=True)
    return exe


@pytest.mark.parametrize("name", sorted(C_HOST_OUTPUT))
def test_a_c_host_loads_steps_and_frees_each_fmu(c_host: Path, tmp_path: Path, name: str) -> None:
    """The C host runs each FMU (built with --link-libpython) for 1 s at 20 Hz and gets, at every step, the
    value fmpy gets: the engine's thrust, the airframe's altitude, the FCS's fuel-flow command. The host
    runs in an environment emptied of everything but PATH and PYTHONPATH (this environment's
    site-packages, where the FMUs' packages are: a non-vendored FMU needs them), without LD_PRELOAD."""
    fmu = ensure_built(ROOT / "fmus", tmp_path, names=[name], link=True)[0]
    md = read_model_description(str(fmu))
    var = C_HOST_OUTPUT[name]
    vr = next(v.valueReference for v in md.modelVariables if v.name == var)
    unzipped = tmp_path / "unzipped"
    zipfile.ZipFile(fmu).extractall(unzipped)
    import sysconfig

    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": sysconfig.get_paths()["purelib"]}
    proc = subprocess.run([str(c_host), str(unzipped), md.coSimulation.modelIdentifier, md.guid, "0.05", "20",
                           str(vr)], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = np.array([[float(x) for x in ln.split()] for ln in proc.stdout.splitlines()])
    assert got.shape == (21, 2) and got[-1, 0] == pytest.approx(1.0)
    ours, _ = _simulate(Path(sys.executable), fmu, [var])
    np.testing.assert_allclose(got[:, 1], ours["values"][var], rtol=1e-12, atol=0, err_msg=var)
    assert np.all(np.isfinite(got[:, 1])) and np.ptp(got[:, 1]) >= 0.0
