"""The one gas path (:func:`openemss.models.engine.gas_path.turbofan`) with and without compilation.

Every off-design, transient and design calculation of the turbofan evaluates the same function; numba
compiles it where it is installed, and without numba (``OPENEMSS_NO_JIT=1``) the same source runs as
plain Python. The two runs must give the same residuals, stations and outputs to rounding (libm's and
numba's elementary functions may differ in the last bit), over random unknowns around matched points, at
flight conditions over the envelope, with shaft ports, bleeds, a booster and inlet distortion, and must
refuse (an error code) at the same points. The transient's compiled chord iteration is compared with the
Python iteration on the same steps.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from openemss.models.engine import jit_kernels
from openemss.models.engine.engine_model import BleedValve, EngineInputs, EngineModel
from openemss.models.engine.gas_path import OUT

pytestmark = pytest.mark.skipif(not jit_kernels.AVAILABLE, reason="numba not importable")


@pytest.fixture(scope="module")
def model() -> EngineModel:
    return EngineModel("larzac04_sls")

#: Evaluates the gas path on a fixed, seeded set of points and prints them as JSON (run in both modes).
_CASES = """
import json, math
import numpy as np
from openemss.models.engine import jit_kernels
from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.distortion import Distortion
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps, _dist_array
from openemss.models.engine.jit_cycle import DEMAND
out = {"compiled": jit_kernels.AVAILABLE, "cases": []}
rng = np.random.default_rng(7)
for preset in ("larzac04_sls", "pycycle_hbtf"):
    dp = design(load_params(preset_path(preset)))
    od = TurbofanOffDesign(dp, scaled_maps(dp))
    conds = [(0.0, 0.0, 0.0), (5000.0, 0.6, 0.0), (7500.0, 0.75, 10.0), (1000.0, 0.3, -15.0)]
    if preset == "pycycle_hbtf":
        conds = [(dp.params.alt_m, dp.params.Mach, 0.0)]
    dists = [(None, None), (Distortion(0.25, 0.1, 10.0), None), (None, Distortion(0.1, 0.05)),
             (Distortion(0.3, 0.08), Distortion(0.2, 0.04, 20.0))]
    for cond in conds:
        pt = od.solve(*cond, N1_pct=90.0)
        for k in range(24):
            dist = dists[k % 4]
            x0 = list(pt.x) + [pt.x[1]] * (dist[0] is not None) + [pt.x[2]] * (dist[1] is not None)
            x = np.array(x0) * (1.0 + (0.08 * rng.standard_normal(len(x0)) if k > 3 else 0.0))
            demand = [("Wf_kg_s", 0.1), ("N1_rpm", 15000.0), ("N1c_rpm", 16000.0), ("Tt4_K", 1200.0),
                      ("Fn_N", 5000.0)][k % 5]
            extras = (0.02 * (k % 3), 2e4 * (k % 2), -1e4 * (k % 4 == 1))
            hb = (None, 0.08, 0.0)[k % 3]
            fc = od.fast
            code = fc.evaluate(x, cond, (DEMAND[demand[0]], demand[1]), extras, hb, _dist_array(dist), True)
            out["cases"].append(dict(preset=preset, code=code, r=fc.r[:x.size].tolist(), o=fc.o.tolist(),
                                     S=fc.S.tolist(), PW=fc.PW.tolist()))
out["designs"] = []
for preset in ("larzac04_sls", "pycycle_hbtf", "reference_study"):
    d = design(load_params(preset_path(preset)))
    out["designs"].append([d.Fn_N, d.Wf_kg_s, d.components["hpt"].PR, d.components["lpt"].PR]
                          + [v for s in d.stations.values() for v in (s.W_kg_s, s.Tt_K, s.Pt_Pa, s.FAR)])
print(json.dumps(out))
"""


def _run_cases(no_jit: bool) -> dict[str, Any]:
    env = dict(os.environ)
    env.pop("OPENEMSS_NO_JIT", None)
    if no_jit:
        env["OPENEMSS_NO_JIT"] = "1"
    res = subprocess.run([sys.executable, "-c", _CASES], env=env, capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_gas_path_compiled_equals_plain_python() -> None:
    """The same source compiled and as plain Python: residuals, stations, powers and outputs to 1e-12
    (relative to their scale), the same refusals."""
    comp, plain = _run_cases(False), _run_cases(True)
    assert comp["compiled"] and not plain["compiled"]
    ok = refused = 0
    for a, b in zip(comp["cases"], plain["cases"], strict=True):
        assert a["code"] == b["code"], (a["preset"], a["code"], b["code"])
        if a["code"]:
            refused += 1
            continue
        ok += 1
        np.testing.assert_allclose(a["r"], b["r"], rtol=1e-11, atol=1e-12)
        for key in ("S", "PW"):
            np.testing.assert_allclose(a[key], b[key], rtol=1e-12, atol=1e-9)
        o_a, o_b = np.array(a["o"]), np.array(b["o"])
        np.testing.assert_allclose(o_a, o_b, rtol=1e-11, atol=1e-12, equal_nan=True,
                                   err_msg=str(list(zip(OUT, o_a, o_b, strict=True))))
    assert ok > 60 and refused > 0, (ok, refused)          # both branches exercised, all configurations
    for a, b in zip(comp["designs"], plain["designs"], strict=True):   # design mode (Fn_target solved by brentq)
        np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-12)


def _stepped(fast: bool, eps: float = 0.0) -> np.ndarray:
    """Outputs of a climbing engine whose fuel flow is cut by 40 % at step 21 (the decel slew acts), 60 steps of
    50 ms; `fast` False: the Python cycle and iteration only; `eps`: relative change of the fuel flow."""
    m = EngineModel("larzac04_sls")
    if not fast:
        m.tr.compiled_iteration = False                     # the Python iteration on the same gas path
    m.start(EngineInputs(0.2, 1000.0, 0.4), N1_pct=90.0)
    Wf0 = m.state.Wf_kg_s * (1.0 + eps)                     # type: ignore[union-attr]
    out = []
    for k in range(60):
        m.step(0.05, EngineInputs(Wf0 * (1.0 - 0.4 * (k > 20)), 1000.0 + 5.0 * k, 0.4 + 0.001 * k))
        out.append(list(m.values))
    return np.array(out)


def test_engine_step_equals_the_python_iteration() -> None:
    """A climbing, throttled engine stepped with the compiled iteration and with the Python one.

    The compiled iteration (:func:`.jit_solve.chord_solve`) makes the same BLAS calls as the Python one; with
    NumPy and SciPy on the same BLAS kernels both paths are bit for bit equal (so here). With another BLAS they
    differ by rounding, and the engine amplifies rounding: the spool accelerations at a step start are corrected
    with the Broyden-updated inverse Jacobian, whose last updates are formed from residual differences near the
    1e-8 tolerance, and whether an iterate passes the tolerance flips with the last bit. The yardstick is then
    the Python path's own spread: the same run with the fuel flow changed by 1e-15 (relative). Every output of
    the compiled run must lie within that spread of the Python run (measured with the products written as
    loops: about a hundredth of it); thrust, speeds and temperatures also within 1e-6 (relative)."""
    py, py_eps, fast = _stepped(False), _stepped(False, 1e-15), _stepped(True)
    spread = np.abs(py_eps - py).max(axis=0)
    diff = np.abs(fast - py).max(axis=0)
    floor = 1e-12 * (1.0 + np.abs(py).max(axis=0))
    assert np.all(diff <= spread + floor), (diff, spread)
    np.testing.assert_allclose(fast[:, :14], py[:, :14], rtol=1e-6, atol=0.0)


def test_free_stream_against_its_defining_relations(model: EngineModel) -> None:
    """The one free stream (:func:`.jit_freestream.free_stream`, what :func:`.atmosphere.free_stream` returns) on a
    grid over the valid range and beyond: V0 = M sqrt(gamma R T), h(Tt0) = h(T) + V0^2/2 and
    Pt0 = p exp((phi(Tt0) - phi(T)) / R) formed with the gas model's own functions at the ISO 2533 static state
    (:mod:`openemss.models.common.atmosphere`, tested against the standard's tables) to 1e-12; the ideal-gas
    relation Tt0 / T = 1 + (gamma - 1) / 2 M^2 to 1e-3 up to Mach 1; the MIL-E-5008B recovery; refused exactly where the
    atmosphere's ranges (altitude, temperature), the gas tables or Mach 0 to 3 are left."""
    from openemss.models.common.atmosphere import AtmosphereRangeError, isa
    from openemss.models.engine.atmosphere import free_stream
    from openemss.models.engine.errors import OutOfRangeError
    from openemss.models.engine.jit_freestream import free_stream as kernel
    fc = model.od.fast
    g = fc.gas
    ok = refused = 0
    for alt in np.linspace(-1500.0, 33000.0, 47):
        for Mach in (-0.1, 0.0, 0.3, 0.75, 0.999, 1.0, 1.6, 3.0, 3.2):
            for dT in (-80.0, -15.0, 0.0, 20.0, 70.0):
                fs = np.empty(6)
                status = kernel(fc.gc, fc.gs, fc.atm, alt, Mach, dT, fs)
                try:
                    a = isa(alt, dT)
                    in_range = 0.0 <= Mach <= 3.0 and a.T_K >= jit_kernels.T_MIN       # and the gas tables
                except AtmosphereRangeError:
                    in_range = False
                if not in_range:
                    assert status == 1, (alt, Mach, dT)
                    with pytest.raises(OutOfRangeError):
                        free_stream(alt, Mach, dT, g)
                    refused += 1
                    continue
                assert status == 0, (alt, Mach, dT)
                T, p = a.T_K, a.p_Pa
                V0 = Mach * math.sqrt(g.gamma(T) * g.R() * T)
                Tt = g.T_from_h(g.h(T) + 0.5 * V0 * V0, 0.0, T)
                Pt = p * math.exp((g.phi(Tt) - g.phi(T)) / g.R())
                eta_r = 1.0 if Mach <= 1.0 else 1.0 - 0.075 * (Mach - 1.0) ** 1.35
                np.testing.assert_allclose(fs, [Tt, Pt, V0, p, Mach, eta_r], rtol=1e-12, atol=1e-12)
                if Mach <= 1.0:                                 # cp hardly changes between T and Tt there
                    assert fs[0] / T == pytest.approx(1.0 + 0.5 * (g.gamma(T) - 1.0) * Mach ** 2, rel=1e-3)
                fr = free_stream(alt, Mach, dT, g)
                assert (fr.Tt0_K, fr.Pt0_Pa, fr.V0_m_s) == (fs[0], fs[1], fs[2])
                ok += 1
    assert ok > 500 and refused > 500


def _profile_model(steps: int, check: Callable[[Any, Any, Any, tuple[Any, ...], dict[str, Any]], None],
                   monkeypatch: pytest.MonkeyPatch) -> EngineModel:
    """An engine flown by a rate-limited fuel controller through a climb to 6000 m with a Mach change, a
    throttle wave and a chop (decel slew, minimum-flow stop), every transient match passed to `check`."""
    m = EngineModel("larzac04_sls")
    m.compiled_step = False                 # the step in Python: every match goes through tr.state
    tr = m.tr
    orig = tr.state

    def state(*args: Any, **kw: Any) -> Any:
        c0 = tr._cache
        s = orig(*args, **kw)
        check(tr, c0, s, args, kw)
        return s

    monkeypatch.setattr(tr, "state", state)
    m.start(EngineInputs(0.1, 0.0, 0.0), N1_pct=70.0)
    Wf_d, wf = m.dp.Wf_kg_s, m.state.Wf_kg_s                   # type: ignore[union-attr]
    for k in range(steps):
        t = 0.05 * k
        n1 = 100.0 if t < 5.0 else (88.0 + 4.0 * math.sin(0.8 * t) if t < 14.0 else 55.0)
        err = n1 - m.values[6]
        wf = max(0.15 * Wf_d, wf + max(-0.01 * Wf_d, min(0.02 * Wf_d, 0.004 * Wf_d * err)))
        m.step(0.05, EngineInputs(wf, min(6000.0, 400.0 * t), min(0.7, 0.05 * t)))
    return m


def test_compiled_iteration_equals_the_python_iteration(monkeypatch: pytest.MonkeyPatch) -> None:
    """On the same steps (the same previous match, cached Jacobian and inputs), the compiled chord/Broyden
    iteration and the Python one (:meth:`.transient.TurbofanTransient._chord` on the Python cycle) give the same
    match. They perform the same operations, the matrix products by the same BLAS calls, so with NumPy and
    SciPy on the same BLAS kernels they agree bit for bit; the tolerances allow another BLAS (another summation
    order): matched unknowns (scaled, order 1) to 1e-11, spool accelerations to 1e-6 rpm/s, kernel outputs to
    1e-10 (relative) of the Python stations (measured with the iteration's products written as loops instead:
    2e-14, 8e-10 rpm/s and 6e-14), all far inside what the 1e-8 matching tolerance leaves open."""
    from openemss.models.engine.transient import TransientState
    seen = {"compiled": 0, "other": 0}

    def check(tr: Any, c0: Any, s: Any, args: tuple[Any, ...], kw: dict[str, Any]) -> None:
        c1 = tr._cache
        if not (isinstance(kw.get("guess"), TransientState) and c1 is not c0 and c1 is not None and len(c1) == 6):
            seen["other"] += 1                                  # not the compiled iteration (start, rebuilds)
            return
        seen["compiled"] += 1
        tr._cache, tr.compiled_iteration = c0, False
        try:
            p = tr.state(*args, **kw)
        finally:
            tr._cache, tr.compiled_iteration = c1, True
        np.testing.assert_allclose(s.x, p.x, rtol=0.0, atol=1e-11)
        assert s.dN1_dt_rpm_s == pytest.approx(p.dN1_dt_rpm_s, rel=0.0, abs=1e-6)
        assert s.dN2_dt_rpm_s == pytest.approx(p.dN2_dt_rpm_s, rel=0.0, abs=1e-6)
        pt = p.point
        o = dict(zip(OUT, s.fast, strict=True))
        for name, ref in (("Fn", pt.Fn_N), ("Tt4", pt.Tt4_K), ("Pt3", pt.Pt3_Pa), ("SM_fan", pt.SM_fan),
                          ("SM_hpc", pt.SM_hpc), ("N1c", pt.N1c_rpm)):
            assert o[name] == pytest.approx(ref, rel=1e-10, abs=1e-12), name

    m = _profile_model(400, check, monkeypatch)
    assert m.failures == 0
    assert seen["compiled"] > 350, seen


def test_compiled_iteration_falls_back_as_python(monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the compiled iteration stalls, the step goes to the Newton solve and a rebuilt Jacobian as the Python
    iteration does; where the kernel refuses, the Python iteration runs from the same start (the same numbers
    as the Python path bit for bit)."""
    from openemss.models.engine import jit_solve, transient
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(0.2, 3000.0, 0.5), N1_pct=85.0)
    for _ in range(3):
        m.step(0.05, EngineInputs(0.19, 3000.0, 0.5))
    tr, s0 = m.tr, m.state
    cache = tr._cache
    assert cache is not None and len(cache) == 6             # the compiled iteration ran
    args = (1.0, s0.N1_rpm * 1.001, s0.N2_rpm * 1.0005, 0.185)  # type: ignore[union-attr]
    kw = dict(alt_m=3010.0, Mach=0.501, guess=s0, tol=1e-8)

    def python() -> Any:
        tr._cache, tr.compiled_iteration = cache, False
        try:
            return tr.state(*args, **kw)                    # type: ignore[arg-type]
        finally:
            tr.compiled_iteration = True

    ref = python()
    for status in (jit_solve.REFUSED, jit_solve.STALLED):
        monkeypatch.setattr(transient, "_chord_solve", lambda *a, st=status: (st, 0))
        tr._cache = cache
        s = tr.state(*args, **kw)                           # type: ignore[arg-type]
        if status == jit_solve.REFUSED:                     # the Python iteration on the kernel's residuals
            assert s.x == ref.x and s.dN1_dt_rpm_s == ref.dN1_dt_rpm_s
            assert tr._cache is not None and len(tr._cache) == 5
        else:                                               # Newton from the previous Jacobian, then rebuilt
            assert tr._cache is not None and tr._cache[1] is not cache[1] and len(tr._cache) == 5
            assert float(np.max(np.abs(np.array(s.point.x) - np.array(ref.x)))) < 1e-6
            assert s.dN1_dt_rpm_s == pytest.approx(ref.dN1_dt_rpm_s, rel=1e-5, abs=1e-3)


def test_python_path_without_numba() -> None:
    """OPENEMSS_NO_JIT=1 (numba not used): the engine runs on the same gas path as plain Python and the Python
    iteration, in a process of its own, and gives the compiled run's outputs to 1e-6 (relative; see the
    rounding spread above)."""
    code = (
        "import json\n"
        "from openemss.models.engine import jit_kernels\n"
        "from openemss.models.engine.engine_model import EngineInputs, EngineModel\n"
        "assert not jit_kernels.AVAILABLE\n"
        "m = EngineModel('larzac04_sls')\n"
        "m.start(EngineInputs(0.2, 2000.0, 0.5), N1_pct=88.0)\n"
        "for k in range(20):\n"
        "    m.step(0.05, EngineInputs(0.2 - 0.002 * k, 2000.0 + 10.0 * k, 0.5))\n"
        "print(json.dumps(m.values))\n")
    env = dict(os.environ, OPENEMSS_NO_JIT="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    py = json.loads(out.stdout.strip().splitlines()[-1])
    m = EngineModel("larzac04_sls")
    m.start(EngineInputs(0.2, 2000.0, 0.5), N1_pct=88.0)
    for k in range(20):
        m.step(0.05, EngineInputs(0.2 - 0.002 * k, 2000.0 + 10.0 * k, 0.5))
    np.testing.assert_allclose(m.values[:14], py[:14], rtol=1e-6, atol=0.0)


def _flown(compiled_step: bool, steps: int = 700, dt_s: float = 0.05, **model: Any) -> tuple[EngineModel, list[Any]]:
    """An engine flown through a take-off, a climb to 6000 m with a Mach change, a throttle wave, a chop (decel
    slew, minimum-flow stop, the handling bleed's valve opening), the shaft ports beyond their limits (clipped,
    an event), a customer bleed beyond its range (clipped, logged), inlet distortion switched on and off, and
    the fuel flow below the burner's minimum (flameout): after every step the outputs, flags, events, the
    state's unknowns and accelerations, the valve and the log."""
    log: list[str] = []
    m = EngineModel("larzac04_sls", logger=log.append, **model)
    m.compiled_step = compiled_step
    m.start(EngineInputs(0.1, 0.0, 0.0), N1_pct=70.0)
    Wf_d, wf = m.dp.Wf_kg_s, m.state.Wf_kg_s                   # type: ignore[union-attr]
    out: list[Any] = []
    python_step = m._step
    m.python_steps = 0                                          # type: ignore[attr-defined]

    def counted(*args: Any) -> Any:
        m.python_steps += 1                                     # type: ignore[attr-defined]
        return python_step(*args)

    m._step = counted                                           # type: ignore[method-assign]
    for k in range(steps):
        t = dt_s * k
        n1 = 100.0 if t < 5.0 else (88.0 + 4.0 * math.sin(0.8 * t) if t < 14.0 else (40.0 if t < 24.0 else 85.0))
        err = n1 - m.values[6]
        wf = max(0.15 * Wf_d, wf + max(-0.01 * Wf_d, min(0.02 * Wf_d, 0.004 * Wf_d * err)))
        u = EngineInputs(0.0 if 30.0 < t < 30.2 else wf, min(6000.0, 400.0 * t), min(0.7, 0.05 * t),
                         offtake_hp_W=3e5 if 8.0 < t < 9.0 else 2e4, offtake_lp_W=-3e5 if 10.0 < t < 11.0 else 0.0,
                         customer_bleed_frac=0.4 if 12.0 < t < 12.5 else 0.02,
                         distortion_on=26.0 < t < 27.0, distortion_dPt_frac=0.05)
        m.step(dt_s, u)
        s = m.state
        assert s is not None
        out.append((list(m.values), list(m.flags), m.events, s.x, s.dN1_dt_rpm_s, s.dN2_dt_rpm_s, m.valve_pos,
                    m.valve_open_cmd, m.failures, len(log)))
    return m, out + [log]


@pytest.mark.parametrize("dt_s", [0.05, 0.12])
def test_compiled_step_equals_the_python_step(dt_s: float) -> None:
    """The compiled step (:mod:`.jit_step`) performs the Python step's operations on the same floats, its matches
    by the same compiled iteration: after every step of a profile that goes through every branch of the step
    (linearised starts, matched starts, the valve, events, clipped inputs, distortion and back: the Python step
    where the compiled one refuses), both give the same numbers, bit for bit, and the same log. With a step of
    0.12 s, three internal steps of 0.04 s."""
    valve = BleedValve.from_file(threshold_N1c_pct=75.0)                  # opens in the chop
    fast, ref = _flown(True, dt_s=dt_s, valve=valve), _flown(False, dt_s=dt_s, valve=valve)
    assert fast[1] == ref[1]
    m = fast[0]
    assert m.events >= 3 and any("clipped" in line for line in fast[1][-1])
    assert any(o[0][25] > 0.0 for o in fast[1][:-1])             # the handling bleed opened
    assert m._buf is not None                                    # back on the compiled step after distortion
    assert ref[0].python_steps == 700 and fast[0].python_steps < 100, fast[0].python_steps   # type: ignore[attr-defined]


def test_compiled_step_state_serves_the_python_api() -> None:
    """After compiled steps, the state and the cached Jacobian the Python API reads are those of the Python step:
    the state's point (its matched gas path, formed on reading) and the fuel sensitivity."""
    fast, ref = _flown(True, 120)[0], _flown(False, 120)[0]
    assert fast.state.point.Fn_N == ref.state.point.Fn_N        # type: ignore[union-attr]
    assert fast.tr.fuel_sensitivity(fast.state) == ref.tr.fuel_sensitivity(ref.state)  # type: ignore[arg-type]
    np.testing.assert_array_equal(fast.state.jacobian, ref.state.jacobian)  # type: ignore[union-attr]


def _borrowing_kernels() -> tuple[Callable[..., Any], Callable[..., Any]]:
    """A kernel that reads and writes arrays of a nested tuple through borrowed views, passing them on to another
    compiled kernel (as the gas path passes its maps to the tables), and one that returns a borrowed view's copy."""
    from openemss.models.engine.jit_kernels import borrowed, jit

    @jit
    def weigh(a: np.ndarray, cells: np.ndarray, k: int) -> float:
        return a[k] * cells[k, 1, 0, 3]

    @jit
    def through_views(t: Any, scale: float) -> float:
        a, (cells, flags), n = borrowed(t)
        s = 0.0
        for k in range(a.shape[0]):
            a[k] *= scale                       # written through the view: the owner's data
            s += weigh(a, cells, k)
        flags[0] = a.shape[0] == n and cells.shape == (3, 2, 1, 4)
        return s

    @jit
    def copied(a: np.ndarray) -> np.ndarray:
        return borrowed(a).copy()               # a copy owns its data (the view itself must not be returned)

    return through_views, copied


def test_borrowed_views_are_the_owners_arrays() -> None:
    """:func:`.jit_kernels.borrowed` gives the same data, shape and strides (writes reach the owner), through nested
    tuples and into compiled callees, many times over without a leak or a crash; its copies own their data."""
    through_views, copied = _borrowing_kernels()
    a, cells = np.arange(1.0, 4.0), np.arange(24.0).reshape(3, 2, 1, 4)
    flags = np.zeros(1, np.bool_)
    expected = float(sum(2.0 * a[k] * cells[k, 1, 0, 3] for k in range(3)))
    assert through_views((a, (cells, flags), 3), 2.0) == expected
    assert a.tolist() == [2.0, 4.0, 6.0] and bool(flags[0])
    for _ in range(20000):
        through_views((a, (cells, flags), 3), 1.0)
    assert a.tolist() == [2.0, 4.0, 6.0]
    c = copied(a)
    del a
    assert c.tolist() == [2.0, 4.0, 6.0]
