"""The identity of an airframe's configuration: what its trimmed performance depends on.

:func:`airframe_digest` hashes exactly what the trims of the flight control's performance data read
(:mod:`openemss.models.performance`): the files that define the aircraft flown
(:attr:`.adapter.Airframe.definition_files`: its JSBSim folder, whose aerodynamics, mass and gear the trims
fly, and the geometry data file: wing area, airbrake, masses) and its mass range (operating empty to maximum
take-off, the masses the drag polar is fitted between). The airframe FMU publishes it as
``airframe_config_id`` (:func:`openemss.models.infra.config_id.as_config_id`). Not in it: the fuel and
added mass of a run (the polar holds for any mass in the range), the weather (the data are ISA's; the
flight control applies the temperature deviation itself).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..infra.config_id import as_config_id, digest

if TYPE_CHECKING:
    from .adapter import Airframe

__all__ = ["airframe_digest", "airframe_config_id"]


def airframe_digest(airframe: Airframe) -> str:
    """SHA-256 hex digest of the airframe's configuration (see the module docstring)."""
    return digest("airframe", {"mass_range_kg": list(airframe.mass_range_kg)}, airframe.definition_files)


def airframe_config_id(airframe: Airframe) -> int:
    """The airframe's identity as the FMU's Integer output ``airframe_config_id``."""
    return as_config_id(airframe_digest(airframe))
