"""Lateral-directional control: roll attitude to aileron, yaw damper/turn coordination to rudder,
heading and track hold as bank-angle commands.

Laws (s = clip(qbar_ref/qbar, s_min, s_max) is the dynamic-pressure gain schedule)::

    aileron = clip(s [k_phi (phi_c - phi) + k_phi_i Int(phi_c - phi) - k_p p], -1, 1)
    r_c     = g sin(phi) cos(theta) / V              (coordinated turn rate)
    rudder  = clip(s [k_beta beta - k_r (r - r_c)], -1, 1)
    phi_c   = clip(k_psi wrap(psi_c - psi), -phi_max, phi_max)   (heading hold; track: chi)

Sign conventions follow the airframe adapter: aileron > 0 rolls right, rudder > 0
yaws the nose right; bank phi > 0 right wing down; sideslip beta > 0 with the
relative wind from the right (nose right corrects it). Angles are radians.

References
----------
D. McLean, "Automatic Flight Control Systems", Prentice Hall, 1990, ch. 8.
B. L. Stevens, F. L. Lewis, E. N. Johnson, "Aircraft Control and Simulation", 3rd ed., 2016, sec. 4.5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..infra.jit import jitable
from ..infra.records import fast_init
from ..mission.geo import wrap_pi
from .atmosphere import G0_M_S2
from .clip import clip
from .tunable import Tunable, field_index, load_params

__all__ = ["LateralParams", "LateralState", "LateralOutput", "LateralController"]


@dataclass(frozen=True, slots=True)
class LateralParams:
    """Gains and limits of the lateral loops (data/lateral.yaml, section ``lateral``)."""

    k_phi_1_rad: float
    k_p_s_rad: float
    k_phi_i_1_rad_s: float
    phi_i_band_rad: float
    phi_i_limit: float
    k_r_s_rad: float
    k_beta_1_rad: float
    qbar_ref_Pa: float
    gain_sched_min: float
    gain_sched_max: float
    k_psi_1_s: float
    phi_max_rad: float

    @classmethod
    def from_file(cls, **overrides: float) -> LateralParams:
        """Parameter set of ``data/lateral.yaml``, section ``lateral``."""
        return load_params(cls, "lateral.yaml", "lateral", **overrides)


@fast_init
@dataclass(frozen=True, slots=True)
class LateralState:
    """Measured lateral-directional state.

    Attributes
    ----------
    phi_rad, theta_rad : float
        Bank and pitch attitude [rad].
    psi_rad : float
        True heading [rad].
    chi_rad : float
        True track (course over ground) [rad].
    p_rad_s, r_rad_s : float
        Body roll and yaw rates [rad/s].
    beta_rad : float
        Sideslip [rad].
    tas_m_s : float
        True airspeed [m/s].
    qbar_Pa : float
        Dynamic pressure [Pa].
    """

    phi_rad: float
    theta_rad: float
    psi_rad: float
    chi_rad: float
    p_rad_s: float
    r_rad_s: float
    beta_rad: float
    tas_m_s: float
    qbar_Pa: float


@fast_init
@dataclass(frozen=True, slots=True)
class LateralOutput:
    """Surface commands and the bank command that produced them.

    Attributes
    ----------
    aileron : float
        Normalised aileron [-1, 1] (> 0 rolls right).
    rudder : float
        Normalised rudder [-1, 1] (> 0 nose right).
    phi_cmd_rad : float
        Bank command [rad].
    """

    aileron: float
    rudder: float
    phi_cmd_rad: float


class LateralController(Tunable[LateralParams]):
    """Roll, yaw-damper/coordination, heading and track hold."""

    tunable_name = "lateral"

    def __init__(self, params: LateralParams | None = None) -> None:
        self._params = params if params is not None else LateralParams.from_file()
        self._s = np.zeros(1)  # the state of lateral_law: the bank-error integral [-]

    def reset(self) -> None:
        """Clear the bank-error integral."""
        self._s[0] = 0.0

    def phi_for_heading(self, psi_cmd_rad: float, psi_rad: float, phi_max_rad: float | None = None) -> float:
        """Bank command that turns the shorter way to heading (or track) ``psi_cmd_rad`` [rad]."""
        p = self._params
        lim = p.phi_max_rad if phi_max_rad is None else min(phi_max_rad, p.phi_max_rad)
        return clip(p.k_psi_1_s * wrap_pi(psi_cmd_rad - psi_rad), -lim, lim)

    def step(self, dt_s: float, x: LateralState, phi_cmd_rad: float | None = None,
             heading_cmd_rad: float | None = None, track_cmd_rad: float | None = None) -> LateralOutput:
        """One step of the lateral loops.

        Parameters
        ----------
        dt_s : float
            Step [s].
        x : LateralState
            Measured state.
        phi_cmd_rad : float, optional
            Bank command [rad] (roll mode; from guidance). Takes precedence.
        heading_cmd_rad, track_cmd_rad : float, optional
            True heading or track to hold [rad].

        Returns
        -------
        LateralOutput
        """
        return LateralOutput(*self.step_values(dt_s, x.phi_rad, x.theta_rad, x.psi_rad, x.chi_rad, x.p_rad_s,
                                               x.r_rad_s, x.beta_rad, x.tas_m_s, x.qbar_Pa, phi_cmd_rad,
                                               heading_cmd_rad, track_cmd_rad))

    def step_values(self, dt_s: float, phi_rad: float, theta_rad: float, psi_rad: float, chi_rad: float,
                    p_rad_s: float, r_rad_s: float, beta_rad: float, tas_m_s: float, qbar_Pa: float,
                    phi_cmd_rad: float | None = None, heading_cmd_rad: float | None = None,
                    track_cmd_rad: float | None = None) -> tuple[float, float, float]:
        """:meth:`step` on plain values (the fields of :class:`LateralState` in their order, then the
        commands); returns (aileron, rudder, phi_cmd_rad), the fields of :class:`LateralOutput` (the FCS's
        per-step path, which builds no records). The one implementation of the loops."""
        a, r, phi_c = lateral_law(self.values(), self._s, dt_s, phi_rad, theta_rad, psi_rad, chi_rad, p_rad_s,
                                  r_rad_s, beta_rad, tas_m_s, qbar_Pa,
                                  math.nan if phi_cmd_rad is None else phi_cmd_rad, phi_cmd_rad is not None,
                                  math.nan if heading_cmd_rad is None else heading_cmd_rad,
                                  heading_cmd_rad is not None, math.nan if track_cmd_rad is None else track_cmd_rad,
                                  track_cmd_rad is not None)
        return float(a), float(r), float(phi_c)


#: Index of each field of LateralParams in :meth:`LateralController.values`.
LP = field_index(LateralParams)


@jitable
def lateral_law(p: np.ndarray, s: np.ndarray, dt_s: float, phi_rad: float, theta_rad: float, psi_rad: float,
                chi_rad: float, p_rad_s: float, r_rad_s: float, beta_rad: float, tas_m_s: float, qbar_Pa: float,
                phi_cmd_rad: float, has_phi: bool, heading_cmd_rad: float, has_heading: bool, track_cmd_rad: float,
                has_track: bool) -> tuple[float, float, float]:
    """One step of the lateral loops on plain values (:meth:`LateralController.step_values`'s arguments, each
    command with its flag): parameters ``p`` (:meth:`LateralController.values`, indexed by :data:`LP`), the
    bank-error integral in ``s[0]`` (updated in place); returns (aileron, rudder, phi_cmd_rad). The one
    implementation of the loops."""
    if not has_phi:
        lim = p[LP.phi_max_rad]
        if has_track:
            phi_cmd_rad = clip(p[LP.k_psi_1_s] * wrap_pi(track_cmd_rad - chi_rad), -lim, lim)
        elif has_heading:
            phi_cmd_rad = clip(p[LP.k_psi_1_s] * wrap_pi(heading_cmd_rad - psi_rad), -lim, lim)
        else:
            phi_cmd_rad = 0.0
    # clip(v, lo, hi) written out as its two comparisons (as in pitch.py)
    s_min, s_max = p[LP.gain_sched_min], p[LP.gain_sched_max]
    g = p[LP.qbar_ref_Pa] / (1.0 if 1.0 > qbar_Pa else qbar_Pa)
    g = s_min if s_min > g else g
    g = s_max if s_max < g else g
    e = phi_cmd_rad - phi_rad
    u_p = g * (p[LP.k_phi_1_rad] * e - p[LP.k_p_s_rad] * p_rad_s)
    u = u_p + s[0]
    if abs(e) < p[LP.phi_i_band_rad] and (-1.0 < u < 1.0 or (u >= 1.0) != (e > 0)):
        i, lim = s[0] + g * p[LP.k_phi_i_1_rad_s] * e * dt_s, p[LP.phi_i_limit]
        i = -lim if -lim > i else i
        s[0] = lim if lim < i else i
    aileron = u_p + s[0]
    aileron = -1.0 if -1.0 > aileron else aileron
    aileron = 1.0 if 1.0 < aileron else aileron
    r_c = G0_M_S2 * math.sin(phi_rad) * math.cos(theta_rad) / (1.0 if 1.0 > tas_m_s else tas_m_s)
    rudder = g * (p[LP.k_beta_1_rad] * beta_rad - p[LP.k_r_s_rad] * (r_rad_s - r_c))
    rudder = -1.0 if -1.0 > rudder else rudder
    return aileron, 1.0 if 1.0 < rudder else rudder, phi_cmd_rad
