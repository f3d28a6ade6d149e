"""FMI variables of a pythonfmu slave from its model's signal table, with batched, pre-resolved I/O.

A slave mixes :class:`SignalIO` in before ``Fmi2Slave`` and calls :meth:`SignalIO.register_signals`
with its model's table (:class:`openemss.models.common.signals.Signal` rows). Then:

* parameters and inputs are attributes of the slave under their own names (their start values
  set from the table); ``set_real`` and the others write a whole batch of them at once;
* outputs are read from one sequence per type, held by the slave in ``_y`` (Real), ``_yb``
  (Boolean), ``_yi`` (Integer) and ``_ys`` (String), at the index the table gives (the order of
  the outputs of that type in the table, or the accessor's position in ``vector_fields``);
  ``get_real`` and the others read a whole batch with one ``operator.itemgetter``;
* the model description gets the FMI ``unit`` of every Real variable and the UnitDefinitions
  (base-unit exponents and factor, FMI 2.0 section 2.2.2) from the table's units.

pythonfmu's own ``get_real``/``set_real`` look every variable up and call its getter or setter
(about 1 us per variable); a master asks for the same value references every step, so the
batch is resolved once, when the references change, and served in one pass afterwards.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from operator import itemgetter
from typing import Any
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Boolean, Fmi2Causality, Fmi2Variability, Integer, Real, String

from openemss.models.common.signals import BASE_UNITS, Signal, si_unit

_KINDS = {"Real": Real, "Boolean": Boolean, "Integer": Integer, "String": String}
_CAUSALITY = {"input": Fmi2Causality.input, "output": Fmi2Causality.output, "parameter": Fmi2Causality.parameter}
_VARIABILITY = {"fixed": Fmi2Variability.fixed, "tunable": Fmi2Variability.tunable,
                "discrete": Fmi2Variability.discrete, "continuous": Fmi2Variability.continuous}
_VECTOR = {"Real": "_y", "Boolean": "_yb", "Integer": "_yi", "String": "_ys"}


def _picker(idx: list[int]) -> Callable[[Sequence[Any]], Any]:
    """A function taking a sequence to the list of its items at ``idx``."""
    if len(idx) == 1:
        i = idx[0]
        return lambda y: [y[i]]
    get = itemgetter(*idx)
    return lambda y: list(get(y))


class SignalIO:
    """Mix-in of a pythonfmu slave whose variables come from signal tables (see the module)."""

    vars: dict[int, Any]

    def register_signals(self, rows: Sequence[Signal], vector_fields: dict[str, Sequence[str]] | None = None) -> None:
        """Register ``rows`` as FMI variables.

        Parameters
        ----------
        rows : sequence of Signal
            The table (or part of it), in the order of registration.
        vector_fields : dict, optional
            Per type (``Real``...), the names of the slots of the slave's output vector of that
            type: an output's index is the position of its accessor there. Without it, the outputs
            of a type are their vector's slots in table order.
        """
        counts = dict.fromkeys(_KINDS, 0)
        for row in rows:
            if row.causality == "output":
                fields = (vector_fields or {}).get(row.type)
                i = list(fields).index(row.source) if fields is not None else counts[row.type]
                counts[row.type] += 1
                vec = _VECTOR[row.type]
                self.register_signal(row, getter=lambda vec=vec, i=i: getattr(self, vec)[i])
                self._out_index[row.name] = i
            else:
                if row.start is not None:
                    setattr(self, row.name, row.start)
                self.register_signal(row)

    def register_signal(self, row: Signal, getter: Callable[[], Any] | None = None,
                        setter: Callable[[Any], None] | None = None, nested: bool = True) -> None:
        """Register one variable (a getter/setter for a variable not held as the slave's attribute)."""
        if not hasattr(self, "_units"):
            self._init_signal_io()
        kind = _KINDS[row.type]
        self.register_variable(kind(row.name, causality=_CAUSALITY[row.causality],  # type: ignore[attr-defined]
                                    variability=_VARIABILITY[row.fmi_variability], description=row.described(),
                                    getter=getter, setter=setter), nested=nested)
        vr = len(self.vars) - 1
        self._rows[vr] = row
        if row.causality == "output":
            self._out_vr[vr] = row
        elif getter is None and setter is None:
            self._attr_vr[vr] = row.name
        if row.type == "Real":
            self._units[row.name] = row.unit

    def _init_signal_io(self) -> None:
        self._units: dict[str, str] = {}
        self._rows: dict[int, Signal] = {}
        self._out_vr: dict[int, Signal] = {}
        self._out_index: dict[str, int] = {}
        self._attr_vr: dict[int, str] = {}
        self._plans: dict[str, tuple[list[int], Any, Any]] = {}
        self._y: Sequence[float] = ()
        self._yb: Sequence[bool] = ()
        self._yi: Sequence[int] = ()
        self._ys: Sequence[str] = ()

    # -- batched access -----------------------------------------------------------------------
    def _get_plan(self, kind: str, vrs: list[int]) -> tuple[list[int], Any, Any]:
        plan = self._plans.get("get" + kind)
        if plan is not None and plan[0] == vrs:
            return plan
        vec = _VECTOR[kind]
        rows = [self._out_vr.get(vr) for vr in vrs]
        if all(r is not None and r.type == kind for r in rows):
            plan = (list(vrs), vec, _picker([self._out_index[r.name] for r in rows]))  # type: ignore[union-attr]
        else:
            for vr in vrs:
                if vr not in self.vars or not isinstance(self.vars[vr], _KINDS[kind]):
                    raise TypeError(f"Variable with valueReference={vr} is not of type {kind}!")
            plan = (list(vrs), None, [self.vars[vr].getter for vr in vrs])
        self._plans["get" + kind] = plan
        return plan

    def _get(self, kind: str, vrs: list[int]) -> list[Any]:
        _, vec, how = self._get_plan(kind, vrs)
        if vec is not None:
            return how(getattr(self, vec))
        return [g() for g in how]

    def _set(self, kind: str, vrs: list[int], values: list[Any]) -> None:
        plan = self._plans.get("set" + kind)
        if plan is None or plan[0] != vrs:
            for vr in vrs:
                if vr not in self.vars or not isinstance(self.vars[vr], _KINDS[kind]):
                    raise TypeError(f"Variable with valueReference={vr} is not of type {kind}!")
            names = [self._attr_vr.get(vr) for vr in vrs]
            plan = (list(vrs), names if all(names) else None, [self.vars[vr].setter for vr in vrs])
            self._plans["set" + kind] = plan
        _, names, setters = plan
        if names is not None:
            self.__dict__.update(zip(names, values))
        else:
            for s, x in zip(setters, values):
                s(x)

    def get_real(self, vrs: list[int]) -> list[float]:
        return self._get("Real", vrs)

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        return [bool(x) for x in self._get("Boolean", vrs)]

    def get_integer(self, vrs: list[int]) -> list[int]:
        return self._get("Integer", vrs)

    def get_string(self, vrs: list[int]) -> list[str]:
        return self._get("String", vrs)

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        self._set("Real", vrs, values)

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        self._set("Boolean", vrs, [bool(x) for x in values])

    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        self._set("Integer", vrs, values)

    def set_string(self, vrs: list[int], values: list[str]) -> None:
        self._set("String", vrs, values)

    # -- model description ----------------------------------------------------------------------
    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """pythonfmu's model description with the ``unit`` of every Real variable and the
        UnitDefinitions of those units (FMI 2.0 section 2.2.2)."""
        root: Element = super().to_xml(model_options or {})  # type: ignore[misc]
        used: dict[str, None] = {}
        for sv in root.iter("ScalarVariable"):
            real = sv.find("Real")
            unit = self._units.get(sv.get("name", ""))
            if real is not None:
                if unit is None:
                    raise ValueError(f"{type(self).__name__}: Real variable '{sv.get('name')}' has no unit: "
                                     "register it from a signal table")
                real.set("unit", unit)
                used[unit] = None
        defs = Element("UnitDefinitions")
        for unit in sorted(used):
            exps, factor = si_unit(unit)
            attrs = {n: str(e) for n, e in zip(BASE_UNITS, exps, strict=True) if e}
            if factor != 1.0:
                attrs["factor"] = repr(factor)
            SubElement(SubElement(defs, "Unit", name=unit), "BaseUnit", attrs)
        cosim = root.find("CoSimulation")
        root.insert(list(root).index(cosim) + 1 if cosim is not None else 0, defs)
        return root
