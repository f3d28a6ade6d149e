"""The plugins' pre-run hook in emss run (orchestrator/cli/hooks.py, called by api.run): its lines are printed as
warnings before the run, with every component's FMU and the bound parameters (--set included); a hook that fails is one
warning line and the run goes ahead; --no-pre-run skips the hooks."""
from __future__ import annotations

import types
from pathlib import Path

import pytest

from openemss.orchestrator.cli import main as cli, hooks


def _plugin(name: str, hook: object) -> types.ModuleType:
    m = types.ModuleType(f"fake_{name}.plugin")
    m.pre_run = hook  # type: ignore[attr-defined]
    return m


def test_pre_run_lines_and_failures(oscillator: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    seen: dict[str, object] = {}

    def ok(components: dict, parameters: dict) -> list[str]:
        seen.update(components=dict(components), parameters=dict(parameters))
        return ["mass1 looks heavy"]

    def broken(components: dict, parameters: dict) -> list[str]:
        raise RuntimeError("boom")

    monkeypatch.setattr(hooks, "plugins", lambda: [_plugin("a", ok), _plugin("b", broken)])
    assert cli.main(["run", str(oscillator), "--stop-time", "0.5", "--out", str(tmp_path / "o"),
                     "--set", "mass2.kc_N_m=40"]) == 0
    err = capsys.readouterr().err
    assert "emss run: warning: mass1 looks heavy" in err
    assert "emss run: warning: pre-run hook 'fake_b' failed: internal error: RuntimeError: boom" in err
    assert set(seen["components"]) == {"mass1", "mass2"}  # type: ignore[arg-type]
    assert all(Path(f).suffix == ".fmu" for f in seen["components"].values())  # type: ignore[union-attr]
    assert seen["parameters"]["mass2.kc_N_m"] == 40.0  # type: ignore[index]
    assert cli.main(["run", str(oscillator), "--stop-time", "0.5", "--out", str(tmp_path / "p"), "--no-pre-run"]) == 0
    assert "looks heavy" not in capsys.readouterr().err
