"""No import cycle anywhere in openEMSS, and the packages import one way only (issues 18, 20, 37.3).

The graph has a node per module of every package pyproject.toml installs (orchestrator/, models/, fmus/,
report/, study/, the package ``openemss`` and the data packages), found through pyproject's ``package-dir``.
Every import that runs makes an edge: relative (``from ..x import y``) and absolute (``from openemss.x import
y``, ``import openemss.x``), at module level or inside a function (a lazy import hides a cycle, it does not
remove it), and ``importlib.import_module("openemss.x")`` with a constant name; imports under
``if TYPE_CHECKING:`` never run and make none. ``from package import name`` is an edge to the module ``name``
when it is one, else to the package's ``__init__``.

Directions (DESIGN.md): cli -> study, report -> orchestrator -> shared infrastructure (models/infra); fmus -> models ->
models/common (physics) -> models/infra. :data:`MAY_IMPORT` says, for each unit (a model package, or a top-level package), which other
units it may import; anything else is a forbidden direction. Inside the orchestrator the parts import one way
down (:data:`PART_LEVEL`, orchestrator/README.md).
"""
from __future__ import annotations

import ast
import tomllib
from fnmatch import fnmatch
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ORCHESTRATOR = ROOT / "orchestrator"

#: What each unit may import besides itself (``models.*``: any model package). A unit is ``models.<package>`` for
#: the model packages and ``orchestrator`` or the top-level package's name for the rest; a model package not
#: listed may import ``models.common`` and ``models.infra`` only.
MAY_IMPORT: dict[str, tuple[str, ...]] = {
    "openemss": ("orchestrator",),  # the Python API (orchestrator/toplevel), re-exported from cli/api.py
    # models/infra holds the shared infrastructure (files, YAML, values, jit) that the orchestrator uses too; the
    # orchestrator imports nothing else of the models (no physics)
    "orchestrator": ("models.infra",),
    "models": (),  # the package openemss.models itself (its __init__)
    "models.infra": (),
    "models.common": ("models.infra",),
    "models.performance": ("models.common", "models.infra", "models.airframe", "models.engine"),
    "models.fcs": ("models.common", "models.infra", "models.mission"),  # the FCS flies the mission
    "fmus": ("models.*",),
    "report": ("orchestrator", "models.*", "fmus"),  # fmus: the engine FMU's default design (mission check)
    "study": ("orchestrator", "models.*", "report"),
    "ssp": ("orchestrator", "models.*", "fmus"),  # ssp/generate.py, the script that writes the shipped system
    "examples": ("openemss",),
    "missions": (), "scenarios": (), "studies": (),
}

#: The level of every part of the orchestrator, lowest first (orchestrator/README.md describes them). A part is
#: a sub-package; "" is the package root, the shared modules (SHARED). A module imports modules of its own part
#: or of lower parts only; fmu/, scenarios/ (the run side) and recording/ (the results side) are side by side.
PART_LEVEL = {"": 0, "ssp": 1, "master": 2, "fmu": 3, "scenarios": 3, "recording": 3, "cli": 4}
SHARED = {"__init__", "errors", "exit_codes", "results", "interrupt"}


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


def _modules(root: Path) -> dict[str, tuple[Path, bool]]:
    """Every module of the distribution by dotted name (``openemss.report.summary``; a package by its own name),
    with its file and whether it is a package's ``__init__``, from pyproject.toml's packages and package-dir."""
    config = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]
    dirs: dict[str, str] = config.get("package-dir", {})
    mods: dict[str, tuple[Path, bool]] = {}
    for pkg in config["packages"]:
        parts = pkg.split(".")
        prefix = next(i for i in range(len(parts), 0, -1) if ".".join(parts[:i]) in dirs)
        folder = root / dirs[".".join(parts[:prefix])] / Path(*parts[prefix:])
        for f in sorted(folder.glob("*.py")):
            mods[pkg if f.stem == "__init__" else f"{pkg}.{f.stem}"] = (f, f.stem == "__init__")
    return mods


def _targets(dotted: str, names: list[str], mods: dict[str, tuple[Path, bool]]) -> set[str]:
    """The modules ``from <dotted> import <names>`` (or ``import <dotted>``, names empty) runs."""
    if dotted in mods:
        subs = {f"{dotted}.{n}" for n in names if f"{dotted}.{n}" in mods}
        return subs if names and len(subs) == len(names) else subs | {dotted}
    parts = dotted.split(".")
    for i in range(len(parts) - 1, 0, -1):  # an attribute path: the longest prefix that is a module
        if ".".join(parts[:i]) in mods:
            return {".".join(parts[:i])}
    return set()


def graph(root: Path) -> dict[str, set[str]]:
    """Module -> the modules of ours it imports when it runs (see the module docstring)."""
    mods = _modules(root)
    g: dict[str, set[str]] = {}
    for name, (f, is_init) in mods.items():
        package = name.split(".") if is_init else name.split(".")[:-1]
        edges = g.setdefault(name, set())
        for node in _runtime_nodes(ast.parse(f.read_text(encoding="utf-8"), filename=str(f))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    anchor = package[:len(package) - (node.level - 1)]
                    dotted = ".".join(anchor + (node.module.split(".") if node.module else []))
                else:
                    dotted = node.module or ""
                edges |= _targets(dotted, [a.name for a in node.names], mods)
            elif isinstance(node, ast.Import):
                for a in node.names:
                    edges |= _targets(a.name, [], mods)
            elif (isinstance(node, ast.Call) and ast.unparse(node.func) in ("importlib.import_module", "import_module",
                                                                             "__import__")
                  and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
                edges |= _targets(node.args[0].value, [], mods)
        edges.discard(name)
    return g


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


def unit(module: str) -> str:
    """``openemss.models.fcs.x`` -> ``models.fcs``; ``openemss.orchestrator.cli.main`` -> ``orchestrator``;
    ``openemss.report.summary`` -> ``report``; ``openemss`` -> ``openemss``."""
    parts = module.split(".")
    if len(parts) == 1:
        return parts[0]
    return ".".join(parts[1:3]) if parts[1] == "models" and len(parts) > 2 else parts[1]


def wrong_directions(g: dict[str, set[str]], may: dict[str, tuple[str, ...]]) -> list[str]:
    """Every import from one unit into another that ``may`` does not allow."""
    out = []
    for m, edges in sorted(g.items()):
        a = unit(m)
        allowed = may.get(a, ("models.common", "models.infra") if a.startswith("models.") else ())
        for e in sorted(edges):
            b = unit(e)
            if b != a and not any(fnmatch(b, pattern) for pattern in allowed):
                out.append(f"{m} ({a}) imports {e} ({b})")
    return out


def _part_in(module: str) -> str | None:
    """An orchestrator module's part: its sub-package, "" for the shared modules at the root; None elsewhere."""
    parts = module.split(".")
    if parts[:2] != ["openemss", "orchestrator"]:
        return None
    head = parts[2] if len(parts) > 2 else "__init__"
    return head if (ORCHESTRATOR / head / "__init__.py").is_file() else ""


def wrong_way_parts(g: dict[str, set[str]], level: dict[str, int]) -> list[str]:
    """Orchestrator imports up the parts, or sideways into another part of the same level."""
    out = []
    for m, edges in sorted(g.items()):
        for e in sorted(edges):
            pm, pe = _part_in(m), _part_in(e)
            if pm in level and pe in level and (level[pe] > level[pm] or (level[pe] == level[pm] and pe != pm)):
                out.append(f"{m} ({pm or 'shared'}) imports {e} ({pe or 'shared'})")
    return out


# -- the checks checked ----------------------------------------------------------------------------
def _tree(tmp_path: Path, files: dict[str, str]) -> Path:
    """A distribution like ours: pyproject.toml mapping ``openemss.<top>`` to folders, and the files."""
    tops = sorted({Path(f).parts[0] for f in files})
    dirs = ", ".join(f'"openemss.{t}" = "{t}"' for t in tops)
    pkgs = sorted({"openemss." + ".".join(Path(f).parent.parts) for f in files if f.endswith("__init__.py")})
    (tmp_path / "pyproject.toml").write_text(f"[tool.setuptools]\npackage-dir = {{ {dirs} }}\npackages = {pkgs!r}\n")
    for f, text in files.items():
        (tmp_path / f).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / f).write_text(text)
    return tmp_path


def test_type_checking_imports_are_not_edges() -> None:
    tree = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .a import X\nfrom .b import Y\n")
    assert [n.module for n in _runtime_nodes(tree) if isinstance(n, ast.ImportFrom) and n.level == 1] == ["b"]


def test_the_search_finds_a_cycle() -> None:
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


def test_the_graph_sees_absolute_relative_lazy_and_dynamic_imports(tmp_path: Path) -> None:
    root = _tree(tmp_path, {
        "report/__init__.py": "", "report/a.py": "from .b import f\n",
        "report/b.py": "def f():\n    from openemss.report import c\n",
        "report/c.py": "import importlib\nimportlib.import_module('openemss.study.x')\n",
        "study/__init__.py": "", "study/x.py": "import openemss.report.a\n",
        "models/__init__.py": "", "models/fcs/__init__.py": "", "models/common/__init__.py": "",
        "models/fcs/m.py": "from ..common import y\nfrom ...report.a import f\n", "models/common/y.py": "",
    })
    g = graph(root)
    assert g["openemss.report.a"] == {"openemss.report.b"} and g["openemss.report.b"] == {"openemss.report.c"}
    assert g["openemss.report.c"] == {"openemss.study.x"} and g["openemss.study.x"] == {"openemss.report.a"}
    assert g["openemss.models.fcs.m"] == {"openemss.models.common.y", "openemss.report.a"}
    assert _cycle(g) == ["openemss.report.a", "openemss.report.b", "openemss.report.c", "openemss.study.x",
                         "openemss.report.a"]
    assert wrong_directions(g, MAY_IMPORT) == [
        "openemss.models.fcs.m (models.fcs) imports openemss.report.a (report)",
        "openemss.report.c (report) imports openemss.study.x (study)"]


def test_the_part_check_finds_upward_and_sideways_imports() -> None:
    g = {"openemss.orchestrator.master.exchange": {"openemss.orchestrator.errors", "openemss.orchestrator.cli.main"},
         "openemss.orchestrator.recording.observers": {"openemss.orchestrator.master.exchange",
                                                      "openemss.orchestrator.fmu.build"},
         "openemss.orchestrator.fmu.build": {"openemss.orchestrator.master.exchange"}}
    assert wrong_way_parts(g, PART_LEVEL) == [
        "openemss.orchestrator.master.exchange (master) imports openemss.orchestrator.cli.main (cli)",
        "openemss.orchestrator.recording.observers (recording) imports openemss.orchestrator.fmu.build (fmu)"]


# -- the project ------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def project() -> dict[str, set[str]]:
    return graph(ROOT)


def test_every_package_is_in_the_graph(project: dict[str, set[str]]) -> None:
    """Every package pyproject installs is walked (its modules are nodes), and each has its line in MAY_IMPORT."""
    units = {unit(m) for m in project}
    assert {"openemss", "orchestrator", "report", "study", "fmus", "models.fcs", "models.engine", "models.airframe",
            "models.electric", "models.common", "models.infra", "models.mission", "ssp", "examples"} <= units
    assert {"openemss.report.summary", "openemss.study.cli", "openemss.fmus.engine",
            "openemss.orchestrator.cli.main"} <= set(project)
    assert {u for u in units if not u.startswith("models.")} - set(MAY_IMPORT) == set(), \
        "give the new package its line in MAY_IMPORT"


def test_no_import_cycle_anywhere(project: dict[str, set[str]]) -> None:
    cycle = _cycle(project)
    assert cycle is None, " -> ".join(cycle or [])


def test_packages_import_one_way(project: dict[str, set[str]]) -> None:
    assert wrong_directions(project, MAY_IMPORT) == []


def test_orchestrator_imports_go_one_way_down_the_parts(project: dict[str, set[str]]) -> None:
    assert wrong_way_parts(project, PART_LEVEL) == []


def _mapped_elsewhere() -> set[str]:
    """Sub-folders of orchestrator/ that pyproject maps to a package of their own (not parts)."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    return {Path(d).relative_to("orchestrator").parts[0] for p, d in config.get("package-dir", {}).items()
            if Path(d).parts[:1] == ("orchestrator",) and len(Path(d).parts) > 1}


def test_every_orchestrator_module_is_in_a_part() -> None:
    flat = {f.stem for f in ORCHESTRATOR.glob("*.py")} - SHARED
    assert flat == set(), "put the new module in its part's sub-package (and in orchestrator/README.md's table)"
    subs = {p.name for p in ORCHESTRATOR.iterdir() if (p / "__init__.py").is_file()} - _mapped_elsewhere()
    assert subs - set(PART_LEVEL) == set(), "give the new sub-package its level in PART_LEVEL (and a README line)"
