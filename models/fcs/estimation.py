"""Rate of change of the true airspeed for the TECS, robust to turbulence: a complementary filter.

The TECS needs ``Vdot``, the rate of the true airspeed. Differencing successive airspeeds
amplifies turbulence: a gust changes the airspeed by a metre per second within a tenth of a
second without the aircraft's energy changing, and the TECS's pitch channel would chase it
(with light MIL-F-8785C turbulence the differenced and low-passed airspeed of UPERA carries
about 2 m/s^2 of noise, 0.2 g in the energy-rate error; the closed loop went into a pitch
oscillation of +-5 g). The aircraft's inertial motion is smooth (a gust reaches it through
the aerodynamic forces, filtered by its mass), so the airspeed rate is estimated as its
inertial part, the ground acceleration along the air path,

    Vdot_i = a . u,     u = cos(alpha) cos(beta) x_b + sin(beta) y_b + sin(alpha) cos(beta) z_b,

exact in a steady wind (d/dt (V_ground - wind) = a), with x_b, y_b, z_b the body axes in north,
east, down (from the Euler angles) and the angle of attack from the flight-path angle: the air
path's down component -sin(gamma) = u_d gives

    cos(phi) cos(theta) sin(alpha) - sin(theta) cos(alpha) = (-sin(gamma) - sin(beta) sin(phi) cos(theta)) / cos(beta)

(alpha = theta in wings-level level flight, tan(alpha) = tan(theta)/cos(phi) in a level turn). The
heading alone is not the air path's direction: in a turn the nose points inside it by about
alpha sin(phi), 5 deg in a 2 g turn at 164 m/s, where the 17 m/s^2 of centripetal acceleration
would then read as 1.5 m/s^2 of speed change. Complemented at low frequency by the
measured airspeed (so a wind that changes along the path, e.g. winds aloft while climbing,
is followed): with an estimate V_e of the airspeed,

    dV_e/dt = Vdot_i + (V - V_e) / tau,     Vdot = Vdot_i + (V - V_e) / tau,

whose output is the measured airspeed's rate below 1/tau and the inertial one above
(a first-order complementary filter; tau is ``estimation.tau_cross_s``, data/estimation.yaml).
The flight control low-passes the rate once more (``tecs.tau_Vdot_s``, 0.3 s) before the TECS:
the inertial rate has no lag, and in speed priority (idle descent) the loop from pitch through
the flight path's gravity component back to the rate, g per radian, then closed at 1 Hz into
an elevator-saturating pitch oscillation on the calibrated airframe.

References
----------
.. [1] Higgins, W. T., "A comparison of complementary and Kalman filtering", IEEE Trans.
   Aerospace and Electronic Systems AES-11(3), 1975, pp. 321-325.
.. [2] Lambregts, A. A., "Vertical flight path and speed control autopilot design using total
   energy principles", AIAA 83-2239, 1983 (the TECS's use of the longitudinal acceleration).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..infra.jit import jitable
from .tunable import Tunable, load_params

__all__ = ["EstimationParams", "AirspeedRateEstimator", "air_path_direction", "estimator_law"]


@dataclass(frozen=True, slots=True)
class EstimationParams:
    """Parameters of the estimator (data/estimation.yaml, section ``estimation``)."""

    tau_cross_s: float

    @classmethod
    def from_file(cls, **overrides: float) -> EstimationParams:
        """Parameter set of ``data/estimation.yaml``."""
        return load_params(cls, "estimation.yaml", "estimation", **overrides)


@jitable
def air_path_direction(phi_rad: float, theta_rad: float, psi_rad: float, beta_rad: float,
                       gamma_rad: float) -> tuple[float, float, float]:
    """Unit vector of the air-relative velocity (north, east, up) from the attitude, sideslip and
    flight-path angle [rad], the angle of attack solved from the path's vertical component."""
    sf, cf = math.sin(phi_rad), math.cos(phi_rad)
    st, ct = math.sin(theta_rad), math.cos(theta_rad)
    sp, cp = math.sin(psi_rad), math.cos(psi_rad)
    sb, cb = math.sin(beta_rad), math.cos(beta_rad)
    # B sin(alpha) - A cos(alpha) = K  <=>  R sin(alpha - delta) = K
    A, B = st, cf * ct
    K = (-math.sin(gamma_rad) - sb * sf * ct) / (1e-6 if 1e-6 > cb else cb)  # max(cb, 1e-6)
    # sqrt of the sum of squares, not math.hypot: CPython's hypot and the C library's (which compiled code calls)
    # differ in the last bit for about one argument pair in 160, and the compiled FCS must equal the plain one
    R = math.sqrt(A * A + B * B)
    if R > 1e-9:
        s = K / R  # max(-1, min(1, K / R)), written out (NaN gives 1, as there)
        s = s if s < 1.0 else 1.0
        alpha = math.atan2(A, B) + math.asin(s if s > -1.0 else -1.0)
    else:
        alpha = 0.0
    ca, sa = math.cos(alpha) * cb, math.sin(alpha) * cb
    # ca x_b + sb y_b + sa z_b, component by component (north, east, down)
    n = ca * (ct * cp) + sb * (sf * st * cp - cf * sp) + sa * (cf * st * cp + sf * sp)
    e = ca * (ct * sp) + sb * (sf * st * sp + cf * cp) + sa * (cf * st * sp - sf * cp)
    d = ca * -st + sb * (sf * ct) + sa * (cf * ct)
    return n, e, -d


class AirspeedRateEstimator(Tunable[EstimationParams]):
    """Complementary filter of the true airspeed rate from the ground velocity and the airspeed.

    Parameters
    ----------
    params : EstimationParams or float, optional
        The parameter set (default: the file's), or just the crossover time constant
        ``tau_cross_s`` [s]; 0 gives the differenced airspeed (no filtering).
    """

    tunable_name = "estimation"

    def __init__(self, params: EstimationParams | float | None = None) -> None:
        if params is None:
            params = EstimationParams.from_file()
        elif not isinstance(params, EstimationParams):
            params = EstimationParams(float(params))
        self._params = params
        # the state of estimator_law: 1 once a step was taken, the airspeed estimate V_e [m/s], the previous
        # step's ground velocity (north, east, up) [m/s] and air path direction (north, east, up) [-]
        self._s = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0])

    @property
    def tas_m_s(self) -> float | None:
        """The filtered true airspeed V_e [m/s] (None before the first step)."""
        return float(self._s[1]) if self._s[0] != 0.0 else None

    def reset(self) -> None:
        """Forget the history (the next step starts from the measured airspeed, rate 0)."""
        self._s[0] = 0.0

    def step(self, dt_s: float, tas_m_s: float, vn_m_s: float, ve_m_s: float, vu_m_s: float, phi_rad: float,
             theta_rad: float, psi_rad: float, beta_rad: float, gamma_rad: float) -> float:
        """The airspeed rate [m/s^2] after one step of ``dt_s`` [s].

        Parameters
        ----------
        tas_m_s : float
            Measured true airspeed [m/s].
        vn_m_s, ve_m_s, vu_m_s : float
            Ground velocity north, east and up [m/s], each the mean over the step just ended (from
            the change of position) or the value now.
        phi_rad, theta_rad, psi_rad : float
            Bank, pitch and true heading [rad].
        beta_rad, gamma_rad : float
            Sideslip and air-relative flight-path angle [rad].
        """
        return float(estimator_law(self._params.tau_cross_s, self._s, dt_s, tas_m_s, vn_m_s, ve_m_s, vu_m_s, phi_rad,
                                   theta_rad, psi_rad, beta_rad, gamma_rad))


@jitable
def estimator_law(tau_cross_s: float, s: np.ndarray, dt_s: float, tas_m_s: float, vn_m_s: float, ve_m_s: float,
                  vu_m_s: float, phi_rad: float, theta_rad: float, psi_rad: float, beta_rad: float,
                  gamma_rad: float) -> float:
    """One step of the complementary filter on plain values (:meth:`AirspeedRateEstimator.step`'s arguments after
    its crossover time constant [s]), its state ``s`` updated in place; returns the airspeed rate [m/s^2]. The one
    implementation of the estimator."""
    un_now, ue_now, uu_now = air_path_direction(phi_rad, theta_rad, psi_rad, beta_rad, gamma_rad)
    v_est = s[1]
    if s[0] == 0.0 or dt_s <= 0.0:
        s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7] = 1.0, tas_m_s, vn_m_s, ve_m_s, vu_m_s, un_now, ue_now, uu_now
        return 0.0
    # the difference of two step-averaged velocities is the acceleration about one step ago: projected
    # on the air path of then (with the path of now, the turn rate times a step would turn some of a
    # turn's centripetal acceleration into a speed change)
    # summed from 0.0 as sum() did (the same rounding, the sign of a zero included)
    vdot_i = (0.0 + (vn_m_s - s[2]) * s[5] + (ve_m_s - s[3]) * s[6] + (vu_m_s - s[4]) * s[7]) / dt_s
    s[2], s[3], s[4], s[5], s[6], s[7] = vn_m_s, ve_m_s, vu_m_s, un_now, ue_now, uu_now
    tau = tau_cross_s
    if tau <= 0.0:
        vdot = (tas_m_s - v_est) / dt_s
        s[1] = tas_m_s
        return vdot
    vdot = vdot_i + (tas_m_s - v_est) / tau
    s[1] = v_est + vdot * dt_s
    return vdot
