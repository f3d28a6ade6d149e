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
      - when: fcs.section_index == 6  # at the first step where an output meets the condition
        after: 30.0                   # [s] later (optional; 'from'/'to' of a ramp count from it too)
        set: {engine.distortion_on: true}

A condition compares one variable (an output or input of any component) with a
number, using one of ``== != < <= > >=``; it is checked at every macro step from
the start and fires once. Times of the events it triggers count from the step
where it held.

While a variable is overridden, the value the master would set (from a
connection, or the one it holds) is replaced, in every algorithm, right before
the FMU gets its inputs; the recorded inputs show the override. A released
connected input follows its connection again; a released unconnected one keeps
its last value. Bad files are refused with one message naming the file and line.
"""
from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from openemss.models.common import safe_yaml

from .errors import ConfigurationError, EmssError

if TYPE_CHECKING:
    from .execution import Execution

KINDS = ("set", "ramp", "hold", "release")
INT32_RANGE = (-(2 ** 31), 2 ** 31 - 1)  #: values of an FMI 2.0 Integer (fmi2Integer is a C int)
OPERATORS: dict[str, Callable[[float, float], bool]] = {
    "==": operator.eq, "!=": operator.ne, "<=": operator.le, ">=": operator.ge, "<": operator.lt, ">": operator.gt}
_CONDITION = re.compile(r"^\s*([A-Za-z_][\w.\[\]]*)\s*(==|!=|<=|>=|<|>)\s*(\S+)\s*$")


@dataclass(frozen=True)
class Condition:
    """``path op value``: fires the events of its scenario entry at the first step it holds."""

    path: str
    op: str
    value: float

    def holds(self, x: float) -> bool:
        return OPERATORS[self.op](x, self.value)

    def __str__(self) -> str:
        return f"{self.path} {self.op} {self.value:g}"


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
    when: Condition | None = None


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
    unknown = [k for k in fields if k not in KINDS + ("at", "from", "to", "when", "after")]
    if unknown:
        raise ScenarioError(f"{where}: event {index}: unknown key '{unknown[0]}' (allowed: at, from, to, when, "
                            f"after, {', '.join(KINDS)})")
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
    elif "when" in fields:
        if "at" in fields:
            raise ScenarioError(f"{where}: event {index}: give 'at' or 'when', not both")
        t0 = t1 = _number(fields["after"], where, "'after'") if "after" in fields else 0.0
    else:
        if "at" not in fields:
            raise ScenarioError(f"{where}: event {index}: '{kind}' needs 'at' [s] or 'when' (a condition)")
        t0 = t1 = _number(fields["at"], where, "'at'")
    if "after" in fields and ("when" not in fields or kind == "ramp"):
        raise ScenarioError(f"{where}: event {index}: 'after' needs 'when' (a ramp counts 'from'/'to' from "
                            "the condition instead)")
    if t0 < 0:
        raise ScenarioError(f"{where}: event {index}: times must be >= 0 s")
    when = _condition(fields["when"], where, index) if "when" in fields else None
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
                events.append(Event(kind, str(path), t0, t1, value, value, vwhere, when))
            else:
                pair = yaml.safe_load(yaml.serialize(v))
                if not (isinstance(pair, list) and len(pair) == 2):
                    raise ScenarioError(f"{vwhere}: ramp of '{path}' takes [start value, end value]")
                events.append(Event(kind, str(path), t0, t1, float(_value(pair[0], vwhere, path)),
                                    float(_value(pair[1], vwhere, path)), vwhere, when))
    else:
        paths = yaml.safe_load(yaml.serialize(body))
        if not (isinstance(paths, list) and all(isinstance(p, str) for p in paths)):
            raise ScenarioError(f"{where}: event {index}: '{kind}' takes a list of component.variable names")
        events.extend(Event(kind, p, t0, t1, None, None, where, when) for p in paths)
    return events


def parse_condition(text: str, where: str) -> Condition:
    """``component.variable OP number`` (OP one of ``== != < <= > >=``; true/false stand for 1/0)."""
    m = _CONDITION.match(str(text))
    if m is None:
        raise ScenarioError(f"{where} must read 'component.variable OP number' with OP one of "
                            f"{' '.join(OPERATORS)}, got {text!r}")
    try:
        value = float({"true": 1.0, "false": 0.0}.get(m.group(3).lower(), m.group(3)))
        if not math.isfinite(value):
            raise ValueError
    except ValueError:
        raise ScenarioError(f"{where} compares with a number (a finite number) or true/false, got {m.group(3)!r}") from None
    return Condition(m.group(1), m.group(2), value)


def _condition(node: yaml.Node, where: str, index: int) -> Condition:
    return parse_condition(_scalar(node, where, "'when'"), f"{where}: event {index}: 'when'")


def load_scenario(path: Path | str) -> list[Event]:
    """Read and check a scenario file; raises ScenarioError naming the file and line."""
    path = Path(path)
    try:  # the project's one YAML reader: duplicate keys, alias bombs, NaN refused with file:line
        root = safe_yaml.compose(safe_yaml.read_text(path, "scenario"), str(path))
    except safe_yaml.YamlError as exc:
        raise ScenarioError(str(exc)) from None
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


def reader(execution: Execution, path: str, where: str) -> Callable[[], float]:
    """A function returning the current value of ``component.variable`` (any causality)."""
    try:
        i, var = execution.system.variable(path)
    except EmssError:
        raise ConfigurationError(f"{where}: 'when' names no variable '{path}' (write component.variable)") from None
    slot = execution.output_slot(path)
    if slot is not None:
        vec, j = slot
        return lambda: float(vec[j])
    if var.type_name not in ("Real", "Integer", "Boolean"):
        raise ConfigurationError(f"{where}: 'when' needs a Real, Integer or Boolean variable; '{path}' is a "
                                 f"{var.type_name}")
    try:
        kind, j = execution.input_slot(path, where)
        if isinstance(kind, str):
            vec = execution.vectors[kind].inputs
            return lambda: float(vec[j])
    except ConfigurationError:
        pass  # an output that is not exchanged, or a parameter: ask the FMU
    slave = execution.slaves[i]
    return lambda: float(slave.get_value(var))


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
        self._pending: list[tuple[Condition, Callable[[], float], list[tuple[_Track, Event]]]] = []
        self.fired: list[tuple[float, str]] = []  # (time [s], condition) of every condition that held

    def variables(self) -> list[str]:
        """The ``component.variable`` paths the scenario touches."""
        return sorted({e.path for e in self.events})

    def attach(self, execution: Execution) -> None:
        """Resolve every variable to where its value goes in the execution."""
        by_path: dict[str, list[Event]] = {}
        for e in self.events:
            by_path.setdefault(e.path, []).append(e)
        self.tracks = []
        conditions: dict[Condition, list[tuple[_Track, Event]]] = {}
        for path, all_events in by_path.items():
            events = [e for e in all_events if e.when is None]
            slot = execution.input_slot(path, all_events[0].where)
            if isinstance(slot[0], str):
                type_name, index = slot
                tr = _Track(path, events, type_name != "Real", vector=execution.vectors[type_name].inputs,
                            index=index)  # type: ignore[arg-type]
            else:
                slave, var = slot
                tr = _Track(path, events, var.type_name != "Real", slave=slave, variable=var,
                            shown=execution.output_slot(path))
            self.tracks.append(tr)
            if tr.is_int:  # an FMI Integer (or Boolean) is 32 bits: a larger value would wrap, silently
                for e in all_events:
                    for v in (e.value0, e.value1):
                        if v is not None and not INT32_RANGE[0] <= v <= INT32_RANGE[1]:
                            raise ScenarioError(f"{e.where}: value {v} for '{path}' is outside the range of an "
                                                f"FMI Integer ({INT32_RANGE[0]} to {INT32_RANGE[1]})")
            for e in all_events:
                if e.when is not None:
                    conditions.setdefault(e.when, []).append((tr, e))
        self._pending = [(c, reader(execution, c.path, pairs[0][1].where), pairs) for c, pairs in conditions.items()]
        self.fired = []

    def _fire(self, time_s: float) -> None:
        """Start the events of every condition that holds at ``time_s`` [s], once."""
        still = []
        for cond, read, pairs in self._pending:
            if not cond.holds(read()):
                still.append((cond, read, pairs))
                continue
            self.fired.append((time_s, str(cond)))
            for tr, e in pairs:
                tr.events.append(replace(e, start_s=time_s + e.start_s, end_s=time_s + e.end_s, when=None))
                tr.events.sort(key=lambda ev: (ev.start_s, ev.end_s))
        self._pending = still

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
        if self._pending:
            self._fire(time_s)
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
