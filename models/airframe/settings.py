"""The airframe's parameters, from ``data/airframe.yaml``: its aircraft and payload, its start, its environment and JSBSim's rate.

Each section of the file fills one frozen dataclass through the models' one parameter mechanism
(:mod:`openemss.models.infra.params`: value, unit, range, note and source of every field, errors naming
``file:line``). The airframe FMU's parameters are these entries under their field names
(:data:`PARAMETER_SETS`), and the FMU collects the sets from them where it builds the model. A start
position left ``null`` in the file is the departure runway's of the FMU's default mission.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TypeVar

from ..infra.params import ParamSet, parameter_set
from .errors import OutOfEnvelopeError

__all__ = ["AirframeAircraft", "AirframeStart", "AirframeEnvironment", "AirframeSimulation", "PARAMETER_SETS", "airframe_set"]

P = TypeVar("P")


def airframe_set(cls: type[P], section: str) -> ParamSet[P]:
    """The parameters of ``section`` of ``data/airframe.yaml`` for the dataclass ``cls`` (read once); a bad
    value is an :class:`.errors.OutOfEnvelopeError` naming the parameter, its range and the file's line."""
    return parameter_set(cls, __package__ or __name__.rpartition(".")[0], "airframe.yaml", section,
                         OutOfEnvelopeError)


@dataclass(frozen=True)
class AirframeAircraft:
    """Which JSBSim aircraft flies (:func:`.aircraft.load_aircraft`) and its payload [kg]."""

    aircraft: str
    payload_kg: float


@dataclass(frozen=True)
class AirframeStart:
    """Where and how the aircraft starts; units in the field names (``*_norm``: 0 to 1).

    ``lat0_deg``, ``lon0_deg``, ``heading0_deg``, ``alt0_m`` and ``ground_elevation_m`` are None in the file:
    the departure runway's of the default mission, which the FMU fills in.
    """

    start_on_runway: bool
    trim_at_start: bool
    lat0_deg: float | None
    lon0_deg: float | None
    heading0_deg: float | None
    alt0_m: float | None
    tas0_m_s: float
    alpha0_rad: float
    ground_elevation_m: float | None
    flaps0_norm: float
    fuel0_kg: float


@dataclass(frozen=True)
class AirframeEnvironment:
    """The atmosphere the aircraft flies in: ISA deviation [K], steady wind [m/s], MIL-F-8785C turbulence, or
    a weather file (winds aloft and turbulence) that replaces the wind and turbulence."""

    weather_file: str
    weather_dT_isa_K: float
    wind_north_m_s: float
    wind_east_m_s: float
    wind_down_m_s: float
    turbulence_wind_20ft_m_s: float
    turbulence_severity: int
    turbulence_seed: int


@dataclass(frozen=True)
class AirframeSimulation:
    """How JSBSim integrates: its rate [Hz]."""

    rate_hz: float


#: The airframe FMU's parameter sets: section of ``data/airframe.yaml`` -> its dataclass (FMU names: the fields).
PARAMETER_SETS: dict[str, type] = {"aircraft": AirframeAircraft, "start": AirframeStart, "environment": AirframeEnvironment,
                                   "simulation": AirframeSimulation}
