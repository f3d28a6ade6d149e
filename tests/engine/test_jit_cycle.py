"""The compiled gas path (:mod:`openemss.models.engine.jit_cycle`) against the Python components it mirrors.

The Python cycle (:meth:`TurbofanOffDesign._cycle`, built from the component modules that the
pyCycle comparisons and conservation tests check) is the reference. The kernel must give the
same residuals and outputs to rounding (1e-12; in practice they are bit for bit the same,
since it performs the same operations in the same order), and must refuse (fall back to
Python) exactly where Python raises.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.engine import jit_kernels
from openemss.models.engine.engine_model import EngineInputs, EngineModel
from openemss.models.engine.errors import ModelError
from openemss.models.engine.jit_cycle import DEMAND, OUT, FastCycle

pytestmark = pytest.mark.skipif(not jit_kernels.AVAILABLE, reason="numba not importable")


@pytest.fixture(scope="module")
def model() -> EngineModel:
    return EngineModel("larzac04_sls")


def test_residuals_and_outputs_equal_the_python_cycle(model: EngineModel) -> None:
    od = model.od
    fc = FastCycle.build(od)
    assert fc is not None
    rng = np.random.default_rng(7)
    cases = [(0.0, 0.0, 0.0), (5000.0, 0.6, 0.0), (7500.0, 0.75, 10.0), (1000.0, 0.3, -15.0)]
    refused = compared = 0
    for cond in cases:
        pt = od.solve(*cond, N1_pct=85.0)
        x0 = np.array(pt.x)
        for k in range(60):
            x = x0 * (1.0 + 0.08 * rng.standard_normal(9)) if k else x0.copy()
            demand = [("Wf_kg_s", 0.1), ("N1_rpm", 15000.0), ("N1c_rpm", 16000.0), ("Tt4_K", 1200.0),
                      ("Fn_N", 5000.0)][k % 5]
            extras = (0.02 * (k % 3), 2e4 * (k % 2), 1e4 * (k % 4 == 1))
            hb = (None, 0.08, 0.0)[k % 3]
            try:
                r, info = od._cycle(x, cond, demand, extras, (None, None), hb)
            except (ModelError, ValueError):
                assert not fc(x, cond, (DEMAND[demand[0]], demand[1]), extras, hb), (cond, k)
                refused += 1
                continue
            assert fc(x, cond, (DEMAND[demand[0]], demand[1]), extras, hb, True), (cond, k)
            np.testing.assert_allclose(fc.r, r, rtol=0.0, atol=1e-12)
            o = dict(zip(OUT, fc.o, strict=True))
            st = info["st"]
            for name, ref in (("Fn", info["Fn"]), ("Fg", info["Fg"]), ("N1c", info["N1c"]), ("Tt4", st["4"].Tt_K),
                              ("T41", st["41"].Tt_K), ("Tt17", st["17"].Tt_K), ("Tt7", st["7"].Tt_K),
                              ("Pt3", st["3"].Pt_Pa), ("FAR4", st["4"].FAR), ("hb", info["hb"])):
                assert o[name] == pytest.approx(ref, rel=1e-12, abs=1e-12), (name, cond, k)
            for key, name in (("SM_fan", "fan"), ("SM_hpc", "hpc")):
                cmap = getattr(od.maps, name)
                Nc, beta = info[f"{name}_sectors"][0]
                try:
                    ref = cmap.surge_margin(Nc, beta)
                except ModelError:
                    ref = math.nan
                assert o[key] == pytest.approx(ref, rel=1e-12, nan_ok=True), (key, cond, k)
            compared += 1
    assert compared > 100 and refused > 5                  # both branches were exercised


def test_engine_step_equals_the_python_path(model: EngineModel, monkeypatch: pytest.MonkeyPatch) -> None:
    """A climbing, throttled engine stepped on the kernel and on Python alone: the same outputs to the
    matching tolerance (the iterations see the same residuals)."""
    def run(fast: bool) -> list[list[float]]:
        m = EngineModel("larzac04_sls")
        if not fast:
            m.od._fast = False                              # the Python cycle only
        m.start(EngineInputs(0.2, 1000.0, 0.4), N1_pct=90.0)
        Wf0 = m.state.Wf_kg_s                               # type: ignore[union-attr]
        out = []
        for k in range(60):
            m.step(0.05, EngineInputs(Wf0 * (1.0 - 0.4 * (k > 20)), 1000.0 + 5.0 * k, 0.4 + 0.001 * k))
            out.append(list(m.values))
        return out

    a, b = np.array(run(True)), np.array(run(False))
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9)
