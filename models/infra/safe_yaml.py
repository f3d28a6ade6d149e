"""The one YAML reader of the project: bounded, strict, with file:line in every message.

Every YAML file a user writes (missions, scenarios, studies) and every data file is read
through :func:`read_text` and :func:`load` (or :func:`compose` for readers that work on
nodes). On top of PyYAML's safe loader they refuse:

* a file larger than :data:`MAX_BYTES` and a file that is not UTF-8 (naming line and column);
* a binary file (a NUL byte), naming its line; a UTF-8 byte-order mark is skipped;
* a mapping that gives one key twice, naming both lines (PyYAML keeps the last silently), and a
  key that is a list or a mapping (a key is a name);
* alias bombs: a document whose nodes, with every alias expanded, number more than
  :data:`MAX_NODES` (counted without expanding, so the check itself is cheap), and recursive aliases;
* numbers that are not finite (``.nan``, ``.inf``) and integers too large for a float (a 401-digit
  integer): no reader of the project has a use for them, and a NaN compares false with every bound,
  so a range check downstream would let it through.

The error is :class:`YamlError` (a ``ValueError``) whose one-line message starts with ``file:line:``;
each reader wraps it in its own error type. JSON files (engine parameters, airframe geometry,
QGroundControl plans) are read by :func:`load_json` with the same rules (no key twice, no ``NaN``,
``Infinity``, ``1e999`` or integer beyond a float, each named with its line); its objects are
:class:`LineDict` s that know the line of each key, for the readers' own messages. The values
themselves (types, ranges) are checked by each reader with :mod:`.values`.
"""
from __future__ import annotations

import json
import math
import re
import sys
from json import decoder as _json_decoder
from json import scanner as _json_scanner
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # PyYAML is imported where YAML is read, so that JSON readers (the airframe FMU) need none
    import yaml

__all__ = ["MAX_BYTES", "MAX_NODES", "MAX_INT_DIGITS", "YamlError", "LineDict", "compose", "load", "load_json",
           "node_lines", "read_text"]

MAX_BYTES = 4 * 1024 * 1024  #: largest YAML file read [bytes]
MAX_NODES = 200_000  #: most nodes of a document with its aliases expanded
#: Most characters of an integer literal: more than a float holds (1.8e308) is refused anyway, and Python
#: refuses to convert more than 4300 digits with an error of its own.
MAX_INT_DIGITS = 330
_BOM = "\ufeff"


class YamlError(ValueError):
    """A YAML or JSON file that cannot be read; the one-line message starts with ``file:line:``."""

    def __init__(self, message: str) -> None:
        super().__init__(" ".join(message.split()))  # one line, whatever the parser's message held


class LineDict(dict):  # type: ignore[type-arg]
    """A mapping read from a file that knows the line of each of its keys (1-based): :attr:`lines`."""

    lines: dict[Any, int]

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.lines = {}

    def line(self, key: Any, default: int | None = None) -> int | None:
        """The line of ``key``, or ``default``."""
        return self.lines.get(key, default)


def _too_large(literal: str) -> bool:
    """An integer literal of more digits than :data:`MAX_INT_DIGITS`, or beyond the largest float."""
    if len(literal) > MAX_INT_DIGITS:
        return True
    try:
        return abs(int(literal.replace("_", ""), 0)) > sys.float_info.max
    except ValueError:  # a form int() does not read (YAML's 0o, sexagesimal): small by the length check
        return False


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
    nul = data.find(b"\0")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        raise YamlError(f"{p}:{line}: the {what} is a binary file, not text "
                        "(a NUL byte); give a UTF-8 text file")
    try:
        return data.decode("utf-8").removeprefix(_BOM)
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise YamlError(f"{p}:{line}: the {what} is not UTF-8 text: byte 0x{data[exc.start]:02x} at column {col} "
                        "(save it as UTF-8)") from None


def _where(source: str, node: yaml.Node) -> str:
    return f"{source}:{node.start_mark.line + 1}"


def _key(constructor: yaml.SafeLoader, k: yaml.ScalarNode) -> Any:
    """A mapping key as the reader will see it (``1`` and ``0x1``, ``yes`` and ``true`` are one key)."""
    import yaml

    if k.tag == "tag:yaml.org,2002:int" and _too_large(k.value):
        return (k.tag, k.value)
    try:
        value = constructor.construct_object(k)
        hash(value)
    except (yaml.YAMLError, ValueError, TypeError):
        return (k.tag, k.value)
    return (type(value) is bool, value)  # True and 1 are equal in Python, not in YAML


def _check(root: yaml.Node, source: str, max_nodes: int) -> None:
    """Duplicate keys, non-finite numbers, recursive aliases and the expanded size, in one pass."""
    import yaml

    floats = yaml.SafeLoader("")
    size: dict[int, int] = {}  # id(node) -> expanded node count, once computed
    keys: dict[int, str] = {}  # id(value node) -> its key, to name a bad value
    float_tag, int_tag = "tag:yaml.org,2002:float", "tag:yaml.org,2002:int"
    # iterative post-order walk: (node, children pushed?)
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    open_: set[int] = set()
    while stack:
        node, expanded = stack.pop()
        nid = id(node)
        if isinstance(node, yaml.ScalarNode):
            if nid not in size:
                key = keys.get(nid)
                named = f"'{key}': " if key is not None else ""
                if node.tag == float_tag and not math.isfinite(floats.construct_yaml_float(node)):
                    raise YamlError(f"{_where(source, node)}: {named}{node.value[:40]!r} is not a finite number")
                if node.tag == int_tag and _too_large(node.value):
                    raise YamlError(f"{_where(source, node)}: {named}an integer of {len(node.value)} characters is "
                                    "too large for a number (at most 1.8e308)")
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
                seen: dict[Any, int] = {}
                for k, v in node.value:
                    if isinstance(k, yaml.ScalarNode):
                        keys.setdefault(id(v), k.value)
                for k, _ in node.value:
                    if not isinstance(k, yaml.ScalarNode):
                        kind = "list" if isinstance(k, yaml.SequenceNode) else "mapping"
                        raise YamlError(f"{_where(source, k)}: a key is a {kind}; a key is a name (write it "
                                        "without brackets, or quote it)")
                    key = _key(floats, k)
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


def node_lines(root: yaml.Node) -> dict[tuple[Any, ...], int]:
    """The line (1-based) where every node of a composed document (:func:`compose`) starts, by its path of
    keys and list indices (the root is ``()``)."""
    out: dict[tuple[Any, ...], int] = {}
    stack: list[tuple[yaml.Node, tuple[Any, ...]]] = [(root, ())]
    while stack:  # iterative pre-order, in document order (a key given twice: its last node's line)
        node, path = stack.pop()
        out[path] = node.start_mark.line + 1
        if node.id == "mapping":
            stack.extend((v, path + (k.value,)) for k, v in reversed(node.value))
        elif node.id == "sequence":
            stack.extend((v, path + (i,)) for i, v in reversed(list(enumerate(node.value))))
    return out


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


class _Refused(ValueError):
    """A JSON value refused where it was scanned (its position added by :func:`_checked`)."""

    def __init__(self, what: str, pos: int | None = None) -> None:
        super().__init__(what)
        self.what, self.pos = what, pos


def _json_int(literal: str) -> int:
    if _too_large(literal):
        raise _Refused(f"an integer of {len(literal)} digits is too large for a number (at most 1.8e308)")
    return int(literal)


def _json_constant(name: str) -> float:
    raise _Refused(f"{name} is not a finite number")


def _checked(scan_once: Any) -> Any:
    """``scan_once`` of the JSON scanner, with every value it returns checked at its position."""
    def scan(s: str, idx: int) -> tuple[Any, int]:
        try:
            value, end = scan_once(s, idx)
        except _Refused as exc:
            raise exc if exc.pos is not None else _Refused(exc.what, idx) from None
        if isinstance(value, float) and not math.isfinite(value):
            raise _Refused(f"{s[idx:end][:40]} is not a finite number", idx)
        return value, end
    return scan


#: The key of an object member, just before its value (``"key" :``).
_KEY_BEFORE = re.compile(r'"((?:[^"\\]|\\.)*)"\s*:\s*\Z')


def _line(text: str, pos: int) -> int:
    return text.count("\n", 0, pos) + 1


def load_json(text: str, source: str) -> Any:
    """The value of a JSON document, its objects as :class:`LineDict` (the line of each key).

    Refused with ``source:line:``: a key given twice in one object, ``NaN``, ``Infinity``, a number
    that overflows a float (``1e999``), an integer beyond the largest float, a syntax error.

    Raises
    ------
    YamlError
        With ``source:line:`` of the problem.
    """
    text = text.removeprefix(_BOM)

    def parse_object(s_and_end: tuple[str, int], strict: bool, scan_once: Any, object_hook: Any,
                     object_pairs_hook: Any, memo: Any = None) -> tuple[LineDict, int]:
        at: list[int] = []  # where each value of this object starts

        def scan_value(s: str, idx: int) -> tuple[Any, int]:
            at.append(idx)
            try:
                return scan_once(s, idx)
            except _Refused as exc:  # a value refused as it was scanned: named by the key just before it
                key = _KEY_BEFORE.search(s, max(0, idx - 300), idx)
                if exc.pos != idx or key is None:
                    raise
                raise _Refused(f"'{key.group(1)}': {exc.what}", idx) from None

        pairs, end = _json_decoder.JSONObject(s_and_end, strict, scan_value, None, list, memo)
        out = LineDict()
        for (k, v), pos in zip(pairs, at, strict=False):
            if k in out:
                raise _Refused(f"key '{k}' is given twice in one object (first at line {out.lines[k]}); "
                               "give each key once", pos)
            out[k], out.lines[k] = v, _line(text, pos)
        return out, end

    def parse_array(s_and_end: tuple[str, int], scan_once: Any) -> tuple[list[Any], int]:
        return _json_decoder.JSONArray(s_and_end, _checked(scan_once))

    ctx = json.JSONDecoder(parse_int=_json_int, parse_constant=_json_constant)
    ctx.parse_object = lambda s_and_end, strict, scan_once, *rest: parse_object(  # type: ignore[method-assign]
        s_and_end, strict, _checked(scan_once), *rest)
    ctx.parse_array = parse_array  # type: ignore[method-assign]
    scan = _checked(_json_scanner.py_make_scanner(ctx))
    ws = _json_decoder.WHITESPACE
    try:
        try:
            value, end = scan(text, ws.match(text, 0).end())
        except StopIteration as exc:
            raise json.JSONDecodeError("Expecting value", text, exc.value) from None
        end = ws.match(text, end).end()
        if end != len(text):
            raise json.JSONDecodeError("Extra data", text, end)
    except json.JSONDecodeError as exc:
        raise YamlError(f"{source}:{exc.lineno}: invalid JSON: {exc.msg}") from None
    except _Refused as exc:
        raise YamlError(f"{source}:{_line(text, exc.pos or 0)}: {exc.what}") from None
    except RecursionError:
        raise YamlError(f"{source}:1: invalid JSON: nested too deeply") from None
    return value
