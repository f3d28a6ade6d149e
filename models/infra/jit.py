"""Compiled kernels with numba, cached on disk by content: the one mechanism of the model packages.

A kernel is a plain-Python function on floats and arrays that numba compiles (:func:`jit`,
:func:`jit_inline`); a function decorated :func:`jitable` stays plain Python for Python callers
and is compiled into the kernels that call it (numba's ``register_jitable``). Without numba, or
with ``OPENEMSS_NO_JIT`` set, the same functions run as Python (the decorators return them
unchanged). The engine's gas path (``models/engine``) and the flight control's inner loops
(``models/fcs``) use it.

Compiled code is cached on disk under ``$OPENEMSS_JIT_CACHE`` (else the user's cache folder), in
one folder per kernel package and content of its modules, of ``models/infra`` and of ``models/common`` (an FMU
unpacks its packages to a new temporary folder on every import, where numba's own cache, kept
beside the source and keyed by its path, would never be found again).

:func:`borrowed` gives a compiled entry point its caller's arrays without numba's atomic
reference counts (see there).
"""

from __future__ import annotations

import hashlib
import inspect
import os
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["AVAILABLE", "borrowed", "entry_point", "jit", "jit_inline", "jitable"]

#: Source folder of each package with kernels -> its cache folder (filled by :func:`jit`).
_FOLDERS: dict[str, str] = {}


def _plain(fn: Callable[..., Any]) -> Callable[..., Any]:
    return fn


def _annotation_name(annotation: Any) -> str | None:
    """The name of a parameter's annotation (a string under ``from __future__ import annotations``)."""
    return annotation if isinstance(annotation, str) else getattr(annotation, "__name__", None)


def _cache_dir(folder: str, package: str) -> str:
    """Where the compiled kernels of the package ``package`` (its modules in ``folder``) are kept:
    $OPENEMSS_JIT_CACHE, else the user's cache folder, then a hash of the package's name and content."""
    root = os.environ.get("OPENEMSS_JIT_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "openemss", "numba")
    digest = hashlib.sha256(package.encode())            # compiled code refers to its modules by name
    # a kernel embeds the kernels it calls and the constants it reads (IntEnum indices of other modules, the
    # common atmosphere): hash every module of the package, of models/infra (this one) and of models/common (when
    # it is there: an FMU carries it only if its models import it), so that no change to what a compiled kernel
    # embeds can leave a stale one in the cache (any change recompiles, once)
    infra = os.path.dirname(os.path.abspath(__file__))
    common = os.path.join(os.path.dirname(infra), "common")
    for where in dict.fromkeys((folder, infra, common)):
        if not os.path.isdir(where):
            continue
        for name in sorted(os.listdir(where)):
            if name.endswith(".py"):
                with open(os.path.join(where, name), "rb") as fh:
                    digest.update(name.encode() + fh.read())
    return os.path.join(root, digest.hexdigest()[:20])


def _register(fn: Callable[..., Any]) -> None:
    """Give the package of ``fn`` its cache folder (once per package)."""
    folder = os.path.dirname(os.path.abspath(fn.__code__.co_filename))
    if folder not in _FOLDERS:
        _FOLDERS[folder] = _cache_dir(folder, fn.__module__.rpartition(".")[0])


def _install_locator(numba_caching: Any) -> None:
    """Cache the kernels by content, not by path.

    numba keeps compiled functions beside their source (``__pycache__``), keyed by the
    file's path. An FMU is extracted to a new temporary folder by every importer, so
    that cache would never be found again and each process would compile the kernels
    anew (10 to 20 s). This locator keeps them in one folder per content of the kernel
    package's modules and its import name (:func:`_cache_dir`), wherever the modules
    were unpacked; numba checks the source's content hash as well.
    """
    base = numba_caching._CacheLocator
    impl = getattr(numba_caching, "CacheImpl", None) or numba_caching._CacheImpl

    class _ContentLocator(base):  # type: ignore[misc, valid-type]
        def __init__(self, py_func: Any, py_file: str) -> None:
            self._py_file, self._lineno = py_file, py_func.__code__.co_firstlineno

        def get_cache_path(self) -> str:
            return self._path

        def get_source_stamp(self) -> Any:
            with open(self._py_file, "rb") as fh:
                return hashlib.sha256(fh.read()).hexdigest()

        def get_disambiguator(self) -> str:
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func: Any, py_file: str) -> Any:
            path = _FOLDERS.get(os.path.dirname(os.path.abspath(py_file)))
            if path is None:
                return None                     # not a kernel of a package registered by jit()
            self = cls(py_func, py_file)
            self._path = path
            try:
                self.ensure_cache_path()
            except OSError:
                return None                     # not writable: numba's own locators
            return self

    if not any(c.__name__ == "_ContentLocator" and c.__module__ == __name__ for c in impl._locator_classes):
        impl._locator_classes.insert(0, _ContentLocator)


try:                                        # numba is a dependency; without it the Python path is used
    if os.environ.get("OPENEMSS_NO_JIT"):
        raise ImportError("OPENEMSS_NO_JIT is set")
    from numba import njit as _njit
    AVAILABLE = True
    try:
        from numba.core import caching as _caching
        _install_locator(_caching)
    except Exception:                       # pragma: no cover - a numba without this internal API: path cache
        pass

    def jit(fn: Callable[..., Any]) -> Callable[..., Any]:
        """numba ``njit``, cached on disk (fastmath off: results equal the Python ones to rounding).

        NumPy's error model: a division by zero gives inf or NaN, as in NumPy, instead of raising, which spares
        every division a test and an exception path (and the reference counting such paths keep alive). The
        kernels never rely on the exception: a non-finite residual or output is refused by the iterations and
        the checks above them, and the plain-Python path (OPENEMSS_NO_JIT) raises where it did."""
        _register(fn)
        return _njit(cache=True, nogil=True, error_model="numpy")(fn)

    def jit_inline(fn: Callable[..., Any]) -> Callable[..., Any]:
        """:func:`jit` inlined into its compiled callers (numba ``inline="always"``), for a thin layer between a
        caller and a large kernel: numba links a kernel's code into every compiled function above it and
        optimises and emits it again there, so each layer over the gas path cost seconds of compilation."""
        _register(fn)
        return _njit(cache=True, nogil=True, error_model="numpy", inline="always")(fn)

    from numba.core import types as _types
    from numba.extending import register_jitable as _register_jitable

    _SCALAR_TYPES = {"float": _types.float64, "int": _types.int64, "bool": _types.boolean}

    def entry_point(fn: Callable[..., Any], args: tuple[Any, ...]) -> Callable[..., Any]:
        """The compiled ``fn`` (a :func:`jit` kernel) for the types of ``args``, compiled or loaded from the cache
        now, as its compiled entry point: a call of it converts the arguments to those types without the
        dispatcher's type resolution (0.4 against 1.0 us for a call of forty arguments, and less of the caches
        touched). For a caller that always passes the same kinds of arguments, as the FCS's step does.

        A parameter annotated ``float``, ``int`` or ``bool`` gets that type whatever its value in ``args``, the
        others the type of their value (arrays): the entry point converts every later argument to these types,
        so an ``int`` given first for a ``float`` parameter must not make it an integer parameter, which would
        truncate every later float. A ``fn`` that is not a compiled kernel is returned as it is."""
        if not hasattr(fn, "typeof_pyval"):     # not a compiled kernel (e.g. a wrapper of one): itself
            return fn
        params = list(inspect.signature(fn.py_func).parameters.values())
        if len(params) != len(args) or any(p.kind not in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
                                           for p in params):
            raise TypeError(f"entry_point({fn.__name__}): give each of its {len(params)} positional parameters")
        sig = tuple(_SCALAR_TYPES.get(_annotation_name(p.annotation)) or fn.typeof_pyval(a)
                    for p, a in zip(params, args, strict=True))
        fn.compile(sig)
        try:
            return fn.overloads[sig].entry_point  # the compile result's Python-callable wrapper
        except (AttributeError, KeyError):      # pragma: no cover - another numba: the dispatcher
            return fn

    def jitable(fn: Callable[..., Any]) -> Callable[..., Any]:
        """``fn`` itself for Python callers, compiled into the compiled functions that call it (numba
        ``register_jitable``): for a law that the compiled step and plain Python callers share, where a
        compiled dispatch from Python (0.2 us and more) would cost more than the law. Its cache is its
        compiled callers', whose folder hashes every module of the package (:func:`_cache_dir`)."""
        _register(fn)
        return _register_jitable(fn)

    from numba.core import cgutils as _cgutils
    from numba.extending import intrinsic as _intrinsic

    def _strip(context: Any, builder: Any, ty: Any, val: Any) -> Any:
        """`val` of type `ty` with the meminfo of each array in it (in nested tuples too) set to null."""
        if isinstance(ty, _types.Array):
            view = context.make_array(ty)(context, builder, value=val)
            view.meminfo = _cgutils.get_null_value(view.meminfo.type)
            return view._getvalue()
        if isinstance(ty, _types.BaseTuple):
            for k, t in enumerate(ty):
                if isinstance(t, (_types.Array, _types.BaseTuple)):
                    val = builder.insert_value(val, _strip(context, builder, t, builder.extract_value(val, k)), k)
        return val

    @_intrinsic
    def _borrowed(typingctx: Any, a: Any) -> Any:
        def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
            return _strip(context, builder, a, args[0])
        return a(a), codegen

    @jit_inline
    def borrowed(a: Any) -> Any:
        """The array `a` (or each array of a tuple, nested tuples too) without its reference count: the same data,
        shape and strides, the same type.

        numba counts the references of every array a compiled function binds, atomically, and its pruning pass
        removes the pairs only where the function's control flow is simple; the gas path's kernels, with their
        early returns and loops, kept them: some twenty atomic operations per call of a map table, about half the
        time of an engine step. A view without the count (its ``meminfo`` null, which numba's increments and
        decrements skip) costs none of them. Only for arrays whose owner outlives every use of the view: the
        arguments of the compiled entry points, held by their Python caller for the call; never for an array
        allocated in compiled code, which numba frees after its last use, nor to be stored or returned."""
        return _borrowed(a)
except ImportError:                         # pragma: no cover
    AVAILABLE = False
    jit = jit_inline = jitable = _plain

    def entry_point(fn: Callable[..., Any], args: tuple[Any, ...]) -> Callable[..., Any]:
        """Without numba: ``fn`` itself (see the compiled version)."""
        return fn

    def borrowed(a: np.ndarray) -> np.ndarray:
        """Without numba: `a` itself (see the compiled version)."""
        return a
