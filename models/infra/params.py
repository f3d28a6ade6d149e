"""One parameter mechanism for every model: parameter files, frozen parameter sets, FMU parameters.

A model keeps each group of its parameters (a controller's gains, an engine's limits, a battery's cell)
in a frozen dataclass, its *parameter set*. The values live in a YAML file (or a JSON file of the same
shape, for a model whose FMU must run without a YAML reader) of the model package's ``data/`` folder,
one section per set and one entry per field::

    tecs:
      source: "where the numbers come from"
      k_TP: {value: 0.25, unit: 1/s, min: 0.0, max: 10.0, note: "what it is", source: "optional, per entry"}

:func:`parameter_set` reads a section against its dataclass once (cached) and gives a :class:`ParamSet`:
every field is stated exactly once, of its field's kind (``bool``, ``int``, ``float``, ``str``), with its
unit, range, note and source, and its value within the range. Every problem is a one-line error naming
``file:line``. The :class:`ParamSet` then

* builds the frozen set (:meth:`ParamSet.make`, with checked overrides), replaces values in one
  (:meth:`ParamSet.replace`) and checks a single value (:meth:`ParamSet.check`);
* collects a set from values held elsewhere under their FMU names (:meth:`ParamSet.collect`);
* gives its entries as rows of a signal table (:meth:`ParamSet.signals`), each with its unit, its
  ``min``/``max`` and its note, so that the FMU's parameters are generated from the file
  (``fmus/signal_io.py`` writes ``min``/``max`` into the modelDescription.xml).

The engine, the airframe, the flight control and the electrical system read their parameters this way.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from importlib import resources
from typing import Any, Generic, TypeVar

from . import safe_yaml, values
from .signals import Signal

__all__ = ["ParameterError", "Param", "ParamSet", "parameter_set", "parameter_set_from_text", "data_file_name",
           "INT_RANGE"]

P = TypeVar("P")
#: The kind of a parameter (its FMI type) from its dataclass field's type.
_KINDS: dict[Any, str] = {bool: "Boolean", int: "Integer", float: "Real", str: "String"}
#: The range of an Integer parameter without bounds of its own: FMI 2.0's 32-bit fmi2Integer.
INT_RANGE = (-(2 ** 31), 2 ** 31 - 1)
#: The keys an entry may have.
_ENTRY_KEYS = ("value", "unit", "min", "max", "note", "source")


class ParameterError(ValueError):
    """A parameter file or value that is not valid; the one-line message says what, where and what is allowed.

    A model package passes its own error class (a subclass of its base error) to :func:`parameter_set`.
    """


@dataclass(frozen=True)
class Param:
    """One entry of a parameter file.

    Attributes
    ----------
    name : str
        The field of the parameter set.
    kind : str
        ``Real``, ``Integer``, ``Boolean`` or ``String`` (from the field's type).
    value : float, int, bool or str
        The file's value, in ``unit``.
    unit : str
        Its unit (SI symbols, ``1`` when dimensionless).
    min, max : float
        The allowed range, inclusive (infinite when the file gives none).
    note : str
        What it is.
    source : str
        Where the value comes from: the entry's own ``source``, else its section's.
    where : str
        ``file:line`` of the entry.
    optional : bool
        The field's type admits None (``float | None``): the file may give ``value: null`` for a value the
        model computes from its own data (e.g. the start on the mission's runway).
    """

    name: str
    kind: str
    value: float | int | bool | str | None
    unit: str
    min: float
    max: float
    note: str
    source: str
    where: str
    optional: bool = False

    def typed(self, value: Any) -> float | int | bool | str | None:
        """``value`` as this parameter's kind, within its range (None for an optional one: its model computes it).

        Raises
        ------
        values.ValueProblem
            Of another kind, not finite, or outside ``[min, max]``.
        """
        if value is None and self.optional:
            return None
        if self.kind == "Boolean":
            return values.flag(value)
        if self.kind == "String":
            return values.text(value)
        if self.kind == "Integer":
            if isinstance(value, float) and value.is_integer():
                value = int(value)  # an FMI Real or a YAML 3.0 that means 3
            lo = int(max(self.min, INT_RANGE[0])) if math.isfinite(self.min) else INT_RANGE[0]
            hi = int(min(self.max, INT_RANGE[1])) if math.isfinite(self.max) else INT_RANGE[1]
            return values.integer(value, lo, hi)
        return values.number(value, self.min, self.max, "" if self.unit in ("1", "-") else self.unit)


@dataclass(frozen=True)
class ParamSet(Generic[P]):
    """The parameters of one frozen dataclass, as one section of a parameter file states them.

    Attributes
    ----------
    cls : type
        The frozen dataclass.
    file : str
        The file, as messages name it.
    section : str
        Its section.
    params : tuple of Param
        One per field of ``cls``, in the fields' order.
    error : type
        The exception raised for a bad value or name (the model package's ``ParameterError``).
    """

    cls: type[P]
    file: str
    section: str
    params: tuple[Param, ...]
    error: type[Exception] = ParameterError

    def names(self) -> tuple[str, ...]:
        """The fields, in order."""
        return tuple(p.name for p in self.params)

    def param(self, name: str) -> Param:
        """The entry of field ``name``."""
        for p in self.params:
            if p.name == name:
                return p
        raise self.error(f"{self.file}:{self.section}: unknown parameter '{name}'; {self.cls.__name__} has: "
                         f"{', '.join(self.names())}")

    def check(self, name: str, value: Any, where: str = "", prefix: str = "") -> float | int | bool | str | None:
        """``value`` for parameter ``name``, typed and within its range; the error names it ``<where>.<prefix><name>``
        (``where`` by default ``<file>:<section>``, ``prefix`` that of its FMU name)."""
        p = self.param(name)
        try:
            return p.typed(value)
        except values.ValueProblem as e:
            raise self.error(f"{where or f'{self.file}:{self.section}'}.{prefix}{name}: {e} (see {p.where})") from None

    def make(self, where: str = "", **overrides: Any) -> P:
        """The parameter set: the file's values with ``overrides`` replacing some, each checked."""
        for k in overrides:
            self.param(k)
        return self.cls(**{p.name: self.check(p.name, overrides[p.name], where) if p.name in overrides else p.value
                           for p in self.params})

    def replace(self, obj: P, where: str = "", **changes: Any) -> P:
        """``obj`` with ``changes`` (each checked against this set's ranges)."""
        return dataclasses.replace(obj, **{k: self.check(k, v, where) for k, v in changes.items()})  # type: ignore[type-var]

    def collect(self, get: Callable[[str], Any], prefix: str = "", where: str = "") -> P:
        """The set from values held under the names ``prefix + field`` (e.g. an FMU's parameters), checked."""
        return self.cls(**{p.name: self.check(p.name, get(prefix + p.name), where, prefix) for p in self.params})

    def signals(self, prefix: str = "", variability: str | None = "tunable",
                starts: Mapping[str, Any] | None = None) -> tuple[Signal, ...]:
        """The entries as parameter rows of a signal table, named ``prefix + field``.

        Parameters
        ----------
        prefix : str
            Put before each field's name (``"tecs."``, ``"bleed_"``, or none).
        variability : str or None
            The FMI variability of the rows (None: ``fixed``, read at the start).
        starts : mapping, optional
            Start values by FMU name that replace the file's (checked like them).
        """
        rows = []
        for p in self.params:
            name = prefix + p.name
            start = self.check(p.name, starts[name]) if starts and name in starts else p.value
            unit = "1" if p.unit in ("", "-") or p.kind != "Real" else p.unit
            rows.append(Signal(name, "parameter", unit, f"{p.note} ({self.file})", p.kind, start,
                               variability=variability, min=_finite(p.min), max=_finite(p.max)))
        return tuple(rows)


def _finite(x: float) -> float | None:
    return x if math.isfinite(x) else None


def data_file_name(package: str, filename: str) -> str:
    """The name of ``data/<filename>`` of ``package`` as messages give it (``models/fcs/data/tecs.yaml``)."""
    parts = package.split(".")
    if "models" in parts:  # the same name where build-fmus vendored the package under a name of its own
        parts = parts[parts.index("models"):]
    return "/".join([*parts, "data", filename])


@functools.cache
def _data_file(package: str, filename: str) -> tuple[Any, dict[tuple, int], str]:
    name = data_file_name(package, filename)
    text = resources.files(package).joinpath("data", filename).read_text(encoding="utf-8")
    return _read(text, name)


def _read(text: str, name: str) -> tuple[Any, dict[tuple, int], str]:
    """The document of a parameter file and the line of each of its keys, by path; a ``.json`` file is read
    as JSON (no YAML reader needed: the engine FMU runs without one), any other as YAML."""
    if name.endswith(".json"):
        doc = safe_yaml.load_json(text, name)
        lines: dict[tuple, int] = {}
        stack: list[tuple[Any, tuple]] = [(doc, ())]
        while stack:
            d, path = stack.pop()
            if isinstance(d, safe_yaml.LineDict):
                for k, v in d.items():
                    lines[path + (k,)] = d.lines.get(k, 1)
                    stack.append((v, path + (k,)))
        return doc, lines, name
    root = safe_yaml.compose(text, name)
    doc = safe_yaml.load(text, name) if root is not None else None
    return doc, safe_yaml.node_lines(root) if root is not None else {}, name


def parameter_set(cls: type[P], package: str, filename: str, section: str,
                  error: type[Exception] = ParameterError) -> ParamSet[P]:
    """The :class:`ParamSet` of ``cls`` from ``section`` of ``data/<filename>`` of ``package`` (read once).

    Raises
    ------
    error
        The file is not valid YAML, lacks the section, or an entry is missing, unknown, malformed, of the
        wrong kind or outside its own range; the message names ``file:line``.
    """
    return _parameter_set(cls, package, filename, section, error)


@functools.cache
def _parameter_set(cls: type[P], package: str, filename: str, section: str,
                   error: type[Exception]) -> ParamSet[P]:
    try:
        doc, lines, name = _data_file(package, filename)
    except safe_yaml.YamlError as e:
        raise error(str(e)) from None
    return _section(cls, doc, lines, name, section, error)


def parameter_set_from_text(cls: type[P], text: str, source: str, section: str,
                            error: type[Exception] = ParameterError) -> ParamSet[P]:
    """The :class:`ParamSet` of ``cls`` from ``section`` of the YAML ``text`` read from ``source`` (a file of
    the user's, a test's text); the same checks as :func:`parameter_set`."""
    try:
        doc, lines, name = _read(text, source)
    except safe_yaml.YamlError as e:
        raise error(str(e)) from None
    return _section(cls, doc, lines, name, section, error)


def _section(cls: type[P], doc: Any, lines: dict[tuple, int], name: str, section: str,
             error: type[Exception]) -> ParamSet[P]:
    def at(*path: Any) -> str:
        while path and path not in lines:
            path = path[:-1]
        return f"{name}:{lines.get(path, 1)}"

    if not isinstance(doc, dict) or section not in doc:
        have = ", ".join(sorted(str(k) for k in doc if not str(k).startswith("_"))) if isinstance(doc, dict) else "none"
        raise error(f"{name}:1: no section '{section}' (sections: {have})")
    block = doc[section]
    if not isinstance(block, dict):
        raise error(f"{at(section)}: section '{section}' must be a mapping of parameters, got {values.show(block)}")
    hints = typing.get_type_hints(cls)
    fields = [f.name for f in dataclasses.fields(cls)]  # type: ignore[arg-type]
    try:
        src = values.text(block.get("source", ""), "the source (text)")
    except values.ValueProblem as e:
        raise error(f"{at(section, 'source')}: {section}.source: {e}") from None
    unknown = [k for k in block if k != "source" and k not in fields]
    if unknown:
        k = unknown[0]
        shown = f"'{k}'" if isinstance(k, str) else values.show(k)
        raise error(f"{at(section, k)}: unknown parameter {shown} in section '{section}'; "
                    f"{cls.__name__} has: {', '.join(fields)}")
    missing = [f for f in fields if f not in block]
    if missing:
        raise error(f"{at(section)}: section '{section}' lacks parameter(s) {', '.join(missing)} of {cls.__name__}")
    params = []
    for f in fields:
        params.append(_entry(f, block[f], hints[f], src, at, section, error))
    return ParamSet(cls, name, section, tuple(params), error)


def _entry(field: str, e: Any, hint: Any, section_source: str, at: Callable[..., str], section: str,
           error: type[Exception]) -> Param:
    """One entry ``{value, unit, min, max, note, source}`` of field ``field`` (of type ``hint``)."""
    where = at(section, field)
    if not isinstance(e, dict) or "value" not in e:
        raise error(f"{where}: {section}.{field}: expected a mapping {{value: ..., unit: ..., min: ..., max: ..., "
                    f"note: ...}}, got {values.show(e)}")
    extra = [k for k in e if k not in _ENTRY_KEYS]
    if extra:
        raise error(f"{at(section, field, extra[0])}: {section}.{field}: unknown key '{extra[0]}' (keys: "
                    f"{', '.join(_ENTRY_KEYS)})")
    args = typing.get_args(hint)
    optional = type(None) in args and len(args) == 2
    kind = _KINDS.get(next(a for a in args if a is not type(None)) if optional else hint)
    if kind is None:
        raise error(f"{where}: {section}.{field}: the field's type {hint!r} is not a parameter's (bool, int, "
                    "float, str)")
    try:
        unit = values.text(e.get("unit", "1"), "a unit (text)").strip() or "1"
        note = values.text(e.get("note", ""), "a note (text)")
        source = values.text(e.get("source", section_source), "a source (text)")
    except values.ValueProblem as exc:
        raise error(f"{where}: {section}.{field}: {exc}") from None
    bounds = []
    for key, default in (("min", -math.inf), ("max", math.inf)):
        if key in e and kind in ("Boolean", "String"):
            raise error(f"{at(section, field, key)}: {section}.{field}: a {kind} has no {key}")
        try:
            bounds.append(values.number(e[key]) if key in e else default)
        except values.ValueProblem as exc:
            raise error(f"{at(section, field, key)}: {section}.{field}.{key}: {exc}") from None
    if bounds[0] > bounds[1]:
        raise error(f"{where}: {section}.{field}: min {bounds[0]!r} is above max {bounds[1]!r}")
    p = Param(field, kind, e["value"], unit, bounds[0], bounds[1], note, source, where, optional)
    try:
        value = p.typed(e["value"])
    except values.ValueProblem as exc:
        raise error(f"{at(section, field, 'value')}: {section}.{field}: {exc}") from None
    return dataclasses.replace(p, value=float(value) if kind == "Real" and value is not None else value)
