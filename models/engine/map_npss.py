"""NPSS map files read as data: the table syntax of NASA's public NPSS models.

An NPSS map file declares a map subelement (``Subelement CompressorRlineMap S_map { ... }`` or
``Subelement TurbinePRmap S_map { ... }``) with its design values (``NcMapDes``, ``RlineMapDes``,
``RlineStall``, ``alphaMapDes``; ``NpMapDes``, ``PRmapDes``) and its tables::

    Table TB_Wc(real alphaMap, real NcorrMap, real RlineMap) {
      alphaMap = 0.000 {
        NcorrMap = 0.500 {
          RlineMap = { 1.000, 1.200, ... }
          WcorrMap = { 22.7411, 24.0487, ... }
        }
        NcorrMap = 0.600 { RlineMap = *; WcorrMap = { ... } }     // * : the previous line's values
      }
      NcorrMap.interp = "lagrange2";                               // interpolation options: not used
    }

Tables are recognised by their name: ``TB_Wc``/``TB_Wp`` (flow), ``TB_eff`` (efficiency), ``TB_PR``
(compressor pressure ratio). The plane of the design's ``alphaMapDes`` (else the first) is read. Units as in
NPSS's English-unit maps: corrected flow lbm/s, turbine flow parameter lbm sqrt(degR)/(s psia), as our JSON
maps store them (:mod:`.maps`). Every speed line must share the second axis' values (our tables are C1
bicubic on a grid, :mod:`.map_interp`); a map that does not is refused, naming the table and the line.

Reference: the public JT9D model of NASA's T-MATS repository (``Resources/JT9D_Public_NPSSv241/
Maps_and_Elements/*.map``), the syntax of NPSS's ``Table`` blocks.
"""

from __future__ import annotations

import re
from pathlib import Path
from types import MappingProxyType
from typing import Any

from .errors import ModelError
from .maps import MapData, MapSource

__all__ = ["read_npss_map", "parse_npss"]

_TOKEN = re.compile(r'\s*(?:(?P<num>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|(?P<id>[A-Za-z_][\w.]*)'
                    r'|(?P<str>"[^"]*")|(?P<sym>[{}()=;,*]))')


def _tokens(text: str, where: str) -> list[tuple[str, str, int]]:
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    out = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.split("//", 1)[0]
        pos = 0
        while pos < len(line):
            if not line[pos:].strip():
                break
            m = _TOKEN.match(line, pos)
            if m is None:
                raise ModelError(f"{where}:{n}: cannot read {line[pos:].strip()[:20]!r}")
            kind = m.lastgroup or ""
            out.append((kind, m.group(kind), n))
            pos = m.end()
    return out


class _Parser:
    def __init__(self, toks: list[tuple[str, str, int]], where: str) -> None:
        self.t, self.i, self.where = toks, 0, where

    def peek(self, k: int = 0) -> tuple[str, str, int]:
        return self.t[self.i + k] if self.i + k < len(self.t) else ("eof", "", self.t[-1][2] if self.t else 1)

    def take(self, value: str | None = None) -> tuple[str, str, int]:
        tok = self.peek()
        if value is not None and tok[1] != value:
            raise ModelError(f"{self.where}:{tok[2]}: expected {value!r}, got {tok[1] or 'the end of the file'!r}")
        self.i += 1
        return tok

    def block(self) -> dict[str, Any]:
        """Statements up to the closing brace: values, ``name = number { block }`` branches, tables, subelements."""
        out: dict[str, Any] = {"values": {}, "branches": [], "tables": {}}
        while self.peek()[1] not in ("}", ""):
            kind, val, line = self.take()
            if val == ";":
                continue
            if val == "Table":
                name = self.take()[1]
                self.take("(")
                args = []
                while self.peek()[1] != ")":
                    tok = self.take()
                    if tok[0] == "id" and tok[1] != "real":
                        args.append(tok[1])
                self.take(")")
                self.take("{")
                out["tables"][name] = (args, self.block(), line)
                self.take("}")
            elif val in ("Subelement", "Element"):
                out["values"]["__type__"] = self.take()[1]
                self.take()
                self.take("{")
                sub = self.block()
                self.take("}")
                out["values"].update(sub["values"])
                out["tables"].update(sub["tables"])
            elif kind == "id" and self.peek()[1] == "=":
                self.take("=")
                nxt = self.peek()
                if nxt[0] == "num" and self.peek(1)[1] == "{":
                    self.take()
                    self.take("{")
                    out["branches"].append((val, float(nxt[1]), self.block(), line))
                    self.take("}")
                else:
                    out["values"][val] = self.value()
            else:
                raise ModelError(f"{self.where}:{line}: unexpected {val!r}")
        return out

    def value(self) -> Any:
        kind, val, line = self.take()
        if val == "*":
            return "*"
        if kind == "num":
            return float(val)
        if kind in ("str", "id"):
            return val
        if val == "{":
            nums = []
            while self.peek()[1] != "}":
                tok = self.take()
                if tok[0] == "num":
                    nums.append(float(tok[1]))
                elif tok[1] != ",":
                    raise ModelError(f"{self.where}:{tok[2]}: expected a number in a list, got {tok[1]!r}")
            self.take("}")
            return nums
        raise ModelError(f"{self.where}:{line}: unexpected {val!r}")


def parse_npss(text: str, where: str) -> dict[str, Any]:
    """The values and tables of an NPSS map file (see the module docstring)."""
    p = _Parser(_tokens(text, where), where)
    out = p.block()
    if p.peek()[0] != "eof":
        raise ModelError(f"{where}:{p.peek()[2]}: unexpected {p.peek()[1]!r}")
    return out


def _grid(table: tuple[list[str], dict[str, Any], int], alpha: float | None,
          where: str) -> tuple[list[float], list[float], list[list[float]]]:
    """(speeds, line values, rows) of a table in the plane `alpha` (its first plane if not found)."""
    args, body, line = table
    if len(args) == 3:
        planes = body["branches"]
        if not planes:
            raise ModelError(f"{where}:{line}: table without {args[0]} planes")
        body = next((b for _, v, b, _ in planes if alpha is not None and v == alpha), planes[0][2])
        args = args[1:]
    if len(args) != 2:
        raise ModelError(f"{where}:{line}: a map table has two axes (and an optional alpha), got {args}")
    speeds, rows, xs = [], [], None
    for _, v, b, ln in body["branches"]:
        vals = b["values"]
        xl = vals.get(args[1])
        if xl == "*":
            xl = xs
        outs = [k for k in vals if k != args[1] and isinstance(vals[k], list)]
        if xl is None or len(outs) != 1:
            raise ModelError(f"{where}:{ln}: {args[0]} = {v:g}: expected {args[1]} = {{...}} (or *) and one output "
                             "list")
        if xs is not None and xl != xs:
            raise ModelError(f"{where}:{ln}: {args[0]} = {v:g}: its {args[1]} values differ from the first line's; "
                             "maps are read on a common grid")
        if len(vals[outs[0]]) != len(xl):
            raise ModelError(f"{where}:{ln}: {args[0]} = {v:g}: {len(vals[outs[0]])} values for {len(xl)} "
                             f"{args[1]} points")
        xs = xl
        speeds.append(v)
        rows.append(vals[outs[0]])
    if xs is None:
        raise ModelError(f"{where}:{line}: table without speed lines")
    return speeds, xs, rows


def read_npss_map(path: str | Path, kind: str) -> MapData:
    """An NPSS map file as :class:`.maps.MapData` (source units; see the module docstring).

    Raises
    ------
    ModelError
        One line naming the file and line of what cannot be read, or a map of the other kind.
    """
    p = Path(path)
    where = str(p)
    try:
        text = p.read_text(encoding="utf-8", errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"NPSS map {p}: cannot be read: {exc}") from None
    d = parse_npss(text, where)
    tb, v = d["tables"], d["values"]

    def find(*prefixes: str) -> Any:
        for name, t in tb.items():
            if any(name.lower().startswith(pf.lower()) for pf in prefixes):
                return t
        return None

    flow, eff, pr = find("TB_Wc", "TB_Wp", "TB_flow"), find("TB_eff"), find("TB_PR")
    typ = str(v.get("__type__", ""))
    found = "compressor" if "Compressor" in typ or (pr is not None and "Turbine" not in typ) else "turbine"
    if found != kind:
        raise ModelError(f"NPSS map {p} is a {found} map; a {kind} map is needed here")
    if flow is None or eff is None or (kind == "compressor" and pr is None):
        raise ModelError(f"NPSS map {p}: needs tables TB_Wc (or TB_Wp) and TB_eff" +
                         (" and TB_PR" if kind == "compressor" else "") + f"; found {', '.join(tb) or 'none'}")
    alpha = v.get("alphaMapDes")
    grids = {k: _grid(t, alpha, where) for k, t in (("flow", flow), ("eff", eff), ("PR", pr)) if t is not None}
    sv, lv, _ = grids["flow"]
    for k, (s2, l2, _) in grids.items():
        if s2 != sv or l2 != lv:
            raise ModelError(f"NPSS map {p}: table {k} is not on the flow table's grid")
    src = MapSource("NPSS map file", "", where, where, "as stated with the file", "NPSS map")
    rows = {k: tuple(tuple(r) for r in g[2]) for k, g in grids.items()}
    if kind == "compressor":
        tables = {"WcMap": rows["flow"], "PRmap": rows["PR"], "effMap": rows["eff"]}
        units = {"NcMap": "-", "RlineMap": "-", "WcMap": "lbm/s", "PRmap": "-", "effMap": "-"}
        return MapData(p.stem, "compressor", "", src, "NcMap", tuple(sv), float(v.get("NcMapDes", 1.0)), "RlineMap",
                       tuple(lv), float(v.get("RlineMapDes", 2.0)), float(v.get("RlineStall", lv[0])),
                       MappingProxyType(tables), MappingProxyType(units), p)
    tables = {"WpMap": rows["flow"], "effMap": rows["eff"]}
    units = {"NpMap": "rpm/sqrt(degR)", "PRmap": "-", "WpMap": "lbm*sqrt(degR)/(s*psia)", "effMap": "-"}
    return MapData(p.stem, "turbine", "", src, "NpMap", tuple(sv), float(v.get("NpMapDes", 100.0)), "PRmap", tuple(lv),
                   float(v.get("PRmapDes", 5.0)), None, MappingProxyType(tables), MappingProxyType(units), p)
