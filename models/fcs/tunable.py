"""One mechanism for the tunable parameters of every controller.

Each controller keeps its gains, limits and time constants in a frozen
dataclass (its *parameter set*). The :class:`Tunable` mixin gives every
controller the same script interface:

``get_parameter(name)``, ``set_parameter(name, value)``, ``parameter_names()``
and ``parameters`` (the frozen set itself). Setting a parameter replaces the
frozen set with :func:`dataclasses.replace`, so a parameter set is never
mutated behind the back of whoever holds a reference to it.

Parameter sets are read from YAML files in ``data/`` by :func:`load_params`.
Each entry there is ``name: {value: ..., unit: ..., min: ..., max: ...,
note: ...}``; every file names its sources. The optional ``min``/``max``
bounds are checked on load and on every ``set_parameter``.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from importlib import resources
from typing import Any, ClassVar, Generic, TypeVar

import numpy as np

from ..common import safe_yaml
from .errors import ParameterError

__all__ = ["Tunable", "load_params", "param_bounds", "field_index", "DATA_PACKAGE"]

#: Package holding the parameter files (relative to this package).
DATA_PACKAGE = "data"

P = TypeVar("P")


def _data_text(filename: str) -> str:
    pkg = __package__ or __name__.rpartition(".")[0]
    return resources.files(pkg).joinpath(DATA_PACKAGE, filename).read_text(encoding="utf-8")


_BOUNDS: dict[tuple[str, str], tuple[float, float]] = {}


def param_bounds(cls: type, name: str) -> tuple[float, float]:
    """Allowed range of parameter ``name`` of parameter-set class ``cls`` [its unit].

    Ranges come from the parameter file (``min``/``max``); unbounded by default.
    """
    return _BOUNDS.get((cls.__name__, name), (-math.inf, math.inf))


def load_params(cls: type[P], filename: str, section: str, **overrides: float) -> P:
    """Build the frozen parameter set ``cls`` from ``section`` of ``data/<filename>``.

    Parameters
    ----------
    cls : type
        Frozen dataclass of the parameter set.
    filename : str
        YAML file in the package's ``data`` folder.
    section : str
        Top-level key of the file holding the entries of ``cls``.
    **overrides : float
        Values that replace those of the file (checked like them).

    Returns
    -------
    P
        The parameter set.

    Raises
    ------
    ParameterError
        If the file lacks a field of ``cls``, has one ``cls`` does not know,
        or a value lies outside its stated ``min``/``max``.
    """
    doc = safe_yaml.load(_data_text(filename), filename)
    where = f"{filename}:{section}"
    if section not in doc:
        raise ParameterError(f"{filename}: no section '{section}' (sections: {', '.join(sorted(doc))})")
    entries = doc[section]
    names = [f.name for f in dataclasses.fields(cls)]
    values: dict[str, Any] = {}
    for key, entry in entries.items():
        if key == "source":
            continue
        if key not in names:
            raise ParameterError(f"{where}: unknown parameter '{key}'; {cls.__name__} has: {', '.join(names)}")
        if not isinstance(entry, dict) or "value" not in entry:
            raise ParameterError(f"{where}.{key}: expected a mapping with 'value' (and 'unit', 'note')")
        try:
            lo = float(entry.get("min", -math.inf))
            hi = float(entry.get("max", math.inf))
        except (TypeError, ValueError):
            raise ParameterError(f"{where}.{key}: min/max must be numbers, got {entry.get('min')!r}, "
                                 f"{entry.get('max')!r}") from None
        _BOUNDS[(cls.__name__, key)] = (lo, hi)
        values[key] = entry["value"]
    missing = [n for n in names if n not in values]
    if missing:
        raise ParameterError(f"{where}: missing parameter(s) {', '.join(missing)} of {cls.__name__}")
    values.update(overrides)
    for key, v in values.items():
        _check(cls, key, v, where)
    return cls(**{k: v if isinstance(v, bool) else float(v) for k, v in values.items()})


def _check(cls: type, name: str, value: Any, where: str) -> None:
    if isinstance(value, bool):
        return
    if isinstance(value, str):
        raise ParameterError(f"{where}.{name}: value {value!r} is a string, not a number (YAML reads 1.0e6 "
                             "as text: write 1.0e+6)")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{where}.{name}: value {value!r} is not a number") from None
    lo, hi = param_bounds(cls, name)
    if not (lo <= x <= hi) or math.isnan(x):
        raise ParameterError(f"{where}.{name} = {value!r} is outside the allowed range [{lo}, {hi}]")


def field_index(cls: type) -> type[enum.IntEnum]:
    """An IntEnum of the fields of the parameter-set class ``cls``, each its index in :meth:`Tunable.values`
    (the compiled laws read their parameters as ``p[I.name]``; numba reads an IntEnum member as a constant)."""
    return enum.IntEnum(f"{cls.__name__}Index", [(f.name, i) for i, f in enumerate(dataclasses.fields(cls))])


class Tunable(Generic[P]):
    """Mixin giving a controller scriptable access to its frozen parameter set.

    The controller stores its set in ``self._params``. Subclasses may
    override :meth:`_on_parameters_changed` to refresh derived quantities.
    """

    _params: P
    _values_of: object = None  # the parameter set that _values holds

    def values(self) -> np.ndarray:
        """The parameter set as floats in its fields' order (:func:`field_index`), for the compiled laws; built
        again whenever ``_params`` is another set (a set is frozen: the same object, the same values)."""
        p = self._params
        if self._values_of is not p:
            self._values = np.array([float(getattr(p, f.name)) for f in dataclasses.fields(p)])  # type: ignore[arg-type]
            self._values_of = p
        return self._values
    #: Name used in error messages.
    tunable_name: ClassVar[str] = "controller"

    @property
    def parameters(self) -> P:
        """The current frozen parameter set."""
        return self._params

    @parameters.setter
    def parameters(self, params: P) -> None:
        if type(params) is not type(self._params):
            raise ParameterError(f"{self.tunable_name}: expected a {type(self._params).__name__}, "
                                 f"got {type(params).__name__}")
        self._params = params
        self._on_parameters_changed()

    def parameter_names(self) -> tuple[str, ...]:
        """Names of all tunable parameters of this controller."""
        return tuple(f.name for f in dataclasses.fields(self._params))  # type: ignore[arg-type]

    def get_parameter(self, name: str) -> float:
        """Value of parameter ``name`` [its unit, see the parameter file]."""
        if name not in self.parameter_names():
            raise ParameterError(f"{self.tunable_name}: unknown parameter '{name}'; "
                                 f"valid names: {', '.join(self.parameter_names())}")
        return getattr(self._params, name)

    def set_parameter(self, name: str, value: float) -> None:
        """Set parameter ``name`` to ``value`` [its unit], checked against its range."""
        if name not in self.parameter_names():
            raise ParameterError(f"{self.tunable_name}: unknown parameter '{name}'; "
                                 f"valid names: {', '.join(self.parameter_names())}")
        _check(type(self._params), name, value, self.tunable_name)
        current = getattr(self._params, name)
        new = bool(value) if isinstance(current, bool) else float(value)
        self._params = dataclasses.replace(self._params, **{name: new})  # type: ignore[type-var]
        self._on_parameters_changed()

    def _on_parameters_changed(self) -> None:
        """Hook called after the parameter set changed (default: nothing)."""
