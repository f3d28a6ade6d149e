"""The distribution installs every sub-package of the repository's folders."""
from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_every_package_folder_is_listed_in_pyproject() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    on_disk = set()
    mapped = {(ROOT / folder).resolve() for folder in config["package-dir"].values()}
    for namespace, folder in config["package-dir"].items():
        for init in (ROOT / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / folder).parts
            if rel and init.parent.resolve() in mapped:  # a folder mapped to a package of its own
                continue
            on_disk.add(".".join((namespace, *rel)))
    assert on_disk == listed, {"missing from pyproject": on_disk - listed, "not on disk": listed - on_disk}


def test_console_scripts_resolve() -> None:
    import importlib

    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert set(scripts) == {"emss", "build-fmus"}
    for target in scripts.values():
        module, func = target.split(":")
        assert callable(getattr(importlib.import_module(module), func))


def test_a_normal_install_flies_the_mission(tmp_path: Path) -> None:
    """Issue 16 point 6: ``pip install .`` (a wheel, not editable) into a fresh venv, then ``emss run`` from
    an empty folder flies the Munich mission's first seconds: the system, missions, scenarios and studies
    travel in the wheel. Offline: the wheel is built by this environment's setuptools
    (``--no-build-isolation``), the fresh venv reaches the dependencies through a ``.pth`` file naming this
    environment's site-packages (a plain path: the editable install's finder there is not run, so only the
    wheel's openemss can be imported) and pip installs the wheel with ``--no-deps --no-index``."""
    import json
    import subprocess
    import sys
    import sysconfig
    import venv
    import zipfile

    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index", "-q",
                    str(ROOT), "-w", str(wheels)], check=True, capture_output=True)
    wheel = next(wheels.glob("openemss-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    for f in ("openemss/ssp/SystemStructure.ssd", "openemss/missions/munich.yaml",
              "openemss/scenarios/stuck_rudder.yaml", "openemss/studies/engine_redesign.yaml",
              "openemss/examples/oscillator/SystemStructure.ssd"):
        assert f in names, f
    env = tmp_path / "venv"
    venv.create(env, with_pip=False)
    py = env / "bin" / "python"
    purelib = subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             check=True, capture_output=True, text=True).stdout.strip()
    Path(purelib, "deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    subprocess.run([sys.executable, "-m", "pip", "--python", str(py), "install", "--no-deps", "--no-index", "-q",
                    str(wheel)], check=True, capture_output=True)
    where = subprocess.run([str(py), "-c", "import openemss.orchestrator as o; print(o.__file__)"],
                           check=True, capture_output=True, text=True).stdout.strip()
    assert where.startswith(purelib), where
    work = tmp_path / "work"
    work.mkdir()
    proc = subprocess.run([str(env / "bin" / "emss"), "run", "--stop-time", "20", "--out", "results/demo",
                           "--format", "csv", "--no-post-run", "--json"], cwd=work, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr[-2000:]
    rows = (work / "results" / "demo" / "timeseries.csv").read_text().splitlines()
    head = rows[0].split(",")
    last = dict(zip(head, rows[-1].split(","), strict=True))
    assert float(last["time_s"]) == 20.0 and float(last["airframe.gs_m_s"]) > 30.0  # rolling for take-off
    assert json.loads((work / "results" / "demo" / "run.json").read_text())["status"] == "completed"
