"""Exit codes (issue 38 point 2): one table, kept by every kind of ending, and never a count.

Each kind of ending is provoked on the oscillator example (a valid run, bad input, a run whose FMU fails
mid-run, an internal error, a validate finding) and its exit code compared with the README's table, which
must be the table the code defines (``orchestrator/exit_codes.py``); ``emss --version`` prints the
installed distribution's version (read back through ``importlib.metadata``, not from our own constant).
"""
from __future__ import annotations

import importlib.metadata
import re
import subprocess
import sys
from pathlib import Path

import pytest

from openemss.orchestrator.cli import main as cli_main
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.exit_codes import MEANINGS, ExitCode, markdown_table

ROOT = Path(__file__).resolve().parents[1]


def _last_err_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) >= 1
    return err[-1]


def test_the_readme_shows_the_table_the_commands_use() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert markdown_table() in readme
    codes = [int(c) for c in re.findall(r"^\| (\d) \|", markdown_table(), flags=re.M)]
    assert codes == sorted(set(codes)) == [int(c) for c in MEANINGS]  # each code once, in order


def test_version_and_help_show_what_is_installed() -> None:
    proc = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "--version"], capture_output=True,
                          text=True, timeout=120, check=False)
    assert proc.returncode == 0 and proc.stdout.strip() == f"emss (openEMSS) {importlib.metadata.version('openemss')}"
    proc = subprocess.run([sys.executable, "-m", "openemss.orchestrator.cli", "--help"], capture_output=True,
                          text=True, timeout=120, check=False)
    assert proc.returncode == 0
    for code in MEANINGS:
        assert re.search(rf"^  {int(code)}  ", proc.stdout, flags=re.M), proc.stdout


def test_each_ending_has_its_own_code(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                      monkeypatch: pytest.MonkeyPatch) -> None:
    assert main(["run", str(oscillator), "--stop-time", "1", "--out", str(tmp_path / "ok")]) == ExitCode.OK
    capsys.readouterr()
    assert main(["run", str(oscillator), "--rate", "1000", "--out", str(tmp_path / "bad")]) == ExitCode.USAGE
    assert "allowed" in _last_err_line(capsys)
    with pytest.raises(SystemExit) as exc:
        main(["run", "--no-such-option"])
    assert exc.value.code == ExitCode.USAGE
    capsys.readouterr()
    def broken(args: object) -> int:
        raise ZeroDivisionError("a defect")

    monkeypatch.setattr(cli_main, "cmd_info", broken)
    monkeypatch.delenv("EMSS_DEBUG", raising=False)
    assert main(["info", str(oscillator)]) == ExitCode.INTERNAL
    assert "internal error" in _last_err_line(capsys)


def test_a_failed_run_is_not_bad_input(oscillator: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """An FMU's error while the master steps (played by the test from the third step on) exits FAILED, with
    what was recorded kept."""
    from openemss.orchestrator.errors import SlaveError
    from openemss.orchestrator.master import execution

    def failing(real):  # type: ignore[no-untyped-def]  # both ways an algorithm steps a component
        def step(self: execution.Execution, i: int, k: int) -> None:
            if k >= 3:
                raise SlaveError("mass1", "fmi2DoStep", self.time_at(k), "the test's failure")
            real(self, i, k)
        return step

    for name in ("step_component", "advance"):
        monkeypatch.setattr(execution.Execution, name, failing(getattr(execution.Execution, name)))
    out = tmp_path / "failed"
    code = main(["run", str(oscillator), "--stop-time", "1", "--out", str(out)])
    line = _last_err_line(capsys)
    assert code == ExitCode.FAILED and "the test's failure" in line, line
    assert (out / "run.json").is_file()


def test_validate_exits_1_whatever_the_count(oscillator: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Four problems were exit code 4 (now the internal error's code): findings are 1, the count printed."""
    ssd = oscillator / "SystemStructure.ssd"
    text = ssd.read_text(encoding="utf-8")
    broken = re.sub(r'endConnector="[^"]+"', 'endConnector="nothing"', text)
    assert broken != text
    ssd.write_text(broken, encoding="utf-8")
    code = main(["validate", str(oscillator)])
    captured = capsys.readouterr()
    problems = [ln for ln in captured.out.splitlines() if ln.strip()]
    assert code == ExitCode.FINDINGS and len(problems) >= 2, captured
    assert f"{len(problems)} problem(s) found" in captured.err
