"""A second estimate of UPERA's aerodynamics from the same geometry, with AeroSandbox.

The handbook model (:mod:`.aero`) is one estimate; this module builds an
``aerosandbox.Airplane`` from the same :class:`~.geometry.Geometry` and evaluates
it with two methods of that library [1]_:

* ``asb.AeroBuildup``: a component build-up. Each lifting surface gets section
  data from NeuralFoil (a neural network trained on XFoil, free transition with
  n_crit = 9), a DATCOM lift-curve slope factor for its aspect ratio and sweep and
  a Nita-Scholz Oswald factor. The fuselage gets slender-body theory with
  Jorgensen's viscous cross-flow [2]_, and friction times the form factor of
  Götten et al. [3]_. Every surface sees the free stream: there is no downwash at the tail.
* ``asb.VortexLatticeMethod``: inviscid, incompressible horseshoe lattice on the
  lifting surfaces (fuselages are ignored). Compressibility is added here by the
  Göthert rule [4]_. The lattice is solved on the airplane stretched by 1/beta
  in x, with the real angles, and its forces are made non-dimensional with the
  real wing area.

Geometry as built (the frame is JSBSim's structural frame, the same as ASB's
geometry axes: x aft, y right, z up, origin at the nose):

* wing: two trapezoidal panels from the centre line (through the fuselage, so the
  covered part stands in for the wing-body carry-over) to the tip; c/4 sweep,
  taper and incidence (twist of both sections about the quarter-chord line) from
  the data file. Airfoil: AeroSandbox's bundled coordinates of the NACA 64A010
  (``"naca64a010"``, t/c 0.0999 at x/c 0.40, the section the data file states).
* horizontal and vertical tail: trapezoids with the quarter-chord point of their
  mean aerodynamic chord at ``ac_x_m``. The horizontal tail sits at ``z_m`` with the
  handbook's tail incidence (so that both models fly the same configuration at zero
  elevator). The vertical tail rises from ``root_z_m``. Section: the NACA 64A010
  scaled to t/c 0.09 (NACA's 6A-series thicknesses scale linearly).
* fuselage: a body of revolution on the x axis, with a tangent-ogive nose of
  ``nose_length_m``, a cylinder, and a tangent-ogive tail cone of
  ``tailcone_length_m`` that closes on the axis. There is no base, as in the
  handbook's closed-body drag.

The atmosphere is ``asb.Atmosphere(method="isa")``. It agrees with :func:`.aero.isa`
to 1e-6 in T, p, rho, a and mu from 0 to 8000 m
(``tests/airframe/test_asb_estimate.py``), so both models see the same q and Re.
Everything runs offline: the airfoil coordinates ship in the AeroSandbox wheel,
and the NeuralFoil weights (``nn_weights_and_biases/*.npz``) ship in the NeuralFoil wheel.

References
----------
.. [1] Sharpe, P. D., *AeroSandbox: A Differentiable Framework for Aircraft Design
   Optimization*, MSc thesis, MIT, 2021; AeroSandbox 4.2, https://github.com/peterdsharpe/AeroSandbox.
.. [2] Jorgensen, L. H., "Prediction of static aerodynamic characteristics for slender
   bodies alone and with lifting surfaces to very high angles of attack", NASA TR R-474, 1977.
.. [3] Götten, F., Havermann, M., Braun, C., Marino, M., Bil, C., "Improved form factor
   for drag estimation of fuselages with various cross sections", J. Aircraft 58(6), 2021.
.. [4] Bertin, J. J., Cummings, R. M., *Aerodynamics for Engineers*, 6th ed., Pearson,
   2014, sect. 9.4 (Göthert rule).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import aerosandbox as asb
import numpy as np

from .aero import geometric_model
from .errors import OutOfEnvelopeError
from .geometry import Geometry, Planform

__all__ = ["BuildupPoint", "LatticePoint", "upera_airplane", "operating_point", "buildup_point",
           "lattice_point", "check_condition", "fuselage_radius_m", "WING_AIRFOIL", "PARTS",
           "ALT_RANGE_M", "MACH_RANGE", "ALPHA_RANGE_DEG"]

WING_AIRFOIL = "naca64a010"  # AeroSandbox's bundled coordinates (UIUC database)
PARTS = ("wing", "htail", "vtail", "fuselage")
LIFTING_PARTS = ("wing", "htail", "vtail")
ALT_RANGE_M = (0.0, 8000.0)
MACH_RANGE = (0.0, 0.85)  # 0 excluded: AeroBuildup needs a speed
ALPHA_RANGE_DEG = (-10.0, 20.0)
N_FUSELAGE_STATIONS = 13  # per cone
LATTICE_SPAN, LATTICE_CHORD = 16, 6  # spanwise panels per side, chordwise panels; convergence in the tests


@dataclass(frozen=True)
class BuildupPoint:
    """AeroBuildup at one condition.

    Forces are in wind axes [N] and the moment is about the design CG [N m].
    Coefficients use the wing area S and the MAC. The ``CL_*`` and ``CD_*`` of the
    parts are each part's lift and profile drag over q S (0 for a part not built).
    ``CD_profile`` includes the wave drag, and ``CD_induced`` is the whole aircraft's.
    """

    alt_m: float
    mach: float
    alpha_rad: float
    tas_m_s: float
    qbar_Pa: float
    re_mac: float
    lift_N: float
    drag_N: float
    pitch_moment_Nm: float
    CL: float
    CD: float
    Cm: float
    CD_profile: float
    CD_induced: float
    CL_wing: float
    CL_htail: float
    CL_fuselage: float
    CD_wing: float
    CD_htail: float
    CD_vtail: float
    CD_fuselage: float


@dataclass(frozen=True)
class LatticePoint:
    """Vortex lattice (inviscid, Göthert-corrected) at one condition: lift and induced drag
    coefficients on S [-], in total and the lift of the wing and of the horizontal tail."""

    alt_m: float
    mach: float
    alpha_rad: float
    CL: float
    CDi: float
    CL_wing: float
    CL_htail: float


def check_condition(alt_m: float, mach: float, alpha_rad: float) -> None:
    """Raise :class:`.errors.OutOfEnvelopeError` naming the valid range if an input is outside it."""
    alpha_deg = math.degrees(alpha_rad)
    for name, value, unit, (lo, hi), lo_open in (("altitude", alt_m, " m", ALT_RANGE_M, False),
                                                 ("Mach", mach, "", MACH_RANGE, True),
                                                 ("alpha", alpha_deg, " deg", ALPHA_RANGE_DEG, False)):
        if not math.isfinite(value) or value > hi or value < lo or (lo_open and value <= lo):
            excl = f" ({lo:g} excluded)" if lo_open else ""
            raise OutOfEnvelopeError(f"{name} = {value:g}{unit} is outside the valid range "
                                     f"{lo:g} to {hi:g}{unit}{excl}")


def fuselage_radius_m(x_m: Sequence[float] | np.ndarray, geom: Geometry) -> np.ndarray:
    """Radius of the fuselage at stations ``x_m`` from the nose [m].

    The nose and tail cones are tangent ogives. Over a cone of length L on a cylinder
    of radius R, with the arc radius rho = (R^2 + L^2)/(2R), the radius is
    ``r(s) = sqrt(rho^2 - (L - s)^2) + R - rho``, where s is the distance from the tip.
    """
    x = np.asarray(x_m, dtype=float)
    fus = geom.raw["fuselage"]
    r, length = geom.fuselage_diameter_m / 2, geom.fuselage_length_m
    ln, lt = float(fus["nose_length_m"]), float(fus["tailcone_length_m"])

    def ogive(s: np.ndarray, cone_m: float) -> np.ndarray:
        rho = (r ** 2 + cone_m ** 2) / (2 * r)
        return np.sqrt(np.maximum(rho ** 2 - (cone_m - s) ** 2, 0.0)) + r - rho

    out = np.full_like(x, r)
    out = np.where(x < ln, ogive(np.clip(x, 0.0, ln), ln), out)
    out = np.where(x > length - lt, ogive(np.clip(length - x, 0.0, lt), lt), out)
    return np.maximum(out, 0.0)


def _surface(p: Planform, name: str, root_le_m: tuple[float, float, float], twist_deg: float,
             airfoil: asb.Airfoil, x_stretch: float, vertical: bool = False,
             root_y_m: float = 0.0) -> asb.Wing:
    """A trapezoidal ``asb.Wing`` (one panel, mirrored unless vertical) from a :class:`Planform`."""
    x0, y0, z0 = root_le_m
    tan_le = p.tan_sweep(0.0)
    s = p.semi_span_m
    stations = ((root_y_m, p.chord_m(root_y_m)), (s, p.chord_m(s)))
    xsecs = []
    for eta, chord in stations:
        xyz = (x0 + eta * tan_le, y0, z0 + eta) if vertical else (x0 + eta * tan_le, y0 + eta, z0)
        xsecs.append(asb.WingXSec(xyz_le=[xyz[0] * x_stretch, xyz[1], xyz[2]], chord=chord * x_stretch,
                                  twist=twist_deg, airfoil=airfoil))
    return asb.Wing(name=name, xsecs=xsecs, symmetric=not vertical)


def _root_le_x_m(p: Planform, ac_x_m: float) -> float:
    """Root leading edge of a surface whose MAC quarter-chord point is at ``ac_x_m`` [m]."""
    return ac_x_m - p.mac_le_offset_m() - 0.25 * p.mac_m


def _fuselage(geom: Geometry) -> asb.Fuselage:
    fus = geom.raw["fuselage"]
    length = geom.fuselage_length_m
    ln, lt = float(fus["nose_length_m"]), float(fus["tailcone_length_m"])
    s = 0.5 * (1 - np.cos(np.linspace(0.0, math.pi, N_FUSELAGE_STATIONS)))  # finer at the tips
    x = np.concatenate([s * ln, length - lt + s * lt])
    return asb.Fuselage(name="fuselage", xsecs=[asb.FuselageXSec(xyz_c=[float(xi), 0.0, 0.0], radius=float(ri))
                                                for xi, ri in zip(x, fuselage_radius_m(x, geom), strict=True)])


def upera_airplane(geom: Geometry | None = None, incidence_tail_rad: float | None = None,
                   parts: Sequence[str] = PARTS, x_stretch: float = 1.0, exposed_wing: bool = False,
                   incidence: bool = True) -> asb.Airplane:
    """UPERA as an ``asb.Airplane`` (see the module docstring for how each part is built).

    Parameters
    ----------
    geom : Geometry, optional
        The geometry (default: the handbook model's, ``geometric_model().geom``).
    incidence_tail_rad : float, optional
        Horizontal-tail incidence [rad] (default: the handbook model's, set for zero
        elevator at its design CL).
    parts : sequence of str
        Which of ``"wing"``, ``"htail"``, ``"vtail"``, ``"fuselage"`` to build.
    x_stretch : float
        Factor on every x coordinate and chord [-] (1/beta for the Göthert rule). A stretched
        airplane is for the lattice only and is built without its fuselage.
    exposed_wing : bool
        Build the wing from the fuselage side outward only (no carry-through) [-].
    incidence : bool
        Set the incidences (False: every surface at zero incidence, for checks).

    Returns
    -------
    aerosandbox.Airplane
        With S, MAC and b of the wing as reference values and the design CG as the moment reference.
    """
    unknown = set(parts) - set(PARTS)
    if unknown:
        raise ValueError(f"unknown parts {sorted(unknown)}; allowed: {', '.join(PARTS)}")
    model = geometric_model()
    g = geom if geom is not None else model.geom
    i_t = model.incidence_tail_rad if incidence_tail_rad is None else incidence_tail_rad
    raw = g.raw
    section = asb.Airfoil(WING_AIRFOIL)
    tail_section = section.scale(1.0, raw["htail"]["thickness_ratio"] / raw["wing"]["thickness_ratio"])
    on = 1.0 if incidence else 0.0
    wings: list[asb.Wing] = []
    if "wing" in parts:
        y_root = g.fuselage_diameter_m / 2 if exposed_wing else 0.0
        wings.append(_surface(g.wing, "wing", (raw["wing"]["root_le_x_m"], 0.0, raw["wing"]["z_m"]),
                              on * raw["wing"]["incidence_deg"], section, x_stretch, root_y_m=y_root))
    if "htail" in parts:
        wings.append(_surface(g.htail, "htail", (_root_le_x_m(g.htail, raw["htail"]["ac_x_m"]), 0.0,
                                                 raw["htail"]["z_m"]),
                              on * math.degrees(i_t), tail_section, x_stretch))
    if "vtail" in parts:
        wings.append(_surface(g.vtail, "vtail", (_root_le_x_m(g.vtail, raw["vtail"]["ac_x_m"]), 0.0,
                                                 raw["vtail"]["root_z_m"]),
                              0.0, tail_section, x_stretch, vertical=True))
    fuselages = [_fuselage(g)] if "fuselage" in parts and x_stretch == 1.0 else []
    return asb.Airplane(name="UPERA", xyz_ref=[g.x_cg_m * x_stretch, 0.0, g.z_cg_m], wings=wings,
                        fuselages=fuselages, s_ref=g.wing.area_m2, c_ref=g.wing.mac_m, b_ref=g.wing.span_m)


@lru_cache(maxsize=32)
def _cached_airplane(parts: tuple[str, ...], x_stretch: float, exposed_wing: bool) -> asb.Airplane:
    return upera_airplane(parts=parts, x_stretch=x_stretch, exposed_wing=exposed_wing)


def operating_point(alt_m: float, mach: float, alpha_rad: float) -> asb.OperatingPoint:
    """``asb.OperatingPoint`` in the ISA at ``alt_m`` [m], Mach [-], alpha [rad], no sideslip or rates."""
    check_condition(alt_m, mach, alpha_rad)
    atm = asb.Atmosphere(altitude=alt_m, method="isa")
    return asb.OperatingPoint(atmosphere=atm, velocity=mach * float(atm.speed_of_sound()),
                              alpha=math.degrees(alpha_rad), beta=0.0)


def _f(x: object) -> float:
    return float(np.squeeze(np.asarray(x, dtype=float)))


def buildup_point(alt_m: float, mach: float, alpha_rad: float, parts: Sequence[str] = PARTS,
                  exposed_wing: bool = False, airplane: asb.Airplane | None = None) -> BuildupPoint:
    """AeroBuildup of UPERA (or of ``parts`` of it, or of ``airplane``) at one condition."""
    op = operating_point(alt_m, mach, alpha_rad)
    ap = airplane if airplane is not None else _cached_airplane(tuple(parts), 1.0, exposed_wing)
    r = asb.AeroBuildup(airplane=ap, op_point=op, xyz_ref=ap.xyz_ref).run()
    q = _f(op.dynamic_pressure())
    qs = q * ap.s_ref
    comp = {"wing": (0.0, 0.0), "htail": (0.0, 0.0), "vtail": (0.0, 0.0), "fuselage": (0.0, 0.0)}
    for wing, c in zip(ap.wings, r["wing_aero_components"], strict=True):
        comp[wing.name] = (_f(c.L) / qs, _f(c.D) / qs)
    for fus, c in zip(ap.fuselages, r["fuselage_aero_components"], strict=True):
        comp[fus.name] = (_f(c.L) / qs, _f(c.D) / qs)
    return BuildupPoint(
        alt_m=alt_m, mach=mach, alpha_rad=alpha_rad, tas_m_s=_f(op.velocity), qbar_Pa=q,
        re_mac=_f(op.reynolds(ap.c_ref)), lift_N=_f(r["L"]), drag_N=_f(r["D"]), pitch_moment_Nm=_f(r["m_b"]),
        CL=_f(r["CL"]), CD=_f(r["CD"]), Cm=_f(r["Cm"]), CD_profile=_f(r["D_profile"]) / qs,
        CD_induced=_f(r["D_induced"]) / qs, CL_wing=comp["wing"][0], CL_htail=comp["htail"][0],
        CL_fuselage=comp["fuselage"][0], CD_wing=comp["wing"][1], CD_htail=comp["htail"][1],
        CD_vtail=comp["vtail"][1], CD_fuselage=comp["fuselage"][1])


def lattice_point(alt_m: float, mach: float, alpha_rad: float, parts: Sequence[str] = LIFTING_PARTS,
                  n_span: int = LATTICE_SPAN, n_chord: int = LATTICE_CHORD,
                  airplane: asb.Airplane | None = None) -> LatticePoint:
    """Vortex lattice of UPERA's lifting surfaces (or of ``airplane``, already stretched) at one condition.

    Göthert rule: the lattice is solved, incompressible, on the airplane stretched by
    1/beta in x (beta = sqrt(1 - M^2)) at the same angles. The lift and the induced
    drag of the real airplane are the stretched airplane's forces over q S, with S the
    real wing area [4]_.
    """
    op = operating_point(alt_m, mach, alpha_rad)
    stretch = 1.0 / math.sqrt(1.0 - mach ** 2)
    ap = airplane if airplane is not None else _cached_airplane(tuple(p for p in parts if p != "fuselage"),
                                                                stretch, False)
    vlm = asb.VortexLatticeMethod(airplane=ap, op_point=op, spanwise_resolution=n_span,
                                  chordwise_resolution=n_chord)
    r = vlm.run()
    qs = _f(op.dynamic_pressure()) * ap.s_ref
    # the lift of each surface: its panels' forces (the lattice meshes the wings in order)
    lift_dir = np.array(op.convert_axes(0.0, 0.0, -1.0, from_axes="wind", to_axes="geometry"), dtype=float)
    panel_lift = np.asarray(vlm.forces_geometry, dtype=float) @ lift_dir
    counts = [2 * n_span * n_chord if w.symmetric else n_span * n_chord for w in ap.wings]
    bounds = np.cumsum([0, *counts])
    if bounds[-1] != len(panel_lift):
        raise RuntimeError(f"lattice has {len(panel_lift)} panels, expected {bounds[-1]}")
    part_cl = {w.name: float(panel_lift[a:b].sum()) / qs for w, a, b in zip(ap.wings, bounds[:-1], bounds[1:],
                                                                            strict=True)}
    return LatticePoint(alt_m=alt_m, mach=mach, alpha_rad=alpha_rad, CL=_f(r["CL"]), CDi=_f(r["CD"]),
                        CL_wing=part_cl.get("wing", 0.0), CL_htail=part_cl.get("htail", 0.0))
