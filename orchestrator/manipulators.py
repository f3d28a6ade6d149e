"""Scenarios: timed overrides of FMU inputs and tunable parameters (fault injection, mission events).

A scenario file (YAML) is a list of events::

    events:
      - at: 2.0                       # [s] from then on, hold this value
        set: {engine.distortion_on: true}
      - from: 4.0                     # [s] ramp linearly between two values, then hold the end value
        to: 6.0
        ramp: {engine.customer_bleed_kg_s: [0.0, 0.2]}
      - at: 8.0                       # freeze at the value it has then
        hold: [airframe.elevator]
      - at: 9.0                       # give the variable back to its connection
        release: [engine.distortion_on, airframe.elevator]

While a variable is overridden, the value the master would set (from a
connection, or the one it holds) is replaced, in every algorithm, right before
the FMU gets its inputs; the recorded inputs show the override. A released
connected input follows its connection again; a released unconnected one keeps
its last value. Bad files are refused with one message naming the file and line.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from .errors import ConfigurationError

if TYPE_CHECKING:
    from .execution import Execution

KINDS = ("set", "ramp", "hold", "release")


@dataclass(frozen=True)
class Event:
    """One timed action on one variable (``component.variable``)."""

    kind: str
    path: str
    start_s: float
    end_s: float
    value0: float | int | bool | None
    value1: float | int | bool | None
    where: str


class ScenarioError(ConfigurationError):
    """A scenario file that cannot be applied."""


def _scalar(node: yaml.Node, where: str, what: str) -> Any:
    if not isinstance(node, yaml.ScalarNode):
        raise ScenarioError(f"{where}: {what} must be a single value")
    return yaml.safe_load(yaml.serialize(node))


def _number(node: yaml.Node, where: str, what: str) -> float:
    v = _scalar(node, where, what)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ScenarioError(f"{where}: {what} must be a number of seconds, got {v!r}")
    return float(v)


def _value(v: Any, where: str, path: str) -> float | int | bool:
    if isinstance(v, (bool, int, float)):
        return v
    raise ScenarioError(f"{where}: value for '{path}' must be a number or true/false, got {v!r}")


def _event(node: yaml.Node, file: str, index: int) -> list[Event]:
    where = f"{file}:{node.start_mark.line + 1}"
    if not isinstance(node, yaml.MappingNode):
        raise ScenarioError(f"{where}: event {index} must be a mapping with 'at' or 'from'/'to' and one of "
                            f"{', '.join(KINDS)}")
    fields = {_scalar(k, where, "a key"): v for k, v in node.value}
    actions = [k for k in fields if k in KINDS]
    unknown = [k for k in fields if k not in KINDS + ("at", "from", "to")]
    if unknown:
        raise ScenarioError(f"{where}: event {index}: unknown key '{unknown[0]}' (allowed: at, from, to, "
                            f"{', '.join(KINDS)})")
    if len(actions) != 1:
        raise ScenarioError(f"{where}: event {index} needs exactly one of {', '.join(KINDS)}")
    kind = actions[0]
    body = fields[kind]
    if kind == "ramp":
        if "from" not in fields or "to" not in fields:
            raise ScenarioError(f"{where}: event {index}: a ramp needs 'from' and 'to' [s]")
        t0 = _number(fields["from"], where, "'from'")
        t1 = _number(fields["to"], where, "'to'")
        if not t1 > t0:
            raise ScenarioError(f"{where}: event {index}: a ramp needs 'to' > 'from' (got {t0} to {t1})")
    else:
        if "at" not in fields:
            raise ScenarioError(f"{where}: event {index}: '{kind}' needs 'at' [s]")
        t0 = t1 = _number(fields["at"], where, "'at'")
    if t0 < 0:
        raise ScenarioError(f"{where}: event {index}: times must be >= 0 s")
    events = []
    if kind in ("set", "ramp"):
        if not isinstance(body, yaml.MappingNode):
            raise ScenarioError(f"{where}: event {index}: '{kind}' takes a mapping of component.variable to "
                                + ("a value" if kind == "set" else "[start value, end value]"))
        for k, v in body.value:
            path = _scalar(k, where, "a variable name")
            vwhere = f"{file}:{v.start_mark.line + 1}"
            if kind == "set":
                value = _value(_scalar(v, vwhere, f"the value of '{path}'"), vwhere, path)
                events.append(Event(kind, str(path), t0, t1, value, value, vwhere))
            else:
                pair = yaml.safe_load(yaml.serialize(v))
                if not (isinstance(pair, list) and len(pair) == 2):
                    raise ScenarioError(f"{vwhere}: ramp of '{path}' takes [start value, end value]")
                events.append(Event(kind, str(path), t0, t1, float(_value(pair[0], vwhere, path)),
                                    float(_value(pair[1], vwhere, path)), vwhere))
    else:
        paths = yaml.safe_load(yaml.serialize(body))
        if not (isinstance(paths, list) and all(isinstance(p, str) for p in paths)):
            raise ScenarioError(f"{where}: event {index}: '{kind}' takes a list of component.variable names")
        events.extend(Event(kind, p, t0, t1, None, None, where) for p in paths)
    return events


def load_scenario(path: Path | str) -> list[Event]:
    """Read and check a scenario file; raises ScenarioError naming the file and line."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read the scenario: {exc.strerror}") from None
    try:
        root = yaml.compose(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark is not None else "?"
        raise ScenarioError(f"{path}:{line}: not valid YAML: {getattr(exc, 'problem', exc)}") from None
    if root is None:
        return []
    if not isinstance(root, yaml.MappingNode):
        raise ScenarioError(f"{path}:1: a scenario is a mapping with the key 'events'")
    fields = {_scalar(k, f"{path}:1", "a key"): v for k, v in root.value}
    unknown = sorted(set(fields) - {"events", "description"})
    if unknown:
        raise ScenarioError(f"{path}:1: unknown key '{unknown[0]}' (allowed: events, description)")
    events_node = fields.get("events")
    if events_node is None:
        return []
    if not isinstance(events_node, yaml.SequenceNode):
        raise ScenarioError(f"{path}:{events_node.start_mark.line + 1}: 'events' must be a list")
    events: list[Event] = []
    for i, node in enumerate(events_node.value, start=1):
        events.extend(_event(node, str(path), i))
    return events


@dataclass
class _Track:
    """The events of one variable and where its value goes.

    A connected input is overridden in the execution's input vector (``vector``,
    ``index``); anything else (an unconnected input, a tunable parameter) is set
    directly on its FMU when the value changes (``slave``, ``variable``).
    """

    path: str
    events: list[Event]
    is_int: bool
    vector: Any = None
    index: int = -1
    slave: Any = None
    variable: Any = None
    shown: tuple[Any, int] | None = None  # where recorders read it, for directly set variables
    frozen: float | None = None
    last_set: float | None = None

    def current(self) -> float:
        if self.vector is not None:
            return float(self.vector[self.index])
        return float(self.slave.get_value(self.variable))


class ScenarioManipulator:
    """Applies scenario events to an execution (see the module docstring).

    Parameters
    ----------
    events : list[Event]
        From ``load_scenario``, or built in Python.
    """

    def __init__(self, events: list[Event]) -> None:
        self.events = sorted(events, key=lambda e: (e.start_s, e.end_s))
        self.tracks: list[_Track] = []

    def variables(self) -> list[str]:
        """The ``component.variable`` paths the scenario touches."""
        return sorted({e.path for e in self.events})

    def attach(self, execution: Execution) -> None:
        """Resolve every variable to where its value goes in the execution."""
        by_path: dict[str, list[Event]] = {}
        for e in self.events:
            by_path.setdefault(e.path, []).append(e)
        self.tracks = []
        for path, events in by_path.items():
            slot = execution.input_slot(path, events[0].where)
            if isinstance(slot[0], str):
                type_name, index = slot
                tr = _Track(path, events, type_name != "Real", vector=execution.vectors[type_name].inputs,
                            index=index)  # type: ignore[arg-type]
            else:
                slave, var = slot
                tr = _Track(path, events, var.type_name != "Real", slave=slave, variable=var,
                            shown=execution.output_slot(path))
            self.tracks.append(tr)

    def _value_at(self, tr: _Track, time_s: float) -> float | None:
        eps = 1e-9 * max(1.0, abs(time_s))
        value: float | None = None
        for e in tr.events:
            if e.start_s > time_s + eps:
                break
            if e.kind == "release":
                value, tr.frozen = None, None
            elif e.kind == "hold":
                if tr.frozen is None:
                    tr.frozen = tr.current() if value is None else value
                value = tr.frozen
            elif e.kind == "set":
                value, tr.frozen = float(e.value0), None  # type: ignore[arg-type]
            else:  # ramp, held at its end value afterwards
                frac = min(1.0, (time_s - e.start_s) / (e.end_s - e.start_s))
                value, tr.frozen = e.value0 + frac * (e.value1 - e.value0), None  # type: ignore[operator]
        if value is not None and tr.is_int:
            value = float(round(value))
        return value

    def apply(self, time_s: float) -> list[tuple[Any, int, float]]:
        """Bring every variable to its scenario value at ``time_s`` [s]; returns the overrides of
        connected inputs for the execution to re-apply after each transfer."""
        active: list[tuple[Any, int, float]] = []
        for tr in self.tracks:
            value = self._value_at(tr, time_s)
            if value is None:
                continue
            if tr.vector is not None:
                tr.vector[tr.index] = value
                active.append((tr.vector, tr.index, value))
                continue
            if value != tr.last_set:
                var = tr.variable
                typed = value if var.type_name == "Real" else (bool(value) if var.type_name == "Boolean"
                                                                else int(value))
                tr.slave.set_value(var, typed)
                tr.last_set = value
            if tr.shown is not None:
                tr.shown[0][tr.shown[1]] = value
        return active
