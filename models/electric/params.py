"""Parameter sets of the electrical system, read from ``data/*.yaml`` (value, unit, min, max, note).

Each section of a file fills one frozen dataclass; every field must be given once, within its stated
range, and of its field's kind (bool, int or float). :func:`entries` lists every parameter with its
unit and note, for the FMU's tunable parameters (dotted names ``<section>.<field>``).

This loader is separate from the flight control's (``models/fcs/tunable.py``), which reads only the FCS
package's own data folder; the file format is the same.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from importlib import resources
from typing import Any, TypeVar

from ..common import safe_yaml
from .errors import ParameterError

__all__ = ["CellParams", "MachineParams", "PackParams", "BusParams", "EmsParams", "ParamEntry",
           "load_section", "entries", "SYSTEM_FILE", "CELL_FILE"]

SYSTEM_FILE = "electric.yaml"
CELL_FILE = "a123_anr26650m1.yaml"
P = TypeVar("P")


@dataclass(frozen=True)
class CellParams:
    """One cell of the Tremblay-Dessaint generic model (see :mod:`.battery`); units in the field names."""

    E0_V: float
    R_ohm: float
    K_V_Ah: float
    A_V: float
    B_1_Ah: float
    Q_Ah: float
    tau_s: float
    mass_kg: float
    V_nominal_V: float
    V_full_V: float
    V_cutoff_V: float
    I_discharge_max_A: float
    I_charge_max_A: float


@dataclass(frozen=True)
class MachineParams:
    """An electric machine on a spool (see :mod:`.machine`); units in the field names."""

    P_max_W: float
    T_max_Nm: float
    n_min_rpm: float
    n_max_rpm: float
    k_c_W_Nm2: float
    k_i_W_s: float
    k_w_W_s3: float
    C_W: float
    ramp_W_s: float
    power_density_W_kg: float


@dataclass(frozen=True)
class PackParams:
    """Battery pack layout and battery-management limits (see :mod:`.battery`)."""

    n_series: int
    n_parallel: int
    soc0: float
    soc_min: float
    soc_max: float
    pack_mass_factor: float


@dataclass(frozen=True)
class BusParams:
    """DC bus loads and wiring mass (see :mod:`.bus`)."""

    avionics_W: float
    pulse_start_s: float
    pulse_duration_s: float
    pulse_period_s: float
    pulse_count: int
    pulse_W: float
    wiring_mass_kg: float


@dataclass(frozen=True)
class EmsParams:
    """Gains and limits of the energy management law (see :mod:`.ems`)."""

    enabled: bool
    boost_W: float
    lever_boost_min: float
    climb_vs_min_m_s: float
    soc_boost_min: float
    charge_W: float
    soc_charge_stop: float
    soc_charge_band: float
    pulse_hp_first: bool


@dataclass(frozen=True)
class ParamEntry:
    """One parameter of a file: dotted name, value, unit, range and note."""

    name: str
    value: float | int | bool
    unit: str
    lo: float
    hi: float
    note: str


def _doc(filename: str) -> dict[str, Any]:
    text = resources.files(__package__).joinpath("data", filename).read_text(encoding="utf-8")
    return safe_yaml.load(text, filename) or {}


def _typed(cls: type, name: str, value: Any, lo: float, hi: float, where: str) -> float | int | bool:
    kind = {f.name: f.type for f in dataclasses.fields(cls)}[name]
    if kind in (bool, "bool"):
        if not isinstance(value, bool):
            raise ParameterError(f"{where}.{name} = {value!r}: expected true or false")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ParameterError(f"{where}.{name} = {value!r}: expected a number")
    if kind in (int, "int"):
        if float(value) != int(value):
            raise ParameterError(f"{where}.{name} = {value!r}: expected a whole number")
        value = int(value)
    else:
        value = float(value)
    if not (lo <= value <= hi) or math.isnan(value):
        raise ParameterError(f"{where}.{name} = {value!r} is outside the allowed range [{lo:g}, {hi:g}]")
    return value


def check(cls: type[P], section: str, values: dict[str, Any], where: str = "") -> P:
    """A parameter set of ``cls`` from ``values``, each checked against the range of the system file."""
    bounds = {e.name.partition(".")[2]: (e.lo, e.hi) for e in entries() if e.name.startswith(section + ".")}
    return cls(**{k: _typed(cls, k, v, *bounds.get(k, (-math.inf, math.inf)), where or section)
                  for k, v in values.items()})


def load_section(cls: type[P], section: str, filename: str = SYSTEM_FILE, **overrides: Any) -> P:
    """The parameter set ``cls`` from ``section`` of ``data/<filename>``, with ``overrides`` replacing values.

    Raises
    ------
    ParameterError
        A field missing or unknown, a value of the wrong kind or outside its range.
    """
    where = f"{filename}:{section}"
    doc = _doc(filename)
    if section not in doc:
        raise ParameterError(f"{filename}: no section '{section}' (sections: {', '.join(sorted(doc))})")
    names = [f.name for f in dataclasses.fields(cls)]
    values: dict[str, Any] = {}
    for key, e in doc[section].items():
        if key == "source":
            continue
        if key not in names:
            raise ParameterError(f"{where}: unknown parameter '{key}'; {cls.__name__} has: {', '.join(names)}")
        values[key] = e["value"]
    missing = [n for n in names if n not in values]
    if missing:
        raise ParameterError(f"{where}: missing parameter(s) {', '.join(missing)} of {cls.__name__}")
    unknown = [k for k in overrides if k not in names]
    if unknown:
        raise ParameterError(f"{where}: unknown parameter '{unknown[0]}'; {cls.__name__} has: {', '.join(names)}")
    values.update(overrides)
    lo_hi = {k: (float(e.get("min", -math.inf)), float(e.get("max", math.inf)))
             for k, e in doc[section].items() if k != "source"}
    return cls(**{k: _typed(cls, k, v, *lo_hi[k], where) for k, v in values.items()})


def entries(filename: str = SYSTEM_FILE) -> tuple[ParamEntry, ...]:
    """Every parameter of ``data/<filename>`` as ``<section>.<name>`` with value, unit, range and note."""
    out: list[ParamEntry] = []
    for section, block in _doc(filename).items():
        for key, e in block.items():
            if key == "source":
                continue
            out.append(ParamEntry(f"{section}.{key}", e["value"], str(e.get("unit", "-")),
                                  float(e.get("min", -math.inf)), float(e.get("max", math.inf)), str(e.get("note", ""))))
    return tuple(out)
