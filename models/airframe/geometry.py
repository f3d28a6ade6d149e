"""UPERA geometry, mass and balance, read from ``data/upera_geometry.json``.

Lengths in [m], areas in [m^2], angles in [deg] where the name says ``_deg``
(otherwise [rad]), masses in [kg]. The structural frame is JSBSim's: origin at
the fuselage nose on the fuselage axis, x aft, y right, z up.

References
----------
.. [1] Raymer, D. P., *Aircraft Design: A Conceptual Approach*, 6th ed., AIAA, 2018,
   ch. 7 (wing geometry: mean aerodynamic chord, sweep conversion).
.. [2] Roskam, J., *Airplane Design Part V: Component Weight Estimation*,
   DARcorporation, 1985, ch. 8 (moments of inertia from non-dimensional radii of gyration).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from ..common.atmosphere import G0_M_S2
from ..infra import safe_yaml
from .errors import AirframeError

__all__ = ["Planform", "Geometry", "load_geometry", "DATA_FILE", "G0"]

DATA_FILE = Path(__file__).resolve().parent / "data" / "upera_geometry.json"
G0 = G0_M_S2  # standard gravity [m/s^2]


@dataclass(frozen=True)
class Planform:
    """A trapezoidal lifting surface (one wing, or both halves of a tail).

    Parameters
    ----------
    area_m2 : float
        Reference (trapezoidal, through the fuselage) area [m^2].
    span_m : float
        Tip-to-tip span [m]; for a vertical tail its height.
    taper : float
        Tip chord / root chord [-].
    sweep_c4_rad : float
        Sweep of the quarter-chord line [rad].
    t_c : float
        Thickness ratio [-].
    x_t_c : float
        Chordwise position of maximum thickness [-].
    halves : int
        2 for a wing or horizontal tail (span covers both halves), 1 for a vertical tail.
    """

    area_m2: float
    span_m: float
    taper: float
    sweep_c4_rad: float
    t_c: float
    x_t_c: float
    halves: int = 2

    @property
    def semi_span_m(self) -> float:
        """Span of one panel [m]."""
        return self.span_m / self.halves

    @property
    def aspect_ratio(self) -> float:
        """Aspect ratio b^2/S [-] (for a vertical tail the geometric h^2/S)."""
        return self.span_m ** 2 / self.area_m2

    @property
    def full_aspect_ratio(self) -> float:
        """Aspect ratio of the full wing the surface is half of (2 h^2/S for a vertical tail) [-]."""
        return (2.0 * self.semi_span_m) ** 2 / (self.area_m2 * 2.0 / self.halves)

    @property
    def root_chord_m(self) -> float:
        """Root chord [m]."""
        return 2.0 * self.area_m2 / (self.halves * self.semi_span_m * (1.0 + self.taper))

    def chord_m(self, y_m: float) -> float:
        """Chord at spanwise station ``y_m`` from the root [m]."""
        return self.root_chord_m * (1.0 - (1.0 - self.taper) * y_m / self.semi_span_m)

    @property
    def mac_m(self) -> float:
        """Mean aerodynamic chord [m] (Raymer eq. 7.5)."""
        lam = self.taper
        return 2.0 / 3.0 * self.root_chord_m * (1 + lam + lam ** 2) / (1 + lam)

    @property
    def y_mac_m(self) -> float:
        """Spanwise station of the mean aerodynamic chord from the root [m] (Raymer eq. 7.6)."""
        lam = self.taper
        return self.semi_span_m / 3.0 * (1 + 2 * lam) / (1 + lam)

    def tan_sweep(self, chord_fraction: float) -> float:
        """Tangent of the sweep of the line at ``chord_fraction`` of the chord [-]."""
        ar = self.full_aspect_ratio
        return math.tan(self.sweep_c4_rad) - 4.0 / ar * (chord_fraction - 0.25) * (1 - self.taper) / (1 + self.taper)

    def sweep(self, chord_fraction: float) -> float:
        """Sweep of the line at ``chord_fraction`` of the chord [rad]."""
        return math.atan(self.tan_sweep(chord_fraction))

    def mac_le_offset_m(self) -> float:
        """Streamwise distance from the root leading edge to the MAC leading edge [m]."""
        return self.y_mac_m * self.tan_sweep(0.0)

    def exposed_area_m2(self, inner_m: float) -> float:
        """Planform area outboard of ``inner_m`` from the root on each panel [m^2]."""
        c_in = self.chord_m(inner_m)
        c_tip = self.chord_m(self.semi_span_m)
        return self.halves * 0.5 * (c_in + c_tip) * (self.semi_span_m - inner_m)

    def chord_moment_m3(self, y1_m: float, y2_m: float) -> float:
        """Integral of c(y) y dy from ``y1_m`` to ``y2_m`` on one panel [m^3]."""
        cr = self.root_chord_m
        k = (1.0 - self.taper) / self.semi_span_m
        f = lambda y: cr * (y ** 2 / 2.0 - k * y ** 3 / 3.0)  # noqa: E731
        return f(y2_m) - f(y1_m)

    def chord_integral_m2(self, y1_m: float, y2_m: float) -> float:
        """Integral of c(y) dy from ``y1_m`` to ``y2_m`` on one panel [m^2]."""
        cr = self.root_chord_m
        k = (1.0 - self.taper) / self.semi_span_m
        return cr * ((y2_m - y1_m) - k * (y2_m ** 2 - y1_m ** 2) / 2.0)


@dataclass(frozen=True)
class Geometry:
    """UPERA as designed: planforms, positions, masses, gear, actuators.

    ``raw`` keeps the data file's sections for the values used only once
    (gear and actuator data); every derived quantity is a property.
    """

    wing: Planform
    htail: Planform
    vtail: Planform
    raw: dict[str, Any]

    # -- sections ---------------------------------------------------------
    def section(self, name: str) -> dict[str, float]:
        """One section of the data file (e.g. ``"gear"``)."""
        return self.raw[name]

    # -- fuselage ---------------------------------------------------------
    @property
    def fuselage_length_m(self) -> float:
        return float(self.raw["fuselage"]["length_m"])

    @property
    def fuselage_diameter_m(self) -> float:
        return float(self.raw["fuselage"]["diameter_m"])

    # -- wing placement -----------------------------------------------------
    @property
    def x_mac_le_m(self) -> float:
        """Leading edge of the wing's mean aerodynamic chord [m]."""
        return self.raw["wing"]["root_le_x_m"] + self.wing.mac_le_offset_m()

    @property
    def x_wing_ac_m(self) -> float:
        """Wing aerodynamic centre (quarter MAC) [m]."""
        return self.x_mac_le_m + 0.25 * self.wing.mac_m

    @property
    def x_cg_m(self) -> float:
        """Design centre of gravity [m] (empty and with fuel: the tank is centred on it)."""
        return self.x_mac_le_m + self.raw["balance"]["cg_mac_fraction"] * self.wing.mac_m

    @property
    def z_cg_m(self) -> float:
        return float(self.raw["balance"]["cg_z_m"])

    @property
    def l_h_m(self) -> float:
        """Tail arm: CG to horizontal tail aerodynamic centre [m]."""
        return self.raw["htail"]["ac_x_m"] - self.x_cg_m

    @property
    def l_v_m(self) -> float:
        """Tail arm: CG to vertical tail aerodynamic centre [m]."""
        return self.raw["vtail"]["ac_x_m"] - self.x_cg_m

    @property
    def z_v_m(self) -> float:
        """Height of the vertical tail's aerodynamic centre above the CG [m]."""
        return self.raw["vtail"]["root_z_m"] + self.vtail.y_mac_m - self.z_cg_m

    @property
    def tail_volume_h(self) -> float:
        """Horizontal tail volume coefficient S_H l_H / (S c) [-]."""
        return self.htail.area_m2 * self.l_h_m / (self.wing.area_m2 * self.wing.mac_m)

    @property
    def tail_volume_v(self) -> float:
        """Vertical tail volume coefficient S_V l_V / (S b) [-]."""
        return self.vtail.area_m2 * self.l_v_m / (self.wing.area_m2 * self.wing.span_m)

    # -- masses -------------------------------------------------------------
    @property
    def oem_kg(self) -> float:
        return float(self.raw["mass"]["oem_kg"])

    @property
    def mtom_kg(self) -> float:
        return float(self.raw["mass"]["mtom_kg"])

    @property
    def fuel_capacity_kg(self) -> float:
        return float(self.raw["mass"]["fuel_capacity_kg"])

    def inertia_kg_m2(self, mass_kg: float) -> tuple[float, float, float]:
        """Moments of inertia (Ixx, Iyy, Izz) [kg m^2] by Roskam's radii of gyration.

        ``I_xx = m (b R_x / 2)^2``, ``I_yy = m (L R_y / 2)^2``,
        ``I_zz = m ((b + L)/2 R_z / 2)^2`` [2]_.
        """
        m = self.raw["mass"]
        b, length = self.wing.span_m, self.fuselage_length_m
        ixx = mass_kg * (b * m["radius_of_gyration_x"] / 2.0) ** 2
        iyy = mass_kg * (length * m["radius_of_gyration_y"] / 2.0) ** 2
        izz = mass_kg * ((b + length) / 2.0 * m["radius_of_gyration_z"] / 2.0) ** 2
        return ixx, iyy, izz


def _planform(sec: dict[str, float], span_m: float, halves: int) -> Planform:
    return Planform(area_m2=float(sec["area_m2"]), span_m=span_m, taper=float(sec["taper_ratio"]),
                    sweep_c4_rad=math.radians(sec["sweep_c4_deg"]), t_c=float(sec["thickness_ratio"]),
                    x_t_c=float(sec["max_thickness_x_c"]), halves=halves)


@lru_cache(maxsize=4)
def load_geometry(path: str | None = None) -> Geometry:
    """Read the geometry data file (default: ``data/upera_geometry.json``).

    Raises
    ------
    AirframeError
        If the file is missing or lacks a section.
    """
    p = Path(path) if path else DATA_FILE
    try:
        raw = safe_yaml.load_json(safe_yaml.read_text(p, "geometry file"), str(p))
        w, h, v = raw["wing"], raw["htail"], raw["vtail"]
        wing = _planform(w, float(w["span_m"]), 2)
        htail = _planform(h, math.sqrt(h["aspect_ratio"] * h["area_m2"]), 2)
        vtail = _planform(v, math.sqrt(v["aspect_ratio"] * v["area_m2"]), 1)
    except (OSError, ValueError, KeyError) as exc:
        raise AirframeError(f"{p}: cannot read the UPERA geometry ({exc.__class__.__name__}: {exc})") from None
    return Geometry(wing=wing, htail=htail, vtail=vtail, raw=raw)
