"""Commands that chain (issue 17): ``emss plot RUN VAR`` for any system, ``emss info --parameters``, ``--params``
before SYSTEM, ``emss info`` without SYSTEM, ``emss engine sweep --out DIR``."""
from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

from openemss.orchestrator.cli.main import main


def test_plot_variables_of_any_system(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = tmp_path / "osc"
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(run)]) == 0
    assert main(["plot", str(run), "mass1.x1_m", "mass2.f_c_N"]) == 0
    assert (run / "plot_mass1-x1_m_mass2-f_c_N.png").is_file()
    page = (run / "plot_mass1-x1_m_mass2-f_c_N.html").read_text()
    assert "mass2.f_c_N [N]" in page
    assert main(["plot", str(run)]) == 0  # no mission: every recorded column (4 here)
    assert (run / "variables.png").is_file()
    capsys.readouterr()
    assert main(["plot", str(run), "mass1.x_1m"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you mean mass1.x1_m" in err[0]


def test_info_parameters_lists_every_parameter_of_the_fmus(oscillator: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(oscillator), "--parameters", "--json"]) == 0
    rows = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    expected = {}
    for fmu in sorted((oscillator / "resources").glob("*.fmu")):
        root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
        comp = {"ForceDrivenMass": "mass1", "DisplacementDrivenMass": "mass2"}[root.attrib["modelName"]]
        for sv in root.iter("ScalarVariable"):
            if sv.attrib.get("causality") == "parameter":
                expected[f"{comp}.{sv.attrib['name']}"] = next(iter(sv)).attrib.get("start")
    assert set(rows) == set(expected)
    for name, start in expected.items():
        assert str(rows[name]["default"]) == str(float(start)) or str(rows[name]["default"]) == start
    assert rows["mass1.x1_start_m"]["unit"] == "m" and rows["mass1.x1_start_m"]["type"] == "Real"


def test_params_does_not_swallow_the_system(oscillator: Path, tmp_path: Path) -> None:
    ssv = tmp_path / "m.ssv"
    ssv.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/'
                   'SSP1/SystemStructureParameterValues" version="1.0" name="m"><ssv:Parameters><ssv:Parameter '
                   'name="mass1.x1_start_m"><ssv:Real value="0.2"/></ssv:Parameter></ssv:Parameters>'
                   '</ssv:ParameterSet>\n')
    assert main(["run", "--params", str(ssv), str(oscillator), "--stop-time", "0.2",
                 "--out", str(tmp_path / "o")]) == 0
    info = json.loads((tmp_path / "o" / "run.json").read_text())
    assert info["parameter_files"] == [str(ssv)] and info["parameters"]["mass1.x1_start_m"] == 0.2


def test_info_defaults_to_the_project_system(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", "--json"]) == 0
    names = {c["name"] for c in json.loads(capsys.readouterr().out)["components"]}
    assert names == {"engine", "airframe", "fcs"}


def test_engine_sweep_creates_its_folder_and_writes_nothing_else(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["engine", "sweep", "--out", "deep/sweep", "--bpr", "1.0", "--opr", "10", "12"]) == 0
    assert sorted(os.listdir(tmp_path)) == ["deep"]
    assert sorted(os.listdir(tmp_path / "deep" / "sweep")) == ["carpet.csv", "carpet.png"]


def test_study_cases_counts_the_redesign_engines(capsys: pytest.CaptureFixture[str]) -> None:
    import yaml

    study = Path(__file__).resolve().parents[1] / "studies" / "engine_redesign.yaml"
    missions = yaml.safe_load(study.read_text())["missions"]
    assert main(["study", "cases", str(study), "--json"]) == 0
    cases = json.loads(capsys.readouterr().out)
    assert len(cases) == 2 * len(missions)  # the baseline and the redesigned engine, per mission
    assert {c["labels"]["variant"] for c in cases} == {"baseline", "redesigned"}


def test_build_fmus_builds_where_emss_run_looks(monkeypatch: pytest.MonkeyPatch) -> None:
    from openemss.orchestrator.cli.api import DEFAULT_SYSTEM
    from openemss.orchestrator.fmu import build

    seen: list[Path] = []
    monkeypatch.setattr(build, "ensure_built", lambda src, out, *a, **k: seen.append(out) or [])
    build.main([])
    assert seen == [DEFAULT_SYSTEM / "resources"]
