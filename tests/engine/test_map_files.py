"""Maps from files (issue 31 point 3): pyCycle's map modules and NPSS map files read as data.

pyCycle: the verbatim copies of ``maps/pycycle_src/`` read by :mod:`map_pycycle` give the numbers of the shipped
JSON maps (transcribed by ``maps/transcribe_pycycle.py`` and checked against the same sources by
``test_maps.py``). NPSS: a map in NPSS's table syntax (comments, ``*`` for a repeated axis, two alpha planes,
interpolation options) is read as written; the Larzac 04 whose HPC map is given as an NPSS file written from the
AXI5 numbers is the same engine as with the JSON map; defects are one line naming the file and line.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from openemss.models.engine.engine_file import ENGINES_DIR
from openemss.models.engine.engine_graph import EngineGraph
from openemss.models.engine.errors import ModelError
from openemss.models.engine.map_npss import read_npss_map
from openemss.models.engine.map_pycycle import read_pycycle_map
from openemss.models.engine.maps import MAP_DIR, load_map_data


@pytest.mark.parametrize("src, name, kind", [("axi5", "axi5", "compressor"), ("LPC_map", "lpc_hbtf", "compressor"),
                                             ("hpt1269", "hpt1269", "turbine"), ("lpt2269", "lpt2269", "turbine")])
def test_pycycle_modules_read_as_the_transcribed_maps(src: str, name: str, kind: str) -> None:
    a = read_pycycle_map(MAP_DIR / "pycycle_src" / f"{src}.py.txt", kind)
    b = load_map_data(name)
    assert (a.kind, a.speed_values, a.line_values, a.speed_design, a.line_design, a.line_surge) == \
        (b.kind, b.speed_values, b.line_values, b.speed_design, b.line_design, b.line_surge)
    assert dict(a.tables) == dict(b.tables)


def _npss(data, alpha_planes: bool = True) -> str:  # type: ignore[no-untyped-def]
    """An NPSS map text of `data` (a compressor's MapData); with `alpha_planes`, a second plane at alpha 90 whose first
    line has one value too many (read only if the reader took the wrong plane)."""
    def table(tb: str, out: str, rows: tuple[tuple[float, ...], ...]) -> str:
        body = []
        for i, (n, row) in enumerate(zip(data.speed_values, rows, strict=True)):
            line = "{ " + ", ".join(repr(v) for v in data.line_values) + " }" if i == 0 else "*;"
            body.append(f"  NcorrMap = {n!r} {{\n    RlineMap = {line}\n    {out} = {{ "
                        + ", ".join(repr(v) for v in row) + " }\n  }")
        plane = "\n".join(body)
        decoy = plane.replace(out + " = { ", out + " = { 7.0, ", 1)
        inner = f" alphaMap = 0.0 {{\n{plane}\n }}\n alphaMap = 90.0 {{\n{decoy}\n }}" if alpha_planes else plane
        args = "real alphaMap, real NcorrMap, real RlineMap" if alpha_planes else "real NcorrMap, real RlineMap"
        return f"Table {tb}({args}) {{\n{inner}\n NcorrMap.interp = \"lagrange2\" ;\n}}\n"
    return ("// an NPSS map written from our data\nSubelement CompressorRlineMap S_map {\n  alphaMapDes = 0.0;\n"
            f"  NcMapDes = {data.speed_design!r};\n  RlineMapDes = {data.line_design!r};\n  RlineStall = "
            f"{data.line_surge!r};\n  /* design values\n  of the map */\n"
            + table("TB_Wc", "WcorrMap", data.tables["WcMap"]) + table("TB_eff", "effMap", data.tables["effMap"])
            + table("TB_PR", "PratioMap", data.tables["PRmap"]) + "}\n")


def test_npss_map_is_read_as_written(tmp_path: Path) -> None:
    b = load_map_data("axi5")
    f = tmp_path / "axi5.map"
    f.write_text(_npss(b))
    a = read_npss_map(f, "compressor")
    assert (a.speed_values, a.line_values, a.speed_design, a.line_design, a.line_surge) == \
        (b.speed_values, b.line_values, b.speed_design, b.line_design, b.line_surge)
    assert dict(a.tables) == dict(b.tables)
    with pytest.raises(ModelError, match="is a compressor map; a turbine map is needed"):
        read_npss_map(f, "turbine")


def test_engine_with_an_npss_map_is_the_same_engine(tmp_path: Path) -> None:
    (tmp_path / "hpc.map").write_text(_npss(load_map_data("axi5"), alpha_planes=False))
    f = tmp_path / "larzac.yaml"
    f.write_text((ENGINES_DIR / "larzac04.yaml").read_text().replace("map: axi5,", "map: hpc.map,"))
    a = EngineGraph(f).solve(3000.0, 0.5, demand=("N_rpm", 0.85 * 17300.0))
    b = EngineGraph("larzac04").solve(3000.0, 0.5, demand=("N_rpm", 0.85 * 17300.0))
    assert a.Fn_N == pytest.approx(b.Fn_N, rel=1e-12) and a.W_kg_s == pytest.approx(b.W_kg_s, rel=1e-12)


@pytest.mark.parametrize("old, new, line, words", [
    ("RlineMap = *;", "RlineMap = { 1.0, 2.0 }", 0, ["differ from the first line's", "common grid"]),
    ("Table TB_PR", "Table TB_XX", None, ["needs tables"]),
    ("NcMapDes = ", "NcMapDes = = ", 4, ["unexpected"]),
])
def test_npss_map_defects_are_one_line(tmp_path: Path, old: str, new: str, line: int | None,
                                       words: list[str]) -> None:
    text = _npss(load_map_data("axi5"), alpha_planes=False)
    assert old in text
    text = text.replace(old, new, 1)
    f = tmp_path / "bad.map"
    f.write_text(text)
    with pytest.raises(ModelError) as ei:
        read_npss_map(f, "compressor")
    msg = str(ei.value)
    print(msg)
    assert "\n" not in msg and str(f) in msg
    if line:
        assert f"{f}:{line}:" in msg
    for w in words:
        assert w in msg
