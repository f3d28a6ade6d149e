"""Parameter sets of the electrical system, read from ``data/*.yaml`` (value, unit, min, max, note, source).

Each section of a file fills one frozen dataclass through the models' one parameter mechanism
(:mod:`openemss.models.infra.params`): every field given once, within its stated range and of its
field's kind (bool, int or float), errors naming ``file:line``. :func:`parameter_sets` gives the sets of
the system file by section; their entries are the FMU's tunable parameters under the dotted names
``<section>.<field>`` (``electric_signals.py``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, TypeVar

from ..infra.params import ParamSet, parameter_set
from .errors import ParameterError

__all__ = ["CellParams", "MachineParams", "PackParams", "BusParams", "EmsParams", "SECTIONS", "load_section",
           "section_set", "parameter_sets", "SYSTEM_FILE", "CELL_FILE"]

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


#: The sections of the system file and the parameter set each fills.
SECTIONS: dict[str, type] = {"hp_machine": MachineParams, "lp_machine": MachineParams, "battery": PackParams,
                             "bus": BusParams, "ems": EmsParams}


def section_set(cls: type[P], section: str, filename: str = SYSTEM_FILE) -> ParamSet[P]:
    """The parameters of ``section`` of ``data/<filename>`` (value, unit, range, note, source), read once."""
    return parameter_set(cls, __package__, filename, section, ParameterError)


def load_section(cls: type[P], section: str, filename: str = SYSTEM_FILE, **overrides: Any) -> P:
    """The parameter set ``cls`` from ``section`` of ``data/<filename>``, with ``overrides`` replacing values.

    Raises
    ------
    ParameterError
        A field missing or unknown, a value of the wrong kind or outside its range (naming file:line).
    """
    return section_set(cls, section, filename).make(**overrides)


def parameter_sets() -> dict[str, ParamSet[Any]]:
    """The parameters of the system file, by section (:data:`SECTIONS`)."""
    return {s: section_set(c, s) for s, c in SECTIONS.items()}
