"""Real FMU state (FMI 2.0 section 2.1.8: ``fmi2GetFMUstate``, ``fmi2SetFMUstate``, serialization) for our slaves.

pythonfmu 0.7's own ``_get_fmu_state`` saves the values of the FMI variables only and its ``_set_fmu_state``
writes them back: the model behind them (spools, integrators, the mission state machine) is not restored,
yet every call returns OK. :class:`FmuState`, mixed in before :class:`openemss.fmus.signal_io.SignalIO`,
replaces them:

* **get**: an *image* of everything the slave holds (its ``__dict__`` less the plumbing of pythonfmu and
  SignalIO, :data:`PLUMBING`): every mutable object reached from it (lists, dicts, sets, NumPy arrays,
  objects with a ``__dict__`` or ``__slots__``, random generators) with a copy of its contents, recorded once
  per object so that two references to one object stay one object; immutable values (numbers, strings,
  functions, frozen dataclasses, read-only mappings) are held by reference.
* **set**: the same objects put back in place and their contents restored *in place*: a compiled step that
  holds the NumPy arrays of a model (the engine's ``StepData``) sees the restored values in its own memory.
* an object of a kind the image does not know (e.g. a JSBSim ``FGFDMExec``) makes get fail with a message
  (pythonfmu reports fmi2Fatal with it): never an OK with a state that would not restore. A slave whose
  state includes such an object leaves it out (:attr:`FmuState.STATE_SKIP`) and restores it itself
  (:meth:`FmuState._state_extra` / :meth:`FmuState._restore_extra`), as the airframe does for JSBSim.
* serialization: the image holds live objects; a slave that declares ``CAN_SERIALIZE`` writes each object as its
  path from the slave, its type and its contents (:mod:`openemss.fmus.state_bytes`: restored into the objects
  an instance holds at those paths, in place, in this instance or another one of the same FMU), or gives its
  own :meth:`FmuState._state_to_plain` / :meth:`FmuState._state_from_plain` (the airframe: its start and
  inputs); the others refuse with a message, and say ``canSerializeFMUstate="false"``.

The model description's ``canGetAndSetFMUstate`` and ``canSerializeFMUstate`` are written from the class's
``CAN_GET_SET`` and ``CAN_SERIALIZE`` (one source). Nothing is added to ``doStep``.

This is our own code because pythonfmu offers no state beyond its variables, and ``copy.deepcopy`` copies
what must be shared (a compiled model's arrays) and fails on read-only mappings.
"""
from __future__ import annotations

import base64
import dataclasses
import json
import random
import types
import weakref
from collections import deque
from collections.abc import Callable
from operator import attrgetter, itemgetter, methodcaller
from typing import Any
from xml.etree.ElementTree import Element

import numpy as np

from openemss.fmus.state_bytes import StateBytesError, from_bytes, to_bytes

#: Attributes of a slave that are the plumbing of pythonfmu and SignalIO, not its state.
PLUMBING = frozenset({"vars", "log_queue", "instance_name", "resources", "visible", "guid", "_plans", "_units",
                      "_rows", "_out_vr", "_out_index", "_attr_vr", "_in_index", "_start_vrs"})
_FORMAT = "openEMSS FMU state 1"
_VALUES = (int, float, complex, bool, str, bytes, type(None), type, types.FunctionType, types.BuiltinFunctionType,
           types.BuiltinMethodType, types.ModuleType, types.MappingProxyType, range, itemgetter, attrgetter,
           methodcaller, np.generic, np.dtype)


class StateError(RuntimeError):
    """A state that cannot be saved, restored or serialized exactly (the FMI call fails with this message)."""


def _frozen(x: Any) -> bool:
    params = getattr(type(x), "__dataclass_params__", None)
    return params is not None and params.frozen and dataclasses.is_dataclass(x)


class _Image:
    """The image of one object graph: per object reached, the object and a copy of its contents."""

    def __init__(self) -> None:
        self.memo: dict[int, Any] = {}
        self.keep: list[Any] = []  # the objects imaged (their ids stay theirs while the image lives)

    def take(self, x: Any, path: str) -> Any:  # noqa: PLR0911 -- one case per kind of object
        """The image of ``x``: ``x`` itself for a value, else ``("o", x, contents)`` (recorded once per object)."""
        if isinstance(x, _VALUES) or _frozen(x):
            return x
        i = id(x)
        if i in self.memo:
            return self.memo[i]
        node: list[Any] = ["o", x, None]
        self.memo[i] = node
        self.keep.append(x)
        t = type(x)
        if t is tuple:
            node[2] = tuple(self.take(v, f"{path}[{k}]") for k, v in enumerate(x))
        elif t is list or t is deque:
            node[2] = [self.take(v, f"{path}[{k}]") for k, v in enumerate(x)]
        elif t is dict:
            node[2] = {k: self.take(v, f"{path}[{k!r}]") for k, v in x.items()}
        elif t is set or t is frozenset:
            node[2] = set(x)
        elif t is np.ndarray:
            node[2] = x.copy()
        elif t is types.MethodType:
            node[2] = self.take(x.__self__, f"{path}.__self__")
        elif isinstance(x, random.Random):
            node[2] = x.getstate()
        elif isinstance(x, np.random.Generator):
            node[2] = x.bit_generator.state
        elif type(x).__name__ == "StepData" and hasattr(x, "_numba_type_"):
            node[2] = None  # a compiled model's view of arrays its model holds: restored through them
        elif hasattr(x, "__dict__") and type(x).__module__.split(".")[0] != "jsbsim":
            slots = [s for c in t.__mro__ for s in getattr(c, "__slots__", ()) if hasattr(x, s)]
            node[2] = ({k: self.take(v, f"{path}.{k}") for k, v in vars(x).items()},
                       {s: self.take(getattr(x, s), f"{path}.{s}") for s in slots if s != "__dict__"})
        elif hasattr(t, "__slots__") and not hasattr(x, "__dict__"):
            slots = [s for c in t.__mro__ for s in getattr(c, "__slots__", ()) if hasattr(x, s)]
            node[2] = ({}, {s: self.take(getattr(x, s), f"{path}.{s}") for s in slots})
        else:
            raise StateError(f"the state holds {path}, a {t.__module__}.{t.__qualname__}, which cannot be saved "
                             "and restored exactly")
        return node


def _put(img: Any, done: set[int]) -> Any:  # noqa: PLR0912 -- one case per kind of object
    """Restore the contents recorded in the image ``img`` into its object, in place; returns the object."""
    if type(img) is not list:
        return img
    _, x, c = img
    if id(x) in done:
        return x
    done.add(id(x))
    t = type(x)
    if t is tuple:
        for v in c:
            _put(v, done)
    elif t is list or t is deque:
        x.clear()
        x.extend(_put(v, done) for v in c)
    elif t is dict:
        x.clear()
        x.update((k, _put(v, done)) for k, v in c.items())
    elif t is set:
        x.clear()
        x.update(c)
    elif t is np.ndarray:
        np.copyto(x, c)
    elif t is types.MethodType:
        _put(c, done)
    elif isinstance(x, random.Random):
        x.setstate(c)
    elif isinstance(x, np.random.Generator):
        x.bit_generator.state = c
    elif c is not None:
        attrs, slots = c
        if attrs or hasattr(x, "__dict__"):
            d = vars(x)
            d.clear()
            d.update((k, _put(v, done)) for k, v in attrs.items())
        for s, v in slots.items():
            object.__setattr__(x, s, _put(v, done))
    return x


@dataclasses.dataclass(frozen=True)
class SlaveState:
    """One saved state of a slave: its class, the image of its attributes and what the slave adds."""

    slave: str
    attrs: dict[str, Any]
    extra: Any
    keep: tuple[Any, ...] = ()
    #: the instance that took it (a weak reference), for the class's serialization calls (see _refuse)
    owner: Callable[[], Any] = lambda: None


class FmuState:
    """Mix-in of a pythonfmu slave: real get, set (and, where declared, serialization) of its state."""

    #: What the model description declares (``canGetAndSetFMUstate``, ``canSerializeFMUstate``).
    CAN_GET_SET: bool = True
    CAN_SERIALIZE: bool = True
    #: Attributes the slave saves and restores itself (:meth:`_state_extra`), besides :data:`PLUMBING`.
    STATE_SKIP: frozenset[str] = frozenset()

    def _state_extra(self) -> Any:
        """What the slave saves itself (the attributes of :attr:`STATE_SKIP`); None by default."""
        return None

    def _restore_extra(self, extra: Any) -> None:
        """Restore what :meth:`_state_extra` saved (called after the attributes are restored)."""

    def _get_fmu_state(self) -> SlaveState:
        if not self.CAN_GET_SET:
            raise StateError(f"{type(self).__name__}: this FMU cannot save its state (canGetAndSetFMUstate=false)")
        skip = PLUMBING | self.STATE_SKIP
        image = _Image()
        attrs = {k: image.take(v, k) for k, v in vars(self).items() if k not in skip}
        return SlaveState(type(self).__name__, attrs, self._state_extra(), tuple(image.keep), weakref.ref(self))

    def _set_fmu_state(self, state: Any) -> None:
        if isinstance(state, Serialized):  # deserialized (_fmu_state_from_bytes has no instance): rebuilt here
            if not self.CAN_SERIALIZE:
                raise StateError(f"{type(self).__name__}: this FMU cannot deserialize a state "
                                 "(canSerializeFMUstate=false)")
            state = self._state_from_plain(_unwrap(state.data, type(self).__name__))
        if not isinstance(state, SlaveState) or state.slave != type(self).__name__:
            raise StateError(f"{type(self).__name__}: not a state of this FMU "
                             f"({getattr(state, 'slave', type(state).__name__)})")
        skip = PLUMBING | self.STATE_SKIP
        d = vars(self)
        for k in [k for k in d if k not in skip and k not in state.attrs]:
            del d[k]  # an attribute made after the state was taken (none of the per-step ones)
        done: set[int] = set()
        for k, img in state.attrs.items():
            d[k] = _put(img, done)
        self._restore_extra(state.extra)

    # -- serialization: pythonfmu calls these on the class, with no instance. An exception that leaves them
    # makes its C layer release the instance's references once too often (orchestrator/fmu/lifecycle.py): a
    # refusal takes them first through the state's owner; deserialization never raises (it has no instance)
    # and leaves the checks to _set_fmu_state, so a state that is not whole fails there, never restored.
    @classmethod
    def _fmu_state_to_bytes(cls, state: Any) -> bytes:
        if isinstance(state, Serialized):  # a state deserialized and not yet set
            return state.data
        try:
            if not cls.CAN_SERIALIZE:
                raise StateError(f"{cls.__name__}: this FMU cannot serialize its state (canSerializeFMUstate=false)")
            if not isinstance(state, SlaveState) or state.slave != cls.__name__:
                raise StateError(f"{cls.__name__}: not a state of this FMU")
            return json.dumps({"format": _FORMAT, "slave": cls.__name__, "state": cls._state_to_plain(state)},
                              allow_nan=True).encode()
        except BaseException:
            owner = state.owner() if isinstance(state, SlaveState) else None
            if owner is not None:
                cls.fmi_escaping(owner)  # type: ignore[attr-defined]
            raise

    @classmethod
    def _fmu_state_from_bytes(cls, data: bytes) -> Serialized:
        return Serialized(bytes(data))

    @classmethod
    def _state_to_plain(cls, state: SlaveState) -> Any:
        """A state as plain JSON data: by default the image of the attributes written by
        :func:`openemss.fmus.state_bytes.to_bytes` (base64), for a slave with nothing of its own (no extra)."""
        if state.extra is not None:
            raise StateError(f"{cls.__name__}: a state with parts of its own needs its own serialization")
        try:
            return {"image": base64.b64encode(to_bytes(state.attrs)).decode("ascii")}
        except StateBytesError as exc:
            raise StateError(f"{cls.__name__}: {exc}") from None

    def _state_from_plain(self, plain: Any) -> SlaveState:
        """The state from :meth:`_state_to_plain`'s data, on the objects this instance holds."""
        try:
            data = base64.b64decode(plain["image"], validate=True)
            return SlaveState(type(self).__name__, from_bytes(self, data), None)
        except (StateBytesError, KeyError, TypeError, ValueError) as exc:
            raise StateError(f"{type(self).__name__}: {exc}") from None

    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """The model description, declaring what the class can do with its state."""
        root: Element = super().to_xml(model_options or {})  # type: ignore[misc]
        cosim = root.find("CoSimulation")
        if cosim is not None:
            cosim.set("canGetAndSetFMUstate", str(self.CAN_GET_SET).lower())
            cosim.set("canSerializeFMUstate", str(self.CAN_SERIALIZE and self.CAN_GET_SET).lower())
        return root


@dataclasses.dataclass(frozen=True)
class Serialized:
    """Bytes given to ``fmi2DeSerializeFMUstate``, checked and rebuilt when the state is set."""

    data: bytes


def _unwrap(data: bytes, slave: str) -> Any:
    """The plain state of serialized bytes, checked to be this FMU's."""
    try:
        doc = json.loads(bytes(data).decode())
    except (UnicodeDecodeError, ValueError) as exc:
        raise StateError(f"{slave}: the bytes are not a serialized state of this FMU ({exc})") from None
    if not isinstance(doc, dict) or doc.get("format") != _FORMAT or doc.get("slave") != slave:
        raise StateError(f"{slave}: the bytes are not a serialized state of this FMU (format "
                         f"{doc.get('format') if isinstance(doc, dict) else '?'!r}, FMU "
                         f"{doc.get('slave') if isinstance(doc, dict) else '?'!r})")
    return doc["state"]


def plain_attrs(attrs: dict[str, Any]) -> dict[str, Any]:
    """The image of a slave's attributes as plain JSON data: values, and lists and tuples of values (the
    contents recorded when the state was taken). Anything else cannot be serialized: :class:`StateError`."""
    def plain(img: Any, path: str) -> Any:
        if type(img) is list:  # ["o", object, contents]
            _, x, c = img
            if type(x) in (list, tuple):
                return {type(x).__name__: [plain(v, f"{path}[{k}]") for k, v in enumerate(c)]}
            raise StateError(f"the state holds {path}, a {type(x).__name__}, which cannot be serialized")
        if img is None or type(img) in (bool, int, float, str):
            return img
        raise StateError(f"the state holds {path}, a {type(img).__name__}, which cannot be serialized")
    return {k: plain(v, k) for k, v in attrs.items()}


def attrs_from_plain(slave: Any, plain: dict[str, Any]) -> dict[str, Any]:
    """The image of a slave's attributes from :func:`plain_attrs`' data; a list is restored into the list the
    slave holds under that name (SignalIO's ``_u`` must stay the object its plans hold)."""
    def image(p: Any, live: Any) -> Any:
        if isinstance(p, dict):
            (kind, items), = p.items()
            if kind == "list":
                return ["o", live if type(live) is list else [], [image(v, None) for v in items]]
            return tuple(_put(image(v, None), set()) for v in items) if kind == "tuple" else p
        return p
    return {k: image(v, getattr(slave, k, None)) for k, v in plain.items()}
