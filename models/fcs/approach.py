"""ILS geometry, and the automatic approach and landing (the runway itself: :mod:`openemss.models.mission.runway`).

Geometry (ICAO Annex 10 Vol. I, 3.1.5): the glide path of angle gs_angle passes
the threshold at the reference datum height tch (15 m), so it meets the runway
at the glide path intercept GPI, tch / tan(gs) past the threshold (286 m at 3 deg).
The localizer antenna stands 300 m beyond the stop end. Positions relative to a
runway are taken in the WGS-84 tangent plane of its threshold (:func:`openemss.models.mission.geo.local_ne_m`),
exact to centimetres over an approach.

Phases of :class:`AutoLand` (each reported as a string):

``HOLD``       only when the approach starts more than hold_enter_m above the approach
               altitude (a descent that could not be completed before, e.g. with a high
               idle thrust): orbit of radius hold_radius_m, gear down for drag, centred on
               the extended centre line two radii beyond the point where the glide path
               passes the approach altitude, descending to that altitude, as a holding
               pattern would. -> ``LOC_ARMED`` within hold_exit_m of the approach altitude.
``LOC_ARMED``  lateral: track to the extended centre line (L1 guidance); vertical:
               hold the approach altitude. -> ``LOC`` when |cross-track| < loc_capture.
``LOC``        localizer tracked; glide slope armed. -> ``GS`` when the aircraft
               is within gs_capture below the path, or above it.
``GS``         path mode: gamma_c = -gs + k_gs (h_gp - h) / V. -> ``FLARE`` below h_flare.
``FLARE``      exponential flare, hdot_c = -h / tau - hdot_td, with tau = h_flare /
               (V sin gs - hdot_td) for a continuous sink rate at flare entry; thrust idle;
               below decrab_height the rudder aligns the heading with the runway (de-crab;
               late, so the aircraft has little time to drift). -> ``DEROTATION`` on touchdown.
``DEROTATION`` pitch command lowered at theta_derot_rate to theta_ground, idle.
               -> ``ROLLOUT`` when the pitch is within nose_down_tol of theta_ground, or derot_settle
               after the command reached theta_ground.
``ROLLOUT``    nose-wheel steering and rudder on the centre line, brakes.
               -> ``STOPPED`` below v_stop.

References
----------
ICAO Annex 10, Aeronautical Telecommunications, Vol. I, 7th ed., 2018, 3.1.5.
D. T. McRuer, I. L. Ashkenas, D. Graham, "Aircraft Dynamics and Automatic Control",
Princeton, 1973, ch. 11 (automatic landing, exponential flare).
B. L. Stevens, F. L. Lewis, E. N. Johnson, "Aircraft Control and Simulation", 3rd ed., 2016, sec. 4.7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.records import fast_init
from ..mission.geo import LatLon, wrap_pi
from ..mission.runway import Runway
from .clip import clip
from .guidance import L1Guidance
from .tunable import Tunable, load_params

__all__ = ["IlsDeviation", "ApproachParams", "ApproachCommand", "AutoLand", "LOC_BEYOND_END_M",
           "ils_deviation", "centreline_steer", "APPROACH_PHASES"]

#: Phases of :class:`AutoLand` in the order of their codes (the FCS FMU's Integer output ``ils_phase``; 0: none).
APPROACH_PHASES = ("", "HOLD", "LOC_ARMED", "LOC", "GS", "FLARE", "DEROTATION", "ROLLOUT", "STOPPED")

#: Localizer antenna beyond the stop end of the runway [m] (typical siting).
LOC_BEYOND_END_M = 300.0


@dataclass(frozen=True, slots=True)
class ApproachParams:
    """Approach and landing parameters (data/lateral.yaml, section ``approach``)."""

    gs_angle_rad: float
    tch_m: float
    loc_capture_m: float
    k_gs_1_s: float
    gs_capture_m: float
    h_flare_m: float
    hdot_td_m_s: float
    theta_derot_rad_s: float
    theta_ground_rad: float
    k_y_steer_1_m: float
    k_psi_steer_1_rad: float
    brake: float
    v_stop_m_s: float
    nose_down_tol_rad: float
    derot_settle_s: float
    decrab_height_m: float
    flare_gamma_max_rad: float
    gear_up_agl_m: float
    climb_engage_agl_m: float
    hold_enter_m: float
    hold_exit_m: float
    hold_radius_m: float
    loc_damping: float

    @classmethod
    def from_file(cls, **overrides: float) -> ApproachParams:
        """Parameter set of ``data/lateral.yaml``, section ``approach``."""
        return load_params(cls, "lateral.yaml", "approach", **overrides)


@fast_init  # built every step of a landing: see records.py
@dataclass(frozen=True, slots=True)
class IlsDeviation:
    """Position relative to the ILS of a runway.

    Attributes
    ----------
    along_m : float
        Along the centre line from the threshold (negative on the approach) [m].
    loc_m : float
        Cross-track from the centre line, right positive [m].
    loc_rad : float
        Angular localizer deviation seen from the antenna, right positive [rad].
    gs_m : float
        Height above the glide path, positive high [m].
    gs_rad : float
        Angular glide slope deviation, positive high [rad].
    h_agl_m : float
        Height above the threshold elevation [m].
    """

    along_m: float
    loc_m: float
    loc_rad: float
    gs_m: float
    gs_rad: float
    h_agl_m: float


def ils_deviation(rwy: Runway, p: ApproachParams, pos: LatLon, alt_m: float) -> IlsDeviation:
    """Localizer and glide slope deviations of an aircraft at ``pos``, altitude ``alt_m`` [m]."""
    along, cross = rwy.local(pos)
    h = alt_m - rwy.elevation_m
    tan_gs = math.tan(p.gs_angle_rad)
    d_gpi = p.tch_m / tan_gs - along  # horizontal distance to the glide path intercept
    h_gp = d_gpi * tan_gs
    d_loc = rwy.length_m + LOC_BEYOND_END_M - along
    # max(d_gpi, 1.0) written out (the builtin costs ~0.1 us a call; the same value)
    return IlsDeviation.make(along, cross, math.atan2(cross, d_loc), h - h_gp,
                             math.atan2(h, 1.0 if 1.0 > d_gpi else d_gpi) - p.gs_angle_rad, h)


def centreline_steer(rwy: Runway, p: ApproachParams, pos: LatLon, psi_rad: float) -> float:
    """Nose-wheel steering [-1, 1] (> 0 right) that holds the centre line of ``rwy``."""
    _, cross = rwy.local(pos)
    steer = -(p.k_y_steer_1_m * cross + p.k_psi_steer_1_rad * wrap_pi(psi_rad - rwy.heading_rad))
    return clip(steer, -1.0, 1.0)


@fast_init  # built every step of a landing: see records.py
@dataclass(frozen=True, slots=True)
class ApproachCommand:
    """Commands of the approach and landing logic for one step.

    ``gamma_cmd_rad`` is None while the altitude ``alt_cmd_m`` is held; ``theta_cmd_rad``
    (direct pitch command) is set on the ground; ``idle`` asks for idle thrust.

    Attributes
    ----------
    phase : str
        See the module docstring.
    phi_cmd_rad : float
        Bank command [rad].
    alt_cmd_m : float or None
        Altitude to hold [m].
    gamma_cmd_rad : float or None
        Flight-path command [rad].
    theta_cmd_rad : float or None
        Pitch command [rad] (de-rotation).
    idle : bool
        Thrust to idle.
    align_heading_rad : float or None
        Heading the rudder should hold (de-crab, roll-out) [rad].
    steer : float
        Nose-wheel steering [-1, 1] (> 0 right).
    brake : float
        Wheel brakes [0, 1].
    ils : IlsDeviation
        The deviations.
    """

    phase: str
    phi_cmd_rad: float
    alt_cmd_m: float | None
    gamma_cmd_rad: float | None
    theta_cmd_rad: float | None
    idle: bool
    align_heading_rad: float | None
    steer: float
    brake: float
    ils: IlsDeviation


class AutoLand(Tunable[ApproachParams]):
    """ILS capture and tracking, flare, touchdown, de-rotation and roll-out on one runway.

    Parameters
    ----------
    runway : Runway
        The landing runway.
    approach_alt_m : float
        Altitude held until the glide slope is captured [m].
    guidance : L1Guidance, optional
        Path follower for the localizer.
    params : ApproachParams, optional
        Parameters (the file's by default).
    """

    tunable_name = "approach"

    def __init__(self, runway: Runway, approach_alt_m: float, guidance: L1Guidance | None = None,
                 params: ApproachParams | None = None) -> None:
        self._params = params if params is not None else ApproachParams.from_file()
        self.runway = runway
        self.approach_alt_m = approach_alt_m
        self._g = guidance if guidance is not None else L1Guidance()
        self.phase = ""  # decided at the first step: HOLD or LOC_ARMED
        self._tau_flare = 1.0
        self._theta_cmd = 0.0
        self._t_nose_down_s = 0.0       # time the de-rotation command has been at theta_ground [s]

    @property
    def done(self) -> bool:
        """The aircraft has stopped on the runway."""
        return self.phase == "STOPPED"

    def hold_center(self) -> LatLon:
        """Centre of the descent hold: on the extended centre line, two hold radii beyond the point
        where the glide path passes the approach altitude, so that the whole circle lies at least one
        radius outside it: at the approach altitude the aircraft leaves the hold below the glide path
        (R tan(gs), 210 m at 4 km and 3 deg) and captures it from below, as in a normal approach."""
        p = self._params
        d_fix = max(self.approach_alt_m - self.runway.elevation_m - p.tch_m, 0.0) / math.tan(p.gs_angle_rad)
        return self.runway.point(-(d_fix + 2.0 * p.hold_radius_m))

    def step(self, dt_s: float, pos: LatLon, alt_m: float, vn_m_s: float, ve_m_s: float, psi_rad: float,
             tas_m_s: float, theta_rad: float, on_ground: bool) -> ApproachCommand:
        """One step of the approach logic.

        Parameters
        ----------
        dt_s : float
            Step [s].
        pos : LatLon
            Aircraft position (of the main gear, or the reference point) .
        alt_m : float
            Altitude above mean sea level [m].
        vn_m_s, ve_m_s : float
            Ground velocity [m/s].
        psi_rad : float
            True heading [rad].
        tas_m_s : float
            True airspeed [m/s].
        theta_rad : float
            Pitch attitude [rad].
        on_ground : bool
            Weight on the main wheels.
        """
        p = self._params
        rwy = self.runway
        ils = ils_deviation(rwy, p, pos, alt_m)
        V = 1.0 if 1.0 > tas_m_s else tas_m_s  # max(tas_m_s, 1.0) written out (as in ils_deviation)
        vg = math.hypot(vn_m_s, ve_m_s)
        lat = self._g.line(rwy.heading_rad, ils.loc_m, vn_m_s, ve_m_s, psi_rad, damping=p.loc_damping)
        phi = lat.phi_cmd_rad
        alt_cmd: float | None = None
        gamma: float | None = None
        theta_cmd: float | None = None
        idle, align, steer, brake = False, None, 0.0, 0.0

        if not self.phase:
            self.phase = "HOLD" if alt_m > self.approach_alt_m + p.hold_enter_m else "LOC_ARMED"
        if self.phase == "HOLD" and alt_m < self.approach_alt_m + p.hold_exit_m:
            self.phase = "LOC_ARMED"
        if self.phase == "LOC_ARMED" and abs(ils.loc_m) < p.loc_capture_m and ils.along_m < 0.0:
            self.phase = "LOC"
        if self.phase == "LOC" and ils.gs_m > -p.gs_capture_m and ils.along_m < 0.0:
            self.phase = "GS"
        if self.phase == "GS" and ils.h_agl_m < p.h_flare_m:
            self.phase = "FLARE"
            sink = V * math.sin(p.gs_angle_rad)
            self._tau_flare = p.h_flare_m / max(sink - p.hdot_td_m_s, 0.5)
        if self.phase in ("GS", "FLARE") and on_ground:
            self.phase = "DEROTATION"
            self._theta_cmd = theta_rad
            self._t_nose_down_s = 0.0
        if self.phase == "DEROTATION":
            # ends with the nose down: the pitch within tolerance of theta_ground, or the command at theta_ground
            # for derot_settle_s (the pitch on three wheels is the gear's and the struts', not exactly
            # theta_ground: after a bounce it can settle a little above the tolerance and stay there)
            if self._theta_cmd <= p.theta_ground_rad:
                self._t_nose_down_s += dt_s
            if theta_rad <= p.theta_ground_rad + p.nose_down_tol_rad or self._t_nose_down_s >= p.derot_settle_s:
                self.phase = "ROLLOUT"
        if self.phase == "ROLLOUT" and vg < p.v_stop_m_s:
            self.phase = "STOPPED"

        if self.phase == "HOLD":
            alt_cmd = self.approach_alt_m
            phi = self._g.orbit(pos, vn_m_s, ve_m_s, self.hold_center(), p.hold_radius_m, 1, psi_rad).phi_cmd_rad
        elif self.phase in ("LOC_ARMED", "LOC"):
            alt_cmd = self.approach_alt_m
        elif self.phase == "GS":
            gamma = -p.gs_angle_rad - p.k_gs_1_s * ils.gs_m / V
        elif self.phase == "FLARE":
            hdot = -max(ils.h_agl_m, 0.0) / self._tau_flare - p.hdot_td_m_s
            gamma = math.asin(max(min(hdot / V, p.flare_gamma_max_rad), -p.flare_gamma_max_rad))
            idle = True
            align = rwy.heading_rad if ils.h_agl_m < p.decrab_height_m else None
        else:  # on the ground
            phi, idle, align = 0.0, True, rwy.heading_rad
            self._theta_cmd = max(self._theta_cmd - p.theta_derot_rad_s * dt_s, p.theta_ground_rad)
            theta_cmd = self._theta_cmd
            steer = centreline_steer(rwy, p, pos, psi_rad)
            if self.phase in ("ROLLOUT", "STOPPED"):
                brake = p.brake
        return ApproachCommand.make(self.phase, phi, alt_cmd, gamma, theta_cmd, idle, align, steer, brake, ils)
