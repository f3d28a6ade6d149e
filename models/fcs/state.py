"""The signals between the aircraft, the mission state machine and the control laws.

:class:`AircraftState` is what the FCS measures (one frozen record per step, SI);
:class:`Targets` is what the active mission section asks of the control laws; both
are recorded so that commanded and flown profiles can be plotted side by side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..infra.records import fast_init
from ..mission.geo import LatLon
from ..mission.speed import SpeedCommand

__all__ = ["AircraftState", "EngineState", "Targets"]


@fast_init
@dataclass(frozen=True, slots=True)
class AircraftState:
    """Measured aircraft state.

    Attributes
    ----------
    pos : LatLon
        Geodetic position.
    alt_m : float
        Altitude above mean sea level (pressure altitude in ISA) [m].
    tas_m_s : float
        True airspeed [m/s].
    Vdot_m_s2 : float
        Rate of change of true airspeed [m/s^2].
    gamma_rad : float
        Air-relative flight-path angle [rad].
    vn_m_s, ve_m_s : float
        Ground velocity north and east [m/s].
    psi_rad, phi_rad, theta_rad : float
        True heading, bank, pitch [rad].
    p_rad_s, q_rad_s, r_rad_s : float
        Body rates [rad/s].
    beta_rad : float
        Sideslip [rad].
    qbar_Pa : float
        Dynamic pressure [Pa].
    mass_kg : float
        Mass [kg].
    on_ground : bool
        Weight on the main wheels.
    dT_isa_K : float
        ISA temperature deviation [K].
    """

    pos: LatLon
    alt_m: float
    tas_m_s: float
    Vdot_m_s2: float
    gamma_rad: float
    vn_m_s: float
    ve_m_s: float
    psi_rad: float
    phi_rad: float
    theta_rad: float
    p_rad_s: float
    q_rad_s: float
    r_rad_s: float
    beta_rad: float
    qbar_Pa: float
    mass_kg: float
    on_ground: bool
    dT_isa_K: float = 0.0

    @property
    def chi_rad(self) -> float:
        """True track [rad]."""
        return math.atan2(self.ve_m_s, self.vn_m_s)

    @property
    def gs_m_s(self) -> float:
        """Ground speed [m/s]."""
        return math.hypot(self.vn_m_s, self.ve_m_s)


@fast_init
@dataclass(frozen=True, slots=True)
class EngineState:
    """Measured engine quantities the fuel controller needs.

    Attributes
    ----------
    N1_pct : float
        Fan speed [% of design].
    N1c_pct : float
        Corrected fan speed [% of design].
    Tt41_K : float
        HP turbine rotor inlet total temperature [K].
    """

    N1_pct: float
    N1c_pct: float
    Tt41_K: float


@fast_init
@dataclass(frozen=True, slots=True)
class Targets:
    """What the active mission section asks of the control laws in this step.

    Vertical: ``theta_cmd_rad`` (direct pitch, on the ground), else TECS with
    ``alt_cmd_m`` (altitude, with the vertical speed ``hdot_ff_m_s`` of a managed path) or
    ``gamma_cmd_rad`` (path); ``lever`` fixes the thrust lever (None: TECS sets it);
    ``priority`` which command TECS keeps when the thrust cannot give both, ``airbrake``
    whether the airbrake may extend the thrust channel below idle; ``vnav_mode`` the
    vertical mode (:data:`.vertical.VNAV_MODES`). Lateral: ``phi_cmd_rad``, else ``heading_cmd_rad``;
    ``align_heading_rad`` makes the rudder hold a heading (de-crab, ground roll).

    Attributes
    ----------
    section_index : int
        Index of the active section (-1 before the start, len(sections) when finished).
    section_name, section_type, phase : str
        Active section, its type and its phase.
    alt_cmd_m, gamma_cmd_rad, theta_cmd_rad : float or None
        Vertical targets [m], [rad], [rad].
    hdot_ff_m_s : float
        Vertical speed of the commanded altitude (a managed path) [m/s].
    priority : str or None
        ``"path"``, ``"speed"`` or None (TECS decides).
    airbrake : bool
        The airbrake may be used.
    vnav_mode : str
        Vertical mode.
    speed : SpeedCommand or None
        Speed target.
    lever : float or None
        Fixed thrust lever [-].
    phi_cmd_rad, heading_cmd_rad, align_heading_rad : float or None
        Lateral targets [rad].
    track_cmd_rad : float
        Desired track, for plots [rad] (NaN when none).
    xtk_m : float
        Cross-track error of the active path [m] (NaN when none).
    steer : float
        Nose-wheel steering [-1, 1].
    brake : float
        Wheel brakes [0, 1].
    gear_down : bool
        Landing gear command.
    """

    section_index: int
    section_name: str
    section_type: str
    phase: str
    alt_cmd_m: float | None = None
    gamma_cmd_rad: float | None = None
    theta_cmd_rad: float | None = None
    speed: SpeedCommand | None = None
    lever: float | None = None
    phi_cmd_rad: float | None = None
    heading_cmd_rad: float | None = None
    align_heading_rad: float | None = None
    track_cmd_rad: float = math.nan
    xtk_m: float = math.nan
    steer: float = 0.0
    brake: float = 0.0
    gear_down: bool = True
    hdot_ff_m_s: float = 0.0
    priority: str | None = None
    airbrake: bool = False
    vnav_mode: str = ""
