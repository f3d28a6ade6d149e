"""The bad-input corpus: each bad system or option gives one clear line and a non-zero exit.

Every message must say what is wrong and where (file:line or component.variable),
and nothing may print a traceback.
"""
from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main
from systems import GAIN_CONNECTORS, Comp, write_ssv, write_system


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    rc = main(list(argv))
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    return rc, err


def gain(name: str, **params: float) -> Comp:
    return Comp(name, "Gain.fmu", GAIN_CONNECTORS, dict(params))


def good_system(folder: Path, fmu_dir: Path) -> Path:
    write_system(folder, fmu_dir, [gain("a"), gain("b")],
                 [("a.y_real", "b.u_real"), ("b.y_real", "a.u_real")], stop_time=1.0)
    return folder


def assert_one_clear_line(rc: int, err: list[str], *fragments: str) -> None:
    assert rc != 0
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    for f in fragments:
        assert f in err[0], (f, err[0])


def test_good_system_runs(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    rc = main(["run", str(system), "--out", str(tmp_path / "out")])
    assert rc == 0, capsys.readouterr().err


def test_malformed_xml(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    ssd = system / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text()[:-60])
    rc, err = run_cli(capsys, "run", str(system))
    assert_one_clear_line(rc, err, "malformed XML", "SystemStructure.ssd:")


def test_schema_invalid_ssd(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    ssd = system / "SystemStructure.ssd"
    ssd.write_text(ssd.read_text().replace('kind="input"', 'kind="sideways"', 1))
    rc, err = run_cli(capsys, "run", str(system))
    assert_one_clear_line(rc, err, "not valid against the SSP 1.0 schema", "SystemStructure.ssd:", "sideways")


def test_missing_fmu_file(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [gain("a"), Comp("b", "Missing.fmu", GAIN_CONNECTORS)], [], stop_time=1.0)
    rc, err = run_cli(capsys, "run", str(folder))
    assert_one_clear_line(rc, err, "component 'b'", "resources/Missing.fmu", "not found", "SystemStructure.ssd:")


def test_connector_not_in_fmu(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS + [("Fn_N", "output", "Real")])], [],
                 stop_time=1.0)
    rc, err = run_cli(capsys, "run", str(folder))
    assert_one_clear_line(rc, err, "'a.Fn_N'", "not a variable", "SystemStructure.ssd:")


def test_type_mismatch_on_connection(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [gain("a"), gain("b")], [("a.y_int", "b.u_real")], stop_time=1.0)
    rc, err = run_cli(capsys, "run", str(folder))
    assert_one_clear_line(rc, err, "a.y_int -> b.u_real", "type mismatch, Integer to Real")


def test_two_connections_into_one_input(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [gain("a"), gain("b"), gain("c")],
                 [("a.y_real", "c.u_real"), ("b.y_real", "c.u_real")], stop_time=1.0)
    rc, err = run_cli(capsys, "run", str(folder))
    assert_one_clear_line(rc, err, "'c.u_real' has two incoming connections")


def test_connection_from_an_input(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [gain("a"), gain("b")], [("a.u_real", "b.u_real")], stop_time=1.0)
    rc, err = run_cli(capsys, "run", str(folder))
    assert_one_clear_line(rc, err, "the start must be an output")


@pytest.mark.parametrize("rate", ["0.05", "200", "0", "-20", "nan"])
def test_rate_out_of_range(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str], rate: str) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    rc, err = run_cli(capsys, "run", str(system), "--rate", rate, "--out", str(tmp_path / "out"))
    assert_one_clear_line(rc, err, "out of range", "allowed: 0.1 to 100.0 Hz")


def test_unknown_parameter(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    ssv = write_ssv(tmp_path / "p.ssv", {"a.kk": 2.0})
    rc, err = run_cli(capsys, "run", str(system), "--params", str(ssv))
    assert_one_clear_line(rc, err, "parameter 'a.kk'", "has no variable 'kk'", "p.ssv:")


def test_parameter_of_wrong_type(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    ssv = write_ssv(tmp_path / "p.ssv", {"a.k": True})
    rc, err = run_cli(capsys, "run", str(system), "--params", str(ssv))
    assert_one_clear_line(rc, err, "parameter 'a.k'", "Boolean value for a Real variable")


def _archive(path: Path, system: Path, extra: dict[str, bytes]) -> Path:
    with zipfile.ZipFile(path, "w") as zf:
        for f in system.rglob("*"):
            if f.is_file():
                zf.write(f, f.relative_to(system).as_posix())
        for name, data in extra.items():
            zf.writestr(name, data)
    return path


@pytest.mark.parametrize("entry", ["../escaped.txt", "resources/../../escaped.txt", "/tmp/emss_absolute_escape.txt"])
def test_archive_with_escaping_entries(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str],
                                       entry: str) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    work = tmp_path / "work"
    work.mkdir()
    archive = _archive(work / "evil.ssp", system, {entry: b"must not be written"})
    rc, err = run_cli(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    assert_one_clear_line(rc, err, "unsafe archive entry", entry.lstrip("/"))
    assert not (tmp_path / "escaped.txt").exists() and not (work.parent.parent / "escaped.txt").exists()
    assert not Path("/tmp/emss_absolute_escape.txt").exists()


def test_good_archive_runs(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    archive = _archive(tmp_path / "good.ssp", system, {})
    rc = main(["run", str(archive), "--out", str(tmp_path / "out")])
    assert rc == 0, capsys.readouterr().err
    assert (tmp_path / "out" / "timeseries.parquet" / "part-00000.parquet").is_file()


def test_not_a_zip(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bogus = tmp_path / "bogus.ssp"
    bogus.write_text("not a zip")
    rc, err = run_cli(capsys, "run", str(bogus))
    assert_one_clear_line(rc, err, "not a readable .ssp")


def test_validate_lists_every_problem_counts_them_and_exits_1(
        tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "sys"
    write_system(folder, fmu_dir, [gain("a"), gain("b"), gain("c"), Comp("d", "Missing.fmu", GAIN_CONNECTORS)],
                 [("a.y_int", "b.u_real"),                          # type mismatch
                  ("a.y_real", "c.u_real"), ("b.y_real", "c.u_real"),  # two into one input
                  ("a.y_bool", "x.u_bool")],                       # no such component
                 stop_time=1.0)
    rc = main(["validate", str(folder)])
    captured = capsys.readouterr()
    out, err = captured.out.strip().splitlines(), captured.err
    assert rc == 1 and len(out) == 4 and "4 problem(s)" in err, (out, err)
    joined = "\n".join(out)
    for fragment in ("type mismatch", "two incoming connections", "no element 'x'", "Missing.fmu"):
        assert fragment in joined


def test_validate_a_good_system_exits_zero(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    assert main(["validate", str(system)]) == 0


def test_the_installed_command_prints_one_line_and_no_traceback(tmp_path: Path, fmu_dir: Path) -> None:
    system = good_system(tmp_path / "sys", fmu_dir)
    proc = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "run", str(system), "--rate", "1000"],
                          capture_output=True, text=True)
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert proc.returncode != 0 and len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
