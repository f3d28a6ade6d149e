"""Every example of the README runs as written, in order (issue 17), in a fresh working folder.

The README's ``bash`` blocks (except the Quick start's install and test commands, and the lines that
show a syntax with placeholders such as ``STUDY.yaml`` or ``tcp://host``) run one after the other as
``emss`` commands, and its ``python`` blocks that hold no ``...`` run in one interpreter. One change,
to keep the test suite short: a whole-mission ``emss run`` gets ``--stop-time 950`` (the first 950 s
of the mission: enough for the README's ``--window 600 900``), an ``emss study run`` ``--stop-time
120`` (every case of the study still runs, each for its first two minutes); everything else is as
written. Each command must exit 0 and the files the README names must be there.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PLACEHOLDERS = ("STUDY.yaml", "tcp://host", "[--", "pip install", "pytest")
STOP_S = "950"
STUDY_STOP_S = "120"


def readme_blocks(kind: str) -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return [m.group(1) for m in re.finditer(rf"```{kind}\n(.*?)```", text, re.S)]


def readme_commands() -> list[list[str]]:
    out = []
    for block in readme_blocks("bash"):
        for line in block.splitlines():
            line = line.split("  #", 1)[0].strip()
            if not line or any(p in line for p in PLACEHOLDERS):
                continue
            argv = shlex.split(line)
            if argv[:2] == ["emss", "run"] and "--stop-time" not in argv:
                argv += ["--stop-time", STOP_S]
            elif argv[:3] == ["emss", "study", "run"] and "--stop-time" not in argv:
                argv += ["--stop-time", STUDY_STOP_S]
            out.append(argv)
    return out


def test_the_readme_examples_run_in_order(tmp_path: Path) -> None:
    for name in ("ssp", "studies", "missions", "scenarios", "examples"):
        (tmp_path / name).symlink_to(ROOT / name)
    commands = readme_commands()
    assert ["emss", "run", "--out", "results/demo", "--stop-time", STOP_S] in commands
    env = dict(os.environ, MPLBACKEND="Agg")
    bindir = Path(sys.executable).parent
    for argv in commands:
        exe = str(bindir / argv[0]) if (bindir / argv[0]).exists() else argv[0]
        proc = subprocess.run([exe, *argv[1:]], cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=1800, check=False)
        assert proc.returncode == 0, (argv, proc.stderr[-3000:])
    demo = tmp_path / "results" / "demo"
    for name in ("timeseries.parquet", "run.json", "summary.json", "report.html", "thrust.png"):
        assert (demo / name).exists(), name
    assert (demo / "compare_redesign" / "report.html").is_file()
    assert (tmp_path / "results" / "demo-csv" / "timeseries.csv").is_file()
    assert (tmp_path / "results" / "study-engine_redesign" / "compare_baseline-munich_redesigned-munich"
            / "report.html").is_file()
    for block in readme_blocks("python"):
        if "..." in block:
            continue
        proc = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, env=env, capture_output=True,
                              text=True, timeout=1800, check=False)
        assert proc.returncode == 0, (block, proc.stderr[-3000:])
