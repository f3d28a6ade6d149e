"""orchestrator/README.md's examples run as written, in order (house rule), and give the right answers."""
from __future__ import annotations

import contextlib
import io
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "orchestrator" / "README.md"


def blocks(kind: str) -> list[str]:
    return re.findall(rf"```{kind}\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_the_readme_examples_run_in_order(tmp_path: Path, fmu_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # The shell steps: the test of the worked example (run by pytest itself) and building the oscillator's
    # FMUs, which the session has built already (fmu_dir) into the same place.
    assert [b.strip() for b in blocks("bash")] == [
        "pytest tests/test_iterative.py -q",
        "build-fmus --src examples/oscillator/fmus --out examples/oscillator/resources"]
    example = tmp_path / "examples" / "oscillator"
    (example / "resources").mkdir(parents=True)
    for f in ("SystemStructure.ssd", "mass2.ssv"):
        shutil.copy2(ROOT / "examples" / "oscillator" / f, example / f)
    for f in ("ForceDrivenMass.fmu", "DisplacementDrivenMass.fmu"):
        shutil.copy2(fmu_dir / f, example / "resources" / f)
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "readme"}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        for code in blocks("python"):
            exec(compile(code, str(README), "exec"), namespace)  # noqa: S102 - the README's own examples
    printed = out.getvalue()
    # the worked algorithm: the loop's input at the analytic fixed point (rtol 1e-8 of the convergence test)
    loop, fixed = namespace["loop"], namespace["fixed_point"]
    assert abs(loop.u[0][0] - fixed) < 1e-8 * abs(fixed) + 1e-10  # type: ignore[attr-defined]
    assert "gauss-seidel-iterative - Gauss-Seidel with every loop" in printed
    # the worked observer: the same run repeated with a recorder has the same peak at the same time
    peak = namespace["peak"]
    ex = Execution(bind_system(load_system("examples/oscillator")), "gauss-seidel", rate_hz=100.0,
                   record=["mass2.x2_m"])
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(10.0)
    r = rec.result()
    j = int(np.argmax(np.abs(r["mass2.x2_m"])))
    assert peak.value == abs(r["mass2.x2_m"][j]) > 0 and peak.time_s == r["time_s"][j]  # type: ignore[attr-defined]
    assert f"peaks at {peak.value:.4f} m" in printed  # type: ignore[attr-defined]
