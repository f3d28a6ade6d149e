"""Serialized FMU state (FMI 2.0 ``fmi2SerializeFMUstate``) for slaves whose state is an image of live objects.

:mod:`openemss.fmus.fmu_state` takes a state as an *image*: per mutable object reached from the slave, the
object and a copy of its contents. The object itself cannot go into bytes, so each is written as its *path*
from the slave (``_model.state.x``, ``_fcs.runner.sections[2]``), its kind and type, and its contents, with
pickle (values exact, shared objects kept shared). Reading the bytes back in an instance, possibly another
one of the same FMU, finds at each path the object that instance holds: when it is of the same kind (and,
for an array, the same shape and dtype) the contents are restored into it *in place*, as a state of this
instance would be (a compiled step that holds a model's arrays sees the restored values); else a new object
of the recorded type is made (``cls.__new__``, then its attributes). A value pickle cannot write (a lambda, a
module) is written as its path and taken from the instance: it is code or configuration, not state. A compiled
model's view (the engine's ``StepData``) must be found at its path: it cannot be made from bytes.

Bytes come from this FMU's own serialization (pickle runs the constructors of the FMU's own classes): a host
keeps them with the state it took, as the FMU itself is trusted. Our own code because FMI states of live
Python objects have no library; ``pickle`` of the live graph itself would copy what must be restored in place.
"""
from __future__ import annotations

import pickle
import random
import types
from collections import deque
from typing import Any

import numpy as np

#: A step of a path from the slave: ("a", name) attribute, ("s", name) slot, ("i", index), ("k", key), ("self",)
Step = tuple[Any, ...]
_MISSING = object()


class StateBytesError(RuntimeError):
    """A state that cannot be written as bytes, or bytes that do not restore into this instance."""


def _kind(x: Any, contents: Any) -> str:  # noqa: PLR0911 -- one name per kind of node (fmu_state._Image.take)
    t = type(x)
    if t in (tuple, list, deque, dict, set, frozenset):
        return t.__name__
    if t is np.ndarray:
        return "ndarray"
    if t is types.MethodType:
        return "method"
    if isinstance(x, random.Random):
        return "random"
    if isinstance(x, np.random.Generator):
        return "generator"
    return "stepdata" if contents is None else "object"


def to_bytes(attrs: dict[str, Any]) -> bytes:
    """The image of a slave's attributes (``SlaveState.attrs``) as bytes."""
    nodes: list[tuple[Any, ...]] = []
    index: dict[int, int] = {}

    def ref(img: Any, path: tuple[Step, ...]) -> tuple[Any, ...]:
        if type(img) is not list:  # a value, held by reference in the image
            try:
                pickle.dumps(img)
            except Exception:  # noqa: BLE001 -- any value pickle refuses is taken from the instance
                return ("live", path)
            return ("v", img)
        if id(img) in index:
            return ("n", index[id(img)])
        i = index[id(img)] = len(nodes)
        nodes.append(())
        _, x, c = img
        kind = _kind(x, c)
        if kind in ("tuple", "list", "deque"):
            payload: Any = [ref(v, (*path, ("i", k))) for k, v in enumerate(c)]
        elif kind == "dict":
            payload = [(k, ref(v, (*path, ("k", k)))) for k, v in c.items()]
        elif kind == "method":
            payload = (x.__func__, ref(c, (*path, ("self",))))
        elif kind == "object":
            attrs_, slots = c
            payload = ({k: ref(v, (*path, ("a", k))) for k, v in attrs_.items()},
                       {k: ref(v, (*path, ("s", k))) for k, v in slots.items()})
        elif kind == "generator":
            payload = (type(x.bit_generator), c)
        else:  # set, frozenset, ndarray, random: their recorded contents; stepdata: None
            payload = c
        nodes[i] = (kind, None if kind in ("method", "tuple") else type(x), path, getattr(x, "maxlen", None), payload)
        return ("n", i)

    roots = {k: ref(v, (("a", k),)) for k, v in attrs.items()}
    try:
        return pickle.dumps((roots, nodes), protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:  # noqa: BLE001 -- a type pickle cannot find again (a class made at run time)
        raise StateBytesError(f"the state cannot be written as bytes: {exc}") from None


def _resolve(slave: Any, path: tuple[Step, ...]) -> Any:
    """The object the live ``slave`` holds at ``path``, or :data:`_MISSING`."""
    cur = slave
    for step in path:
        try:
            if step[0] == "a":
                d = getattr(cur, "__dict__", None)
                cur = d.get(step[1], _MISSING) if d is not None else _MISSING
            elif step[0] == "s":
                cur = getattr(cur, step[1], _MISSING)
            elif step[0] == "i":
                cur = cur[step[1]] if type(cur) in (tuple, list, deque) and step[1] < len(cur) else _MISSING
            elif step[0] == "k":
                cur = cur.get(step[1], _MISSING) if type(cur) is dict else _MISSING
            else:
                cur = getattr(cur, "__self__", _MISSING)
        except Exception:  # noqa: BLE001 -- a path the instance does not have
            return _MISSING
        if cur is _MISSING:
            return _MISSING
    return cur


def _fresh(kind: str, cls: type, maxlen: int | None, payload: Any) -> Any:  # noqa: PLR0911 -- one per kind
    if kind in ("list", "dict", "set"):
        return cls()
    if kind == "deque":
        return deque(maxlen=maxlen)
    if kind == "frozenset":
        return frozenset(payload)
    if kind == "ndarray":
        return np.array(payload, copy=True)
    if kind == "random":
        return cls()
    if kind == "generator":
        return np.random.Generator(payload[0]())
    return cls.__new__(cls)


def from_bytes(slave: Any, data: bytes) -> dict[str, Any]:
    """The image of a slave's attributes from :func:`to_bytes`' bytes, on the objects ``slave`` holds where they
    match (restored in place by ``fmu_state``), new ones elsewhere."""
    try:
        roots, nodes = pickle.loads(data)  # noqa: S301 -- this FMU's own bytes (see the module docstring)
    except Exception as exc:  # noqa: BLE001 -- not bytes of this FMU's serialization
        raise StateBytesError(f"the bytes are not a serialized state of this FMU ({exc})") from None
    objs: dict[int, Any] = {}

    def obj(i: int) -> Any:
        if i in objs:
            return objs[i]
        kind, cls, path, maxlen, payload = nodes[i]
        live = _resolve(slave, path)
        if kind == "tuple":
            objs[i] = tuple(value(r) for r in payload)
        elif kind == "method":
            objs[i] = types.MethodType(payload[0], value(payload[1]))
        elif kind == "stepdata":
            if live is _MISSING or type(live) is not cls:
                raise StateBytesError(f"a compiled view ({cls.__name__}) at {_show(path)} that this instance "
                                      "does not hold: the state cannot be restored here")
            objs[i] = live
        elif live is not _MISSING and type(live) is cls and kind != "frozenset" and (
                kind != "ndarray" or (live.shape == payload.shape and live.dtype == payload.dtype)):
            objs[i] = live
        else:
            objs[i] = _fresh(kind, cls, maxlen, payload)
        return objs[i]

    def value(r: tuple[Any, ...]) -> Any:
        if r[0] == "v":
            return r[1]
        if r[0] == "n":
            return obj(r[1])
        v = _resolve(slave, r[1])
        if v is _MISSING:
            raise StateBytesError(f"{_show(r[1])}: a value that is not in the bytes and that this instance "
                                  "does not hold")
        return v

    images: list[list[Any]] = [["o", None, None] for _ in nodes]

    def image(r: tuple[Any, ...]) -> Any:
        return images[r[1]] if r[0] == "n" else value(r)

    for i, (kind, _cls, _path, _maxlen, payload) in enumerate(nodes):
        img = images[i]
        img[1] = obj(i)
        if kind in ("tuple", "list", "deque"):
            items = [image(r) for r in payload]
            img[2] = tuple(items) if kind == "tuple" else items
        elif kind == "dict":
            img[2] = {k: image(r) for k, r in payload}
        elif kind == "method":
            img[2] = image(payload[1])
        elif kind == "object":
            img[2] = ({k: image(r) for k, r in payload[0].items()}, {k: image(r) for k, r in payload[1].items()})
        elif kind == "generator":
            img[2] = payload[1]
        elif kind == "set":
            img[2] = set(payload)
        else:  # frozenset, ndarray, random: contents as recorded; stepdata: None
            img[2] = payload
    return {k: image(r) for k, r in roots.items()}


def _show(path: tuple[Step, ...]) -> str:
    out = ""
    for step in path:
        out += {"a": f".{step[1]}", "s": f".{step[1]}", "i": f"[{step[1]}]", "k": f"[{step[1]!r}]"}.get(
            step[0], ".__self__") if len(step) > 1 else ".__self__"
    return out.lstrip(".")
