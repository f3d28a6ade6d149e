"""`build-fmus`: code added to every slave script so that its FMU survives every legal host sequence.

pythonfmu's C++ layer (``PySlaveInstance.cpp`` of pythonfmu 0.7.0, the binary every pythonfmu FMU carries)
has two faults this code works around from the Python side, where a build can reach them:

* **Free after a failure.** When a Python method of the slave raises, ``handle_py_exception`` calls
  ``cleanPyObject``, which releases its references to the slave class, the instance and its log queue
  (``Py_XDECREF``) but keeps the pointers; it reports ``fmi2Fatal``. ``fmi2FreeInstance`` then releases
  them a second time (the destructor calls ``cleanPyObject`` again). The instance or its log queue is
  freed while still in use and the class loses a reference for every failure: the host crashes in a
  later garbage collection (a segmentation fault, with fmpy after a few failed instances of any of our
  FMUs). Every method the C layer calls on an instance is therefore wrapped here: when an exception
  leaves it towards the C layer, the three references the C layer is about to drop are taken first
  (``Py_IncRef``), so the C layer's extra release balances and ``fmi2FreeInstance`` frees the instance
  once, as it should. An exception caught by the slave's own code (the wrapper's caller is code of this
  FMU) takes nothing. A method marked ``fmi_guarded`` is left as it is: it calls the class's
  ``fmi_escaping`` itself (``fmus/signal_io.py``'s batched get and set, called every step: no call added);
  functions a slave sets on an instance for the C layer are wrapped with the class's ``fmi_guard``
  (``fmus/initial_outputs.py``).
* **One module per process.** pythonfmu imports the slave module once per process (by its name) and for
  every later instance runs the script again inside that first module, with the new instance's
  resources folder first on ``sys.path``. An instance extracted elsewhere (a host that extracts per
  instance, a second FMU file of the same build) then ran the first extraction's code and found its
  data files beside it: gone when the host removed that folder (a second ``fmpy.simulate_fmu`` failed
  with "Failed to instantiate model"), or another FMU's when that one was tampered with or failed (a
  failed run poisoned the next run of an intact system). Here, an instance runs the code of its own
  extraction, or the first module's when that is still there and the same byte for byte (the slave
  module and its vendored package: our master's instances of one FMU file share one extraction, of two
  copies of one build one module, as before). Otherwise the modules of this FMU's vendored package
  imported from another folder are dropped from ``sys.modules`` (with the numba cache locators they
  installed: ``models/infra/jit.py`` keeps one per process), the copy in the instance's resources is
  imported and its slave class handed to pythonfmu (which takes the class by name from the first module).

:func:`lifecycle_head` goes after the requirements check, before the slave's imports;
:func:`lifecycle_tail` at the end of the script.
"""
from __future__ import annotations

#: The methods pythonfmu's C layer calls on an instance (``PyObject_CallMethod``).
FMI_METHODS = ("setup_experiment", "enter_initialization_mode", "exit_initialization_mode", "terminate", "do_step",
               "get_real", "get_integer", "get_boolean", "get_string", "set_real", "set_integer", "set_boolean",
               "set_string", "_get_fmu_state", "_set_fmu_state")


def lifecycle_head(lib: str) -> str:
    """Python source run before the slave's imports: this instance's own copy of the FMU's code."""
    return f'''
# -- added by build-fmus: an instance runs the code of its own extraction (orchestrator/fmu/lifecycle.py) --
import importlib as _emss_importlib

_emss_lib = {lib!r}
# pythonfmu runs this file again in the module it imported first, for every new instance, compiled under the
# bare module name and with that instance's resources first on sys.path. What that run defines is local to
# it: a function defined here sees the first run's globals, so these take everything as arguments.
_emss_rerun = _emss_sys._getframe(0).f_code.co_filename != __file__
_emss_own = _emss_Path(_emss_sys.path[0]).resolve() if _emss_rerun else _emss_Path(__file__).resolve().parent


def _emss_outside(module, own) -> bool:
    """Whether a module was not loaded from the folder ``own``."""
    from pathlib import Path

    f = getattr(module, "__file__", None)
    return not f or not Path(f).resolve().is_relative_to(own)


def _emss_code(folder, lib, module) -> bytes:
    """A digest of the slave module and its vendored package in ``folder``."""
    import hashlib

    h = hashlib.sha256()
    for p in [folder / (module + ".py"), *sorted((folder / lib).rglob("*"))]:
        if p.is_file() and "__pycache__" not in p.parts:
            h.update(str(p.relative_to(folder)).encode() + b"\\0" + p.read_bytes())
    return h.digest()


_emss_stale = True  # a first run: nothing of the vendored package may stay from another folder
if _emss_rerun:  # the first module's copy serves when it still exists and is this one's, byte for byte
    _emss_first = getattr(_emss_sys.modules.get(__name__), "__file__", None)
    _emss_first = _emss_Path(_emss_first).resolve().parent if _emss_first else None
    _emss_stale = _emss_first != _emss_own and not (
        _emss_first is not None and _emss_first.is_dir()
        and _emss_code(_emss_first, _emss_lib, __name__) == _emss_code(_emss_own, _emss_lib, __name__))
if _emss_stale:
    _emss_gone = {{_n for _n, _m in list(_emss_sys.modules.items())
                  if (_n == _emss_lib or _n.startswith(_emss_lib + ".")) and _emss_outside(_m, _emss_own)}}
    for _emss_name in _emss_gone:
        del _emss_sys.modules[_emss_name]
    _emss_numba = _emss_sys.modules.get("numba.core.caching")  # cache locators those modules installed go too
    for _emss_impl in (getattr(_emss_numba, "CacheImpl", None), getattr(_emss_numba, "_CacheImpl", None)):
        if _emss_gone and isinstance(getattr(_emss_impl, "_locator_classes", None), list):
            _emss_impl._locator_classes[:] = [_c for _c in _emss_impl._locator_classes
                                              if _c.__module__ not in _emss_gone]
if _emss_stale and _emss_rerun and (_emss_own / (__name__ + ".py")).is_file():
    _emss_sys.modules.pop(__name__, None)
    try:
        _emss_fresh = vars(_emss_importlib.import_module(__name__))  # from _emss_own, first on sys.path
    except Exception as _emss_exc:
        # This run stops here. pythonfmu ignores its failure, looks through what it defined for the slave class
        # with the exception still set (a crash once it meets a class: none is left) and fails to find one,
        # naming no cause: it is said here.
        print(f"{{__name__}}: the FMU's code in {{_emss_own}} cannot be imported: {{_emss_exc!r}}",
              file=_emss_sys.stderr)
        for _emss_key in [_k for _k, _v in locals().items() if isinstance(_v, type)]:
            del locals()[_emss_key]
        raise
    for _emss_key, _emss_value in _emss_fresh.items():  # the slave class pythonfmu takes by name
        if isinstance(_emss_value, type) and _emss_value.__module__ == __name__ and _emss_key in globals():
            globals()[_emss_key] = _emss_value
# ---------------------------------------------------------------------------------------------------
'''


def lifecycle_tail() -> str:
    """Python source appended to the script: the slave classes' FMI methods wrapped (see the module)."""
    # one wrapper per number of arguments (no packing of *args in the hot path), and one for any other signature
    templates = {0: ("", ""), 1: (", a", "a"), 2: (", a, b", "a, b"), 3: (", a, b, c", "a, b, c"),
                 "any": (", *a, **k", "*a, **k")}
    makers = "".join(f'''
def _emss_method_{n}(fn):
    def method(self{params}):
        try:
            return fn(self{params})
        except BaseException:
            _emss_escaping(self)
            raise
    method.fmi_guarded = True
    return method


def _emss_bound_{n}(fn, slave):
    def bound({args}):
        try:
            return fn({args})
        except BaseException:
            _emss_escaping(slave)
            raise
    bound.fmi_guarded = True
    return bound
''' for n, (params, args) in templates.items())
    return f'''

# -- added by build-fmus: the C layer may free an instance after any failure (orchestrator/fmu/lifecycle.py) --
import ctypes as _emss_ctypes
from inspect import getattr_static as _emss_getattr_static
from types import FunctionType as _EmssFunctionType

from pythonfmu import Fmi2Slave as _EmssFmi2Slave

try:
    _emss_incref = _emss_ctypes.pythonapi.Py_IncRef
    _emss_incref.argtypes = [_emss_ctypes.py_object]
    _emss_incref.restype = None
except (AttributeError, OSError):  # the interpreter's symbols not reachable: hold them for good instead
    _emss_incref = [].append
_EMSS_FMI_METHODS = {FMI_METHODS!r}


def _emss_escaping(slave) -> None:
    """An exception leaves a method for pythonfmu's C layer, which will release the class, the instance and
    its log queue once more than it holds them: take those references first (not for a caller of this FMU's
    own code, which may catch it)."""
    try:
        caller = _emss_sys._getframe(2)  # 0: this, 1: the wrapper, 2: its caller
    except ValueError:  # no Python frame below: a host that is not Python
        caller = None
    name = caller.f_globals.get("__name__", "") if caller is not None else ""
    if name in (__name__, _emss_lib, "pythonfmu") or name.startswith((_emss_lib + ".", "pythonfmu.")):
        return
    for obj in (type(slave), slave, slave.log_queue):
        _emss_incref(obj)
{makers}

def _emss_guard(fn, slave=None):
    """``fn`` (a method of the class, or with ``slave`` a function set on that instance) with the references
    the C layer drops on an exception taken first."""
    if getattr(fn, "fmi_guarded", False):  # wrapped already, or calls fmi_escaping itself (fmus/signal_io.py)
        return fn
    code = fn.__code__ if isinstance(fn, _EmssFunctionType) else None
    exact = code is not None and not code.co_flags & 0x0C and not code.co_kwonlyargcount  # no *a, **k, k=
    n = code.co_argcount - (slave is None) if exact else "any"
    n = n if n in _EMSS_MAKERS else "any"
    return _EMSS_MAKERS[n](fn) if slave is None else _EMSS_BOUND[n](fn, slave)


_EMSS_MAKERS = {{{", ".join(f"{n!r}: _emss_method_{n}" for n in templates)}}}
_EMSS_BOUND = {{{", ".join(f"{n!r}: _emss_bound_{n}" for n in templates)}}}
if not _emss_rerun:
    for _emss_cls in [_v for _v in list(globals().values()) if isinstance(_v, type) and
                      issubclass(_v, _EmssFmi2Slave) and _v.__module__ == __name__]:
        for _emss_method in _EMSS_FMI_METHODS:
            _emss_fn = _emss_getattr_static(_emss_cls, _emss_method, None)
            if callable(_emss_fn) and not isinstance(_emss_fn, (staticmethod, classmethod)):
                setattr(_emss_cls, _emss_method, _emss_guard(_emss_fn))
        _emss_cls.fmi_guard = staticmethod(_emss_guard)  # for functions a slave sets on its instances
        _emss_cls.fmi_escaping = staticmethod(_emss_escaping)  # for methods that guard themselves
# ---------------------------------------------------------------------------------------------------
'''
