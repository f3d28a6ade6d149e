"""A speed of a mission: a Mach number, a calibrated or a true airspeed, and its true airspeed at an altitude.

A mission file gives a speed as a mapping with exactly one of ``mach`` [-], ``cas_m_s`` or ``tas_m_s`` [m/s]
(:func:`.mission.speed_from_mapping`); the flight control turns it into true airspeed where it flies
(:meth:`SpeedCommand.tas_m_s`, ISO 2533 with the day's ISA deviation).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from ..common.airspeed import tas_from_cas, tas_from_mach
from ..common.atmosphere import Atmosphere, isa

__all__ = ["SpeedKind", "SpeedCommand"]


class SpeedKind(StrEnum):
    """How a speed command is expressed."""

    MACH = "mach"
    CAS = "cas"
    TAS = "tas"


_MACH, _CAS = SpeedKind.MACH, SpeedKind.CAS


@dataclass(frozen=True, slots=True)
class SpeedCommand:
    """A speed target: ``value`` is a Mach number [-] or an airspeed [m/s] per ``kind``."""

    value: float
    kind: SpeedKind = SpeedKind.TAS

    def tas_m_s(self, alt_m: float, dT_isa_K: float = 0.0, atm: Atmosphere | None = None) -> float:
        """The target as true airspeed at altitude ``alt_m`` [m/s] (``atm``: that altitude's atmosphere, when the
        caller has it)."""
        atm = atm if atm is not None else isa(alt_m, dT_isa_K)
        kind = self.kind
        if kind is _MACH:  # (a module constant: SpeedKind.MACH, an enum class's attribute, costs ~0.2 us a look-up)
            return tas_from_mach(self.value, atm)
        if kind is _CAS:
            return tas_from_cas(self.value, atm)
        return self.value
