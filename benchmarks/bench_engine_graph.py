"""Engine files' speed (issue 31, point 8): an off-design point of pyCycle's high-bypass turbofan, cold and warm,
one graph evaluation, and a transient step, against the compiled Larzac 04's transient step in the same run.

Prints median and best of several repeats [ms] and the ratios; asserts nothing (DESIGN.md: speed goes in
benchmarks, no timing in tests). Target of issue 31 point 8: an off-design point of the turbofan at most 2 ms.
The profile (cProfile of a cold point) says where a point's time goes: a cold point is about 30 evaluations of the
graph (a Jacobian by differences over its 11 unknowns, the iterations, and a fresh Jacobian at the solution for
the next warm start), each about 0.35 ms of Python over the compiled kernels; a warm point (a neighbouring point's
unknowns and Jacobian) is about 7 evaluations.

    python benchmarks/bench_engine_graph.py [--repeat 5] [--number 20]
"""

from __future__ import annotations

import argparse

from bench_engine import _time  # the engine benchmark's timing: median and best of the repeats [s]

from openemss.models.engine.engine_graph import EngineGraph
from openemss.models.engine.engine_model import EngineInputs, EngineModel
from openemss.models.engine.graph_transient import GraphTransient


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--number", type=int, default=20)
    a = ap.parse_args()
    g = EngineGraph("pycycle_hbtf")
    d = g.design()
    cond = (10668.0, 0.8)
    p0 = g.solve(*cond, demand=("Fn_N", 0.8 * d.Fn_N))
    k = [0]

    def warm() -> None:
        k[0] += 1
        g.solve(*cond, demand=("Fn_N", (0.8 + 0.001 * (k[0] % 20)) * d.Fn_N), guess=p0)

    vals = g._vals(list(g.offdesign_system(("Fn_N", 0.0, None))[0]), p0.x)
    fs = g._fs((*cond, 0.0))
    tr = GraphTransient(g)
    m = [tr.steady((*cond, 0.0), ("Fn_N", 0.8 * d.Fn_N))]
    Wf = 1.01 * m[0].Wf_kg_s

    def tstep() -> None:
        m[0] = tr.step(m[0], 0.05, Wf)

    lz = EngineModel("larzac04_sls")
    lz.start(EngineInputs(0.12, 3000.0, 0.5))
    u = EngineInputs(0.125, 3000.0, 0.5)
    rows = [("hbtf off-design point, cold", lambda: g.solve(*cond, demand=("Fn_N", 0.8 * d.Fn_N))),
            ("hbtf off-design point, warm (neighbour)", warm),
            ("hbtf one graph evaluation", lambda: g.run(False, fs, vals, {})),
            ("hbtf transient step 50 ms (GraphTransient)", tstep),
            ("Larzac 04 transient step 50 ms (compiled)", lambda: lz.step(0.05, u))]
    res = {name: tuple(1e3 * t for t in _time(fn, a.number, a.repeat)) for name, fn in rows}   # [ms]
    base = res["Larzac 04 transient step 50 ms (compiled)"][0]
    print(f"{'case':45s} {'median ms':>10s} {'best ms':>9s} {'/ Larzac step':>14s}")
    for name, (med, best) in res.items():
        print(f"{name:45s} {med:10.3f} {best:9.3f} {med / base:14.1f}")
    print(f"cold point: {p0.evaluations} graph evaluations; target of point 8: 2 ms per off-design point")


if __name__ == "__main__":
    main()
