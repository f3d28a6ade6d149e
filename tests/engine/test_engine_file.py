"""Engine files (issue 31 points 1 and 10): the Larzac 04 written as an engine file and solved by the general
graph solver gives the answers of the turbofan's own gas path (design and off-design, 1e-6 relative), conserves
mass, and every defect of a file is one line naming the file, the line and the element.

The comparison is with another implementation of the same cycle: the turbofan's hand-written gas path
(:mod:`gas_path`, parameters from ``presets/larzac04_sls.json``), independent of the element graph, its
equations written per architecture; both call the same component kernels. Independent checks: the design
meets the published thrust within 1 % (as ``test_cycle_design.py``), mass is conserved to 1e-12.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from openemss.models.engine.cycle_design import design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.engine_file import ENGINES_DIR, EngineFileError, read_engine_file
from openemss.models.engine.engine_graph import EngineGraph
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps

REL = 1e-6
LARZAC = ENGINES_DIR / "larzac04.yaml"


@pytest.fixture(scope="module")
def graph() -> EngineGraph:
    return EngineGraph("larzac04")


@pytest.fixture(scope="module")
def preset() -> TurbofanOffDesign:
    dp = design(load_params(preset_path("larzac04_sls")))
    return TurbofanOffDesign(dp, scaled_maps(dp))


def test_larzac_file_design_is_the_presets(graph: EngineGraph, preset: TurbofanOffDesign) -> None:
    d, dp = graph.design(), preset.dp
    assert d.Fn_N == pytest.approx(13.0e3, rel=0.01)                 # the published thrust (SPEC.md)
    for a, b in ((d.Fn_N, dp.Fn_N), (d.Wf_kg_s, dp.Wf_kg_s), (d.OPR, dp.OPR), (d.SFC_kg_N_s, dp.SFC_kg_N_s),
                 (d.elements["hpt"]["PR"], dp.components["hpt"].PR), (d.elements["lpt"]["PR"], dp.components["lpt"].PR),
                 (d.elements["core_nozzle"]["A_geom_m2"], dp.nozzles["core"].A_geom_m2),
                 (d.elements["bypass_nozzle"]["A_geom_m2"], dp.nozzles["bypass"].A_geom_m2)):
        assert a == pytest.approx(b, rel=REL)
    for k, s in d.stations.items():
        t = dp.stations[k]
        for x, y in ((s.W_kg_s, t.W_kg_s), (s.Tt_K, t.Tt_K), (s.Pt_Pa, t.Pt_Pa), (s.FAR, t.FAR)):
            assert x == pytest.approx(y, rel=REL, abs=1e-12), k


@pytest.mark.parametrize("alt_m, Mach, kind, value", [
    (0.0, 0.0, "N1_pct", 90.0), (7500.0, 0.75, "N1_pct", 95.0), (0.0, 0.0, "N1_pct", 60.0),
    (3000.0, 0.5, "Fn_N", 2500.0), (5000.0, 0.6, "Tt4_K", 1200.0), (0.0, 0.3, "Wf_kg_s", 0.15)])
def test_larzac_file_offdesign_is_the_presets(graph: EngineGraph, preset: TurbofanOffDesign, alt_m: float,
                                              Mach: float, kind: str, value: float) -> None:
    demand = {"N1_pct": ("N_rpm", value / 100.0 * 17300.0), "Fn_N": ("Fn_N", value), "Tt4_K": ("Tt_K", value),
              "Wf_kg_s": ("Wf_kg_s", value)}[kind]
    p = graph.solve(alt_m, Mach, demand=demand)
    q = preset.solve(alt_m, Mach, **{kind: value})
    print(f"\n{alt_m} m M{Mach} {kind}={value}: Fn {p.Fn_N:.3f} / {q.Fn_N:.3f} N, handling bleed "
          f"{q.handling_bleed_frac}")
    for a, b in ((p.Fn_N, q.Fn_N), (p.Wf_kg_s, q.Wf_kg_s), (p.W_kg_s, q.stations["2"].W_kg_s), (p.OPR, q.OPR),
                 (p.shafts["lp"]["N_rpm"], q.N1_rpm), (p.shafts["hp"]["N_rpm"], q.N2_rpm),
                 (p.elements["fan"]["BPR"], q.BPR), (p.elements["hpt"]["PR"], q.PR_hpt),
                 (p.elements["lpt"]["PR"], q.PR_lpt), (p.stations["4"].Tt_K, q.Tt4_K)):
        assert a == pytest.approx(b, rel=REL)
    for k, s in p.stations.items():
        assert s.Tt_K == pytest.approx(q.stations[k].Tt_K, rel=REL) and s.Pt_Pa == pytest.approx(q.stations[k].Pt_Pa,
                                                                                                 rel=REL), k


def test_mass_is_conserved(graph: EngineGraph) -> None:
    p = graph.solve(2000.0, 0.4, demand=("N_rpm", 0.58 * 17300.0))      # handling bleed open into the bypass
    st = p.stations
    assert st["7"].W_kg_s + st["17"].W_kg_s == pytest.approx(p.W_kg_s + p.Wf_kg_s, rel=1e-12)
    assert st["17"].W_kg_s > st["13"].W_kg_s                           # the handling bleed returned to it


def _write(tmp_path: Path, text: str) -> Path:
    f = tmp_path / "e.yaml"
    f.write_text(text)
    return f


def _edit(tmp_path: Path, old: str, new: str) -> Path:
    text = LARZAC.read_text()
    assert old in text
    return _write(tmp_path, text.replace(old, new))


def _line(text: str, needle: str) -> int:
    return next(i for i, t in enumerate(text.splitlines(), 1) if needle in t)


@pytest.mark.parametrize("old, new, needle, words", [
    ('  "17": bypass_duct -> bypass_nozzle\n', "", "  bypass_duct: {kind",
     ["bypass_duct", "port 'out' is not connected"]),
    ('  "7": jet_pipe -> core_nozzle\n', '  "7": jet_pipe -> bypass_nozzle\n', '"17": bypass_duct',
     ["element 'bypass_nozzle'", "already connected"]),
    ("  hp: {N_rpm: 22900.0, eta_mech: 0.99, I_kg_m2: 0.25}\n",
     "  hp: {N_rpm: 22900.0, eta_mech: 0.99, I_kg_m2: 0.25}\n  gear: {N_rpm: 5000.0}\n", "  gear:",
     ["shaft 'gear'", "no turbine"]),
    ("map: axi5,", "map: axi5, map_Nc_rel: 1.4,", "  hpc: {kind", ["element 'hpc'", "does not cover the design point"]),
    ("map: axi5,", "map: axi5, held_Rline: 2.0,", "  elements:", ["a balance cannot be formed", "held_Rline"]),
    ("  hpt: {kind: turbine, shaft: hp, map: hpt1269, eta: 0.85}",
     "  hpt: {kind: turbine, shaft: hp, map: hpt1269, eta: 0.85, PR: 2.0}", "  hp: {N_rpm",
     ["a balance cannot be formed", "shaft 'hp'"]),
    ("eta: 0.80, stages: 4}", "eta: 0.80, stages: 4, efficency: 0.8}", "  hpc: {kind",
     ["element 'hpc'", "unknown attribute 'efficency'", "allowed"]),
    ("Tt_K: 1403.0", "Tt_K: hot", "  burner: {kind", ["element 'burner'", "'Tt_K'", "finite number"]),
    ("shaft: hp, map: hpt1269", "shaft: hq, map: hpt1269", "  hpt: {kind", ["element 'hpt'", "'hq'", "not declared"]),
])
def test_bad_engine_files_are_one_line_naming_file_line_element(tmp_path: Path, old: str, new: str, needle: str,
                                                                words: list[str]) -> None:
    f = _edit(tmp_path, old, new)
    text = f.read_text()
    with pytest.raises(EngineFileError) as ei:
        EngineGraph(read_engine_file(f)).solve(0.0, 0.0, demand=("Fn_N", 10e3))
    msg = str(ei.value)
    print(msg)
    assert "\n" not in msg and msg.startswith(f"{f}:{_line(text, needle.strip())}:"), msg
    for w in words:
        assert w in msg, msg


def test_a_flow_path_that_does_not_close(tmp_path: Path) -> None:
    text = LARZAC.read_text().replace('  "4": burner -> hpt\n',
                                      '  "4": burner -> hpt\n  "99": spare -> bypass_nozzle\n')
    text = text.replace("  bypass_nozzle: {kind", "  spare: {kind: duct}\n  bypass_nozzle: {kind")
    text = text.replace('  "17": bypass_duct -> bypass_nozzle\n', '  "17": bypass_duct -> spare\n')
    text = text.replace('  "99": spare -> bypass_nozzle\n',
                        '  "99": spare -> bypass_nozzle\n  "98": spare2 -> spare2\n')
    text = text.replace("  spare: {kind: duct}\n", "  spare: {kind: duct}\n  spare2: {kind: duct}\n")
    f = _write(tmp_path, text)
    with pytest.raises(EngineFileError) as ei:
        read_engine_file(f)
    msg = str(ei.value)
    assert msg.startswith(f"{f}:{_line(text, 'spare2: {kind')}: element 'spare2': the flow path does not close"), msg
