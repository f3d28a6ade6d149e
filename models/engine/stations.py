"""Engine station numbering, the one place where stations are defined.

Stations follow SAE AS755 (Aircraft Propulsion System Performance Station
Designation). Every flow station of the cycle modules is keyed by one of the
strings below; result dictionaries and JSON output use the same keys, and a
quantity at a station is named symbol + station (``Tt4``, ``Pt3``, ``W2``).

References
----------
SAE AS755F, "Aircraft Propulsion System Performance Station Designation", SAE
International, 2016 (and earlier revisions, ARP755).
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, ch. 5.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

__all__ = ["STATIONS", "TURBOFAN_STATIONS", "TURBOJET_STATIONS", "describe"]

#: Station number -> meaning.
STATIONS: Mapping[str, str] = MappingProxyType({
    "0": "free stream",
    "2": "fan (or compressor) face, inlet exit",
    "13": "fan bypass (outer) exit",
    "16": "bypass duct, after any bleed returned to the bypass",
    "17": "bypass nozzle inlet",
    "18": "bypass nozzle throat",
    "21": "fan core (inner) exit",
    "24": "booster (LPC) exit, if the engine has a booster",
    "25": "HPC inlet",
    "3": "HPC exit",
    "31": "burner inlet, after the HPC exit bleeds (customer, cooling)",
    "4": "burner exit",
    "41": "HPT rotor inlet: burner exit mixed with the HPT inlet cooling flows",
    "44": "HPT exit, with the HPT exit cooling flows mixed in",
    "45": "LPT inlet",
    "5": "LPT exit, with the LPT cooling flows mixed in",
    "7": "core nozzle inlet",
    "8": "core nozzle throat",
})

#: Stations carried by the two-spool separate-flow turbofan, in flow order.
TURBOFAN_STATIONS: tuple[str, ...] = (
    "0", "2", "21", "24", "25", "3", "31", "4", "41", "44", "45", "5", "7", "8", "13", "16", "17", "18")

#: Stations carried by the single-spool turbojet, in flow order.
TURBOJET_STATIONS: tuple[str, ...] = ("0", "2", "3", "31", "4", "41", "5", "7", "8")


def describe(station: str) -> str:
    """Meaning of a station number; raises KeyError naming the known stations."""
    try:
        return STATIONS[station]
    except KeyError:
        raise KeyError(f"unknown station {station!r}; known: {', '.join(STATIONS)}") from None
