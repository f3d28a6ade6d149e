"""The one YAML reader of the project: bounded, strict, with file:line in every message.

Every YAML file a user writes (missions, scenarios, studies) and every data file is read
through :func:`read_text` and :func:`load` (or :func:`compose` for readers that work on
nodes). On top of PyYAML's safe loader they refuse:

* a file larger than :data:`MAX_BYTES` and a file that is not UTF-8 (naming line and column);
* a mapping that gives one key twice, naming both lines (PyYAML keeps the last silently);
* alias bombs: a document whose nodes, with every alias expanded, number more than
  :data:`MAX_NODES` (counted without expanding, so the check itself is cheap), and recursive aliases;
* numbers that are not finite (``.nan``, ``.inf``): no reader of the project has a use for them,
  and a NaN compares false with every bound, so a range check downstream would let it through.

The error is :class:`YamlError` (a ``ValueError``) whose message starts with ``file:line:``;
each reader wraps it in its own error type. JSON files (engine parameters, airframe geometry,
QGroundControl plans) are read by :func:`load_json` with the same rules: no key twice, no
``NaN`` or ``Infinity``.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # PyYAML is imported where YAML is read, so that JSON readers (the airframe FMU) need none
    import yaml

__all__ = ["MAX_BYTES", "MAX_NODES", "YamlError", "compose", "load", "load_json", "read_text"]

MAX_BYTES = 4 * 1024 * 1024  #: largest YAML file read [bytes]
MAX_NODES = 200_000  #: most nodes of a document with its aliases expanded


class YamlError(ValueError):
    """A YAML file that cannot be read; the message starts with ``file:line:``."""


def read_text(path: str | Path, what: str = "file", max_bytes: int = MAX_BYTES) -> str:
    """The text of a UTF-8 file of at most ``max_bytes``.

    Raises
    ------
    YamlError
        When the file cannot be read, is too large or is not UTF-8 (with line and column).
    """
    p = Path(path)
    try:
        with open(p, "rb") as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise YamlError(f"{p}: cannot read the {what}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise YamlError(f"{p}: the {what} is larger than {max_bytes // 1024} KiB; refused")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise YamlError(f"{p}:{line}: the {what} is not UTF-8 text: byte 0x{data[exc.start]:02x} at column {col} "
                        "(save it as UTF-8)") from None


def _where(source: str, node: yaml.Node) -> str:
    return f"{source}:{node.start_mark.line + 1}"


def _check(root: yaml.Node, source: str, max_nodes: int) -> None:
    """Duplicate keys, non-finite numbers, recursive aliases and the expanded size, in one pass."""
    import yaml

    floats = yaml.SafeLoader("")
    size: dict[int, int] = {}  # id(node) -> expanded node count, once computed
    keys: dict[int, str] = {}  # id(value node) -> its key, to name a bad value
    float_tag = "tag:yaml.org,2002:float"
    # iterative post-order walk: (node, children pushed?)
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    open_: set[int] = set()
    while stack:
        node, expanded = stack.pop()
        nid = id(node)
        if isinstance(node, yaml.ScalarNode):
            if nid not in size:
                if node.tag == float_tag and not math.isfinite(floats.construct_yaml_float(node)):
                    key = keys.get(nid)
                    named = f"'{key}': " if key is not None else ""
                    raise YamlError(f"{_where(source, node)}: {named}{node.value!r} is not a finite number")
                size[nid] = 1
            continue
        children = [c for pair in node.value for c in pair] if isinstance(node, yaml.MappingNode) else list(node.value)
        if not expanded:
            if nid in size:
                continue
            if nid in open_:
                raise YamlError(f"{_where(source, node)}: a recursive alias (a node that contains itself); refused")
            open_.add(nid)
            if isinstance(node, yaml.MappingNode):
                seen: dict[tuple[str, str], int] = {}
                for k, v in node.value:
                    if isinstance(k, yaml.ScalarNode):
                        keys.setdefault(id(v), k.value)
                for k, _ in node.value:
                    if isinstance(k, yaml.ScalarNode):
                        key = (k.tag, k.value)
                        if key in seen:
                            raise YamlError(f"{_where(source, k)}: key '{k.value}' is given twice in one mapping "
                                            f"(first at line {seen[key]}); give each key once")
                        seen[key] = k.start_mark.line + 1
            stack.append((node, True))
            stack.extend((c, False) for c in children if id(c) not in size)
            continue
        open_.discard(nid)
        size[nid] = 1 + sum(size[id(c)] for c in children)
        if size[nid] > max_nodes:
            raise YamlError(f"{_where(source, node)}: the document expands to more than {max_nodes} nodes "
                            "(aliases included); refused")


def compose(text: str, source: str, max_nodes: int = MAX_NODES) -> yaml.Node | None:
    """The checked node tree of one YAML document (None for an empty one).

    Raises
    ------
    YamlError
        Not valid YAML, a key given twice, an alias bomb, a non-finite number.
    """
    import yaml

    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else 1
        raise YamlError(f"{source}:{line}: not valid YAML: {getattr(exc, 'problem', None) or exc}") from None
    if root is not None:
        _check(root, source, max_nodes)
    return root


def load(text: str, source: str, loader: type[yaml.SafeLoader] | None = None, max_nodes: int = MAX_NODES) -> Any:
    """The Python value of one checked YAML document (see :func:`compose`); ``loader`` is a
    ``yaml.SafeLoader`` subclass whose constructors build the value (default: ``yaml.SafeLoader``)."""
    import yaml

    loader = loader or yaml.SafeLoader
    root = compose(text, source, max_nodes)
    if root is None:
        return None
    constructor = loader("")
    try:
        return constructor.construct_document(root)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else 1
        raise YamlError(f"{source}:{line}: not valid YAML: {getattr(exc, 'problem', None) or exc}") from None
    finally:
        constructor.dispose()


def load_json(text: str, source: str) -> Any:
    """The value of a JSON document; a key given twice in one object, ``NaN`` and ``Infinity`` refused.

    Raises
    ------
    YamlError
        With ``source:line:`` (the line of the syntax error, or of the object holding the duplicate key).
    """
    def pairs(items: list[tuple[str, Any]]) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for k, v in items:
            if k in out:
                raise ValueError(f"key '{k}' is given twice in one object; give each key once")
            out[k] = v
        return out

    def constant(name: str) -> float:
        raise ValueError(f"{name} is not a finite number")

    try:
        return json.loads(text, object_pairs_hook=pairs, parse_constant=constant)
    except json.JSONDecodeError as exc:
        raise YamlError(f"{source}:{exc.lineno}: invalid JSON: {exc.msg}") from None
    except ValueError as exc:
        raise YamlError(f"{source}: {exc}") from None
