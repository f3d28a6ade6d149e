"""UPERA aerodynamics from its geometry: handbook methods, no wind-tunnel data.

Every coefficient the JSBSim file uses is computed here (the file's tables are
written by :mod:`.xmlgen` from this module; a test checks they agree). Angles
in [rad], coefficients non-dimensional, referred to the wing area S, mean
aerodynamic chord c and span b; moments about the design CG; rates made
non-dimensional with c/(2V) or b/(2V) (JSBSim's ``aero/ci2vel``, ``aero/bi2vel``).

Sign conventions of the controls (all positive deflections in [rad]):
elevator positive trailing edge down (nose-down moment); aileron positive rolls
right (right aileron up); rudder positive yaws the nose right.

Origin of each term (see ``README.md`` for the derivation in prose):

* lift-curve slope: Helmbold/DATCOM formula with Prandtl-Glauert compressibility
  and sweep of the maximum-thickness line, fuselage lift factor [1]_ (eq. 12.6);
* downwash gradient: DATCOM section 4.4.1 [2]_, scaled with CL_alpha(M)/CL_alpha(0);
* maximum lift: 0.9 c_lmax cos(sweep) [1]_ (eq. 12.15); flaps by the zero-lift-angle
  shift times flapped area [1]_ (eq. 12.20);
* zero-lift drag: component build-up with turbulent/laminar skin friction,
  cut-off Reynolds number for roughness, form factors and interference factors
  [1]_ (sect. 12.5), plus intake, gear (frontal-area D/q) and leakage/protuberances;
* drag due to lift: k = 1/(pi A e), 1/e = 1/(u s) + pi A K CD0 (Kroo [10]_) with the planform
  efficiency u of Nita and Scholz [3]_;
* wave drag: Korn equation for the drag-divergence Mach number and Lock's
  drag-rise law CD_w = 20 (M - M_cr)^4 [4]_;
* pitching moment: wing-body, fuselage (Munk/Multhopp via Raymer's K_f) and tail
  with downwash; tail incidence set for zero elevator at the design CL;
* damping and control derivatives: tail-volume formulas [5]_ (ch. 2, 3, 5) and
  strip theory for roll damping and aileron power [6]_;
* ground effect on the drag due to lift: McCormick's factor [7]_;
* airbrake: flat plate normal to the flow on the panels' frontal area [11]_.

References
----------
.. [1] Raymer, D. P., *Aircraft Design: A Conceptual Approach*, 6th ed., AIAA, 2018.
.. [2] Finck, R. D., *USAF Stability and Control DATCOM*, AFWAL-TR-83-3048, 1978.
.. [3] Nita, M., Scholz, D., "Estimating the Oswald factor from basic aircraft
   geometrical parameters", Deutscher Luft- und Raumfahrtkongress, 2012.
.. [4] Mason, W. H., "Analytic models for technology integration in aircraft
   design", AIAA-90-3262, 1990 (Korn equation); Hilton, W. F., *High-Speed
   Aerodynamics*, Longmans, 1951 (Lock's law).
.. [5] Nelson, R. C., *Flight Stability and Automatic Control*, 2nd ed., McGraw-Hill, 1998.
.. [6] Etkin, B., Reid, L. D., *Dynamics of Flight*, 3rd ed., Wiley, 1996, ch. 5.
.. [7] McCormick, B. W., *Aerodynamics, Aeronautics and Flight Mechanics*, Wiley, 1979, ch. 4
   (ground effect on induced drag), as quoted in Raymer sect. 17.8.
.. [8] Shevell, R. S., *Fundamentals of Flight*, 2nd ed., Prentice Hall, 1989, ch. 11 (form factor
   of lifting surfaces from the supervelocity).
.. [9] Gur, O., Mason, W. H., Schetz, J. A., "Full-configuration drag estimation", *Journal of
   Aircraft* 47(4), 2010, pp. 1356-1367.
.. [10] Kroo, I., *Aircraft Design: Synthesis and Analysis*, Stanford University, 2001, "Lift-dependent
   drag" (1/e = 1/(u s) + pi A K CD0, K about 0.38).
.. [11] Hoerner, S. F., *Fluid-Dynamic Drag*, published by the author, 1965, ch. 3 (flat plates
   normal to the flow) and ch. 8 (obstacles on a wall).
.. [12] Stephenson, J. D., "The effects of aerodynamic brakes upon the speed characteristics of
   airplanes", NACA TN 1939, 1949 (measured drag increments of wing and fuselage brakes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..common import atmosphere as _atm
from .corrections import AeroCorrections, load_corrections
from .errors import OutOfEnvelopeError
from .geometry import Geometry, Planform, load_geometry

__all__ = ["AeroModel", "aero_model", "build_aero_model", "geometric_model", "helmbold_slope", "skin_friction", "korn_mcrit",
           "wave_drag", "planform_efficiency_nita_scholz", "oswald_kroo", "lifting_form_factor", "isa"]

MAX_MACH = 0.95  # highest Mach number of the tables (JSBSim holds the last value beyond)
LEAKAGE_PROTUBERANCE = 0.05  # fraction of parasite drag [1] sect. 12.5.8
ELEVATOR_EMPIRICAL = 0.80  # correction of thin-airfoil flap effectiveness for viscosity [2] fig. 6.1.1.1-40
DESIGN_CL = 0.30  # lift coefficient at which the tail incidence gives zero elevator
DESIGN_MACH = 0.5
DESIGN_ALT_M = 5000.0  # altitude of the design condition (Reynolds number of the viscous drag due to lift)


def isa(alt_m: float, dT_isa_K: float = 0.0) -> tuple[float, float, float, float, float]:
    """The standard atmosphere (:mod:`openemss.models.common.atmosphere`, ISO 2533) with Sutherland's
    viscosity, as a tuple for the aerodynamic formulas.

    Returns
    -------
    T_K, p_Pa, rho_kg_m3, a_m_s, mu_Pa_s
        Temperature [K], pressure [Pa], density [kg/m^3], speed of sound [m/s],
        dynamic viscosity by Sutherland's law [Pa s].

    Raises
    ------
    OutOfEnvelopeError
        Outside the standard's range (-1000 to 32000 m, 150 to 350 K).
    """
    try:
        a = _atm.isa(alt_m, dT_isa_K)
    except _atm.AtmosphereRangeError as exc:
        raise OutOfEnvelopeError(str(exc)) from None
    return a.T_K, a.p_Pa, a.rho_kg_m3, a.a_m_s, _atm.sutherland_viscosity(a.T_K)


def helmbold_slope(aspect: float, tan_sweep_tmax: float, mach: ArrayLike, eta: float = 0.95) -> NDArray:
    """Lift-curve slope of a finite wing, Helmbold/DATCOM with Prandtl-Glauert [1]_ eq. 12.6 [1/rad].

    ``CL_a = 2 pi A / (2 + sqrt(4 + A^2 beta^2 / eta^2 (1 + tan^2 L / beta^2)))``, beta^2 = 1 - M^2.
    """
    m = np.minimum(np.asarray(mach, dtype=float), 0.99)
    beta2 = 1.0 - m ** 2
    return 2 * np.pi * aspect / (2 + np.sqrt(4 + aspect ** 2 * beta2 / eta ** 2 * (1 + tan_sweep_tmax ** 2 / beta2)))


def compressibility_factor(mach: ArrayLike) -> NDArray:
    """Prandtl-Glauert factor ``1/sqrt(1 - M^2)`` on the whole lift of wing-body and tail [-].

    Lifting-surface theory (Goethert's rule, Helmbold's formula with the compressible aspect ratio
    A beta, :func:`helmbold_slope`) makes a wing of aspect ratio 3.2 gain only 10 % of lift slope from
    Mach 0.4 to 0.75, a sixth of the two-dimensional Prandtl-Glauert gain. That is the inviscid,
    linear limit. Above the critical Mach number (0.71 at CL 0.14 by Korn) the supercritical
    pocket on the upper surface adds lift until the shock stall near the drag-divergence Mach number
    (DATCOM [2]_ sect. 4.1.3.2, transonic lift-curve slopes above the subsonic theory; Hilton [4]_). Held against
    the CFD's lift of this aircraft, whose three points lie on both sides of M_cr, the lift grows with
    Mach as fast as 1/beta (2 % over the range, against 15 % for Helmbold's law): the lift is scaled by
    1/beta, incidence and zero-lift angle included, up to Mach 0.9 (the Mach tables hold 0.9 above,
    past the drag divergence, where this rule would overstate the lift).
    """
    m = np.minimum(np.asarray(mach, dtype=float), 0.9)
    return 1.0 / np.sqrt(1.0 - m ** 2)


def skin_friction(re: ArrayLike, mach: ArrayLike, length_m: float, roughness_m: float,
                  laminar_fraction: float) -> NDArray:
    """Flat-plate skin-friction coefficient, mixed laminar/turbulent [1]_ eqs. 12.24-12.28.

    Turbulent: ``0.455 / (log10 Re)^2.58 / (1 + 0.144 M^2)^0.65`` with Re limited to the
    cut-off ``38.21 (l/k)^1.053`` for surface roughness k; laminar: ``1.328/sqrt(Re)``.
    """
    re = np.asarray(re, dtype=float)
    m = np.asarray(mach, dtype=float)
    re_cut = 38.21 * (length_m / roughness_m) ** 1.053
    re_t = np.minimum(re, re_cut)
    cf_t = 0.455 / np.log10(re_t) ** 2.58 / (1 + 0.144 * m ** 2) ** 0.65
    cf_l = 1.328 / np.sqrt(re)
    return laminar_fraction * cf_l + (1 - laminar_fraction) * cf_t


def lifting_form_factor(p: Planform, mach: ArrayLike) -> NDArray:
    """Form factor of a wing or tail, Shevell's supervelocity law [8]_ [-].

    ``FF = 1 + Z (t/c) + 100 (t/c)^4`` with ``Z = (2 - M^2) cos L / sqrt(1 - M^2 cos^2 L)``, L the
    quarter-chord sweep. The first-order supervelocity of a thickness distribution grows with the
    Prandtl-Glauert factor of the Mach number normal to the sweep, so the form factor rises only
    slowly with Mach (1.195 at M 0.2 and 1.20 at M 0.75 for UPERA's wing).

    Raymer's eq. 12.30 (used before) multiplies a thickness term by ``1.34 M^0.18``: a fit whose Mach
    term alone raises the lifting surfaces' profile drag by 12 % from Mach 0.4 to 0.75 and stands at
    1.16 already at Mach 0.5. Gur, Mason and Schetz [9]_ compare the published form factors: at
    t/c 0.10 they span 1.13 (DATCOM) to 1.28 (Torenbeek) at low speed, and Raymer's is the highest
    of them at cruise Mach. Shevell's law is the one that follows from the supervelocity it models.
    """
    m = np.asarray(mach, dtype=float)
    c = math.cos(p.sweep(0.25))
    z = (2.0 - m ** 2) * c / np.sqrt(1.0 - (m * c) ** 2)
    return 1.0 + z * p.t_c + 100.0 * p.t_c ** 4


def korn_mcrit(cl: ArrayLike, t_c: float, sweep_rad: float, kappa: float) -> NDArray:
    """Critical Mach number from the Korn equation and Lock's definition of M_DD [4]_.

    ``M_DD = kappa/cos L - (t/c)/cos^2 L - CL/(10 cos^3 L)``; ``M_cr = M_DD - (0.1/80)^(1/3)``
    (the Mach number where ``dCD_w/dM = 0.1`` with ``CD_w = 20 (M - M_cr)^4``).
    """
    c = math.cos(sweep_rad)
    mdd = kappa / c - t_c / c ** 2 - np.abs(np.asarray(cl, dtype=float)) / (10 * c ** 3)
    return mdd - (0.1 / 80.0) ** (1.0 / 3.0)


def wave_drag(mach: ArrayLike, mcrit: ArrayLike) -> NDArray:
    """Lock's drag-rise law ``CD_w = 20 (M - M_cr)^4`` for M > M_cr, else 0 [4]_."""
    dm = np.maximum(np.asarray(mach, dtype=float) - np.asarray(mcrit, dtype=float), 0.0)
    return 20.0 * dm ** 4


def planform_efficiency_nita_scholz(aspect: float, taper: float, sweep_c4_deg: float) -> float:
    """Inviscid span efficiency of a trapezoidal planform, ``e_theo`` of Nita and Scholz [3]_ [-]:
    ``1/(1 + f(taper - d_taper(sweep)) A)`` (Hoerner's optimum taper shifted for sweep)."""
    d_lam = -0.357 + 0.45 * math.exp(-0.0375 * sweep_c4_deg)
    x = taper - d_lam
    f = 0.0524 * x ** 4 - 0.15 * x ** 3 + 0.1659 * x ** 2 - 0.0706 * x + 0.0119
    return 1.0 / (1.0 + f * aspect)


def oswald_kroo(aspect: float, taper: float, sweep_c4_deg: float, d_fus_over_b: float, cd0: float,
                k_viscous: float = 0.38) -> float:
    """Oswald factor with the viscous drag due to lift written as a drag, not a factor [10]_ [-].

    ``1/e = 1/(u s) + pi A K CD0``: u the planform's inviscid span efficiency
    (:func:`planform_efficiency_nita_scholz`), ``s = 1 - 2 (d/b)^2`` the fuselage's loss of lift
    carry-over, and ``K CD0 CL^2`` (K = 0.38) the profile drag's growth with lift.

    Nita and Scholz [3]_ take the viscous part as a constant factor on e (0.873 for jets), fitted on
    transport aircraft of aspect ratio 7 to 10. Their factor is the same for every aspect ratio,
    while the viscous drag due to lift is not; its share of the drag due to lift is
    ``pi A e K CD0``, proportional to A. So at UPERA's aspect ratio of 3.2 the fixed factor
    overstates it about two and a half times (e 0.83 instead of 0.91). Raymer's statistical fits
    for real aircraft [1]_ eqs. 12.48-12.49 give 0.96 at this aspect ratio. Kroo's form holds at
    every aspect ratio.
    """
    u = planform_efficiency_nita_scholz(aspect, taper, sweep_c4_deg)
    s = 1.0 - 2.0 * d_fus_over_b ** 2
    return 1.0 / (1.0 / (u * s) + math.pi * aspect * k_viscous * cd0)


def _datcom_downwash_gradient(g: Geometry) -> float:
    """d(epsilon)/d(alpha) at low speed, DATCOM 4.4.1 [2]_."""
    w = g.wing
    a = w.aspect_ratio
    k_a = 1 / a - 1 / (1 + a ** 1.7)
    k_l = (10 - 3 * w.taper) / 7
    h_h = abs(g.raw["htail"]["z_m"] - g.raw["wing"]["z_m"])
    k_h = (1 - h_h / w.span_m) / (2 * g.l_h_m / w.span_m) ** (1 / 3)
    return 4.44 * (k_a * k_l * k_h * math.sqrt(math.cos(w.sweep_c4_rad))) ** 1.19


def _flap_effectiveness(chord_ratio: float) -> float:
    """Thin-airfoil flap effectiveness tau = 1 - (theta - sin theta)/pi, cos theta = 2 cf/c - 1,
    times the empirical viscous correction [2]_."""
    th = math.acos(2 * chord_ratio - 1)
    return ELEVATOR_EMPIRICAL * (1 - (th - math.sin(th)) / math.pi)


@dataclass(frozen=True)
class AeroModel:
    """UPERA's aerodynamic model; scalars derived once from a :class:`Geometry`."""

    geom: Geometry
    incidence_wing_rad: float
    incidence_tail_rad: float
    deps_dalpha0: float
    eta_h: float
    oswald: float
    clmax_clean: float
    tau_e: float
    tau_a: float
    tau_r: float
    cm_alpha_fus: float
    cd_gear: float
    intake_drag_area_m2: float
    flapped_area_ratio: float
    corrections: AeroCorrections = AeroCorrections()

    # -- lift ---------------------------------------------------------------
    def a_wb(self, mach: ArrayLike) -> NDArray:
        """Wing-body lift-curve slope [1/rad]; ``S_exp/S F`` capped at 0.98 as Raymer advises; times the
        calibrated ``cla_factor``."""
        w = self.geom.wing
        s_exp = w.exposed_area_m2(self.geom.fuselage_diameter_m / 2) / w.area_m2
        f = 1.07 * (1 + self.geom.fuselage_diameter_m / w.span_m) ** 2
        return helmbold_slope(w.aspect_ratio, w.tan_sweep(w.x_t_c), 0.0) * compressibility_factor(mach) * \
            min(s_exp * f, 0.98) * self.corrections.cla_factor

    def a_h(self, mach: ArrayLike) -> NDArray:
        """Horizontal-tail lift-curve slope [1/rad], times the calibrated ``cla_factor``."""
        h = self.geom.htail
        return helmbold_slope(h.aspect_ratio, h.tan_sweep(h.x_t_c), 0.0) * compressibility_factor(mach) * \
            self.corrections.cla_factor

    def a_v(self, mach: ArrayLike) -> NDArray:
        """Vertical-tail lift-curve slope [1/rad], effective aspect ratio 1.55 A_v (end plates)."""
        v = self.geom.vtail
        return helmbold_slope(1.55 * v.aspect_ratio, v.tan_sweep(v.x_t_c), mach)

    def deps_dalpha(self, mach: ArrayLike) -> NDArray:
        """Downwash gradient at the tail [-].

        The low-speed DATCOM value of the geometric wing, scaled with the wing's lift slope as DATCOM
        scales it with Mach [2]_ 4.4.1: the downwash follows the wing's lift, so a calibrated slope
        (``cla_factor``) scales it too. Held below 0.9: a tail that saw all of the wing's angle change
        as downwash would lose its stabilising lift, which no attached flow does.
        """
        return np.minimum(self.deps_dalpha0 * self.corrections.cla_factor * compressibility_factor(mach), 0.9)

    def _alpha_geometric(self, alpha: ArrayLike) -> NDArray:
        """The angle of attack the geometric model sees [rad]: the aircraft's angle less the calibrated
        zero-lift shift (the whole lift curve, wing, fuselage and tail, moves by the shift)."""
        return np.asarray(alpha, dtype=float) - self.corrections.alpha0_shift_rad

    def tail_alpha(self, alpha: ArrayLike, mach: ArrayLike) -> NDArray:
        """Angle of attack of the horizontal tail [rad]."""
        al = self._alpha_geometric(alpha)
        return al + self.incidence_tail_rad - self.deps_dalpha(mach) * (al + self.incidence_wing_rad)

    def cl_linear(self, alpha: ArrayLike, mach: ArrayLike) -> NDArray:
        """Aircraft lift coefficient at zero elevator and flap, linear range [-].

        Prandtl-Glauert/Goethert compressibility through the slopes multiplies the whole lift: the
        angle from zero lift (wing incidence and the calibrated zero-lift shift included), not only
        the angle of attack.
        """
        g = self.geom
        al = np.asarray(alpha, dtype=float)
        ag = self._alpha_geometric(al)
        return self.a_wb(mach) * (ag + self.incidence_wing_rad) + \
            self.eta_h * g.htail.area_m2 / g.wing.area_m2 * self.a_h(mach) * self.tail_alpha(al, mach)

    def cl_alpha(self, mach: ArrayLike) -> NDArray:
        """Aircraft lift-curve slope (tail included) [1/rad]."""
        g = self.geom
        return self.a_wb(mach) + self.eta_h * g.htail.area_m2 / g.wing.area_m2 * self.a_h(mach) * \
            (1 - self.deps_dalpha(mach))

    def cl_basic(self, alpha: ArrayLike, mach: ArrayLike) -> NDArray:
        """Aircraft lift coefficient at zero elevator and flap with a smooth stall [-].

        Linear up to 0.8 CL_max, then an exponential approach to CL_max; past the
        angle where 99 % of CL_max is reached, lift falls by 35 % of CL_max over 0.12 rad.
        Symmetric for negative lift.
        """
        cl = self.cl_linear(alpha, mach)
        x = np.abs(cl) / self.clmax_clean
        g = np.where(x <= 0.8, x, 0.8 + 0.2 * (1 - np.exp(-(x - 0.8) / 0.2)))
        x_peak = 0.8 + 0.2 * math.log(1 / 0.05)  # where g reaches 0.99
        cla = self.cl_alpha(mach)
        excess = np.maximum(x - x_peak, 0.0) * self.clmax_clean / cla  # angle beyond the peak [rad]
        g = g - 0.35 * np.minimum(excess / 0.12, 1.0)
        return np.sign(cl) * g * self.clmax_clean

    def alpha_stall(self, mach: float) -> float:
        """Angle of attack of the peak lift (clean) [rad]."""
        x_peak = 0.8 + 0.2 * math.log(1 / 0.05)
        cl0 = float(self.cl_linear(0.0, mach))
        return (x_peak * self.clmax_clean - cl0) / float(self.cl_alpha(mach))

    def dcl_flap_full(self, mach: ArrayLike) -> NDArray:
        """Lift increment of full flap [-]: a_wb |d alpha_0L| (S_flapped/S) cos(hinge sweep)."""
        f = self.geom.section("flap")
        w = self.geom.wing
        return self.a_wb(mach) * math.radians(-f["zero_lift_angle_shift_full_deg"]) * \
            self.flapped_area_ratio * math.cos(w.sweep(1 - f["chord_ratio"]))

    def clmax(self, flap_norm: float = 0.0) -> float:
        """Maximum lift coefficient, low speed [-]."""
        return self.clmax_clean + flap_norm * float(self.dcl_flap_full(0.0))

    # -- drag ---------------------------------------------------------------
    def cd0(self, mach: ArrayLike, re_cbar: ArrayLike) -> NDArray:
        """Zero-lift drag coefficient, clean [-]: the build-up :meth:`cd0_geometric` times the
        calibrated ``cd0_factor``."""
        return self.cd0_geometric(mach, re_cbar) * self.corrections.cd0_factor

    def cd0_geometric(self, mach: ArrayLike, re_cbar: ArrayLike) -> NDArray:
        """Zero-lift drag coefficient from the geometry alone, clean [-], component build-up [1]_ 12.5.

        ``re_cbar`` is the Reynolds number on the wing MAC (JSBSim's ``aero/Re``).
        """
        g = self.geom
        m = np.asarray(mach, dtype=float)
        re = np.asarray(re_cbar, dtype=float)
        c = g.wing.mac_m
        k = g.raw["surface_roughness_m"]
        total = np.zeros(np.broadcast(m, re).shape)
        for p, sec, exposed in ((g.wing, g.raw["wing"], g.wing.exposed_area_m2(g.fuselage_diameter_m / 2)),
                                (g.htail, g.raw["htail"], g.htail.exposed_area_m2(0.2)),
                                (g.vtail, g.raw["vtail"], g.vtail.area_m2)):
            swet = exposed * (1.977 + 0.52 * p.t_c)
            cf = skin_friction(re * p.mac_m / c, m, p.mac_m, k, sec["laminar_fraction"])
            total = total + cf * lifting_form_factor(p, m) * sec["interference_factor"] * swet
        d, length = g.fuselage_diameter_m, g.fuselage_length_m
        f = length / d
        swet_f = math.pi * d * length * (1 - 2 / f) ** (2 / 3) * (1 + 1 / f ** 2)  # Torenbeek
        ff_f = 0.9 + 5 / f ** 1.5 + f / 400
        total = total + skin_friction(re * length / c, m, length, k, 0.0) * ff_f * swet_f
        total = total + self.intake_drag_area_m2
        return total * (1 + LEAKAGE_PROTUBERANCE) / g.wing.area_m2

    def k_induced(self) -> float:
        """Drag-due-to-lift factor 1/(pi A e) [-], times the calibrated ``k_factor``."""
        return self.corrections.k_factor / (math.pi * self.geom.wing.aspect_ratio * self.oswald)

    @staticmethod
    def ground_effect(h_over_b: ArrayLike) -> NDArray:
        """Factor on the drag due to lift near the ground, (16 h/b)^2 / (1 + (16 h/b)^2) [-], h the
        wing's height above the ground [7]_."""
        x = (16.0 * np.asarray(h_over_b, dtype=float)) ** 2
        return x / (1.0 + x)

    def mcrit(self, cl: ArrayLike) -> NDArray:
        """Critical Mach number at lift coefficient ``cl`` [-]."""
        w = self.geom.wing
        return korn_mcrit(cl, w.t_c, w.sweep_c4_rad, self.geom.raw["wing"]["korn_technology_factor"])

    def cd_wave(self, mach: ArrayLike, cl: ArrayLike) -> NDArray:
        """Wave drag [-] at Mach and lift coefficient."""
        return wave_drag(mach, self.mcrit(cl))

    def cd_separation(self, alpha: ArrayLike, mach: ArrayLike) -> NDArray:
        """Extra drag past the stall: sin^2 of the angle beyond the lift peak [-]."""
        al = np.asarray(alpha, dtype=float)
        a_s = self.alpha_stall(float(np.max(mach)) if np.ndim(mach) == 0 else DESIGN_MACH)
        a_neg = -a_s - 2 * self.incidence_wing_rad
        return np.sin(np.maximum(al - a_s, 0.0)) ** 2 + np.sin(np.maximum(a_neg - al, 0.0)) ** 2

    def cd_flap_profile(self, flap_norm: ArrayLike) -> NDArray:
        """Profile drag of the flap [1]_ eq. 12.61: F (cf/c)(S_flapped/S)(delta_f - 10 deg), >= 0."""
        f = self.geom.section("flap")
        delta = np.asarray(flap_norm, dtype=float) * f["max_deg"]
        return f["drag_factor"] * f["chord_ratio"] * self.flapped_area_ratio * np.maximum(delta - 10.0, 0.0)

    # -- airbrake (fuselage side panels) ------------------------------------
    def airbrake_frontal_area_m2(self, airbrake_norm: ArrayLike = 1.0) -> NDArray:
        """Frontal (projected) area of the airbrake panels at a deflection [m^2]: n l h sin(delta),
        delta = airbrake_norm x max_deg, the panels hinged at their leading edges."""
        ab = self.geom.section("airbrake")
        delta = np.radians(np.clip(np.asarray(airbrake_norm, dtype=float), 0.0, 1.0) * ab["max_deg"])
        return ab["panels"] * ab["panel_length_m"] * ab["panel_height_m"] * np.sin(delta)

    def cd_airbrake(self, airbrake_norm: ArrayLike) -> NDArray:
        """Drag increment of the airbrake [-] on the wing area: eta CD_plate A_frontal / S.

        CD_plate is the drag of a flat plate normal to the flow on its frontal area (1.18 for a
        plate of aspect ratio 1 to 2, Hoerner [11]_ ch. 3); eta (0.85) allows for the panels standing
        partly in the fuselage boundary layer (Hoerner [11]_ ch. 8, plates on a wall; NACA TN 1939
        [12]_ collects measured fuselage brakes for calibration). Lift and pitching moment unchanged:
        the panels sit at the CG height.
        """
        ab = self.geom.section("airbrake")
        return ab["installation_factor"] * ab["plate_cd"] * self.airbrake_frontal_area_m2(airbrake_norm) / \
            self.geom.wing.area_m2

    def drag_coefficient(self, alpha: float, mach: float, re_cbar: float, flap_norm: float = 0.0,
                         gear_norm: float = 0.0, h_over_b: float = math.inf, airbrake_norm: float = 0.0) -> float:
        """The drag polar the JSBSim file implements, at zero elevator and rates [-].

        ``CD = CD0(M, Re) + phi(h/b) k CL_wb^2 + CD_w(M, CL_wb) + CD_sep(alpha) + CD_flap + CD_gear + CD_ab``
        with ``CL_wb = CL_basic(alpha, M) + dCL_flap`` and phi the ground effect (1 far from the ground).
        """
        clw = float(self.cl_basic(alpha, mach)) + flap_norm * float(self.dcl_flap_full(mach))
        phi = 1.0 if math.isinf(h_over_b) else float(self.ground_effect(h_over_b))
        return float(self.cd0(mach, re_cbar) + phi * self.k_induced() * clw ** 2 + self.cd_wave(mach, clw)
                     + self.cd_separation(alpha, DESIGN_MACH) + self.cd_flap_profile(flap_norm)
                     + gear_norm * self.cd_gear + self.cd_airbrake(airbrake_norm))

    # -- pitch --------------------------------------------------------------
    def cm_basic(self, alpha: ArrayLike, mach: ArrayLike) -> NDArray:
        """Pitching moment about the design CG at zero elevator and flap [-]."""
        g = self.geom
        al = np.asarray(alpha, dtype=float)
        ag = self._alpha_geometric(al)
        h_arm = (g.x_cg_m - g.x_wing_ac_m) / g.wing.mac_m
        return self.a_wb(mach) * (ag + self.incidence_wing_rad) * h_arm + self.cm_alpha_fus * ag - \
            self.eta_h * g.tail_volume_h * self.a_h(mach) * self.tail_alpha(al, mach)

    def cm_alpha(self, mach: ArrayLike) -> NDArray:
        """dCm/dalpha about the design CG [1/rad]."""
        g = self.geom
        h_arm = (g.x_cg_m - g.x_wing_ac_m) / g.wing.mac_m
        return self.a_wb(mach) * h_arm + self.cm_alpha_fus - \
            self.eta_h * g.tail_volume_h * self.a_h(mach) * (1 - self.deps_dalpha(mach))

    def static_margin(self, mach: ArrayLike = 0.0) -> NDArray:
        """Static margin -Cm_alpha/CL_alpha (stick fixed), fraction of the MAC [-]."""
        return -self.cm_alpha(mach) / self.cl_alpha(mach)

    def cl_de(self, mach: ArrayLike) -> NDArray:
        return self.eta_h * self.geom.htail.area_m2 / self.geom.wing.area_m2 * self.a_h(mach) * self.tau_e

    def cm_de(self, mach: ArrayLike) -> NDArray:
        return -self.eta_h * self.geom.tail_volume_h * self.a_h(mach) * self.tau_e

    def cl_q(self, mach: ArrayLike) -> NDArray:
        return 2 * self.eta_h * self.geom.tail_volume_h * self.a_h(mach)

    def cm_q(self, mach: ArrayLike) -> NDArray:
        """Pitch damping [1/rad]: tail term times 1.1 for wing and fuselage [5]_ sect. 3.7."""
        g = self.geom
        return -1.1 * 2 * self.eta_h * g.tail_volume_h * self.a_h(mach) * g.l_h_m / g.wing.mac_m

    def cl_adot(self, mach: ArrayLike) -> NDArray:
        return 2 * self.eta_h * self.geom.tail_volume_h * self.a_h(mach) * self.deps_dalpha(mach)

    def cm_adot(self, mach: ArrayLike) -> NDArray:
        g = self.geom
        return -2 * self.eta_h * g.tail_volume_h * self.a_h(mach) * g.l_h_m / g.wing.mac_m * self.deps_dalpha(mach)

    def cm_flap_full(self, mach: ArrayLike) -> NDArray:
        """Nose-down moment of full flap [-]: flap lift acting at 40 % MAC, tail downwash neglected."""
        g = self.geom
        arm = 0.40 - (g.x_cg_m - g.x_mac_le_m) / g.wing.mac_m
        return -self.dcl_flap_full(mach) * arm


def build_aero_model(g: Geometry, corrections: AeroCorrections) -> AeroModel:
    """The aerodynamic model of geometry ``g`` with ``corrections`` (not cached; see :func:`aero_model`)."""
    w, fus = g.wing, g.raw["fuselage"]
    # Fuselage pitching moment (Munk/Multhopp), Raymer eq. 16.25 with K_f read for the wing
    # quarter-chord root position at this fraction of the fuselage length [1] fig. 16.14.
    x_frac = (g.raw["wing"]["root_le_x_m"] + 0.25 * w.root_chord_m) / g.fuselage_length_m
    k_f = float(np.interp(x_frac, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], [0.0035, 0.005, 0.0085, 0.0135, 0.0205, 0.031]))
    cm_a_fus = k_f * g.fuselage_diameter_m ** 2 * g.fuselage_length_m / (w.mac_m * w.area_m2) * 180 / math.pi
    # Gear drag: Raymer table 12.6, D/q per frontal area 0.25 for a wheel and tyre, 1.2 for a round strut,
    # three legs, +20 % for mutual interference and wheel wells.
    gr = g.raw["gear"]
    dq_leg = 0.25 * gr["wheel_diameter_m"] * gr["wheel_width_m"] + 1.2 * gr["strut_length_m"] * gr["strut_width_m"]
    cd_gear = 1.2 * 3 * dq_leg / w.area_m2
    fl = g.raw["flap"]
    y1, y2 = fl["inner_span_fraction"] * w.semi_span_m, fl["outer_span_fraction"] * w.semi_span_m
    flapped = 2 * w.chord_integral_m2(y1, y2) / w.area_m2
    i_w = math.radians(g.raw["wing"]["incidence_deg"])
    base = AeroModel(
        geom=g, incidence_wing_rad=i_w, incidence_tail_rad=0.0, deps_dalpha0=_datcom_downwash_gradient(g),
        eta_h=g.raw["htail"]["dynamic_pressure_ratio"], oswald=1.0,
        clmax_clean=0.9 * g.raw["wing"]["airfoil_clmax"] * math.cos(w.sweep_c4_rad),
        tau_e=_flap_effectiveness(g.raw["htail"]["elevator_chord_ratio"]),
        tau_a=_flap_effectiveness(g.raw["aileron"]["chord_ratio"]),
        tau_r=_flap_effectiveness(g.raw["vtail"]["rudder_chord_ratio"]),
        cm_alpha_fus=cm_a_fus, cd_gear=cd_gear, intake_drag_area_m2=fus["intake_drag_area_m2"],
        flapped_area_ratio=flapped, corrections=corrections)
    # Oswald factor with the viscous part from the geometric CD0 at the design condition.
    _, _, rho, a_snd, mu = isa(DESIGN_ALT_M)
    re_design = rho * DESIGN_MACH * a_snd * w.mac_m / mu
    oswald = oswald_kroo(w.aspect_ratio, w.taper, math.degrees(w.sweep_c4_rad), g.fuselage_diameter_m / w.span_m,
                         float(base.cd0_geometric(DESIGN_MACH, re_design)))
    base = AeroModel(**{**base.__dict__, "oswald": oswald})
    # Tail incidence: Cm = 0 at the design CL and Mach with zero elevator (both linear in i_t).
    cla = float(base.cl_alpha(DESIGN_MACH))

    def residual(i_t: float) -> float:
        m = AeroModel(**{**base.__dict__, "incidence_tail_rad": i_t})
        cl0 = float(m.cl_linear(0.0, DESIGN_MACH))
        alpha = (DESIGN_CL - cl0) / cla
        return float(m.cm_basic(alpha, DESIGN_MACH))

    r0, r1 = residual(0.0), residual(0.01)
    i_t = -r0 * 0.01 / (r1 - r0)
    return AeroModel(**{**base.__dict__, "incidence_tail_rad": i_t})


@lru_cache(maxsize=8)
def aero_model(path: str | None = None, corrections: AeroCorrections | None = None) -> AeroModel:
    """The aerodynamic model of the geometry in ``path`` (default data file) with ``corrections``
    (default: the shipped calibration, ``data/upera_calibration.json``; neutral if it is absent)."""
    return build_aero_model(load_geometry(path), corrections if corrections is not None else load_corrections())


def geometric_model(path: str | None = None) -> AeroModel:
    """The model from the geometry alone, with no calibration."""
    return aero_model(path, AeroCorrections())
