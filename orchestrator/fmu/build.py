"""`build-fmus`: build FMI 2.0 co-simulation FMUs from pythonfmu slaves.

Each FMU is self-contained. The model code a slave imports (``openemss.models.X``)
and the helper modules beside it (imported as ``openemss.fmus.X`` or ``X``) are copied into the FMU's resources under a
package name made of the slave's name and a hash of every file it contains
(``emss_<slave>_<hash>_lib``); the slave module itself is renamed the same way.
pythonfmu runs every Python FMU in the host's interpreter and appends the
resources folder to ``sys.path``, so a plain name such as ``models`` or
``linear_step`` would resolve to whichever copy was imported first, possibly an
installed openEMSS of another version, or another FMU's helper. Unique names
cannot collide.

A slave may also list data files of the repository it needs at run time in a
module-level ``DATA_FILES`` list (paths relative to the repository root, e.g.
``["missions/munich.yaml"]``); they are copied to the same relative path under the
FMU's ``resources/`` folder, where the slave finds them through pythonfmu's
``resources`` argument.

Also added to the FMU: ``requirements.txt`` (the slave's ``REQUIREMENTS`` list, for
``pythonfmu deploy``), ``openemss_build.json`` (source hash, for staleness), and
the ``ModelStructure/InitialUnknowns`` that pythonfmu leaves out (without them
``fmpy validate`` rejects the FMU).
"""
from __future__ import annotations

import argparse
import ast
import functools
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from fmpy.validation import validate_fmu
from lxml import etree

from openemss.models.infra.files import atomic_copy

from .. import interrupt
from ..errors import BuildError, EmssError
from ..exit_codes import ExitCode
from ..master.slave import BUILD_RECORD, FREE_AFTER_FAILURE
from ..results import os_reason
from .fmu_deps import insert_guard, link_libpython, requirements_guard, vendor_packages
from .lifecycle import lifecycle_head, lifecycle_tail

PACKAGE_ROOT = Path(__file__).resolve().parent.parent.parent  # folder holding orchestrator/, models/, fmus/
MODELS_DIR = PACKAGE_ROOT / "models"
DEFAULT_SOURCE_DIR = PACKAGE_ROOT / "fmus"
BUILD_INFO = BUILD_RECORD
#: pythonfmu runs the slave in the host's interpreter: the host needs it too (requirements.txt lists it)
PYTHONFMU_REQUIREMENT = "pythonfmu>=0.6.5"


@dataclass(frozen=True)
class SlaveSource:
    """A pythonfmu slave script and what it needs inside its FMU."""

    script: Path
    siblings: tuple[Path, ...]  # helper modules beside the script
    model_packages: tuple[str, ...]  # sub-packages of openemss.models
    requirements: tuple[str, ...]
    data_files: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return self.script.stem


def _imports(tree: ast.Module) -> list[str]:
    """Absolute module names imported anywhere in a module (``from a import b`` gives ``a`` and ``a.b``)."""
    names: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.append(node.module)
            names.extend(f"{node.module}.{a.name}" for a in node.names if a.name != "*")
    return names


def _is_slave(tree: ast.Module) -> bool:
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            for base in node.bases:
                if (isinstance(base, ast.Name) and base.id == "Fmi2Slave") or \
                        (isinstance(base, ast.Attribute) and base.attr == "Fmi2Slave"):
                    return True
    return False


def _literal_list(tree: ast.Module, script: Path, name: str) -> tuple[str, ...]:
    """A module-level ``NAME = [...]`` list of strings, or () when absent."""
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == name for t in node.targets):
            try:
                value = ast.literal_eval(node.value)
            except ValueError:
                raise BuildError(f"{script}:{node.lineno}: {name} must be a literal list of strings") from None
            if not (isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value)):
                raise BuildError(f"{script}:{node.lineno}: {name} must be a literal list of strings")
            return tuple(value)
    return ()


def analyse(script: Path) -> SlaveSource:
    """Find the sibling modules and model packages a slave script needs."""
    script = Path(script).resolve()
    tree = ast.parse(script.read_text(encoding="utf-8"), filename=str(script))
    siblings: list[Path] = []
    packages: set[str] = set()
    todo = [(script, tree)]
    seen = {script}
    while todo:
        path, t = todo.pop()
        for name in _imports(t):
            top = name.split(".")[0]
            if name.startswith("openemss."):
                parts = name.split(".")
                if parts[1] == "fmus" and len(parts) > 2 and (script.parent / f"{parts[2]}.py").is_file():
                    top = parts[2]  # a helper module beside the slave, imported through the package
                elif parts[1] != "models":
                    raise BuildError(f"{path}: imports '{name}'; an FMU may depend only on openemss.models "
                                     "and on the modules beside it")
                else:
                    if len(parts) > 2 and (MODELS_DIR / parts[2]).is_dir():
                        packages.add(parts[2])
                    continue
            sibling = script.parent / f"{top}.py"
            if sibling.is_file() and sibling not in seen:
                seen.add(sibling)
                siblings.append(sibling)
                todo.append((sibling, ast.parse(sibling.read_text(encoding="utf-8"), filename=str(sibling))))
    for pkg in packages:
        if not (MODELS_DIR / pkg / "__init__.py").is_file():
            raise BuildError(f"{script}: imports openemss.models.{pkg}, which does not exist in {MODELS_DIR}")
    packages |= _package_closure(packages)
    data_files = _literal_list(tree, script, "DATA_FILES")
    for f in data_files:
        target = (PACKAGE_ROOT / f).resolve()
        if ".." in Path(f).parts or Path(f).is_absolute() or not target.is_file():
            raise BuildError(f"{script}: DATA_FILES entry '{f}' must name a file below {PACKAGE_ROOT}")
    return SlaveSource(script, tuple(sorted(siblings)), tuple(sorted(packages)),
                       _literal_list(tree, script, "REQUIREMENTS"), data_files)


def _package_closure(packages: set[str]) -> set[str]:
    """The model packages that ``packages`` import among themselves, transitively: a package's
    ``from ..other import x`` (relative, two dots: a sibling package of ``models``) brings ``other``
    (for example ``common``, the shared atmosphere)."""
    found, todo = set(packages), list(packages)
    while todo:
        pkg = todo.pop()
        for f in _package_files(pkg):
            if f.suffix != ".py":
                continue
            st = f.stat()
            for level, names in _relative_imports(str(f), st.st_mtime_ns, st.st_size):
                depth = len(f.relative_to(MODELS_DIR / pkg).parts)  # 1 for a module at the package's top
                if level != depth + 1:
                    continue                                          # inside the package itself
                for other in names:
                    if other not in found and (MODELS_DIR / other / "__init__.py").is_file():
                        found.add(other)
                        todo.append(other)
    return found


@functools.lru_cache(maxsize=4096)
def _relative_imports(path: str, mtime_ns: int, size: int) -> tuple[tuple[int, tuple[str, ...]], ...]:
    """(level, first names) of every ``from ..x import y`` (level >= 2) of a module, by its file's path, time and
    size: the FMUs of one system share most model packages, and a process that checks them again (a study's
    client) parses a file only once while it is unchanged."""
    out = []
    for node in ast.walk(ast.parse(Path(path).read_text(encoding="utf-8"), filename=path)):
        if isinstance(node, ast.ImportFrom) and node.level >= 2:
            out.append((node.level, (node.module.split(".")[0],) if node.module else tuple(a.name for a in node.names)))
    return tuple(out)


def _package_files(pkg: str) -> list[Path]:
    root = MODELS_DIR / pkg
    return sorted(p for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts
                  and p.suffix not in (".pyc", ".pyo"))


def source_hash(src: SlaveSource) -> str:
    """SHA-256 over every file that goes into the FMU (names and contents)."""
    h = hashlib.sha256()
    named = [(f.name, f) for f in (src.script, *src.siblings)]
    if src.model_packages:
        named.append(("models/__init__.py", MODELS_DIR / "__init__.py"))
    for pkg in src.model_packages:
        named.extend((f"models/{f.relative_to(MODELS_DIR).as_posix()}", f) for f in _package_files(pkg))
    named.extend((f"data/{f}", PACKAGE_ROOT / f) for f in src.data_files)
    for name, f in named:
        h.update(name.encode())
        h.update(f.read_bytes())
    h.update(repr(src.requirements).encode())
    h.update((lifecycle_head("") + lifecycle_tail()).encode())  # the code build-fmus adds to the slave
    return h.hexdigest()


def _rewrite_imports(code: str, path: Path, lib: str, siblings: set[str]) -> str:
    """Point imports of openemss.models and of sibling modules at the vendored package."""
    tree = ast.parse(code, filename=str(path))
    lines = code.splitlines(keepends=True)
    edits: list[tuple[ast.stmt, str]] = []

    def target(module: str) -> str | None:
        if module == "openemss.models" or module.startswith("openemss.models."):
            return lib + module[len("openemss"):]
        if module.startswith("openemss.fmus.") and module.split(".")[2] in siblings:
            return f"{lib}.{module[len('openemss.fmus.'):]}"
        top = module.split(".")[0]
        if top in siblings:
            return f"{lib}.{module}"
        return None

    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module and target(node.module):
            new = ast.ImportFrom(module=target(node.module), names=node.names, level=0)
            edits.append((node, ast.unparse(new)))
        elif isinstance(node, ast.Import) and any(target(a.name) for a in node.names):
            parts = []
            for a in node.names:
                t = target(a.name)
                if t is None:
                    parts.append(ast.unparse(ast.Import(names=[a])))
                elif a.asname is None and "." in a.name:
                    raise BuildError(f"{path}:{node.lineno}: write 'import {a.name} as NAME' or "
                                     f"'from {a.name} import ...' so the import can be vendored")
                else:
                    parts.append(f"import {t} as {a.asname or a.name}")
            edits.append((node, "; ".join(parts)))
    for node, text in sorted(edits, key=lambda e: (e[0].lineno, e[0].col_offset), reverse=True):
        first, last = node.lineno - 1, node.end_lineno - 1
        prefix = lines[first][: node.col_offset]
        suffix = lines[last][node.end_col_offset:]
        lines[first: last + 1] = [prefix + text + suffix]
    return "".join(lines)


def _check_relative_only(pkg_dir: Path) -> None:
    """Every module of the vendored packages imports its own package relatively. A script in a data folder
    (no ``__init__.py``, e.g. ``models/engine/maps/transcribe_pycycle.py``) is no module of the package: the
    FMU never imports it, and it may import the installed ``openemss``."""
    for f in pkg_dir.rglob("*.py"):
        if not (f.parent / "__init__.py").is_file():
            continue
        for name in _imports(ast.parse(f.read_text(encoding="utf-8"), filename=str(f))):
            if name == "openemss" or name.startswith("openemss."):
                raise BuildError(f"{f}: model code must import its own package relatively "
                                 f"(found absolute import of '{name}')")


def _stage(src: SlaveSource, digest: str, stage: Path, options: dict[str, bool]) -> tuple[Path, list[Path]]:
    """Lay out the slave, its vendored code and metadata in ``stage``; return script and project files."""
    lib = f"emss_{src.name}_{digest[:10]}_lib"
    lib_dir = stage / lib
    lib_dir.mkdir()
    (lib_dir / "__init__.py").write_text(f'"""Code vendored into the {src.name} FMU by build-fmus."""\n')
    sibling_names = {s.stem for s in src.siblings}
    for s in src.siblings:
        (lib_dir / s.name).write_text(_rewrite_imports(s.read_text(encoding="utf-8"), s, lib, sibling_names))
    if src.model_packages:
        (lib_dir / "models").mkdir()
        shutil.copy2(MODELS_DIR / "__init__.py", lib_dir / "models" / "__init__.py")
        for pkg in src.model_packages:
            shutil.copytree(MODELS_DIR / pkg, lib_dir / "models" / pkg,
                            ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        _check_relative_only(lib_dir / "models")
    script = stage / f"emss_{src.name}_{digest[:10]}.py"
    code = _rewrite_imports(src.script.read_text(encoding="utf-8"), src.script, lib, sibling_names)
    guard = requirements_guard(fmu_name(src.script), src.requirements) + lifecycle_head(lib)
    script.write_text(insert_guard(code, guard) + lifecycle_tail())
    req = stage / "requirements.txt"
    req.write_text("".join(f"{r}\n" for r in (*src.requirements, PYTHONFMU_REQUIREMENT)))
    info = stage / BUILD_INFO
    from .. import __version__

    record = {"source": src.script.name, "source_sha256": digest, "openemss": __version__,
              FREE_AFTER_FAILURE: True, **options}
    if options.get("vendor"):
        record["vendored_bytes"] = vendor_packages(src.requirements, stage / "vendor")
    info.write_text(json.dumps(record, indent=2))
    project = [lib_dir, req, info, *([stage / "vendor"] if options.get("vendor") else [])]
    for f in src.data_files:  # pythonfmu copies a project folder under its own name into resources/
        top = Path(f).parts[0]
        (stage / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(PACKAGE_ROOT / f, stage / f)
        if stage / top not in project:
            project.append(stage / top)
    return script, project


def _add_initial_unknowns(fmu: Path) -> None:
    """Add ModelStructure/InitialUnknowns (outputs and calculated parameters with initial
    approx/calculated), which pythonfmu omits; FMI 2.0 section 2.2.8 requires them."""
    with zipfile.ZipFile(fmu) as zf:
        entries = {i.filename: zf.read(i.filename) for i in zf.infolist()}
    root = etree.fromstring(entries["modelDescription.xml"])
    variables = root.findall("ModelVariables/ScalarVariable")
    structure = root.find("ModelStructure")
    for old in structure.findall("InitialUnknowns"):
        structure.remove(old)
    unknowns = []
    for i, v in enumerate(variables, start=1):
        causality = v.get("causality", "local")
        initial = v.get("initial")
        if causality == "output" and initial in (None, "approx", "calculated"):
            unknowns.append(i)
        elif causality == "calculatedParameter" and initial in (None, "approx", "calculated"):
            unknowns.append(i)
    if unknowns:
        node = etree.SubElement(structure, "InitialUnknowns")
        for i in unknowns:
            etree.SubElement(node, "Unknown", index=str(i))
    entries["modelDescription.xml"] = etree.tostring(root, xml_declaration=True, encoding="UTF-8",
                                                     pretty_print=True)
    tmp = fmu.with_suffix(".fmu.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in entries.items():
            zf.writestr(name, data)
    tmp.replace(fmu)


def build_info(fmu: Path) -> dict:  # type: ignore[type-arg]
    """What ``build-fmus`` recorded in a built FMU (source hash, options), or {}."""
    try:
        with zipfile.ZipFile(fmu) as zf:
            return dict(json.loads(zf.read(f"resources/{BUILD_INFO}")))
    except (OSError, KeyError, ValueError, zipfile.BadZipFile):
        return {}


def built_hash(fmu: Path) -> str | None:
    """The source hash recorded in a built FMU, or None."""
    return build_info(fmu).get("source_sha256")


def build_fmu(script: Path, out_dir: Path, vendor: bool = False, link: bool = False) -> Path:
    """Build one FMU from a slave script into ``out_dir``; returns the FMU path.

    ``vendor`` bundles its Python packages (and links libpython); ``link`` makes its binary need the
    building interpreter's libpython, for hosts that are not Python (see :mod:`.fmu_deps`).

    The FMU is made in a staging folder (removed whatever happens, an interruption included) and then
    copied beside its target under a temporary name, flushed to the disk and renamed over it: a run
    reading the old FMU meanwhile reads it whole, and a full disk leaves the old FMU as it was.

    Raises
    ------
    BuildError
        When the FMU cannot be built or written (one line; the FMU in ``out_dir`` is then unchanged).
    """
    src = analyse(script)
    digest = source_hash(src)
    options = {"vendor": vendor, "link_libpython": vendor or link}
    out_dir = Path(out_dir).resolve()
    target = out_dir / fmu_name(src.script)
    unchanged = f"{target} is unchanged" if target.is_file() else f"no {target.name} was written"
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(prefix="emss_build_") as tmp:
            built = _build_in(src, digest, options, Path(tmp), target.name)
            atomic_copy(built, target)
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        raise BuildError(f"{script}: cannot build {target.name}: {where}{os_reason(exc)}; {unchanged}") from None
    except BuildError as exc:
        raise BuildError(f"{exc}; {unchanged}") from None
    return target


def _build_in(src: SlaveSource, digest: str, options: dict[str, bool], tmp: Path, name: str) -> Path:
    """Stage, build (pythonfmu, in a child process whose temporary files stay in ``tmp``), complete and
    validate the FMU ``name`` of ``src`` in the folder ``tmp``; returns the FMU there."""
    script = src.script
    stage = tmp / "stage"
    stage.mkdir()
    staged, project_files = _stage(src, digest, stage, options)
    interrupt.phase("build-stage", f"while building {name}")
    dest = tmp / "out"
    code = ("import sys; from pythonfmu.builder import FmuBuilder; "
            "p = FmuBuilder.build_FMU(sys.argv[1], dest=sys.argv[2], project_files=sys.argv[3:]); print(p)")
    # A fresh interpreter per build: pythonfmu imports the slave module to read its
    # variables, and that module must not stay cached in the caller's sys.modules.
    proc = subprocess.run([sys.executable, "-c", code, str(staged), str(dest), *map(str, project_files)],
                          capture_output=True, text=True, cwd=tmp, env=dict(os.environ, TMPDIR=str(tmp)))
    if proc.returncode != 0:
        lines = [ln for ln in proc.stderr.strip().splitlines() if ln.strip()]
        raise BuildError(f"{script}: pythonfmu could not build the FMU: {lines[-1] if lines else 'no output'}")
    built = Path(proc.stdout.strip().splitlines()[-1])
    _add_initial_unknowns(built)
    if options["link_libpython"]:
        link_libpython(built)
    problems = validate_fmu(str(built))
    if problems:
        raise BuildError(f"{script}: the FMU fails 'fmpy validate' ({len(problems)} problem(s)): "
                         + "; ".join(p.strip() for p in problems))
    return built


def discover(source_dir: Path) -> dict[str, Path]:
    """Slave scripts in ``source_dir`` (``*.py`` defining an Fmi2Slave subclass), by name."""
    found: dict[str, Path] = {}
    for f in sorted(Path(source_dir).glob("*.py")):
        if f.name.startswith("_"):
            continue
        if _is_slave(ast.parse(f.read_text(encoding="utf-8"), filename=str(f))):
            found[f.stem] = f
    return found


def fmu_name(script: Path) -> str:
    """File name of the FMU pythonfmu will write for a slave (its class name + .fmu)."""
    tree = ast.parse(Path(script).read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and _is_slave(ast.Module(body=[node], type_ignores=[])):
            return f"{node.name}.fmu"
    raise BuildError(f"{script}: no Fmi2Slave subclass found")


def ensure_built(source_dir: Path, out_dir: Path, names: list[str] | None = None, force: bool = False,
                 report=None, vendor: bool = False, link: bool = False,  # type: ignore[no-untyped-def]
                 report_up_to_date: bool = True) -> list[Path]:
    """Build the FMUs of ``source_dir`` that are missing or older than their sources (or built with
    other options); ``report`` hears of each FMU built and, with ``report_up_to_date``, of each left as it was."""
    wanted = {"vendor": vendor, "link_libpython": vendor or link}
    slaves = discover(source_dir)
    if names:
        unknown = [n for n in names if n not in slaves]
        if unknown:
            raise BuildError(f"no slave named {', '.join(unknown)} in {source_dir} "
                             f"(available: {', '.join(slaves) or 'none'})")
        slaves = {n: slaves[n] for n in names}
    built = []
    for script in slaves.values():
        target = Path(out_dir) / fmu_name(script)
        info = build_info(target) if target.is_file() else {}
        same_options = all(bool(info.get(k, False)) == v for k, v in wanted.items())
        if not force and same_options and info.get("source_sha256") == source_hash(analyse(script)):
            if report and report_up_to_date:
                report(f"up to date: {target}")
            built.append(target)
            continue
        path = build_fmu(script, out_dir, vendor=vendor, link=link)
        if report:
            report(f"built: {path}")
        built.append(path)
    return built


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``build-fmus`` command."""
    parser = argparse.ArgumentParser(
        prog="build-fmus",
        description="Build FMI 2.0 co-simulation FMUs from the pythonfmu slaves in a folder "
                    "(default: the project's fmus/). Each FMU carries the model code it needs under a "
                    "unique name, a requirements.txt for 'pythonfmu deploy', and is rebuilt only when a "
                    "source changed.")
    parser.add_argument("names", nargs="*", help="slaves to build (file names without .py); default: all")
    parser.add_argument("--src", type=Path, default=DEFAULT_SOURCE_DIR, help="folder of slave scripts")
    parser.add_argument("--out", type=Path, default=PACKAGE_ROOT / "ssp" / "resources",
                        help="where to write the FMUs (default: ssp/resources/, where emss run builds and finds "
                             "them)")
    parser.add_argument("--force", action="store_true", help="rebuild even when up to date")
    parser.add_argument("--vendor", action="store_true",
                        help="bundle the FMU's Python packages (for this platform and Python version) inside it, "
                             "so that the target needs only a CPython of the same version; implies --link-libpython")
    parser.add_argument("--link-libpython", action="store_true",
                        help="make the FMU's binary need this Python's shared libpython, so that hosts that are "
                             "not Python (a C program) can load it without preloading libpython")
    args = parser.parse_args(argv)
    interrupt.phase("build", "during the build", f"every FMU in {args.out} is whole (the old one or the new)")
    try:
        if not args.src.is_dir():
            raise BuildError(f"source folder {args.src} does not exist")
        paths = ensure_built(args.src, args.out, args.names or None, args.force, report=print, vendor=args.vendor,
                             link=args.link_libpython)
        if not paths:
            print(f"no pythonfmu slaves found in {args.src}")
    except EmssError as exc:
        print(f"build-fmus: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE
    except OSError as exc:  # the source folder, the output folder: one line naming it
        print(f"build-fmus: error: {exc.filename or args.out}: {os_reason(exc)}", file=sys.stderr)
        return ExitCode.USAGE
    except KeyboardInterrupt as exc:
        return interrupt.report("build-fmus", exc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
