"""The emss command: info, run options, JSON output."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import columns, table
from openemss.orchestrator.cli.main import main


def test_info_prints_components_connections_and_gauss_seidel_order(
        oscillator: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(oscillator)]) == 0
    out = capsys.readouterr().out
    assert "component mass1: resources/ForceDrivenMass.fmu" in out
    assert "mass2.f_c_N -> mass1.f_c_N" in out
    assert "Gauss-Seidel order: mass1 -> mass2" in out
    assert "cycle breaks): mass2 -> mass1" in out
    assert "mass2.kc_N_m = 50.0" in out  # from the component's .ssv file


def test_info_json(oscillator: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(oscillator), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["gauss_seidel_order"] == ["mass1", "mass2"]
    assert d["default_experiment"]["stop_time_s"] == 10.0


def test_run_records_selected_variables_with_wildcards(
        oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    rc = main(["run", str(oscillator), "--stop-time", "1", "--rate", "10", "--algorithm", "gauss-seidel",
               "--record", "mass1.x1_*,mass2.f_c_N", "--out", str(out), "--json"])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "completed" and summary["steps"] == 10 and summary["rows"] == 11
    assert columns(out) == ["time_s", "mass1.x1_start_m", "mass1.x1_m", "mass2.f_c_N"]
    assert list(table(out)["time_s"]) == pytest.approx([k * 0.1 for k in range(11)])
    run = json.loads((out / "run.json").read_text())
    assert run["algorithm"] == "gauss-seidel" and run["rate_hz"] == 10.0 and run["steps"] == 10
    assert set(run["step_statistics"]) == {"mass1", "mass2"}
    assert run["versions"]["fmpy"]


def test_time_is_t0_plus_k_h_without_drift(oscillator: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["run", str(oscillator), "--stop-time", "100", "--rate", "30", "--record", "mass1.x1_m",
                 "--out", str(out)]) == 0
    times = list(table(out)["time_s"])
    assert len(times) == 3001
    # k / 30 exactly as printed with 15 digits: an accumulated t += h would drift by ~1e-13 here
    assert all(abs(t - k / 30.0) <= 1e-12 * max(1.0, t) for k, t in enumerate(times))
    assert times[-1] == 100.0


@pytest.mark.parametrize("argv, fragment", [
    (["--step-multiple", "mass2"], "expected COMPONENT=N"),
    (["--step-multiple", "nobody=2"], "unknown component"),
    (["--record", "mass9.*"], "matches no variable"),
    (["--record-every", "0"], "must be an integer >= 1"),
    (["--algorithm", "newton"], "invalid choice"),
])
def test_bad_options_give_one_line(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                   argv: list[str], fragment: str) -> None:
    try:
        rc = main(["run", str(oscillator), "--out", str(tmp_path / "o"), *argv])
    except SystemExit as exc:  # argparse usage errors
        rc = exc.code
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert rc != 0 and len(err) == 1 and fragment in err[0], err


def _set_base_step(system: Path, step: str) -> None:
    ssd = system / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text().replace('baseStepSize="0.05"', f'baseStepSize="{step}"'))


def test_default_rate_comes_from_the_ssd_annotation(oscillator: Path, tmp_path: Path) -> None:
    _set_base_step(oscillator, "0.1")
    out = tmp_path / "out"
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(out)]) == 0
    run = json.loads((out / "run.json").read_text())
    assert run["rate_hz"] == pytest.approx(10.0) and run["steps"] == 10


def test_ssd_step_outside_the_allowed_rates_is_refused_unless_overridden(
        oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _set_base_step(oscillator, "0.001")
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "1000" in err[0] and "allowed: 0.1 to 100.0 Hz" in err[0]
    assert main(["run", str(oscillator), "--stop-time", "1", "--rate", "50", "--out", str(tmp_path / "b")]) == 0


def test_commands_come_only_through_the_plugin_entry_points(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """A module named by an entry point of ``openemss.plugins`` contributes its commands and its errors print as
    one line; the same module as a model package's ``cli`` without an entry point contributes nothing (the
    command scans no package), and the shipped commands are all entry points."""
    from importlib.metadata import EntryPoint

    import openemss.models as models
    from openemss.orchestrator.cli import plugins

    pkg = tmp_path / "zz_fake_model"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "cli.py").write_text(
        "class FakeError(Exception):\n    pass\n\n"
        "def _go(args):\n    if args.x < 0:\n        raise FakeError(f'x = {args.x} must be >= 0')\n"
        "    print('ok', args.x)\n    return 0\n\n"
        "def register(sub):\n    p = sub.add_parser('fake', help='a fake model command')\n"
        "    p.add_argument('--x', type=float, default=1.0)\n    p.set_defaults(handler=_go)\n"
        "    return (FakeError,)\n")
    shipped = {ep.name: ep.value for ep in plugins.entry_points(group=plugins.GROUP)}
    assert {"engine": "openemss.models.engine.cli", "airframe": "openemss.models.airframe.cli",
            "study": "openemss.study.cli", "report": "openemss.report.plugin"}.items() <= shipped.items(), \
        "the installed entry points are not pyproject.toml's: pip install -e . again"

    monkeypatch.setattr(models, "__path__", [*models.__path__, str(tmp_path)])
    monkeypatch.setattr(plugins, "_loaded", None)
    with pytest.raises(SystemExit):
        main(["fake", "--x", "2"])
    assert "invalid choice: 'fake'" in capsys.readouterr().err

    monkeypatch.syspath_prepend(str(tmp_path))
    real = plugins.entry_points
    fake = EntryPoint("fake", "zz_fake_model.cli", plugins.GROUP)
    monkeypatch.setattr(plugins, "entry_points", lambda group: [*real(group=group), fake])
    monkeypatch.setattr(plugins, "_loaded", None)
    try:
        assert main(["fake", "--x", "2"]) == 0
        assert capsys.readouterr().out.strip() == "ok 2.0"
        assert main(["fake", "--x", "-1"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err == ["emss fake: error: x = -1.0 must be >= 0"]
    finally:
        plugins._loaded = None  # the next command loads the real plugins again


def test_export_writes_one_fmu_and_refuses_what_the_container_cannot_do(
        oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import zipfile

    from fmpy.validation import validate_fmu

    out = tmp_path / "Oscillator.fmu"
    assert main(["export", str(oscillator), "--container", str(out)]) == 0
    assert "written as" in capsys.readouterr().out
    names = zipfile.ZipFile(out).namelist()
    assert "modelDescription.xml" in names and "resources/container.json" in names
    assert validate_fmu(str(out)) == []
    ssd = oscillator / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text().replace(
        '<ssd:Connection startElement="mass1" startConnector="x1_m" endElement="mass2" endConnector="x1_m"/>',
        '<ssd:Connection startElement="mass1" startConnector="x1_m" endElement="mass2" endConnector="x1_m">'
        '<ssc:LinearTransformation factor="2.0"/></ssd:Connection>'))
    assert main(["export", str(oscillator), "--container", str(tmp_path / "bad.fmu")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "mass1.x1_m -> mass2.x1_m" in err[0] and not (tmp_path / "bad.fmu").exists()


def test_set_overrides_a_parameter_and_is_kept_with_the_results(oscillator: Path, tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(oscillator), "--set", "mass2.kc_N_m=75"]) == 0
    assert "mass2.kc_N_m = 75.0" in capsys.readouterr().out  # over the component's .ssv (50)
    out = tmp_path / "out"
    assert main(["run", str(oscillator), "--stop-time", "0.5", "--set", "mass2.kc_N_m=75", "--out", str(out)]) == 0
    assert 'name="mass2.kc_N_m"' in (out / "cli_parameters.ssv").read_text()


@pytest.mark.parametrize("item, fragment", [("mass2.kc_N_m", "write component.variable=value"),
                                            ("mass2.nope=1", "no variable 'mass2.nope'"),
                                            ("mass2.kc_N_m=stiff", "not a valid Real value")])
def test_bad_set_is_one_line(oscillator: Path, tmp_path: Path, item: str, fragment: str,
                             capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(oscillator), "--set", item, "--out", str(tmp_path / "o")]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0], err


def test_run_without_a_system_flies_the_project_system(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The README's main command: no SYSTEM runs ssp/ (engine, airframe, FCS; the Munich mission), building
    its FMUs first if needed; here its first two seconds."""
    out = tmp_path / "run"
    assert main(["run", "--stop-time", "2", "--out", str(out), "--no-post-run"]) == 0
    assert "openEMSS: 40 steps" in capsys.readouterr().out
    head = columns(out)
    assert "engine.Fn_N" in head and "fcs.section_index" in head and "airframe.alt_m" in head
