"""Warm cases (issue 35 point 2): a worker's case process resets its FMUs between cases (fmi2Reset through the
master's instance pool) instead of a new process and new instances, and a case run warm is the case run cold.

The reference is independent of the pool: the same case as ``emss run`` in a process of its own, whose FMUs
are instantiated new. The warm case process first flies another case (another engine preset, so that every FMU
ends in another state), then the case twice; every recorded column must equal the cold run's bit for bit (NaN
where NaN), and run.json must say that the FMUs were reset, not instantiated.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from openemss.orchestrator.master import pool
from openemss.orchestrator.recording.timeseries import read_timeseries
from openemss.study.warm import CaseHost
from systems import Comp, write_system

MASS1 = [("f_c_N", "input", "Real"), ("x1_m", "output", "Real"), ("v1_m_s", "output", "Real")]
MASS2 = [("x1_m", "input", "Real"), ("v1_m_s", "input", "Real"), ("x2_m", "output", "Real"),
         ("f_c_N", "output", "Real")]
LINKS = [("mass1.x1_m", "mass2.x1_m"), ("mass1.v1_m_s", "mass2.v1_m_s"), ("mass2.f_c_N", "mass1.f_c_N")]

STOP_S = "20"  # [s] simulated: the engine's start and the take-off roll, every FMU well away from its start


def _args(system: Path, out: Path, *sets: str) -> list[str]:
    return ["run", str(system), "--out", str(out), "--stop-time", STOP_S, "--no-pre-run", "--no-figures",
            "--no-build", *(["--set", *sets] if sets else [])]


def test_a_warm_case_equals_the_same_case_run_cold(tmp_path: Path, project_system: Path) -> None:
    ref = ("engine.preset=reference_study",)
    cold = tmp_path / "cold"
    subprocess.run([sys.executable, "-m", "openemss.study.child", *_args(project_system, cold, *ref)], check=True,
                   capture_output=True, cwd=tmp_path)
    host = CaseHost(dict(os.environ))
    try:
        runs = {}
        for name, sets in (("other", ()), ("warm1", ref), ("warm2", ref)):
            folder = tmp_path / name
            folder.mkdir()
            assert host.run(_args(project_system, folder, *sets), folder) == 0, (folder / "stderr.log").read_text()
            runs[name] = folder
    finally:
        host.close()
    components = ("fcs", "engine", "airframe")
    assert json.loads((cold / "run.json").read_text())["instances"] == dict.fromkeys(components, "instantiated")
    assert json.loads((runs["other"] / "run.json").read_text())["instances"] == dict.fromkeys(components,
                                                                                             "instantiated")
    want = read_timeseries(cold).data
    assert len(want["time_s"]) == int(float(STOP_S) * 20) + 1
    for name in ("warm1", "warm2"):
        info = json.loads((runs[name] / "run.json").read_text())
        assert info["instances"] == dict.fromkeys(components, "reset")
        got = read_timeseries(runs[name]).data
        assert sorted(got) == sorted(want)
        differ = [k for k in want if not np.array_equal(got[k], want[k], equal_nan=True)]
        assert differ == [], f"{name}: columns not bit-identical to the cold run: {differ[:8]}"
    # the other case flew another engine: the comparison can tell the two apart
    other = read_timeseries(runs["other"]).data
    assert not np.array_equal(other["engine.Wf_kg_s"], want["engine.Wf_kg_s"])


def test_the_pool_is_off_unless_enabled_and_keeps_only_clean_instances(tmp_path: Path, fmu_dir: Path) -> None:
    """In this process: without the pool nothing is kept; with it, a run that ended cleanly leaves its instances
    and the next run resets them (same rows as a new instance's); a run that failed (the test FMU FailingClock
    raises at its fail_time_s) leaves none."""
    import openemss

    system = write_system(tmp_path / "osc_clock", fmu_dir, [Comp("mass1", "ForceDrivenMass.fmu", MASS1),
                                                            Comp("mass2", "DisplacementDrivenMass.fmu", MASS2),
                                                            Comp("clock", "FailingClock.fmu",
                                                                 [("clock_s", "output", "Real")])],
                          LINKS, name="OscillatorWithClock", stop_time=1.0)
    never = {"clock.fail_time_s": 100.0}
    assert not pool.enabled()
    cold = openemss.run(system, out=tmp_path / "a", set=never, post_run=False)
    assert pool.counts()["held"] == 0 and set(cold.info["instances"].values()) == {"instantiated"}
    pool.enable()
    try:
        first = openemss.run(system, out=tmp_path / "b", set=never, post_run=False)
        assert pool.counts()["held"] == 3 and set(first.info["instances"].values()) == {"instantiated"}
        second = openemss.run(system, out=tmp_path / "c", set=never, post_run=False)
        assert set(second.info["instances"].values()) == {"reset"} and pool.counts()["held"] == 3
        want = cold.timeseries.data
        assert len(want["time_s"]) > 10
        for k, v in want.items():
            assert np.array_equal(v, second.timeseries.data[k], equal_nan=True), k
        failed = openemss.run(system, out=tmp_path / "d", set={"clock.fail_time_s": 0.5}, post_run=False)
        assert failed.status == "failed" and pool.counts()["held"] == 0
    finally:
        pool.enable(False)
    assert pool.counts()["held"] == 0


def test_a_study_file_asks_for_checks_and_figures_per_case(tmp_path: Path) -> None:
    """pre_run and figures (study file) become emss run's options; neither changes a case's digest (its results)."""
    from openemss.study.case import emss_args
    from openemss.study.plan import expand_cases
    from openemss.study.spec import load_study

    osc = Path(__file__).resolve().parents[2] / "examples" / "oscillator"
    digests, args = [], []
    for extra in ("", "pre_run: true\nfigures: true\n"):
        path = tmp_path / f"s{len(extra)}.yaml"
        path.write_text(f"study: s\nsystem: {osc}\nstop_time_s: 1\n{extra}", encoding="utf-8")
        (case,) = expand_cases(load_study(path))
        digests.append(case.digest)
        args.append(emss_args(case, tmp_path))
    assert digests[0] == digests[1]
    assert {"--no-pre-run", "--no-figures", "--no-build"} <= set(args[0])
    assert "--no-pre-run" not in args[1] and "--no-figures" not in args[1] and "--no-build" in args[1]
