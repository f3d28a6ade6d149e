"""The electrical power system's signal table: every variable of its FMU, one row each.

Built from the model's own lists (:data:`openemss.models.electric.system.INPUTS`, ``OUTPUTS``,
``FLAGS``) and its parameter file (``data/electric.yaml``: value, unit, range, note of every entry, through
:func:`.params.parameter_sets`),
so that a variable is named, described and given its unit once. ``fmus/electric.py`` registers these
rows (``fmus/README.md``), ``ssp/generate.py`` connects them by name.
"""
from __future__ import annotations

from ..infra.signals import Signal, check_table
from .params import parameter_sets
from .system import FLAGS, INPUTS, OUTPUTS

__all__ = ["PARAMETERS", "SIGNALS"]


def _unit(text: str) -> str:
    return "1" if text in ("", "-") else text


#: The tunable parameters, every entry of data/electric.yaml under its dotted name, with its range.
PARAMETERS: tuple[Signal, ...] = check_table(
    tuple(row for section, spec in parameter_sets().items() for row in spec.signals(f"{section}.")),
    "models/electric/data/electric.yaml")

#: Inputs, outputs (Real in the order of ``ElectricSystem.values``, Boolean in that of its flags) and mode.
SIGNALS: tuple[Signal, ...] = check_table((
    *(Signal(name, "input", _unit(unit), text, start=0.0) for name, unit, text in INPUTS),
    Signal("on_ground", "input", "1", "A wheel carries weight", "Boolean", True),
    *(Signal(name, "output", _unit(unit), text) for name, unit, text in OUTPUTS),
    *(Signal(name, "output", "1", text, "Boolean") for name, text in FLAGS),
    Signal("ems_mode", "output", "1", "Energy management mode: 0 generate, 1 boost, 2 charge, 3 pulse", "Integer"),
), "models/electric/electric_signals.py")
