"""Line numbers of the nodes of a YAML document, for errors that name ``file:line`` (mission and
weather files share them; each reader imports this module, neither imports the other)."""
from __future__ import annotations

from collections.abc import Callable, Mapping

from ..infra import safe_yaml, values
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
            self.map = safe_yaml.node_lines(root)

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
