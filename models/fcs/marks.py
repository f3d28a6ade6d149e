"""Line numbers of the nodes of a YAML document, for errors that name ``file:line`` (mission and
weather files share them; each reader imports this module, neither imports the other)."""
from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from ..common import safe_yaml, values
from .errors import MissionError

__all__ = ["Lines", "Context", "check_notes"]


class Lines:
    """Line numbers of the YAML nodes, by path of keys and indices."""

    def __init__(self, text: str) -> None:
        self.map: dict[tuple, int] = {}
        try:  # checked (an alias bomb is refused, not walked); the reader reports its errors
            root = safe_yaml.compose(text, "<lines>")
        except safe_yaml.YamlError:
            root = None
        if root is not None:
            self._walk(root, ())

    def _walk(self, node: Any, path: tuple) -> None:
        self.map[path] = node.start_mark.line + 1
        if node.id == "mapping":  # yaml.MappingNode
            for k, v in node.value:
                self.map[path + (k.value,)] = k.start_mark.line + 1
                self._walk(v, path + (k.value,))
        elif node.id == "sequence":  # yaml.SequenceNode
            for i, v in enumerate(node.value):
                self._walk(v, path + (i,))

    def line(self, path: tuple) -> int:
        while path and path not in self.map:
            path = path[:-1]
        return self.map.get(path, 1)


class Context:
    """A file's name and its line marks: :meth:`fail` makes the one-line error of a node."""

    def __init__(self, source: str, lines: Lines) -> None:
        self.source, self.lines = source, lines

    def fail(self, path: tuple, what: str) -> MissionError:
        return MissionError(f"{self.source}:{self.lines.line(path)}: {what}")


def check_notes(m: Mapping, keys: tuple[str, ...], what: str, path: tuple,
                fail: Callable[[tuple, str], Exception]) -> None:
    """The free-text fields ``keys`` of the mapping ``m`` at ``path`` (a note, a source): text, when given;
    ``fail(path, what)`` makes the error (with the file and line)."""
    for k in keys:
        if k in m:
            try:
                values.text(m[k])
            except ValueError as e:
                raise fail(path + (k,), f"{what} field '{k}': {e}") from None
