"""Inner pitch loop: pitch attitude command to elevator.

    u = s(qbar) [k_theta (theta_c - theta) + k_theta_i Int(theta_c - theta) dt - k_q q]
    elevator = -clip(u, -1, 1)

with the gain schedule s = clip(qbar_ref / qbar, s_min, s_max) (surface
effectiveness grows with dynamic pressure). The elevator sign follows the
airframe adapter: elevator > 0 is trailing edge down, nose down, so a nose-up
demand u > 0 gives a negative elevator. The integral (trim) has its own
authority limit and stops integrating while the surface is saturated
(conditional integration, no wind-up).

References
----------
D. McLean, "Automatic Flight Control Systems", Prentice Hall, 1990, ch. 7.
B. L. Stevens, F. L. Lewis, E. N. Johnson, "Aircraft Control and Simulation", 3rd ed., 2016, sec. 4.4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..infra.jit import jitable
from .atmosphere import G0_M_S2
from .tunable import Tunable, field_index, load_params

__all__ = ["PitchParams", "PitchController", "pitch_law", "turn_pitch_rate"]


@dataclass(frozen=True, slots=True)
class PitchParams:
    """Gains of the pitch loop (data/tecs.yaml, section ``pitch``); see the file for units."""

    k_theta_1_rad: float
    k_q_s_rad: float
    k_theta_i_1_rad_s: float
    k_theta_ground_1_rad: float
    k_q_ground_s_rad: float
    k_theta_i_ground_1_rad_s: float
    qbar_ref_Pa: float
    gain_sched_min: float
    gain_sched_max: float
    trim_limit: float

    @classmethod
    def from_file(cls, **overrides: float) -> PitchParams:
        """Parameter set of ``data/tecs.yaml``, section ``pitch``."""
        return load_params(cls, "tecs.yaml", "pitch", **overrides)


class PitchController(Tunable[PitchParams]):
    """Pitch attitude hold with rate damping: theta command [rad] -> elevator [-1, 1] (> 0 nose down)."""

    tunable_name = "pitch"

    def __init__(self, params: PitchParams | None = None) -> None:
        self._params = params if params is not None else PitchParams.from_file()
        self._s = np.zeros(1)  # the state of pitch_law: the integral (trim) [-]

    def reset(self, elevator_trim: float = 0.0) -> None:
        """Start from elevator ``elevator_trim`` [-] (bumpless engagement)."""
        self._s[0] = -elevator_trim

    def step(self, dt_s: float, theta_cmd_rad: float, theta_rad: float, q_rad_s: float,
             qbar_Pa: float, q_turn_rad_s: float = 0.0, on_ground: bool = False) -> float:
        """One step; returns the normalised elevator command [-1, 1] (> 0 nose down).

        Parameters
        ----------
        dt_s : float
            Step [s].
        theta_cmd_rad, theta_rad : float
            Commanded and measured pitch attitude [rad].
        q_rad_s : float
            Pitch rate [rad/s].
        qbar_Pa : float
            Dynamic pressure [Pa].
        q_turn_rad_s : float
            Pitch rate of the steady turn being flown [rad/s] (:func:`turn_pitch_rate`): the rate
            damping acts on the pitch rate less this, so that it damps the short period and does not
            oppose the steady pull of a banked turn (turn compensation, McLean ch. 7).
        on_ground : bool
            Weight on wheels: the ground gains (``*_ground``) act, as the gear carries the aircraft
            and the attitude answers the elevator only through the rotation about the main wheels
            (gain switching on weight on wheels).
        """
        return float(pitch_law(self.values(), self._s, dt_s, theta_cmd_rad, theta_rad, q_rad_s, qbar_Pa, q_turn_rad_s,
                               on_ground))


#: Index of each field of PitchParams in :meth:`PitchController.values`.
PP = field_index(PitchParams)


@jitable
def pitch_law(p: np.ndarray, s: np.ndarray, dt_s: float, theta_cmd_rad: float, theta_rad: float, q_rad_s: float,
              qbar_Pa: float, q_turn_rad_s: float, on_ground: bool) -> float:
    """One step of the pitch loop on plain values (:meth:`PitchController.step`'s arguments): parameters ``p``
    (:meth:`PitchController.values`, indexed by :data:`PP`), the integral in ``s[0]`` (updated in place); returns
    the elevator [-1, 1] (> 0 nose down). The one implementation of the loop."""
    # clip(v, lo, hi) written out as its two comparisons (clip.py: the same value, NaN included)
    s_min, s_max = p[PP.gain_sched_min], p[PP.gain_sched_max]
    g = p[PP.qbar_ref_Pa] / (1.0 if 1.0 > qbar_Pa else qbar_Pa)
    g = s_min if s_min > g else g
    g = s_max if s_max < g else g
    e = theta_cmd_rad - theta_rad
    if on_ground:
        k_th, k_q, k_i = p[PP.k_theta_ground_1_rad], p[PP.k_q_ground_s_rad], p[PP.k_theta_i_ground_1_rad_s]
    else:
        k_th, k_q, k_i = p[PP.k_theta_1_rad], p[PP.k_q_s_rad], p[PP.k_theta_i_1_rad_s]
    u_p = g * (k_th * e - k_q * (q_rad_s - q_turn_rad_s))
    u = u_p + s[0]
    if -1.0 < u < 1.0 or (u >= 1.0) != (e > 0):
        i, lim = s[0] + g * k_i * e * dt_s, p[PP.trim_limit]
        i = -lim if -lim > i else i
        s[0] = lim if lim < i else i
    u = u_p + s[0]
    u = -1.0 if -1.0 > u else u
    return -(1.0 if 1.0 < u else u)


@jitable
def turn_pitch_rate(phi_rad: float, tas_m_s: float) -> float:
    """Body pitch rate of a steady, level, coordinated turn at bank ``phi_rad`` [rad/s].

    The turn rate is ``Omega = g tan(phi) / V``; its component on the body y axis is
    ``q = Omega sin(phi) = g sin(phi) tan(phi) / V`` (Etkin and Reid, *Dynamics of Flight*, 3rd ed.,
    sect. 4.7). Bank held to 80 deg and speed above 10 m/s so that the rate stays finite.
    """
    phi = abs(phi_rad)
    if _PHI_TURN_MAX_RAD < phi:  # min(|phi|, 80 deg)
        phi = _PHI_TURN_MAX_RAD
    return G0_M_S2 * math.sin(phi) * math.tan(phi) / (10.0 if 10.0 > tas_m_s else tas_m_s)


_PHI_TURN_MAX_RAD = math.radians(80.0)
