"""Two-mass oscillator split into two FMUs (force/displacement coupling) against its exact solution.

The monolithic system is linear, so x(t) = expm(A t) x0 is exact. Each FMU also
steps exactly (matrix exponential with its inputs held), so the only error is the
coupling error of the master algorithm: zero-order-hold coupling makes both
Jacobi and Gauss-Seidel first-order in the communication step h. Gauss-Seidel
uses the new displacement of mass 1 in the same step, so its error is smaller.

References
----------
Schweizer, B., Li, P., Lu, D. (2015). Explicit and implicit cosimulation methods:
stability and convergence analysis for different solver coupling approaches.
J. Comput. Nonlinear Dynam. 10(5). (the two-mass oscillator as coupling benchmark)
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from systems import write_ssv

# Natural frequencies about 2 and 4 rad/s: at 12.5 to 100 Hz the coupling is in its asymptotic range.
P = dict(m1=1.0, k1=4.0, d1=0.1, m2=1.0, k2=4.0, d2=0.1, kc=5.0, dc=0.1, x1=0.1, v1=0.0, x2=-0.05, v2=0.0)
STOP_S = 4.0


def exact(t: np.ndarray) -> np.ndarray:
    """x1(t) [m] of the monolithic two-mass oscillator."""
    m1, m2, k1, k2, d1, d2, kc, dc = (P[k] for k in ("m1", "m2", "k1", "k2", "d1", "d2", "kc", "dc"))
    a = np.array([
        [0, 1, 0, 0],
        [-(k1 + kc) / m1, -(d1 + dc) / m1, kc / m1, dc / m1],
        [0, 0, 0, 1],
        [kc / m2, dc / m2, -(k2 + kc) / m2, -(d2 + dc) / m2],
    ])
    x0 = np.array([P["x1"], P["v1"], P["x2"], P["v2"]])
    return np.array([(expm(a * ti) @ x0)[0] for ti in t])


def params_file(folder: Path) -> Path:
    return write_ssv(folder / "test_params.ssv", {
        "mass1.m1_kg": P["m1"], "mass1.k1_N_m": P["k1"], "mass1.d1_N_s_m": P["d1"],
        "mass1.x1_start_m": P["x1"], "mass1.v1_start_m_s": P["v1"],
        "mass2.m2_kg": P["m2"], "mass2.k2_N_m": P["k2"], "mass2.d2_N_s_m": P["d2"],
        "mass2.kc_N_m": P["kc"], "mass2.dc_N_s_m": P["dc"],
        "mass2.x2_start_m": P["x2"], "mass2.v2_start_m_s": P["v2"]})


def run(system: Path, rate_hz: float, algorithm: str, multiples: dict[str, int] | None = None) \
        -> dict[str, np.ndarray]:
    bound = bind_system(load_system(system), [params_file(system)])
    ex = Execution(bound, rate_hz=rate_hz, algorithm=algorithm, multiples=multiples)
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(STOP_S)
    return rec.result()


def max_error(result: dict[str, np.ndarray]) -> float:
    return float(np.max(np.abs(result["mass1.x1_m"] - exact(result["time_s"]))))


RATES_HZ = (12.5, 25.0, 50.0, 100.0)


@pytest.fixture(scope="module")
def errors(tmp_path_factory: pytest.TempPathFactory, fmu_dir: Path) -> dict[str, list[float]]:
    import shutil

    from conftest import OSCILLATOR

    folder = tmp_path_factory.mktemp("osc")
    (folder / "resources").mkdir()
    for f in ("SystemStructure.ssd", "mass2.ssv"):
        shutil.copy2(OSCILLATOR / f, folder / f)
    for f in ("ForceDrivenMass.fmu", "DisplacementDrivenMass.fmu"):
        shutil.copy2(fmu_dir / f, folder / "resources" / f)
    return {alg: [max_error(run(folder, r, alg)) for r in RATES_HZ] for alg in ("jacobi", "gauss-seidel")}


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_global_error_is_first_order_in_the_step(errors: dict[str, list[float]], algorithm: str) -> None:
    e = errors[algorithm]
    orders = [np.log2(e[i] / e[i + 1]) for i in range(len(e) - 1)]
    # Zero-order-hold coupling is first order: halving h halves the error (0.9..1.2 allows for
    # the remaining pre-asymptotic terms).
    assert all(0.9 < p < 1.2 for p in orders), (algorithm, e, orders)
    assert e[-1] < 0.1 * P["x1"], e  # and the error is small against the 0.1 m amplitude at 100 Hz


def test_gauss_seidel_is_more_accurate_than_jacobi(errors: dict[str, list[float]]) -> None:
    for ej, eg in zip(errors["jacobi"], errors["gauss-seidel"], strict=False):
        assert eg < ej, errors


def test_step_multiple_steps_less_often_with_the_coarser_coupling_error(
        oscillator: Path, errors: dict[str, list[float]]) -> None:
    bound = bind_system(load_system(oscillator), [params_file(oscillator)])
    ex = Execution(bound, rate_hz=100.0, algorithm="jacobi", multiples={"mass2": 2})
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(STOP_S)
    stats = ex.stats()
    assert stats["mass1"]["steps"] == 400 and stats["mass2"]["steps"] == 200
    # The coupling force now changes only every 0.02 s: the coupling error is that of 50 Hz
    # exchange (within 10 %), clearly above that of 100 Hz.
    err = max_error(rec.result())
    e_50, e_100 = errors["jacobi"][2], errors["jacobi"][3]
    assert err > 1.5 * e_100 and abs(err - e_50) < 0.1 * e_50, (e_100, err, e_50)
