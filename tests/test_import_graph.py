"""No import cycles inside a model package (issue 18) or the orchestrator (issue 20): every relative import that
runs, at module level or inside a function (a lazy import hides a cycle, it does not remove it), makes an edge of
the package's graph. The orchestrator's modules also import one way only, from the command line down to the SSP
model (issue 20): a module's part is its sub-package of orchestrator/."""
from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import pytest

MODELS = Path(__file__).resolve().parents[1] / "models"
ORCHESTRATOR = Path(__file__).resolve().parents[1] / "orchestrator"

#: The level of every part of the orchestrator, lowest first (orchestrator/README.md describes them). A part is
#: a sub-package; "" is the package root, the shared modules (SHARED). A module imports modules of its own part
#: or of lower parts only; fmu/ and scenarios/ are side by side.
PART_LEVEL = {"": 0, "ssp": 1, "master": 2, "fmu": 3, "scenarios": 3, "cli": 4}
SHARED = {"__init__", "errors", "results", "interrupt"}


def _runtime_nodes(tree: ast.AST) -> list[ast.AST]:
    """Every node but those under ``if TYPE_CHECKING:`` (imports for type hints only, never run)."""
    out: list[ast.AST] = []
    todo = [tree]
    while todo:
        node = todo.pop()
        out.append(node)
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and ast.unparse(child.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING"):
                todo.extend(child.orelse)
                continue
            todo.append(child)
    return out


def _graph(pkg: Path) -> dict[str, set[str]]:
    g: dict[str, set[str]] = {}
    for f in sorted(pkg.glob("*.py")):
        edges = g.setdefault(f.stem, set())
        for node in _runtime_nodes(ast.parse(f.read_text(encoding="utf-8"), filename=str(f))):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                if node.module:
                    edges.add(node.module.split(".")[0])
                else:
                    edges.update(a.name for a in node.names)
    return {m: {e for e in es if e in g or (pkg / f"{e}.py").is_file()} for m, es in g.items()}


def _cycle(g: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``g`` (depth-first search with colours), or None."""
    colour: dict[str, int] = {}
    path: list[str] = []

    def visit(v: str) -> list[str] | None:
        colour[v] = 1
        path.append(v)
        for w in sorted(g.get(v, ())):
            if colour.get(w) == 1:
                return path[path.index(w):] + [w]
            if colour.get(w) is None and (c := visit(w)):
                return c
        colour[v] = 2
        path.pop()
        return None

    for v in sorted(g):
        if colour.get(v) is None and (c := visit(v)):
            return c
    return None


def test_type_checking_imports_are_not_edges() -> None:
    tree = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .a import X\nfrom .b import Y\n")
    assert [n.module for n in _runtime_nodes(tree) if isinstance(n, ast.ImportFrom) and n.level == 1] == ["b"]


def test_the_search_finds_a_cycle() -> None:
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


@pytest.mark.parametrize("pkg", sorted(p.name for p in MODELS.iterdir() if (p / "__init__.py").is_file()))
def test_no_import_cycle_in_model_package(pkg: str) -> None:
    cycle = _cycle(_graph(MODELS / pkg))
    assert cycle is None, " -> ".join(cycle or [])


def _modules(pkg: Path) -> dict[str, Path]:
    """Every module of the orchestrator by dotted name relative to it (``master.exchange``; ``master.__init__``)."""
    mods: dict[str, Path] = {}
    for f in sorted(pkg.rglob("*.py")):
        rel = f.relative_to(pkg).with_suffix("").parts
        if any(not (pkg.joinpath(*rel[:i]) / "__init__.py").is_file() for i in range(1, len(rel))):
            continue  # not in a package (a data folder, a package mapped elsewhere has its own __init__)
        mods[".".join(rel)] = f
    return mods


def _resolve(target: list[str], names: list[str], mods: dict[str, Path]) -> set[str]:
    """The modules that ``from <target> import <names>`` runs (``target`` relative to the orchestrator)."""
    dotted = ".".join(target)
    if dotted in mods:
        return {dotted}
    if f"{dotted}.__init__" in mods or not target:
        base = f"{dotted}." if target else ""
        subs = {f"{base}{n}" for n in names if f"{base}{n}" in mods}
        subs |= {f"{base}{n}.__init__" for n in names if f"{base}{n}.__init__" in mods}
        return subs if names and len(subs) == len(names) else subs | {f"{base}__init__"}
    for i in range(len(target) - 1, 0, -1):  # an attribute path: the longest prefix that is a module
        if ".".join(target[:i]) in mods:
            return {".".join(target[:i])}
    return set()


def _orchestrator_graph(pkg: Path) -> dict[str, set[str]]:
    """Module -> the orchestrator modules it imports when it runs (relative and ``openemss.orchestrator`` imports)."""
    mods = _modules(pkg)
    g: dict[str, set[str]] = {}
    for name, f in mods.items():
        base = name.split(".")[:-1]  # the package the module is in
        edges = g.setdefault(name, set())
        for node in _runtime_nodes(ast.parse(f.read_text(encoding="utf-8"), filename=str(f))):
            if isinstance(node, ast.ImportFrom) and node.level:
                up = node.level - 1
                if up > len(base):
                    continue
                anchor = base[:len(base) - up]
                target = anchor + (node.module.split(".") if node.module else [])
                edges |= _resolve(target, [a.name for a in node.names], mods)
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("openemss.orchestrator"):
                edges |= _resolve(node.module.split(".")[2:], [a.name for a in node.names], mods)
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.startswith("openemss.orchestrator."):
                        edges |= _resolve(a.name.split(".")[2:], [], mods)
        edges.discard(name)
    return g


def _wrong_way(pkg: Path, level: dict[str, int]) -> list[str]:
    """Imports up the parts, or sideways into another part of the same level."""
    out = []
    for m, edges in sorted(_orchestrator_graph(pkg).items()):
        for e in sorted(edges):
            pm, pe = _part_in(pkg, m), _part_in(pkg, e)
            if pm in level and pe in level and (level[pe] > level[pm] or (level[pe] == level[pm] and pe != pm)):
                out.append(f"{m} ({pm or 'shared'}) imports {e} ({pe or 'shared'})")
    return out


def _part_in(pkg: Path, module: str) -> str:
    """A module's part: its sub-package, or "" for the shared modules at the package root."""
    head = module.split(".")[0]
    return head if (pkg / head / "__init__.py").is_file() else ""


def _mapped_elsewhere() -> set[str]:
    """Sub-folders of orchestrator/ that pyproject maps to a package of their own (not parts)."""
    config = tomllib.loads((ORCHESTRATOR.parent / "pyproject.toml").read_text())["tool"]["setuptools"]
    return {Path(d).relative_to("orchestrator").parts[0] for p, d in config.get("package-dir", {}).items()
            if Path(d).parts[:1] == ("orchestrator",) and len(Path(d).parts) > 1}


def test_the_part_check_finds_upward_and_sideways_imports(tmp_path: Path) -> None:
    for sub in ("master", "scenarios", "fmu", "cli"):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "__init__.py").write_text("")
    (tmp_path / "__init__.py").write_text("")
    (tmp_path / "errors.py").write_text("")
    (tmp_path / "cli" / "main.py").write_text("")
    (tmp_path / "master" / "exchange.py").write_text("from ..errors import X\n\ndef f():\n    from ..cli import main\n")
    (tmp_path / "scenarios" / "observers.py").write_text("from ..master.exchange import E\nfrom ..fmu.build import B\n")
    (tmp_path / "fmu" / "build.py").write_text("from openemss.orchestrator.master import exchange\n")
    assert _wrong_way(tmp_path, {"": 0, "master": 2, "scenarios": 3, "fmu": 3, "cli": 4}) == [
        "master.exchange (master) imports cli.main (cli)",
        "scenarios.observers (scenarios) imports fmu.build (fmu)"]
    assert _cycle(_orchestrator_graph(tmp_path)) is None
    (tmp_path / "errors.py").write_text("from .master import exchange\n")
    assert _cycle(_orchestrator_graph(tmp_path)) == ["errors", "master.exchange", "errors"]


def test_no_import_cycle_in_the_orchestrator() -> None:
    cycle = _cycle(_orchestrator_graph(ORCHESTRATOR))
    assert cycle is None, " -> ".join(cycle or [])


def test_every_orchestrator_module_is_in_a_part() -> None:
    flat = {f.stem for f in ORCHESTRATOR.glob("*.py")} - SHARED
    assert flat == set(), "put the new module in its part's sub-package (and in orchestrator/README.md's table)"
    subs = {p.name for p in ORCHESTRATOR.iterdir() if (p / "__init__.py").is_file()} - _mapped_elsewhere()
    assert subs - set(PART_LEVEL) == set(), "give the new sub-package its level in PART_LEVEL (and a README line)"


def test_orchestrator_imports_go_one_way_down_the_parts() -> None:
    assert _wrong_way(ORCHESTRATOR, PART_LEVEL) == []
