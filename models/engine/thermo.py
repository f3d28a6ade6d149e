"""NASA Glenn polynomial data for individual species: loader and evaluation.

The data file ``data/nasa_glenn_thermo.json`` holds, for each species, the
NASA Glenn 9-coefficient polynomials (McBride, Zehe & Gordon 2002) copied from
NASA CEA's ``thermo.inp``; ``data/README.md`` states the source and licence.
This module reads that file (one loader, :func:`load_thermo_data`) and evaluates
the dimensionless functions of one species:

.. math::

    c_p^\\circ/R &= a_1 T^{-2} + a_2 T^{-1} + a_3 + a_4 T + a_5 T^2 + a_6 T^3 + a_7 T^4 \\\\
    H^\\circ/R   &= -a_1 T^{-1} + a_2 \\ln T + a_3 T + a_4 T^2/2 + a_5 T^3/3
                   + a_6 T^4/4 + a_7 T^5/5 + b_1 \\\\
    S^\\circ/R   &= -a_1 T^{-2}/2 - a_2 T^{-1} + a_3 \\ln T + a_4 T + a_5 T^2/2
                   + a_6 T^3/3 + a_7 T^4/4 + b_2

with T in K, H including the heat of formation at 298.15 K and S the absolute
entropy at the standard pressure of 1 bar. The gas mixtures of the engine are
built on top of this in :mod:`.gas`.

References
----------
B. J. McBride, M. J. Zehe, S. Gordon, "NASA Glenn Coefficients for Calculating
Thermodynamic Properties of Individual Species", NASA/TP-2002-211556, 2002.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

from .errors import ModelError, OutOfRangeError

__all__ = [
    "DATA_FILE",
    "T_REF_K",
    "NasaInterval",
    "SpeciesThermo",
    "ThermoData",
    "load_thermo_data",
]

#: The data file read by :func:`load_thermo_data` when no path is given.
DATA_FILE: Path = Path(__file__).resolve().parent / "data" / "nasa_glenn_thermo.json"

#: Thermochemical reference temperature [K] of the heats of formation.
T_REF_K: float = 298.15


@dataclass(frozen=True, slots=True)
class NasaInterval:
    """One temperature interval of a NASA Glenn 9-coefficient polynomial.

    Attributes
    ----------
    T_min_K, T_max_K : float
        Interval of validity [K].
    a : tuple of float
        The seven coefficients a1..a7 of cp/R [-] (powers -2 to 4 of T in K).
    b : tuple of float
        The integration constants b1 [K] (enthalpy) and b2 [-] (entropy).
    """

    T_min_K: float
    T_max_K: float
    a: tuple[float, float, float, float, float, float, float]
    b: tuple[float, float]


@dataclass(frozen=True, slots=True)
class SpeciesThermo:
    """Thermodynamic data of one species as stored in the data file.

    Attributes
    ----------
    name : str
        Key of the species in the data file (e.g. ``"CO2"``, ``"Jet-A(L)"``).
    elements : Mapping[str, float]
        Atoms per molecule, e.g. ``{"C": 1.0, "O": 2.0}``.
    condensed : bool
        True for a condensed (liquid) species, False for a gas.
    molar_mass_kg_mol : float
        Molar mass [kg/mol].
    Hf298_J_mol : float
        Heat of formation at 298.15 K [J/mol], from the record's header.
    intervals : tuple of NasaInterval
        Temperature intervals in increasing order, contiguous.
    reference : str
        The record's comment naming the underlying data (e.g. "Gurvich,1991").
    """

    name: str
    elements: Mapping[str, float]
    condensed: bool
    molar_mass_kg_mol: float
    Hf298_J_mol: float
    intervals: tuple[NasaInterval, ...]
    reference: str

    @property
    def T_min_K(self) -> float:
        """Lowest temperature of validity [K]."""
        return self.intervals[0].T_min_K

    @property
    def T_max_K(self) -> float:
        """Highest temperature of validity [K]."""
        return self.intervals[-1].T_max_K

    def interval(self, T_K: float) -> NasaInterval:
        """Return the interval that holds `T_K` [K] (the lower one at a breakpoint).

        Raises
        ------
        OutOfRangeError
            If `T_K` lies outside [T_min_K, T_max_K].
        """
        if not (self.T_min_K <= T_K <= self.T_max_K):
            raise OutOfRangeError(
                f"thermo.{self.name}: T_K={T_K!r} K is outside the range of its NASA "
                f"polynomial, {self.T_min_K} K to {self.T_max_K} K"
            )
        for iv in self.intervals:
            if T_K <= iv.T_max_K:
                return iv
        return self.intervals[-1]  # pragma: no cover (unreachable after the check)

    def cp_R(self, T_K: float) -> float:
        """Isobaric heat capacity over R, cp/R [-], at `T_K` [K]."""
        a1, a2, a3, a4, a5, a6, a7 = self.interval(T_K).a
        T = T_K
        return a1 / (T * T) + a2 / T + a3 + T * (a4 + T * (a5 + T * (a6 + T * a7)))

    def H_R(self, T_K: float) -> float:
        """Standard enthalpy over R, H/R [K], at `T_K` [K] (includes Hf at 298.15 K)."""
        iv = self.interval(T_K)
        a1, a2, a3, a4, a5, a6, a7 = iv.a
        T = T_K
        return (-a1 / T + a2 * math.log(T)
                + T * (a3 + T * (a4 / 2 + T * (a5 / 3 + T * (a6 / 4 + T * a7 / 5))))
                + iv.b[0])

    def S_R(self, T_K: float) -> float:
        """Standard-state (1 bar) absolute entropy over R, S/R [-], at `T_K` [K]."""
        iv = self.interval(T_K)
        a1, a2, a3, a4, a5, a6, a7 = iv.a
        T = T_K
        return (-a1 / (2 * T * T) - a2 / T + a3 * math.log(T)
                + T * (a4 + T * (a5 / 2 + T * (a6 / 3 + T * a7 / 4)))
                + iv.b[1])


@dataclass(frozen=True, slots=True)
class ThermoData:
    """Contents of the data file.

    Attributes
    ----------
    gas_constant_J_molK : float
        Universal gas constant [J/(mol K)] that dimensions the polynomials
        (the value NASA CEA uses with them).
    species : Mapping[str, SpeciesThermo]
        Species by name.
    air_mole_fractions : Mapping[str, float]
        Composition of dry air by mole [-] stated by the source.
    source : str
        Reference and source file, for messages and reports.
    path : str
        The file the data were read from.
    """

    gas_constant_J_molK: float
    species: Mapping[str, SpeciesThermo]
    air_mole_fractions: Mapping[str, float]
    source: str
    path: str


def _species_from_json(name: str, rec: Mapping[str, Any], where: str) -> SpeciesThermo:
    intervals = []
    for k, iv in enumerate(rec["intervals"]):
        a = tuple(float(x) for x in iv["a"])
        b = tuple(float(x) for x in iv["b"])
        if len(a) != 7 or len(b) != 2:
            raise ModelError(
                f"{where}: species {name!r}, interval {k}: expected 7 coefficients a and "
                f"2 constants b, found {len(a)} and {len(b)}"
            )
        intervals.append(NasaInterval(float(iv["T_min_K"]), float(iv["T_max_K"]), a, b))  # type: ignore[arg-type]
    if not intervals:
        raise ModelError(f"{where}: species {name!r} has no temperature interval")
    for lo, hi in zip(intervals[:-1], intervals[1:], strict=True):
        if lo.T_max_K != hi.T_min_K:
            raise ModelError(
                f"{where}: species {name!r}: intervals are not contiguous "
                f"({lo.T_max_K} K then {hi.T_min_K} K)"
            )
    return SpeciesThermo(
        name=name,
        elements=MappingProxyType({str(e): float(n) for e, n in rec["elements"].items()}),
        condensed=rec["phase"] != "gas",
        molar_mass_kg_mol=float(rec["molar_mass_g_mol"]) * 1e-3,
        Hf298_J_mol=float(rec["Hf298_J_mol"]),
        intervals=tuple(intervals),
        reference=str(rec.get("comment", "")),
    )


@lru_cache(maxsize=8)
def load_thermo_data(path: str | Path | None = None) -> ThermoData:
    """Read a NASA Glenn species data file (JSON) into a :class:`ThermoData`.

    Parameters
    ----------
    path : str or Path, optional
        The file to read; default :data:`DATA_FILE`. Results are cached per path.

    Returns
    -------
    ThermoData

    Raises
    ------
    ModelError
        If the file is missing, is not JSON, or lacks a required entry; the
        message names the file and the entry.
    """
    p = Path(path) if path is not None else DATA_FILE
    try:
        raw = json.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ModelError(f"thermo: cannot read data file {p}: {exc}") from exc
    except json.JSONDecodeError as exc:
        raise ModelError(f"{p}:{exc.lineno}: not valid JSON: {exc.msg}") from exc
    try:
        species = {name: _species_from_json(name, rec, str(p))
                   for name, rec in raw["species"].items()}
        air = {str(k): float(v) for k, v in raw["air_mole_fractions"].items()}
        R_u = float(raw["gas_constant_J_molK"])
        source = f"{raw['reference']} Copied from {raw['source_file']}."
    except KeyError as exc:
        raise ModelError(f"{p}: required entry {exc.args[0]!r} is missing") from exc
    missing = [s for s in air if s not in species]
    if missing:
        raise ModelError(f"{p}: air_mole_fractions names species without data: {missing}")
    if abs(sum(air.values()) - 1.0) > 1e-6:
        raise ModelError(
            f"{p}: air_mole_fractions sum to {sum(air.values())!r}; they must sum to 1 within 1e-6"
        )
    return ThermoData(
        gas_constant_J_molK=R_u,
        species=MappingProxyType(species),
        air_mole_fractions=MappingProxyType(air),
        source=source,
        path=str(p),
    )
