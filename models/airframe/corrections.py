"""Correction factors of UPERA's geometric aerodynamics, fitted to higher-fidelity data.

The handbook model of :mod:`.aero` is computed from the geometry alone. Four bounded factors,
each with a physical meaning, let it be calibrated on CFD or wind-tunnel points
(:mod:`.calibrate`, ``emss airframe calibrate``):

==================  ==========================================================  ==============
factor              acts on                                                      bounds
==================  ==========================================================  ==============
``cd0_factor``      the zero-lift drag build-up CD0(M, Re) (friction, form,      0.6 to 1.5
                    interference, excrescences)
``k_factor``        the drag-due-to-lift factor k = 1/(pi A e)                   0.9 to 1.6
``cla_factor``      the lift-curve slopes of wing-body and horizontal tail       0.5 to 1.3
``alpha0_shift_deg`` the aircraft's zero-lift angle (camber, incidence,          -3 to +3 deg
                    wing-body setting): the lift curve moves right by this angle
==================  ==========================================================  ==============

The factors are kept in ``data/upera_calibration.json`` with the data's source; the JSBSim
file written by :mod:`.xmlgen` carries them in its header. A missing file means the
uncorrected geometric model (all factors neutral).
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from ..infra import safe_yaml
from ..infra.files import atomic_write
from .errors import CalibrationError

__all__ = ["AeroCorrections", "FACTOR_BOUNDS", "FACTOR_UNITS", "CALIBRATION_FILE", "load_corrections",
           "save_corrections", "CalibrationError"]

CALIBRATION_FILE = Path(__file__).resolve().parent / "data" / "upera_calibration.json"

#: Lower and upper bound of each factor. The bounds are what the physics allows for a model
#: built from this geometry: a build-up misses at most about a third of the parasite drag; the
#: span efficiency e/k_factor stays at or below about 1 (elliptic loading; the model's e is 0.91)
#: and above 0.57; a measured lift-curve slope of a low-aspect-ratio wing-body lies between half
#: and 1.3 times the lifting-surface theory; a zero-lift angle set by incidence and camber moves
#: by a few degrees at most.
FACTOR_BOUNDS: dict[str, tuple[float, float]] = {
    "cd0_factor": (0.6, 1.5),
    "k_factor": (0.9, 1.6),
    "cla_factor": (0.5, 1.3),
    "alpha0_shift_deg": (-3.0, 3.0),
}
FACTOR_UNITS: dict[str, str] = {"cd0_factor": "-", "k_factor": "-", "cla_factor": "-", "alpha0_shift_deg": "deg"}
NEUTRAL: dict[str, float] = {"cd0_factor": 1.0, "k_factor": 1.0, "cla_factor": 1.0, "alpha0_shift_deg": 0.0}


@dataclass(frozen=True)
class AeroCorrections:
    """The correction factors of the geometric model, and where they come from.

    Attributes
    ----------
    cd0_factor, k_factor, cla_factor : float
        Multipliers on CD0, on k and on the lift-curve slopes [-].
    alpha0_shift_deg : float
        Shift of the zero-lift angle [deg] (positive: less lift at a given angle of attack).
    source : str
        What the factors were fitted to (the data file and its own source lines).
    fitted : tuple of str
        The names of the factors that were fitted (the others are neutral).
    """

    cd0_factor: float = 1.0
    k_factor: float = 1.0
    cla_factor: float = 1.0
    alpha0_shift_deg: float = 0.0
    source: str = "none (geometric model)"
    fitted: tuple[str, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        for name, (lo, hi) in FACTOR_BOUNDS.items():
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and lo <= v <= hi):
                raise CalibrationError(f"correction {name} = {v!r} is outside its allowed range [{lo:g}, {hi:g}]")

    @property
    def alpha0_shift_rad(self) -> float:
        """Zero-lift angle shift [rad]."""
        return math.radians(self.alpha0_shift_deg)

    @property
    def is_neutral(self) -> bool:
        """True when every factor leaves the geometric model unchanged."""
        return all(getattr(self, k) == v for k, v in NEUTRAL.items())

    def factors(self) -> dict[str, float]:
        """The four factors by name."""
        return {k: float(getattr(self, k)) for k in FACTOR_BOUNDS}


def load_corrections(path: Path | str | None = None) -> AeroCorrections:
    """Read a calibration file (default: the shipped one); neutral factors when the default is absent."""
    p = Path(path) if path is not None else CALIBRATION_FILE
    if not p.exists():
        if path is None:
            return AeroCorrections()
        raise CalibrationError(f"{p}: no such calibration file")
    try:
        raw: dict[str, Any] = safe_yaml.load_json(safe_yaml.read_text(p, "calibration file"), str(p))
    except (OSError, ValueError) as exc:
        raise CalibrationError(f"{p}: not a readable JSON calibration file ({exc})") from None
    if not isinstance(raw, dict) or not isinstance(raw.get("factors"), dict):
        raise CalibrationError(f"{p}: expected an object with 'factors' ({', '.join(FACTOR_BOUNDS)})")
    unknown = set(raw["factors"]) - set(FACTOR_BOUNDS)
    if unknown:
        raise CalibrationError(f"{p}: unknown factor(s) {sorted(unknown)}; allowed: {', '.join(FACTOR_BOUNDS)}")
    names = {f.name for f in fields(AeroCorrections)}
    kw = {k: v for k, v in raw["factors"].items() if k in names}
    return AeroCorrections(**kw, source=str(raw.get("source", "")), fitted=tuple(raw.get("fitted", ())))


def save_corrections(c: AeroCorrections, path: Path, extra: dict[str, Any] | None = None) -> Path:
    """Write ``c`` (and ``extra``, e.g. the residuals) as JSON, whole (write then rename)."""
    d = asdict(c)
    out = {"_about": "Correction factors of UPERA's geometric aerodynamics (models/airframe/corrections.py), "
                     "written by 'emss airframe calibrate'.",
           "factors": {k: d[k] for k in FACTOR_BOUNDS}, "units": FACTOR_UNITS, "bounds": FACTOR_BOUNDS,
           "source": c.source, "fitted": list(c.fitted), **(extra or {})}
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, json.dumps(out, indent=2) + "\n")
