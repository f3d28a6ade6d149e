"""Conditions on a variable (``component.variable OP number``) and the stop condition of a run.

One grammar for the scenario files' ``when:`` and ``emss run --until``; both read the variable
through the exchange's one :meth:`~.exchange.Exchange.probe`. The stop condition is the
execution's (it owns time): :meth:`.Execution.stop_when` arms one.
"""
from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import ScenarioError
from .exchange import Exchange

OPERATORS: dict[str, Callable[[float, float], bool]] = {
    "==": operator.eq, "!=": operator.ne, "<=": operator.le, ">=": operator.ge, "<": operator.lt, ">": operator.gt}
_CONDITION = re.compile(r"^\s*([A-Za-z_][\w.\[\]]*)\s*(==|!=|<=|>=|<|>)\s*(\S+)\s*$")


@dataclass(frozen=True)
class Condition:
    """``path op value``: holds when the variable's current value compares so with ``value``."""

    path: str
    op: str
    value: float

    def holds(self, x: float) -> bool:
        return OPERATORS[self.op](x, self.value)

    def watch(self, exchange: Exchange, where: str) -> Callable[[], bool]:
        """A function telling whether the condition holds now (the variable read through the probe)."""
        read = exchange.probe(self.path, where, numeric=True)
        test, value = OPERATORS[self.op], self.value
        return lambda: test(float(read()), value)  # type: ignore[arg-type]

    def __str__(self) -> str:
        return f"{self.path} {self.op} {self.value:g}"


def parse_condition(text: str, where: str) -> Condition:
    """``component.variable OP number`` (OP one of ``== != < <= > >=``; true/false stand for 1/0).

    Raises
    ------
    ScenarioError
        Naming ``where`` and what is allowed.
    """
    m = _CONDITION.match(str(text))
    if m is None:
        raise ScenarioError(f"{where} must read 'component.variable OP number' with OP one of "
                            f"{' '.join(OPERATORS)}, got {text!r}")
    try:
        value = float({"true": 1.0, "false": 0.0}.get(m.group(3).lower(), m.group(3)))
        if not math.isfinite(value):
            raise ValueError
    except ValueError:
        raise ScenarioError(f"{where} compares with a number (a finite number) or true/false, "
                            f"got {m.group(3)!r}") from None
    return Condition(m.group(1), m.group(2), value)


class StopCondition:
    """Ends a run after the first macro step at which a condition holds (``emss run --until``).

    Parameters
    ----------
    text : str
        ``component.variable OP number``, e.g. ``"fcs.mission_completed == 1"``.
    where : str
        What gave the condition, for messages.
    """

    def __init__(self, text: str, where: str = "--until") -> None:
        self.condition = parse_condition(text, where)
        self.where = where
        self.holds: Callable[[], bool] = lambda: False

    def attach(self, exchange: Exchange) -> None:
        """Resolve the variable (raises ConfigurationError when the system has none of that name)."""
        self.holds = self.condition.watch(exchange, self.where)

    def __str__(self) -> str:
        return str(self.condition)
