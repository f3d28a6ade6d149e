"""NPSS models converted to engine files: ``emss engine convert npss MODEL.mdl --out ENGINE_FILE``.

An NPSS model is text: ``Element Kind Name { attributes }``, map files included (``#include <FAN.map>``), ports
linked by ``linkPorts("A.Fl_O", "B.Fl_I", "FS_2")``. :func:`convert_npss` reads a model made of the element kinds
of :mod:`.element_kinds` (table :data:`NPSS_KINDS`: each NPSS kind, our kind and how each attribute carries over,
with its unit conversion), then input files of assignments (``Fan.PRdes = 1.6;``, as a ``.run`` includes them),
and writes an engine file (:mod:`.engine_file`) whose map attributes name the included map files (read by
:mod:`.map_npss`) relative to the new file.

What it cannot carry is refused with one line naming the file, the line and the thing: an element kind we do not
have, an attribute whose effect we cannot express, a statement other than the above, and a function body (NPSS runs
user code: ``void preexecute() { ... }``). A function body may be dropped explicitly (``--drop Inlet.preexecute``):
the engine file's notes list what was dropped, and the user owns the difference (e.g. a recovery a ``preexecute``
would have set). Attributes that only place statics or size geometry (``Fl_O.MN``, ``Afs``) and output-only items
(``FlowStation`` declarations, an ``EngPerf`` element) do not change the totals and are listed in the notes.

Design: NPSS's design mode balances each shaft with its turbine's pressure ratio (``PRbase`` is only the start of
that iteration), as our engine files do when a turbine has no ``PR``; the burner keeps its ``FAR`` (or ``TtCombOut``);
the mass flow is ``InletStart``'s ``W_in``; the flight condition the ``Ambient``'s.

References
----------
NASA T-MATS repository (Apache-2.0), ``Resources/JT9D_Public_NPSSv241``: the public JT9D model (S. M. Jones, NASA
Glenn, 2011) and its published NPSS output; the element and port names of NPSS's standard elements as it uses them.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..infra.files import atomic_write
from .engine_file import EngineFileError, read_engine_file
from .errors import ModelError

__all__ = ["NpssConvertError", "NPSS_KINDS", "convert_npss", "parse_model"]

LBM_KG, LBF_N, FT_M, BTU_LBM_J_KG, HP_W = 0.45359237, 4.4482216152605, 0.3048, 2326.0, 745.69987158227
R_K = 5.0 / 9.0


class NpssConvertError(ModelError):
    """An NPSS model that cannot be converted: one line, ``file:line: what; what is allowed``."""


@dataclass
class Block:
    """A parsed ``Type Name { ... }`` (or ``Type Name;``) with its statements and line."""

    type: str
    name: str
    line: int
    file: str
    assigns: dict[str, tuple[str, int]] = field(default_factory=dict)
    blocks: list[Block] = field(default_factory=list)
    includes: list[tuple[str, int]] = field(default_factory=list)
    functions: list[tuple[str, int]] = field(default_factory=list)
    decls: list[tuple[str, str, int]] = field(default_factory=list)
    calls: list[tuple[str, list[str], int]] = field(default_factory=list)


def _strip(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
    return re.sub(r"//[^\n]*", lambda m: " " * len(m.group(0)), text)


def _match(text: str, i: int, where: Callable[[int], str]) -> int:
    """Index of the brace closing the one at `i`."""
    depth = 0
    for j in range(i, len(text)):
        c = text[j]
        if c == '"':
            continue
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                return j
    raise NpssConvertError(f"{where(i)}: an opening brace is not closed")


_HEAD = re.compile(r"^(?:(?P<el>Element)\s+)?(?P<type>[A-Za-z_]\w*)\s+(?P<name>[A-Za-z_]\w*)\s*(?P<args>\(.*\))?$", re.S)


def parse_block(text: str, start: int, end: int, blk: Block, line0: Callable[[int], int]) -> None:
    """Statements of ``text[start:end]`` into `blk`."""
    where = lambda i: f"{blk.file}:{line0(i)}"  # noqa: E731
    i = start
    while i < end:
        while i < end and text[i] in " \t\r\n;":
            i += 1
        if i >= end:
            break
        if text.startswith("#include", i):
            nl = text.find("\n", i)
            nl = end if nl < 0 or nl > end else nl
            m = re.match(r'#include\s*[<"]([^>"]+)[>"]', text[i:nl])
            if m is None:
                raise NpssConvertError(f"{where(i)}: an #include names a file as <path> or \"path\"")
            blk.includes.append((m.group(1), line0(i)))
            i = nl
            continue
        j = i
        while j < end and text[j] not in ";{":
            if text[j] == '"':
                j = text.index('"', j + 1)
            j += 1
        head = " ".join(text[i:j].split())
        if j < end and text[j] == "{":
            k = _match(text, j, where)
            if re.match(r"^\w+\s*=", head):             # a table's axis block inside a Table: not ours to read
                i = k + 1
                continue
            m = _HEAD.match(head)
            if m is None:
                raise NpssConvertError(f"{where(i)}: cannot read {head[:40]!r}")
            if m.group("args") is not None and m.group("type") != "Table":
                blk.functions.append((f"{m.group('name')}", line0(i)))
            else:
                sub = Block(("Element " if m.group("el") else "") + m.group("type"), m.group("name"), line0(i),
                            blk.file)
                if m.group("type") != "Table":
                    parse_block(text, j + 1, k, sub, line0)
                blk.blocks.append(sub)
            i = k + 1
            continue
        stmt, i = head, j + 1
        if not stmt:
            continue
        m = re.match(r"^([A-Za-z_][\w.]*)\s*=\s*(.+)$", stmt)
        if m:
            blk.assigns[m.group(1)] = (m.group(2).strip(), line0(j))
            continue
        m = re.match(r"^([A-Za-z_]\w*)\s*\((.*)\)$", stmt)
        if m:
            blk.calls.append((m.group(1), [a.strip().strip('"').strip() for a in m.group(2).split(",")], line0(j)))
            continue
        m = re.match(r"^([A-Za-z_]\w*)\s+(.+)$", stmt)
        if m:
            decl_type, rest = m.groups()
            for nm in rest.split(","):
                nm = nm.strip()
                if "=" in nm:
                    nm, v = (x.strip() for x in nm.split("=", 1))
                    blk.assigns[nm] = (v, line0(j))
                blk.decls.append((decl_type, nm, line0(j)))
            continue
        raise NpssConvertError(f"{where(i)}: cannot read {stmt[:40]!r}")


def parse_model(path: Path) -> Block:
    """The top-level statements of an NPSS file (comments removed; included map files are not opened)."""
    try:
        raw = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise NpssConvertError(f"{path}: cannot read: {exc.strerror}") from None
    text = _strip(raw)
    starts = [0] + [m.end() for m in re.finditer("\n", text)]
    import bisect
    top = Block("file", path.name, 1, str(path))
    parse_block(text, 0, len(text), top, lambda i: bisect.bisect_right(starts, i))
    return top


# ---------------------------------------------------------------------------------------------- translation
#: NPSS element kind -> (our element kind or a role, {NPSS attribute: (our attribute, conversion)}, attributes that
#: change no total (statics, geometry, names of ambient stations)).
NPSS_KINDS: dict[str, tuple[str, dict[str, tuple[str, Callable[[float], float]]], tuple[str, ...]]] = {
    "Ambient": ("design", {"alt_in": ("alt_m", lambda v: v * FT_M), "MN_in": ("Mach", float),
                           "dTs_in": ("dT_isa_K", lambda v: v * R_K)}, ()),
    "InletStart": ("design", {"W_in": ("W_kg_s", lambda v: v * LBM_KG)}, ("AmbientName",)),
    "Inlet": ("inlet", {"eRamBase": ("pi", float)}, ("Afs", "Fl_O.MN")),
    "Compressor": ("compressor", {"PRdes": ("PR", float), "effDes": ("eta", float),
                                  "S_map.NcMapDes": ("map_Nc_rel", float), "S_map.RlineMapDes": ("map_line", float)},
                   ("Fl_O.MN",)),
    "Splitter": ("splitter", {"BPRdes": ("BPR", float)}, ("Fl_O1.MN", "Fl_O2.MN")),
    "Duct": ("duct", {"dPqP_dmd": ("dPqP", float)}, ("Fl_O.MN",)),
    "Bleed": ("duct", {}, ("Fl_O.MN", "WrefName")),
    "FuelStart": ("fuel", {"LHV": ("LHV_J_kg", lambda v: v * BTU_LBM_J_KG)}, ("Carbon", "Hydrogen")),
    "Burner": ("burner", {"effBase": ("eta", float), "dPqP_dmd": ("dPqP", float), "FAR": ("FAR", float),
                          "TtCombOut": ("Tt_K", lambda v: v * R_K)}, ("Fl_O.MN", "switchHotLoss", "switchBurn")),
    "Turbine": ("turbine", {"effDes": ("eta", float), "S_map.PRmapDes": ("map_line", float),
                            "S_map.NpMapDes": ("map_Nc_rel", float)}, ("Fl_O.MN", "PRbase")),
    "Nozzle": ("nozzle", {"Cv_in": ("Cv", float), "CdTh_in": ("Cd", float)},
               ("PsExhName", "switchType", "switchCoef")),
    "Shaft": ("shaft", {"Nmech": ("N_rpm", float), "HPX": ("offtake_W", lambda v: v * HP_W),
                        "fracLoss": ("eta_mech", lambda v: 1.0 - v), "inertia": ("I_kg_m2", lambda v: v * 1.3558179483314)},
              ()),
    "FlowEnd": ("end", {}, ()),
    "EngPerf": ("output", {}, ()),
}
_PORT_ATTRS = {"InterStageBleedOutPort": {"fracBldW": "frac_W", "fracBldP": "frac_P", "fracBldWork": "frac_work"},
               "BleedOutPort": {"fracW": "frac_W"}, "InterStageBleedInPort": {"Pfract": "entry"}, "BleedInPort": {}}
_OUT = {"Fl_O": "out", "Fl_O1": "core", "Fl_O2": "bypass"}


def _value(v: str, where: str, what: str) -> Any:
    s = v.strip()
    if s.startswith('"') and s.endswith('"'):
        return s[1:-1]
    try:
        return float(s)
    except ValueError:
        raise NpssConvertError(f"{where}: {what} = {s!r}: an expression cannot be carried; give a number") from None


def _station(s: str) -> str:
    return s[3:] if s.startswith("FS_") and len(s) > 3 else re.sub(r"\W", "_", s)


def convert_npss(model: str | Path, out: str | Path, inputs: tuple[str | Path, ...] = (),
                 drop: tuple[str, ...] = ()) -> Path:
    """Convert the NPSS model `model` (with input files `inputs` applied after it) to the engine file `out`.

    Parameters
    ----------
    drop : names of function bodies (``Element.function``), elements or assignment targets to leave out, each
        listed in the engine file's notes.

    Raises
    ------
    NpssConvertError
        What cannot be carried, one line naming the file, line and item; `out` exists already.
    """
    import yaml
    model, out = Path(model), Path(out)
    if out.exists():
        raise NpssConvertError(f"--out {out}: exists already; nothing is overwritten: give a new file name")
    if out.suffix not in (".yaml", ".yml"):
        raise NpssConvertError(f"--out {out}: an engine file's name ends in .yaml")
    if not model.is_file():
        raise NpssConvertError(f"{model}: the NPSS model does not exist")
    top = parse_model(model)
    dropped: list[str] = []
    used_drop: set[str] = set()

    def dropping(name: str) -> bool:
        hit = [d for d in drop if name == d or name.startswith(d + ".")]
        used_drop.update(hit)
        if hit:
            dropped.append(name)
        return bool(hit)

    for f, line in top.functions:
        if not dropping(f):
            raise NpssConvertError(f"{model}:{line}: function {f}(): a function body cannot be converted (drop it "
                                   f"with --drop {f})")
    els = {b.name: b for b in top.blocks if b.type.startswith("Element ")}
    for b in top.blocks:
        if not b.type.startswith("Element "):
            raise NpssConvertError(f"{b.file}:{b.line}: {b.type} {b.name}: only Element blocks are converted")
    for inp in inputs:
        p = Path(inp)
        if not p.is_file():
            raise NpssConvertError(f"--input {p}: the file does not exist")
        extra = parse_model(p)
        if extra.blocks or extra.functions or extra.calls:
            first = (extra.blocks[0].line if extra.blocks else extra.functions[0][1] if extra.functions
                     else extra.calls[0][2])
            raise NpssConvertError(f"{p}:{first}: an input file holds assignments only (Element.attribute = value;)")
        for k, (v, line) in extra.assigns.items():
            if "." not in k:
                top.assigns[k] = (v, line)
            else:
                el, rest = k.split(".", 1)
                if el not in els:
                    if dropping(k):
                        continue
                    raise NpssConvertError(f"{p}:{line}: {k}: {el!r} is not an element of {model.name} (a solver "
                                           f"variable cannot be carried: drop it with --drop {el})")
                port, _, attr = rest.rpartition(".")
                sub = next((s for s in els[el].blocks if s.name == port), None) if port else None
                (sub or els[el]).assigns[attr if sub else rest] = (v, line)
    return _write(top, els, model, out, dropping, dropped, used_drop, drop, yaml)


def _write(top: Block, els: dict[str, Block], model: Path, out: Path, dropping: Callable[[str], bool],
           dropped: list[str], used_drop: set[str], drop: tuple[str, ...], yaml: Any) -> Path:
    from .map_files import map_data_of
    design: dict[str, float] = {}
    fuel: dict[str, float] = {}
    elements: dict[str, dict[str, Any]] = {}
    shafts: dict[str, dict[str, Any]] = {}
    notes: list[str] = []
    roles: dict[str, str] = {}
    ports: dict[tuple[str, str], Block] = {}
    for name, b in els.items():
        kind = b.type.split()[1]
        w = f"{b.file}:{b.line}: element {name!r} ({kind})"
        if kind not in NPSS_KINDS:
            if dropping(name):
                continue
            raise NpssConvertError(f"{w}: no element kind of ours carries an NPSS {kind} (ours: "
                                   f"{', '.join(NPSS_KINDS)}); drop it with --drop {name} if it only reports")
        role, amap, inert = NPSS_KINDS[kind]
        roles[name] = role
        for f, line in b.functions:
            if not dropping(f"{name}.{f}"):
                raise NpssConvertError(f"{b.file}:{line}: element {name!r}: function {f}(): a function body cannot "
                                       f"be converted (drop it with --drop {name}.{f})")
        if role == "output":
            notes.append(f"{kind} {name}: output only, not carried")
            continue
        variables = set()
        for decl, nm, ln in b.decls:
            if decl in _PORT_ATTRS:
                ports[(name, nm)] = Block(decl, nm, ln, b.file)
            elif decl != "ShaftInputPort":
                variables.add(nm)
                notes.append(f"{name}: {decl} {nm} (a declaration) not carried")
        for sub in b.blocks:
            if sub.type == "Table":
                notes.append(f"{name}: table {sub.name} not carried (read only by a function)")
            elif sub.type in _PORT_ATTRS:
                ports[(name, sub.name)] = sub
            else:
                raise NpssConvertError(f"{b.file}:{sub.line}: element {name!r}: {sub.type} {sub.name}: not carried "
                                       f"(ports: {', '.join(_PORT_ATTRS)})")
        attrs: dict[str, Any] = {}
        for k, (v, line) in b.assigns.items():
            wl = f"{b.file}:{line}: element {name!r}"
            port = k.split(".")[0]
            if k in variables:
                continue
            if (name, port) in ports and "." in k:
                ports[(name, port)].assigns[k.split(".", 1)[1]] = (v, line)
                continue
            if k in inert:
                if kind == "Nozzle" and k in ("switchType", "switchCoef"):
                    ok = {"switchType": {"CONIC": "convergent", "CONV": "convergent", "CD": "cd"},
                          "switchCoef": {"CV": "CV"}}[k]
                    val = _value(v, wl, k)
                    if val not in ok:
                        raise NpssConvertError(f"{wl}: {k} = {val!r} cannot be carried (allowed: {', '.join(ok)})")
                    if k == "switchType":
                        attrs["type"] = ok[val]
                elif kind == "Burner" and k == "switchBurn":
                    val = _value(v, wl, k)
                    if val not in ("FAR", "TEMPERATURE"):
                        raise NpssConvertError(f"{wl}: switchBurn = {val!r} cannot be carried (allowed: FAR, "
                                               "TEMPERATURE)")
                    attrs["_burn"] = val
                elif kind == "Bleed" and k == "WrefName":
                    attrs["_wref"] = (_value(v, wl, k), line)
                elif kind == "FuelStart":
                    attrs["_" + k] = _value(v, wl, k)
                elif kind == "Turbine" and k == "PRbase":
                    notes.append(f"{name}.PRbase = {_value(v, wl, k)}: not carried (NPSS's design balances the shaft "
                                 "with the turbine's PR; PRbase starts that iteration)")
                continue
            if k not in amap:
                if dropping(f"{name}.{k}"):
                    continue
                raise NpssConvertError(f"{wl}: {k} = {v}: this attribute cannot be carried (carried: "
                                       f"{', '.join(amap) or 'none'}; no effect on totals: {', '.join(inert) or 'none'})")
            attrs[amap[k][0]] = amap[k][1](_value(v, wl, k))
        for inc, line in b.includes:
            if role not in ("compressor", "turbine"):
                raise NpssConvertError(f"{b.file}:{line}: element {name!r}: #include <{inc}> in a {kind}: only "
                                       "turbomachines include maps")
            path = (model.parent / inc).resolve()
            try:
                md = map_data_of(str(path), model.parent, role)
            except ModelError as exc:
                raise NpssConvertError(f"{b.file}:{line}: element {name!r}: map {inc}: {exc}") from None
            attrs["map"] = os.path.relpath(path, out.resolve().parent)
            if "map_Nc_rel" in attrs:
                attrs["map_Nc_rel"] /= md.speed_design
        if role == "design":
            design.update(attrs)
        elif role == "fuel":
            if "_Carbon" in attrs and "_Hydrogen" in attrs:     # mass of carbon and of hydrogen: atom ratio H/C
                fuel["hc_ratio"] = (attrs["_Hydrogen"] / 1.00794) / (attrs["_Carbon"] / 12.0107)
            if "LHV_J_kg" in attrs:
                fuel["LHV_J_kg"] = attrs["LHV_J_kg"]
        elif role == "shaft":
            shafts[name] = attrs
        elif role != "end":
            burn = attrs.pop("_burn", "FAR")
            if role == "burner":
                attrs.pop("Tt_K" if burn == "FAR" else "FAR", None)
            attrs.pop("_wref", None) if role != "duct" else None
            elements[name] = {"kind": role, **attrs}
    flow, bleeds = _links(top, els, roles, ports, elements, shafts, model)
    for name, e in elements.items():
        wref = e.pop("_wref", None)
        if wref is not None:
            _check_wref(name, wref, flow, elements, bleeds, els[name])
    unused = [d for d in drop if d not in used_drop]
    if unused:
        raise NpssConvertError(f"--drop {unused[0]}: nothing of that name in {model.name}")
    name = top.assigns.get("MODELNAME", (model.stem, 0))[0].strip('"')
    doc = {"name": name, "sources": [f"converted from the NPSS model {model.name} by emss engine convert npss"
                                     + (f" ({top.assigns['AUTHOR'][0].strip(chr(34))})" if "AUTHOR" in top.assigns
                                        else "")],
           "notes": notes + [f"dropped: {d}" for d in dropped] or ["nothing dropped"],
           "design": design, **({"fuel": fuel} if fuel else {}), "elements": elements, "shafts": shafts,
           "flow": flow, **({"bleeds": bleeds} if bleeds else {})}
    text = yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=118)
    tmp = out.with_name(f".{out.name}.check.yaml")
    try:
        atomic_write(tmp, text)
        read_engine_file(tmp)
    except EngineFileError as exc:
        raise NpssConvertError(f"{model}: the converted engine does not read: {exc}".replace(str(tmp), str(out))) \
            from None
    finally:
        tmp.unlink(missing_ok=True)
    if out.exists():
        raise NpssConvertError(f"--out {out}: exists already; nothing is overwritten: give a new file name")
    return atomic_write(out, text)


def _split(port: str, line: int, model: Path) -> tuple[str, str]:
    el, dot, p = port.partition(".")
    if not dot:
        raise NpssConvertError(f"{model}:{line}: linkPorts: {port!r} is not Element.Port")
    return el, p


def _links(top: Block, els: dict[str, Block], roles: dict[str, str], ports: dict[tuple[str, str], Block],
           elements: dict[str, dict[str, Any]], shafts: dict[str, dict[str, Any]],
           model: Path) -> tuple[dict[str, str], dict[str, dict[str, Any]]]:
    flow: dict[str, str] = {}
    bleeds: dict[str, dict[str, Any]] = {}
    for fn, args, line in top.calls:
        if fn != "linkPorts":
            raise NpssConvertError(f"{model}:{line}: {fn}(...): only linkPorts calls are converted")
        if len(args) != 3:
            raise NpssConvertError(f"{model}:{line}: linkPorts takes (from, to, name)")
        (a, ap), (b, bp) = _split(args[0], line, model), _split(args[1], line, model)
        for el in (a, b):
            if el not in els:
                raise NpssConvertError(f"{model}:{line}: linkPorts: no element {el!r}")
        ra, rb = roles.get(a), roles.get(b)
        if ra in (None, "output") or rb in (None, "output"):
            continue
        if ap == "Sh_O":
            if rb != "shaft":
                raise NpssConvertError(f"{model}:{line}: linkPorts: {args[0]} goes to a shaft")
            elements[a]["shaft"] = b
            continue
        if ra in ("design", "fuel") or (ra == "nozzle" and rb == "end"):
            continue                              # the free stream into the inlet, the fuel, a nozzle's exhaust
        if (a, ap) in ports:
            src = ports[(a, ap)]
            bl: dict[str, Any] = {"from": a}
            for k, (v, ln) in src.assigns.items():
                amap = _PORT_ATTRS[src.type]
                if k not in amap:
                    raise NpssConvertError(f"{src.file}:{ln}: {a}.{ap}.{k}: cannot be carried (carried: "
                                           f"{', '.join(amap)})")
                bl[amap[k]] = _value(v, f"{src.file}:{ln}", k)
            if rb == "end":
                bl["to"] = "overboard"
            elif (b, bp) in ports:
                dst = ports[(b, bp)]
                bl["to"] = b
                for k, (v, ln) in dst.assigns.items():
                    amap = _PORT_ATTRS[dst.type]
                    if k == "diaPump" and _value(v, f"{dst.file}:{ln}", k) == 0.0:
                        continue
                    if k not in amap:
                        raise NpssConvertError(f"{dst.file}:{ln}: {b}.{bp}.{k}: cannot be carried (carried: "
                                               f"{', '.join(amap) or 'none'})")
                    bl[amap[k]] = _value(v, f"{dst.file}:{ln}", k)
            else:
                raise NpssConvertError(f"{model}:{line}: linkPorts: bleed {args[0]} must go to a bleed port or a "
                                       "FlowEnd (overboard)")
            bleeds[re.sub(r"\W", "_", args[2])] = bl
            continue
        if ap not in _OUT or bp != "Fl_I" or rb in ("end", "design", "fuel", "shaft"):
            raise NpssConvertError(f"{model}:{line}: linkPorts({args[0]}, {args[1]}): not a flow link we carry "
                                   "(Fl_O/Fl_O1/Fl_O2 to Fl_I, a bleed port, a shaft port)")
        src = a if ap == "Fl_O" and ra != "splitter" else f"{a}.{_OUT[ap]}"
        flow[_station(args[2])] = f"{src} -> {b}"
    return flow, bleeds


def _check_wref(name: str, wref: tuple[str, int], flow: dict[str, str], elements: dict[str, dict[str, Any]],
                bleeds: dict[str, dict[str, Any]], b: Block) -> None:
    """A Bleed's fractions of another station's flow are ours (of its own inflow) when no flow leaves or enters
    between that station and the bleed element."""
    ref, line = wref
    st = _station(ref.split(".")[0])
    where = f"{b.file}:{line}: element {name!r}: WrefName = {ref!r}"
    if st not in flow:
        raise NpssConvertError(f"{where}: no station {st!r}")
    cur = flow[st].split("->")[1].strip()
    seen = 0
    while cur != name:
        e = elements.get(cur, {})
        moving = [k for k, v in bleeds.items() if (v["from"] == cur or v.get("to") == cur) and v.get("frac_W", 0.0)]
        if e.get("kind") in ("burner", "splitter") or moving or seen > len(elements):
            raise NpssConvertError(f"{where}: fractions of another station's flow, with flow leaving or entering on "
                                   f"the way ({cur}): cannot be carried (our bleeds are fractions of their source's "
                                   "inflow)")
        nxt = [s for s, v in flow.items() if v.split("->")[0].strip().split(".")[0] == cur]
        if len(nxt) != 1:
            raise NpssConvertError(f"{where}: the way from {st} to {name} is not one flow path")
        cur, seen = flow[nxt[0]].split("->")[1].strip(), seen + 1
