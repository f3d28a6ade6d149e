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

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from openemss.models.infra import safe_yaml

from ..errors import ScenarioError
from ..master.condition import OPERATORS, Condition, parse_condition
from ..master.exchange import InputModifier
from ..ssp.values import INT32_RANGE

if TYPE_CHECKING:
    from ..master.execution import Execution

__all__ = ["INT32_RANGE", "KINDS", "OPERATORS", "Condition", "Event", "ScenarioError", "ScenarioManipulator",
           "load_scenario", "parse_condition"]

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
    when: Condition | None = None


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
    """The events of one variable and the exchange's modifier that gives it its value."""

    path: str
    events: list[Event]
    modifier: InputModifier
    frozen: float | None = None

    @property
    def is_int(self) -> bool:
        return self.modifier.is_int


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
        self._pending: list[tuple[Condition, Callable[[], bool], list[tuple[_Track, Event]]]] = []
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
            tr = _Track(path, events, execution.exchange.modifier(path, all_events[0].where))
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
        self._pending = [(c, c.watch(execution.exchange, f"{pairs[0][1].where}: 'when'"), pairs)
                         for c, pairs in conditions.items()]
        self.fired = []

    def _fire(self, time_s: float) -> None:
        """Start the events of every condition that holds at ``time_s`` [s], once."""
        still = []
        for cond, holds, pairs in self._pending:
            if not holds():
                still.append((cond, holds, pairs))
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
                    tr.frozen = tr.modifier.current() if value is None else value
                value = tr.frozen
            elif e.kind == "set":
                value, tr.frozen = float(e.value0), None  # type: ignore[arg-type]
            else:  # ramp, held at its end value afterwards
                frac = min(1.0, (time_s - e.start_s) / (e.end_s - e.start_s))
                value, tr.frozen = e.value0 + frac * (e.value1 - e.value0), None  # type: ignore[operator]
        if value is not None and tr.is_int:
            value = float(round(value))
        return value

    def apply(self, time_s: float) -> None:
        """Bring every variable to its scenario value at ``time_s`` [s], through the exchange's modifiers."""
        if self._pending:
            self._fire(time_s)
        for tr in self.tracks:
            value = self._value_at(tr, time_s)
            if value is None:
                tr.modifier.release()
            else:
                tr.modifier.override(value)
