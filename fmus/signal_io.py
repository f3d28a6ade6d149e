"""FMI variables of a pythonfmu slave from its model's signal table, with batched, pre-resolved I/O.

A slave mixes :class:`SignalIO` in before ``Fmi2Slave`` and calls :meth:`SignalIO.register_signals`
with its model's table (:class:`openemss.models.infra.signals.Signal` rows). Then:

* parameters and inputs are attributes of the slave under their own names (their start values
  set from the table); the Real inputs are held in one list, ``_u``, behind properties of those
  names, so that ``set_real`` of all of them is one slice assignment;
* outputs are read from one sequence per type, held by the slave in ``_y`` (Real), ``_yb``
  (Boolean), ``_yi`` (Integer) and ``_ys`` (String), at the index the table gives (the order of
  the outputs of that type in the table, or the accessor's position in ``vector_fields``);
  ``get_real`` and the others read a whole batch with one ``operator.itemgetter``;
* the model description gets the FMI ``unit`` of every Real variable and the UnitDefinitions
  (base-unit exponents and factor, FMI 2.0 section 2.2.2) from the table's units, and the ``min``/``max``
  of every Real and Integer row that states a range (parameters generated from a parameter file,
  :meth:`openemss.models.infra.params.ParamSet.signals`).

pythonfmu's own ``get_real``/``set_real`` look every variable up and call its getter or setter
(about 1 us per variable); a master asks for the same value references every step, so the
batch is resolved once, when the references change, and served in one pass afterwards.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from operator import attrgetter, itemgetter
from typing import Any
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Boolean, Fmi2Causality, Fmi2Variability, Integer, Real, String

from openemss.models.infra.signals import BASE_UNITS, Signal, si_unit

_KINDS = {"Real": Real, "Boolean": Boolean, "Integer": Integer, "String": String}
_CAUSALITY = {"input": Fmi2Causality.input, "output": Fmi2Causality.output, "parameter": Fmi2Causality.parameter}
_VARIABILITY = {"fixed": Fmi2Variability.fixed, "tunable": Fmi2Variability.tunable,
                "discrete": Fmi2Variability.discrete, "continuous": Fmi2Variability.continuous}
_VECTOR = {"Real": "_y", "Boolean": "_yb", "Integer": "_yi", "String": "_ys"}


def _picker(slave: Any, vector: str, idx: list[int]) -> Callable[[], list[Any]]:
    """A function giving the list of the items at ``idx`` of the slave's output vector ``vector`` (read when
    called: a slave may replace its vector every step)."""
    vec = attrgetter(vector)
    if idx == list(range(len(getattr(slave, vector)))):  # the whole vector, in order
        return lambda: list(vec(slave))
    if len(idx) == 1:
        i = idx[0]
        return lambda: [vec(slave)[i]]
    get = itemgetter(*idx)
    return lambda: list(get(vec(slave)))


def _tuple_getter(idx: list[int]) -> Callable[[Sequence[Any]], tuple[Any, ...]]:
    """A function giving the tuple of the items at ``idx`` of a sequence (of none, one or more)."""
    if not idx:
        return lambda seq: ()
    if len(idx) == 1:
        i = idx[0]
        return lambda seq: (seq[i],)
    return itemgetter(*idx)  # type: ignore[return-value]


def _attrs_getter(names: list[str]) -> Callable[[Any], tuple[Any, ...]]:
    """A function giving the tuple of the attributes ``names`` of an object (of one or more)."""
    if len(names) == 1:
        name = names[0]
        return lambda obj: (getattr(obj, name),)
    return attrgetter(*names)  # type: ignore[return-value]


def fmi_guarded(method: Callable[..., Any]) -> Callable[..., Any]:
    """Mark a method that calls ``self.fmi_escaping(self)`` before an exception leaves it (see SignalIO)."""
    method.fmi_guarded = True  # type: ignore[attr-defined]
    return method


def _batched_get(kind: str, slot: int) -> Callable[[Any, list[int]], list[Any]]:
    """SignalIO's ``get_<kind>``: the values through the plan for these references, held in ``_plans[slot]``."""
    @fmi_guarded
    def get(self: Any, vrs: list[int]) -> list[Any]:
        try:
            plans = self._plans
            p = plans[slot]
            if p[0] != vrs:
                p = plans[slot] = self._get_plan(kind, vrs)
            return p[1]()  # type: ignore[no-any-return]
        except BaseException:
            self.fmi_escaping(self)
            raise
    get.__name__ = get.__qualname__ = f"get_{kind.lower()}"
    return get


def _batched_set(kind: str, slot: int) -> Callable[[Any, list[int], list[Any]], None]:
    """SignalIO's ``set_<kind>``: the values set through the plan for these references, held in ``_plans[slot]``."""
    @fmi_guarded
    def put(self: Any, vrs: list[int], values: list[Any]) -> None:
        try:
            plans = self._plans
            p = plans[slot]
            if p[0] != vrs:
                p = plans[slot] = self._set_plan(kind, vrs)
            p[1](values)
        except BaseException:
            self.fmi_escaping(self)
            raise
    put.__name__ = put.__qualname__ = f"set_{kind.lower()}"
    return put


class SignalIO:
    """Mix-in of a pythonfmu slave whose variables come from signal tables (see the module)."""

    vars: dict[int, Any]

    def register_signals(self, rows: Sequence[Signal], vector_fields: dict[str, Sequence[str]] | None = None,
                         starts: dict[str, Any] | None = None) -> None:
        """Register ``rows`` as FMI variables.

        Parameters
        ----------
        rows : sequence of Signal
            The table (or part of it), in the order of registration.
        vector_fields : dict, optional
            Per type (``Real``...), the names of the slots of the slave's output vector of that
            type: an output's index is the position of its accessor there. Without it, the outputs
            of a type are their vector's slots in table order.
        starts : dict, optional
            Start values that replace the table's (computed by the slave, e.g. from its data files).
            A Real input is a property of the class once one instance has registered it: give its start
            here, never as an attribute set before this call.
        """
        starts = starts or {}
        counts = dict.fromkeys(_KINDS, 0)
        for row in rows:
            if row.causality == "output":
                fields = (vector_fields or {}).get(row.type)
                i = list(fields).index(row.source) if fields is not None else counts[row.type]
                counts[row.type] += 1
                vec = _VECTOR[row.type]
                self.register_signal(row, getter=lambda vec=vec, i=i: getattr(self, vec)[i])
                self._out_index[row.name] = i
            elif row.causality == "input" and row.type == "Real":
                # the Real inputs live in one list, self._u (set in one slice assignment), read by name
                # through a property of the class
                if not hasattr(self, "_units"):
                    self._init_signal_io()
                j = len(self._u)
                start = starts.get(row.name, row.start)
                self._u.append(float(start if start is not None else 0.0))
                cls = type(self)
                if not isinstance(cls.__dict__.get(row.name), property):
                    setattr(cls, row.name, property(lambda slave, j=j: slave._u[j],
                                                    lambda slave, x, j=j: slave._u.__setitem__(j, x),
                                                    doc=row.described()))
                self.register_signal(row)
                vr = len(self.vars) - 1
                self._in_index[vr] = j
                del self._attr_vr[vr]  # a property, not an entry of the instance's __dict__
            else:
                start = starts.get(row.name, row.start)
                if start is not None:
                    setattr(self, row.name, start)
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
        self._in_index: dict[int, int] = {}  # value reference of a Real input -> its slot in self._u
        self._u: list[float] = []
        none: tuple[list[int] | None, Any] = (None, None)
        self._plans: list[tuple[list[int] | None, Any]] = [none] * 8  # of get and set per type (_batched_get)
        self._y: Sequence[float] = ()
        self._yb: Sequence[bool] = ()
        self._yi: Sequence[int] = ()
        self._ys: Sequence[str] = ()

    # -- batched access -----------------------------------------------------------------------
    # An exception that leaves these methods for pythonfmu's C layer goes through ``fmi_escaping`` first, which
    # build-fmus sets on the slave class (orchestrator/fmu/lifecycle.py: that layer releases the instance once
    # too often after a failure); marked ``fmi_guarded``, they are not wrapped there (no call added per step).
    fmi_escaping: Callable[[Any], None] = staticmethod(lambda slave: None)  # type: ignore[assignment]

    # A plan is (value references, function): the function serves a call for exactly those references,
    # and is replaced when a call brings others. Outputs come from the type's vector with one itemgetter,
    # attributes are written with one __dict__.update; anything else goes through pythonfmu's getters and
    # setters (the same results as pythonfmu's own methods, one variable at a time).
    def _check(self, kind: str, vrs: list[int]) -> None:
        for vr in vrs:
            if vr not in self.vars or not isinstance(self.vars[vr], _KINDS[kind]):
                raise TypeError(f"Variable with valueReference={vr} is not of type {kind}!")

    def _get_plan(self, kind: str, vrs: list[int]) -> tuple[list[int], Callable[[], list[Any]]]:
        self._check(kind, vrs)
        rows = [self._out_vr.get(vr) for vr in vrs]
        if all(r is not None for r in rows):
            return list(vrs), _picker(self, _VECTOR[kind], [self._out_index[r.name] for r in rows])  # type: ignore[union-attr]
        held = {"Real": self._in_index, "Boolean": self._attr_vr, "Integer": self._attr_vr}.get(kind, {})
        if all(r is not None or vr in held for vr, r in zip(vrs, rows, strict=True)):
            # outputs and inputs (a recorder's batch): the outputs from their vector, the inputs from _u (Real)
            # or the slave's attributes (Boolean, Integer), one getter each, put back in the order asked by a
            # third (no cast: pythonfmu's C layer takes the truth or the integer of what it gets)
            outs = [(k, self._out_index[r.name]) for k, r in enumerate(rows) if r is not None]
            ins = [(k, held[vr]) for k, (vr, r) in enumerate(zip(vrs, rows, strict=True)) if r is None]
            order = [k for k, _ in outs] + [k for k, _ in ins]
            get_y, vec = _tuple_getter([i for _, i in outs]), attrgetter(_VECTOR[kind])
            get_in, source = ((_tuple_getter([j for _, j in ins]), self._u) if kind == "Real"  # (_u is never replaced)
                              else (_attrs_getter([name for _, name in ins]), self))
            back = itemgetter(*sorted(range(len(order)), key=order.__getitem__)) if len(order) > 1 else None
            if back is None:
                return list(vrs), lambda: [*get_y(vec(self)), *get_in(source)]
            return list(vrs), lambda: list(back(get_y(vec(self)) + get_in(source)))
        getters = [self.vars[vr].getter for vr in vrs]
        cast = {"Real": float, "Boolean": bool, "Integer": int, "String": str}[kind]
        return list(vrs), lambda: [cast(g()) for g in getters]

    def _set_plan(self, kind: str, vrs: list[int]) -> tuple[list[int], Callable[[list[Any]], None]]:
        self._check(kind, vrs)
        slots = [self._in_index.get(vr) for vr in vrs]
        if kind == "Real" and vrs and all(j is not None for j in slots):
            u = self._u  # never replaced: the plan may hold it
            if slots == list(range(len(u))):
                def every(values: list[float]) -> None:
                    u[:] = values
                return list(vrs), every
            pairs = list(zip(slots, range(len(slots)), strict=True))

            def some(values: list[float]) -> None:
                for j, k in pairs:
                    u[j] = values[k]
            return list(vrs), some
        names = [self._attr_vr.get(vr) for vr in vrs]
        if len(names) == 1 and names[0]:
            name = names[0]
            return list(vrs), lambda values: setattr(self, name, values[0])
        if all(names):
            return list(vrs), lambda values: self.__dict__.update(zip(names, values))
        setters = [partial(self._u.__setitem__, self._in_index[vr]) if vr in self._in_index else self.vars[vr].setter
                   for vr in vrs]

        def each(values: list[Any]) -> None:
            for f, x in zip(setters, values, strict=True):
                f(x)
        return list(vrs), each

    get_real = _batched_get("Real", 0)
    get_boolean = _batched_get("Boolean", 1)
    get_integer = _batched_get("Integer", 2)
    get_string = _batched_get("String", 3)
    set_real = _batched_set("Real", 4)
    set_boolean = _batched_set("Boolean", 5)  # pythonfmu passes Python bools
    set_integer = _batched_set("Integer", 6)
    set_string = _batched_set("String", 7)

    # -- model description ----------------------------------------------------------------------
    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """pythonfmu's model description with the ``unit`` of every Real variable, the ``min`` and ``max`` of
        every Real and Integer variable whose row gives them (pythonfmu 0.7's ``Real``/``Integer`` take no range)
        and the UnitDefinitions of those units (FMI 2.0 sections 2.2.2 and 2.2.7)."""
        root: Element = super().to_xml(model_options or {})  # type: ignore[misc]
        used: dict[str, None] = {}
        rows = {row.name: row for row in self._rows.values()}
        for sv in root.iter("ScalarVariable"):
            real = sv.find("Real")
            unit = self._units.get(sv.get("name", ""))
            row = rows.get(sv.get("name", ""))
            for kind, text in (("Real", repr), ("Integer", lambda x: str(int(x)))):
                elem = sv.find(kind)
                if elem is not None and row is not None:  # the range (pythonfmu 0.7's variables take none)
                    for key in ("min", "max"):
                        if getattr(row, key) is not None:
                            elem.set(key, text(getattr(row, key)))
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
