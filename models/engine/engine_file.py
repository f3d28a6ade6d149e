"""Engine files: an engine's elements, flow links by station, shaft links, bleed links, design values and maps.

An engine file is YAML (``models/engine/README.md``, "Define your engine", documents it with examples)::

    name: Larzac 04-C6
    sources: [...]                        # where each number comes from (free text)
    design: {alt_m: 0, Mach: 0, W_kg_s: 27.64}        # or Fn_N: the design sizes the mass flow
    fuel: {LHV_J_kg: 43.1e+6}             # optional
    elements:                             # name: {kind: ..., attributes}; kinds in element_kinds.KINDS
      inlet: {kind: inlet, pi: 0.995}
      fan: {kind: fan, shaft: lp, map: lpc_hbtf, PR: 2.25, eta: 0.83, BPR: 1.13}
      ...
    shafts:                               # name: {N_rpm: ..., eta_mech: ..., offtake_W: ...}
      lp: {N_rpm: 17300}
    flow:                                 # station: from[.port] -> to[.port]
      "2": inlet -> fan
      "13": fan.bypass -> bypass_duct
    bleeds:                               # name: {from: compressor or duct, to: turbine, duct or overboard, ...}
      cool_ngv: {from: hpc, to: hpt, frac_W: 0.063}

:func:`read_engine_file` reads it into an :class:`EngineDef` and checks what the file alone can tell: every
attribute (type, unit, range), every name, every port connected once, one inlet, every element reached from it
and no loop (the flow path closes), every shaft driven by a turbine. Each problem is one line naming the file,
the line and the element (:class:`EngineFileError`). What needs the cycle (a map that does not cover the design
point, a balance that cannot be formed) is checked by :mod:`.engine_graph` with the same kind of message.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..infra import safe_yaml, values
from .element_kinds import (
    BLEED_ATTRS,
    DESIGN_ATTRS,
    FUEL_ATTRS,
    KINDS,
    LIMIT_ATTRS,
    REQUIRED,
    SCHEDULE_ATTRS,
    SHAFT_ATTRS,
    Attr,
    check_attr,
)
from .errors import ModelError

__all__ = ["EngineFileError", "ElementDef", "FlowLink", "BleedDef", "ShaftDef", "EngineDef", "read_engine_file",
           "engine_path", "ENGINES_DIR", "scale_engine"]

#: Folder of the shipped engine files.
ENGINES_DIR: Path = Path(__file__).resolve().parent / "engines"
TOP_KEYS = ("name", "sources", "notes", "design", "fuel", "elements", "shafts", "flow", "bleeds", "limits", "outputs")
#: An output of the file (``outputs:``): ``name: element.quantity`` or ``name: shaft NAME.quantity``.
_OUTPUT = re.compile(r"^\s*(?:(shaft)\s+)?([A-Za-z_]\w*)\.([A-Za-z_]\w*)\s*$")
_LINK = re.compile(r"^\s*([A-Za-z_][\w]*)(?:\.([A-Za-z_]\w*))?\s*->\s*([A-Za-z_][\w]*)(?:\.([A-Za-z_]\w*))?\s*$")
_NAME = re.compile(r"^[A-Za-z_][\w]*$")


class EngineFileError(ModelError):
    """An engine file that cannot be used: one line, ``file:line: element 'name': what; what is allowed``."""


@dataclass(frozen=True)
class ElementDef:
    """An element: its name, kind, checked attributes (defaults filled), and the file lines of each."""

    name: str
    kind: str
    attrs: Mapping[str, Any]
    line: int
    lines: Mapping[str, int]


@dataclass(frozen=True)
class FlowLink:
    """A flow link: station name, source element and outlet port, destination element and inlet port."""

    station: str
    src: str
    src_port: str
    dst: str
    dst_port: str
    line: int


@dataclass(frozen=True)
class BleedDef:
    """A bleed link (attributes of :data:`.element_kinds.BLEED_ATTRS`; ``to`` None: overboard)."""

    name: str
    src: str
    dst: str | None
    frac_W: float
    frac_P: float
    frac_work: float
    stage: int | None
    entry: float
    schedule: Mapping[str, Any] | None
    line: int


@dataclass(frozen=True)
class ShaftDef:
    """A shaft (attributes of :data:`.element_kinds.SHAFT_ATTRS`)."""

    name: str
    attrs: Mapping[str, Any]
    line: int


@dataclass(frozen=True)
class EngineDef:
    """A read and checked engine file."""

    name: str
    file: str
    elements: Mapping[str, ElementDef]
    links: tuple[FlowLink, ...]
    bleeds: tuple[BleedDef, ...]
    shafts: Mapping[str, ShaftDef]
    design: Mapping[str, Any]
    fuel: Mapping[str, Any]
    order: tuple[str, ...]          #: elements in flow order (sources before sinks, bleeds included)
    lines: Mapping[str, int]        #: line of each top-level key
    limits: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))  #: the FCS's limits (LIMIT_ATTRS)
    #: the file's own outputs: name -> ("element" or "shaft", its name, quantity, line)
    outputs: Mapping[str, tuple[str, str, str, int]] = field(default_factory=lambda: MappingProxyType({}))

    def where(self, element: str | None = None, attr: str | None = None, line: int | None = None) -> str:
        """``file:line: element 'name':`` for messages (the attribute's line where known)."""
        if line is None:
            e = self.elements.get(element) if element else None
            line = (e.lines.get(attr, e.line) if attr else e.line) if e else 1
        return f"{self.file}:{line}: " + (f"element {element!r}: " if element else "")


class _Lines(safe_yaml.LineDict):
    pass


def _loader() -> Any:
    import yaml

    class Loader(yaml.SafeLoader):
        def construct_mapping(self, node: Any, deep: bool = False) -> _Lines:  # type: ignore[override]
            out = _Lines(super().construct_mapping(node, deep=True))
            out.lines = {self.construct_object(k, deep=True): k.start_mark.line + 1 for k, _ in node.value}
            return out

    Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, Loader.construct_mapping)
    return Loader


def engine_path(name_or_path: str | Path) -> Path:
    """The file of a shipped engine name (``larzac04``) or a path as given."""
    p = Path(name_or_path)
    if p.suffix in (".yaml", ".yml") or len(p.parts) > 1:
        return p
    q = ENGINES_DIR / f"{name_or_path}.yaml"
    if not q.is_file():
        known = ", ".join(sorted(x.stem for x in ENGINES_DIR.glob("*.yaml")))
        raise EngineFileError(f"no engine {str(name_or_path)!r}: give an engine file (.yaml) or a shipped name "
                              f"({known})")
    return q


def read_engine_file(name_or_path: str | Path) -> EngineDef:
    """Read and check an engine file (a path, or a shipped name of :data:`ENGINES_DIR`).

    Raises
    ------
    EngineFileError
        One line naming the file, the line, the element and what is allowed.
    """
    p = engine_path(name_or_path)
    f = str(p)
    if not p.is_file():
        raise EngineFileError(f"engine file {f} does not exist")
    try:
        data = safe_yaml.load(safe_yaml.read_text(p, "engine file"), f, loader=_loader())
    except safe_yaml.YamlError as exc:
        raise EngineFileError(str(exc)) from None
    if not isinstance(data, dict):
        raise EngineFileError(f"{f}:1: an engine file is a mapping with the keys {', '.join(TOP_KEYS)}")
    ln = dict(getattr(data, "lines", {}))
    for k in data:
        if k not in TOP_KEYS:
            raise EngineFileError(f"{f}:{ln.get(k, 1)}: unknown key {k!r}; allowed: {', '.join(TOP_KEYS)}")
    for k in ("elements", "flow"):
        if not isinstance(data.get(k), dict) or not data[k]:
            raise EngineFileError(f"{f}:{ln.get(k, 1)}: {k!r} must be a non-empty mapping"
                                  + ("" if k in data else " (missing)"))
    for k in ("sources", "notes"):
        for item in data.get(k) if isinstance(data.get(k), list) else ([data[k]] if k in data else []):
            _wrap(lambda it=item: values.text(it, "a text or a list of texts"), f, ln.get(k, 1), k)
    name = _wrap(lambda: values.text(data.get("name", p.stem), "a name"), f, ln.get("name", 1), "name")
    design = _attrs(data.get("design", {}), DESIGN_ATTRS, f, ln.get("design", 1), "design")
    if (design["W_kg_s"] is None) == (design["Fn_N"] is None) and "design" in data and not _sized_otherwise(data):
        raise EngineFileError(f"{f}:{ln.get('design', 1)}: design: give one of W_kg_s and Fn_N (or size the engine "
                              "by a nozzle's PR_design and a shaft's load_W)")
    fuel = _attrs(data.get("fuel", {}), FUEL_ATTRS, f, ln.get("fuel", 1), "fuel")
    limits = _attrs(data.get("limits", {}), LIMIT_ATTRS, f, ln.get("limits", 1), "limits")
    shafts = {}
    raw_sh = data.get("shafts", {}) or {}
    if not isinstance(raw_sh, dict):
        raise EngineFileError(f"{f}:{ln.get('shafts', 1)}: 'shafts' must be a mapping of shaft names")
    for s, v in raw_sh.items():
        line = raw_sh.lines[s]
        _check_name(s, f, line, "shaft")
        shafts[s] = ShaftDef(s, _attrs(v, SHAFT_ATTRS, f, line, f"shaft {s!r}"), line)
    elements = {}
    for e, v in data["elements"].items():
        line = data["elements"].lines[e]
        _check_name(e, f, line, "element")
        elements[e] = _element(e, v, f, line, shafts)
    links = _links(data["flow"], elements, f)
    bleeds = _bleeds(data.get("bleeds", {}) or {}, elements, f, ln.get("bleeds", 1))
    eng = EngineDef(str(name), f, MappingProxyType(elements), tuple(links), tuple(bleeds), MappingProxyType(shafts),
                    MappingProxyType(design), MappingProxyType(fuel), (), MappingProxyType(ln))
    order = _check_topology(eng)
    return EngineDef(eng.name, f, eng.elements, eng.links, eng.bleeds, eng.shafts, eng.design, eng.fuel, order,
                     eng.lines, MappingProxyType(limits), _outputs(data.get("outputs", {}) or {}, eng, ln))


def _outputs(raw: Any, eng: EngineDef, ln: Mapping[str, int]) -> Mapping[str, tuple[str, str, str, int]]:
    """The file's own outputs (``outputs: {name: element.quantity | shaft NAME.quantity}``), names checked; the
    quantities are checked where the engine is first evaluated (:mod:`.graph_engine`)."""
    f, line0 = eng.file, ln.get("outputs", 1)
    if not isinstance(raw, dict):
        raise EngineFileError(f"{f}:{line0}: 'outputs' must be a mapping name: element.quantity or shaft NAME.quantity")
    out = {}
    for name, v in raw.items():
        line = raw.lines[name]
        _check_name(name, f, line, "output")
        m = _OUTPUT.match(v) if isinstance(v, str) else None
        if m is None:
            raise EngineFileError(f"{f}:{line}: output {name!r}: {values.show(v)} is not element.quantity or "
                                  "shaft NAME.quantity (e.g. ab.Wf_kg_s, shaft pt.torque_N_m)")
        kind, target, q = ("shaft" if m.group(1) else "element"), m.group(2), m.group(3)
        known = eng.shafts if kind == "shaft" else eng.elements
        if target not in known:
            raise EngineFileError(f"{f}:{line}: output {name!r}: no {kind} {target!r} (the file's: "
                                  f"{', '.join(known) or 'none'})")
        out[name] = (kind, target, q, line)
    return MappingProxyType(out)


def _sized_otherwise(data: Any) -> bool:
    """A design without W_kg_s and Fn_N is sized by a nozzle's PR_design (checked as a balance later)."""
    d = data.get("design", {}) or {}
    if d.get("W_kg_s") is not None and d.get("Fn_N") is not None:
        return False
    els = data.get("elements", {})
    return any(isinstance(v, dict) and "PR_design" in v for v in els.values())


def _wrap(fn: Any, f: str, line: int, what: str) -> Any:
    try:
        return fn()
    except values.ValueProblem as exc:
        raise EngineFileError(f"{f}:{line}: {what}: {exc}") from None


def _check_name(n: Any, f: str, line: int, what: str) -> None:
    if not isinstance(n, str) or not _NAME.match(n):
        raise EngineFileError(f"{f}:{line}: {what} name {n!r}: a name is letters, digits and _, not starting with "
                              "a digit")


def _attrs(v: Any, spec: Mapping[str, Attr], f: str, line: int, what: str,
           skip: tuple[str, ...] = ()) -> dict[str, Any]:
    """The attributes of mapping `v` checked against `spec`, defaults filled (None: not given)."""
    if not isinstance(v, dict):
        raise EngineFileError(f"{f}:{line}: {what}: expected a mapping of attributes, got {values.show(v)}")
    lines = getattr(v, "lines", {})
    out: dict[str, Any] = {}
    for k, x in v.items():
        if k in skip:
            continue
        at = lines.get(k, line)
        if k not in spec:
            raise EngineFileError(f"{f}:{at}: {what}: unknown attribute {k!r}; allowed: {', '.join(spec)}")
        out[k] = _wrap(lambda a=spec[k], x=x: check_attr(a, x), f, at, f"{what} '{k}'")
    for k, a in spec.items():
        if k not in out:
            if a.default is REQUIRED:
                raise EngineFileError(f"{f}:{line}: {what}: attribute {k!r} is missing ({a.doc})")
            out[k] = a.default
    return out


def _element(name: str, v: Any, f: str, line: int, shafts: Mapping[str, ShaftDef]) -> ElementDef:
    if not isinstance(v, dict) or "kind" not in v:
        raise EngineFileError(f"{f}:{line}: element {name!r}: expected a mapping with 'kind' (one of "
                              f"{', '.join(KINDS)})")
    kind = _wrap(lambda: values.choice(v["kind"], KINDS), f, v.lines.get("kind", line), f"element {name!r} 'kind'")
    attrs = _attrs(v, KINDS[kind].attrs, f, line, f"element {name!r}", skip=("kind",))
    lines = dict(v.lines)
    if KINDS[kind].shaft and attrs["shaft"] not in shafts:
        raise EngineFileError(f"{f}:{lines.get('shaft', line)}: element {name!r}: shaft {attrs['shaft']!r} is not "
                              f"declared under 'shafts' ({', '.join(shafts) or 'none declared'})")
    return ElementDef(name, kind, MappingProxyType(attrs), line, MappingProxyType(lines))


def _links(flow: Any, elements: Mapping[str, ElementDef], f: str) -> list[FlowLink]:
    out: list[FlowLink] = []
    used: dict[tuple[str, str], int] = {}
    for st, v in flow.items():
        line = flow.lines[st]
        st = values.name(st, "a station name") if not isinstance(st, bool) else str(st)
        m = _LINK.match(v) if isinstance(v, str) else None
        if m is None:
            raise EngineFileError(f"{f}:{line}: station {st!r}: expected 'element[.port] -> element[.port]', got "
                                  f"{values.show(v)}")
        a, ap, b, bp = m.groups()
        ends = []
        for el, port, side in ((a, ap, "outlets"), (b, bp, "inlets")):
            if el not in elements:
                raise EngineFileError(f"{f}:{line}: station {st!r}: no element {el!r} (elements: "
                                      f"{', '.join(elements)})")
            ports = getattr(KINDS[elements[el].kind], side)
            if port is None:
                if len(ports) != 1:
                    raise EngineFileError(f"{f}:{line}: station {st!r}: element {el!r} ({elements[el].kind}) has "
                                          + (f"no {side[:-1]} port" if not ports else
                                             f"the {side[:-1]} ports {', '.join(ports)}: name one as {el}.port"))
                port = ports[0]
            elif port not in ports:
                raise EngineFileError(f"{f}:{line}: station {st!r}: element {el!r} ({elements[el].kind}) has no "
                                      f"{side[:-1]} port {port!r} (its {side[:-1]} ports: "
                                      f"{', '.join(ports) or 'none'})")
            if (el, port) in used:
                raise EngineFileError(f"{f}:{line}: station {st!r}: element {el!r}: port {port!r} is already "
                                      f"connected at line {used[(el, port)]}")
            used[(el, port)] = line
            ends.append(port)
        out.append(FlowLink(st, a, ends[0], b, ends[1], line))
    for e in elements.values():
        k = KINDS[e.kind]
        for port in k.inlets + k.outlets:
            if (e.name, port) not in used:
                raise EngineFileError(f"{f}:{e.line}: element {e.name!r} ({e.kind}): port {port!r} is not "
                                      "connected; connect it under 'flow:' (station: from.port -> to.port)")
    return out


def _bleeds(raw: Any, elements: Mapping[str, ElementDef], f: str, line0: int) -> list[BleedDef]:
    if not isinstance(raw, dict):
        raise EngineFileError(f"{f}:{line0}: 'bleeds' must be a mapping of bleed names")
    out = []
    for n, v in raw.items():
        line = raw.lines[n]
        _check_name(n, f, line, "bleed")
        a = _attrs(v, BLEED_ATTRS, f, line, f"bleed {n!r}")
        src, dst = a["from"], a["to"]
        if src not in elements or not KINDS[elements[src].kind].bleed_source:
            ok = [e for e in elements if KINDS[elements[e].kind].bleed_source]
            raise EngineFileError(f"{f}:{v.lines.get('from', line)}: bleed {n!r}: 'from' must be a compressor or "
                                  f"duct ({', '.join(ok) or 'none'}), got {src!r}")
        if dst != "overboard" and (dst not in elements or not KINDS[elements[dst].kind].bleed_sink):
            ok = [e for e in elements if KINDS[elements[e].kind].bleed_sink]
            raise EngineFileError(f"{f}:{v.lines.get('to', line)}: bleed {n!r}: 'to' must be a turbine, a duct "
                                  f"({', '.join(ok) or 'none'}) or overboard, got {dst!r}")
        if a["stage"] is not None:
            stages = elements[src].attrs.get("stages")
            if stages is None or a["stage"] > stages:
                raise EngineFileError(f"{f}:{v.lines.get('stage', line)}: bleed {n!r}: stage {a['stage']} of "
                                      f"element {src!r}, which has {stages or 'no'} stages")
        sched = None
        if a["schedule"] is not None:
            sl = v.lines.get("schedule", line)
            sched = MappingProxyType(_attrs(a["schedule"], SCHEDULE_ATTRS, f, sl, f"bleed {n!r} schedule"))
            if sched["of"] not in elements or elements[sched["of"]].kind not in ("compressor", "fan"):
                raise EngineFileError(f"{f}:{sl}: bleed {n!r}: schedule 'of' must name a compressor, got "
                                      f"{sched['of']!r}")
        out.append(BleedDef(n, src, None if dst == "overboard" else dst, a["frac_W"], a["frac_P"], a["frac_work"],
                            a["stage"], a["entry"], sched, line))
    return out


def _check_topology(eng: EngineDef) -> tuple[str, ...]:
    """Flow order of the elements (Kahn's algorithm over flow and bleed links); one inlet, every element reached
    from it, no loop; every shaft driven by a turbine."""
    f = eng.file
    inlets = [e for e in eng.elements.values() if e.kind == "inlet"]
    if len(inlets) != 1:
        raise EngineFileError(f"{f}:{eng.lines.get('elements', 1)}: an engine has one element of kind 'inlet', "
                              f"this one has {len(inlets)}")
    succ: dict[str, list[str]] = {e: [] for e in eng.elements}
    for lk in eng.links:
        succ[lk.src].append(lk.dst)
    reached, todo = {inlets[0].name}, [inlets[0].name]
    while todo:
        for n in succ[todo.pop()]:
            if n not in reached:
                reached.add(n)
                todo.append(n)
    for e in eng.elements.values():
        if e.name not in reached:
            raise EngineFileError(f"{eng.where(e.name)}the flow path does not close: no flow from the inlet reaches "
                                  "it (check the stations under 'flow:')")
    for b in eng.bleeds:
        if b.dst is not None:
            succ[b.src].append(b.dst)
        if b.schedule is not None:
            succ[b.schedule["of"]].append(b.src)
    indeg = {e: 0 for e in eng.elements}
    for s in succ.values():
        for n in s:
            indeg[n] += 1
    ready = [e for e in eng.elements if indeg[e] == 0]
    order = []
    while ready:
        e = ready.pop(0)
        order.append(e)
        for n in succ[e]:
            indeg[n] -= 1
            if indeg[n] == 0:
                ready.append(n)
    if len(order) != len(eng.elements):
        stuck = next(e for e in eng.elements if e not in order)
        raise EngineFileError(f"{eng.where(stuck)}the flow path loops back on itself here (a flow or bleed link, "
                              "or a bleed schedule read downstream): loops are not supported")
    for s in eng.shafts.values():
        on = [e for e in eng.elements.values() if KINDS[e.kind].shaft and e.attrs["shaft"] == s.name]
        if not any(e.kind == "turbine" for e in on):
            raise EngineFileError(f"{f}:{s.line}: shaft {s.name!r}: no turbine drives it (on it: "
                                  f"{', '.join(e.name for e in on) or 'nothing'})")
    return tuple(order)


def scale_engine(eng: EngineDef, thrust_scale: float) -> EngineDef:
    """The engine scaled at constant cycle by geometric similarity: airflow, thrust, fuel flow, powers and every
    area by `thrust_scale` (the design's ``W_kg_s`` or ``Fn_N``, each shaft's ``load_W`` and ``offtake_W``; the
    areas follow, sized by the design), lengths by its square root, so that at the same tip speeds each shaft's
    ``N_rpm`` goes with ``thrust_scale**-0.5`` and its ``I_kg_m2`` (mass times length squared) with
    ``thrust_scale**2.5``. Temperatures, pressures, pressure ratios, SFC and relative speeds are unchanged; a
    spool's time constant I omega^2 / P goes with ``thrust_scale**0.5``.

    References
    ----------
    P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 4 (scaling an engine at constant
    cycle: flow and thrust with the square of the linear scale, speeds with its inverse).

    Raises
    ------
    EngineFileError
        `thrust_scale` not a finite number > 0.
    """
    s = float(thrust_scale)
    if not (s > 0.0 and s < math.inf):
        raise EngineFileError(f"{eng.file}: thrust_scale={thrust_scale!r} must be a finite number > 0")
    if s == 1.0:
        return eng
    design = dict(eng.design)
    for k in ("W_kg_s", "Fn_N"):
        if design[k] is not None:
            design[k] = design[k] * s
    shafts = {}
    for name, sh in eng.shafts.items():
        a = dict(sh.attrs)
        a["N_rpm"] = a["N_rpm"] / math.sqrt(s)
        a["I_kg_m2"] = a["I_kg_m2"] * s ** 2.5
        a["offtake_W"] = a["offtake_W"] * s
        if a["load_W"] is not None:
            a["load_W"] = a["load_W"] * s
        shafts[name] = ShaftDef(name, MappingProxyType(a), sh.line)
    return replace(eng, design=MappingProxyType(design), shafts=MappingProxyType(shafts))
