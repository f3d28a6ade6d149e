"""The tunable parameters of every controller, on the models' one parameter mechanism.

Each controller keeps its gains, limits and time constants in a frozen dataclass (its *parameter set*),
read from a YAML file in ``data/`` by :func:`load_params` through :mod:`openemss.models.infra.params`
(each entry ``name: {value, unit, min, max, note}``, every file names its sources; ranges checked on load
and on every ``set_parameter``, errors naming ``file:line``). The :class:`Tunable` mixin gives every
controller the same script interface:

``get_parameter(name)``, ``set_parameter(name, value)``, ``parameter_names()``
and ``parameters`` (the frozen set itself). Setting a parameter replaces the
frozen set with :func:`dataclasses.replace`, so a parameter set is never
mutated behind the back of whoever holds a reference to it.
"""

from __future__ import annotations

import dataclasses
import enum
from typing import Any, ClassVar, Generic, TypeVar

import numpy as np

from ..infra.params import ParamSet, parameter_set
from .errors import ParameterError

__all__ = ["Tunable", "load_params", "param_spec", "field_index"]

P = TypeVar("P")
_PACKAGE = __package__ or __name__.rpartition(".")[0]
#: The parameter set of each class, as its file states it (a class is read from one section of one file).
_SPECS: dict[type, ParamSet[Any]] = {}


def param_spec(cls: type[P]) -> ParamSet[P]:
    """The :class:`~openemss.models.infra.params.ParamSet` of the parameter-set class ``cls`` (value, unit,
    range, note and source of each field), read from its file by the class's ``from_file``."""
    if cls not in _SPECS:
        cls.from_file()  # type: ignore[attr-defined]
    return _SPECS[cls]


def load_params(cls: type[P], filename: str, section: str, **overrides: Any) -> P:
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
        or a value is of the wrong kind or outside its stated ``min``/``max`` (naming file:line).
    """
    spec = _SPECS[cls] = parameter_set(cls, _PACKAGE, filename, section, ParameterError)
    return spec.make(**overrides)


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

    def parameter_set(self) -> ParamSet[P]:
        """The value, unit, range, note and source of each parameter, as its file states them."""
        return param_spec(type(self._params))

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
        self._params = param_spec(type(self._params)).replace(self._params, self.tunable_name, **{name: value})
        self._on_parameters_changed()

    def _on_parameters_changed(self) -> None:
        """Hook called after the parameter set changed (default: nothing)."""
