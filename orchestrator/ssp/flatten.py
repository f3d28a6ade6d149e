"""Flatten an SSP system tree: nested systems and signal dictionaries become end-to-end connections.

Components of a nested system ``S`` are named ``S.component``. Every FMU input is
traced back, through the connectors of enclosing or nested systems and through
signal-dictionary entries, to the FMU output that feeds it; the connections met
on the way are kept in order (``Hop``), with their transformations and the units
at each end, so that system.py can compose them into one conversion.
"""
from __future__ import annotations

from dataclasses import replace

from ..errors import Problem
from .model import (
    ComponentDef,
    FlatConnection,
    Hop,
    ParameterBindingDef,
    SignalDictionaryDef,
    SystemNode,
)

Port = tuple[str, str, str]  # (kind: c(omponent) | s(ystem) | d(ictionary), owner path, connector name)


def _describe(port: Port) -> str:
    kind, owner, name = port
    if kind == "c":
        return f"{owner}.{name}"
    if kind == "s":
        return f"system connector '{owner.rstrip('.') or '<top>'}.{name}'" if owner else f"system connector '{name}'"
    return f"signal '{name}' of dictionary '{owner}'"


class _Flattener:
    def __init__(self, problems: list[Problem]) -> None:
        self.problems = problems
        self.components: list[ComponentDef] = []
        self.bindings: list[ParameterBindingDef] = []
        self.port_unit: dict[Port, str | None] = {}
        self.incoming: dict[Port, tuple[Port, Hop]] = {}
        self.component_ports: set[Port] = set()

    def visit(self, system: SystemNode, prefix: str, scopes: tuple[dict[str, tuple[str, SignalDictionaryDef]], ...]) \
            -> None:
        own = {d.name: (f"{prefix}{d.name}", d) for d in system.dictionaries}
        scopes = (own, *scopes)
        for k in system.connectors:
            self.port_unit[("s", prefix, k.name)] = k.unit
        for b in system.bindings:
            self.bindings.append(replace(b, prefix=prefix + b.prefix))
        elements: dict[str, str] = {}  # element name -> kind
        for c in system.components:
            full = prefix + c.name
            self.components.append(replace(c, name=full))
            elements[c.name] = "c"
            for k in c.connectors:
                self.port_unit[("c", full, k.name)] = k.unit
                self.component_ports.add(("c", full, k.name))
        references: dict[str, str] = {}
        for r in system.references:
            elements[r.name] = "d"
            found = next((scope[r.dictionary] for scope in scopes if r.dictionary in scope), None)
            if found is None:
                self.problems.append(Problem(r.where, f"signal dictionary reference '{r.name}': no dictionary "
                                                      f"named '{r.dictionary}' in this system or its parents"))
                continue
            ident, dictionary = found
            references[r.name] = ident
            for k in r.connectors:
                entry = dictionary.entries.get(k.name)
                if entry is None:
                    self.problems.append(Problem(k.where, f"'{r.name}.{k.name}': dictionary '{r.dictionary}' has "
                                                          f"no entry '{k.name}'"))
                    continue
                self.port_unit[("d", ident, k.name)] = k.unit or entry.unit
        for sub in system.systems:
            elements[sub.name] = "s"
            self.visit(sub, f"{prefix}{sub.name}.", scopes)
        declared = {name: {k.name for k in conns} for name, conns in
                    [(c.name, c.connectors) for c in system.components]
                    + [(s.name, s.connectors) for s in system.systems]
                    + [(r.name, r.connectors) for r in system.references]}
        own_connectors = {k.name for k in system.connectors}
        for conn in system.connections:
            ends = []
            for elem, cname in ((conn.start_element, conn.start_connector), (conn.end_element, conn.end_connector)):
                port = self._port(elem, cname, prefix, elements, references, declared, own_connectors, conn.where)
                ends.append(port)
            start, end = ends
            if start is None or end is None:
                continue
            hop = Hop(conn.transformation, conn.suppress_unit_conversion, self.port_unit.get(start),
                      self.port_unit.get(end), conn.where)
            if end in self.incoming:
                other = self.incoming[end][1].where
                self.problems.append(Problem(conn.where, f"input '{_describe(end)}' has two incoming connections "
                                                         f"(the other at {other}); an input takes exactly one"))
                continue
            self.incoming[end] = (start, hop)

    def _port(self, elem: str, cname: str, prefix: str, elements: dict[str, str], references: dict[str, str],
              declared: dict[str, set[str]], own_connectors: set[str], where: str) -> Port | None:
        if not elem:
            if cname not in own_connectors:
                self.problems.append(Problem(where, f"connection names system connector '{cname}', which the "
                                                    "system does not declare"))
                return None
            return ("s", prefix, cname)
        kind = elements.get(elem)
        if kind is None:
            self.problems.append(Problem(where, f"connection names no element '{elem}' (elements here: "
                                                f"{', '.join(sorted(elements)) or 'none'})"))
            return None
        if kind == "c":
            if cname not in declared[elem]:
                self.problems.append(Problem(where, f"component '{prefix}{elem}' declares no connector '{cname}'"))
                return None
            return ("c", prefix + elem, cname)
        if cname not in declared[elem]:
            what = "system" if kind == "s" else "signal dictionary reference"
            self.problems.append(Problem(where, f"{what} '{prefix}{elem}' declares no connector '{cname}'"))
            return None
        if kind == "s":
            return ("s", f"{prefix}{elem}.", cname)
        return ("d", references[elem], cname) if elem in references else None

    def connections(self) -> list[FlatConnection]:
        flat: list[FlatConnection] = []
        for end in sorted(p for p in self.incoming if p[0] == "c"):
            hops: list[Hop] = []
            port: Port = end
            seen = {end}
            while True:
                src, hop = self.incoming[port]
                hops.insert(0, hop)
                if src[0] == "c":
                    flat.append(FlatConnection(src[1], src[2], end[1], end[2], tuple(hops)))
                    break
                if src in seen:
                    self.problems.append(Problem(hop.where, f"connections around {_describe(src)} form a loop "
                                                            "without a component"))
                    break
                seen.add(src)
                if src not in self.incoming:
                    self.problems.append(Problem(hop.where, f"'{_describe(end)}' is fed by {_describe(src)}, which "
                                                            "nothing feeds (top-level system inputs are not "
                                                            "supported: use a parameter or a scenario)"))
                    break
                port = src
        return flat


def flatten(root: SystemNode, problems: list[Problem]) \
        -> tuple[tuple[ComponentDef, ...], tuple[FlatConnection, ...], tuple[ParameterBindingDef, ...]]:
    """Components (dotted names), end-to-end connections and system-level bindings of a system tree."""
    f = _Flattener(problems)
    f.visit(root, "", ())
    return tuple(f.components), tuple(f.connections()), tuple(f.bindings)

