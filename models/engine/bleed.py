"""Bleeds: air taken from a compressor, at a stage or at its exit, and where it goes.

A bleed is described as in pyCycle and NPSS, by fractions of the compressor:

* ``frac_W``    bleed mass flow / compressor inlet mass flow [-];
* ``frac_P``    (Pt_bleed - Pt_in) / (Pt_out - Pt_in) [-];
* ``frac_work`` (ht_bleed - ht_in) / (ht_out - ht_in) [-]: the share of the
  compressor's specific work the bleed air has received.

An exit bleed has frac_P = frac_work = 1. For an interstage bleed behind
stage k of n stages of equal work and equal pressure ratio,
frac_work = k/n and frac_P = (PR^(k/n) - 1)/(PR - 1) (:func:`stage_fractions`).

Where the air goes (``sink``):

* ``"overboard"``: leaves the engine (customer bleed, anti-ice, handling
  bleed dumped overboard);
* ``"bypass"``: returned to the bypass duct ahead of the bypass nozzle (the
  handling bleed of the turbofan of SPEC.md);
* ``"hpt"`` / ``"lpt"``: turbine cooling air, re-entering the turbine at
  ``sink_frac_P`` of its pressure drop (1: at the inlet, so it does work in
  the whole turbine; 0: at the exit, no work), as in pyCycle.

References
----------
E. S. Hendricks, J. S. Gray, "pyCycle: A Tool for Efficient Optimization of Gas
Turbine Engine Cycles", Aerospace 6(87), 2019 (bleed fractions frac_W, frac_P, frac_work).
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.13 (bleeds).
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import OutOfRangeError
from .flow import FlowStation, flow_hP
from .gas import DEFAULT_GAS, GasModel

__all__ = ["SINKS", "BleedSpec", "stage_fractions", "bleed_station"]

#: Allowed destinations of a bleed.
SINKS: tuple[str, ...] = ("overboard", "bypass", "hpt", "lpt")


@dataclass(frozen=True, slots=True)
class BleedSpec:
    """One bleed of a compressor.

    Attributes
    ----------
    name : str
        Name, used in results (``"handling"``, ``"customer"``, ``"cool_hpt"``...).
    frac_W : float
        Bleed flow / compressor inlet flow [-], in [0, 1).
    frac_P : float
        Pressure fraction [-], in [0, 1]; 1 at the compressor exit.
    frac_work : float
        Work fraction [-], in [0, 1]; 1 at the compressor exit.
    sink : str
        Destination, one of :data:`SINKS`.
    sink_frac_P : float
        For turbine cooling: where in the turbine's pressure drop it re-enters
        [-], 1 at the turbine inlet, 0 at its exit.
    """

    name: str
    frac_W: float
    frac_P: float = 1.0
    frac_work: float = 1.0
    sink: str = "overboard"
    sink_frac_P: float = 1.0

    def __post_init__(self) -> None:
        if not (0.0 <= self.frac_W < 1.0):
            raise OutOfRangeError(f"bleed {self.name!r}: frac_W={self.frac_W!r} is outside [0, 1)")
        for attr in ("frac_P", "frac_work", "sink_frac_P"):
            v = getattr(self, attr)
            if not (0.0 <= v <= 1.0):
                raise OutOfRangeError(f"bleed {self.name!r}: {attr}={v!r} is outside [0, 1]")
        if self.sink not in SINKS:
            raise OutOfRangeError(f"bleed {self.name!r}: sink={self.sink!r} is not one of {SINKS}")

    @property
    def at_exit(self) -> bool:
        """True for a bleed from the compressor exit (frac_P = frac_work = 1)."""
        return self.frac_P == 1.0 and self.frac_work == 1.0


def stage_fractions(stage: int, n_stages: int, PR: float) -> tuple[float, float]:
    """(frac_P, frac_work) [-] behind stage `stage` of `n_stages` of equal work and pressure ratio.

    frac_work = stage/n_stages; frac_P = (PR^(stage/n_stages) - 1)/(PR - 1).
    """
    if not (1 <= stage <= n_stages):
        raise OutOfRangeError(f"bleed.stage_fractions: stage={stage!r} must lie in 1..{n_stages}")
    if not PR > 1.0:
        raise OutOfRangeError(f"bleed.stage_fractions: PR={PR!r} must exceed 1")
    x = stage / n_stages
    return (PR ** x - 1.0) / (PR - 1.0), x


def bleed_station(spec: BleedSpec, fs_in: FlowStation, fs_out: FlowStation,
                  gas: GasModel = DEFAULT_GAS) -> FlowStation:
    """The bleed stream of a compressor with inlet `fs_in` and (unbled) exit state `fs_out`.

    W = frac_W W_in, ht = ht_in + frac_work (ht_out - ht_in),
    Pt = Pt_in + frac_P (Pt_out - Pt_in), FAR of the inlet.
    """
    ht = fs_in.ht_J_kg + spec.frac_work * (fs_out.ht_J_kg - fs_in.ht_J_kg)
    Pt = fs_in.Pt_Pa + spec.frac_P * (fs_out.Pt_Pa - fs_in.Pt_Pa)
    if spec.at_exit:
        return FlowStation(spec.frac_W * fs_in.W_kg_s, fs_out.Tt_K, fs_out.Pt_Pa, fs_out.FAR, fs_out.ht_J_kg)
    return flow_hP(spec.frac_W * fs_in.W_kg_s, ht, Pt, fs_in.FAR, gas, fs_in.Tt_K)
