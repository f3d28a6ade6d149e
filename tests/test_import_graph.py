"""No import cycles inside a model package (issue 18) or the orchestrator (issue 20): every relative import that
runs, at module level or inside a function (a lazy import hides a cycle, it does not remove it), makes an edge of
the package's graph. The orchestrator's modules also import one way only, from the command line down to the SSP
model (issue 20), so that grouping them into sub-packages by part is a pure move."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

MODELS = Path(__file__).resolve().parents[1] / "models"
ORCHESTRATOR = Path(__file__).resolve().parents[1] / "orchestrator"

#: The part of every orchestrator module, lowest first (orchestrator/README.md describes them). A module imports
#: modules of its own part or of lower parts only; "export" and "scenarios" are side by side, both over "master".
PART_LEVEL = {"shared": 0, "ssp": 1, "master": 2, "scenarios": 3, "export": 3, "cli": 4}
PARTS = {
    "__init__": "shared", "errors": "shared", "results": "shared",
    "units": "ssp", "conversion": "ssp", "ssp_model": "ssp", "ssp": "ssp", "flatten": "ssp", "ssp_write": "ssp",
    "system_model": "ssp", "parameters": "ssp", "system": "ssp",
    "transfer": "master", "slave": "master", "exchange": "master", "algorithm": "master",
    "iterative": "master", "algorithm_registry": "master", "condition": "master", "execution": "master",
    "manipulators": "scenarios", "observers": "scenarios", "timeseries": "scenarios",
    "build": "export", "export": "export", "fmu_deps": "export",
    "cli": "cli", "plugins": "cli", "hooks": "cli", "api": "cli", "describe": "cli",
}


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


def test_no_import_cycle_in_the_orchestrator() -> None:
    cycle = _cycle(_graph(ORCHESTRATOR))
    assert cycle is None, " -> ".join(cycle or [])


def test_every_orchestrator_module_has_a_part() -> None:
    on_disk = {f.stem for f in ORCHESTRATOR.glob("*.py")}
    assert on_disk - set(PARTS) == set(), "give the new module its part in PARTS (and in orchestrator/README.md)"



def test_orchestrator_imports_go_one_way_down_the_parts() -> None:
    upward = [f"{m} ({PARTS[m]}) imports {e} ({PARTS[e]})" for m, edges in sorted(_graph(ORCHESTRATOR).items())
              for e in sorted(edges) if m in PARTS and e in PARTS and PART_LEVEL[PARTS[e]] > PART_LEVEL[PARTS[m]]
              or (m in PARTS and e in PARTS and PART_LEVEL[PARTS[e]] == PART_LEVEL[PARTS[m]] and PARTS[e] != PARTS[m])]
    assert upward == []
