"""Inlet distortion by the parallel compressor model.

A compressor face with a sector distortion is split into two compressors
working side by side on the same map at the same mechanical speed: a clean
sector (share 1 - theta of the annulus) with the undistorted inlet state, and
a distorted sector (share theta) whose inlet total pressure is lower by a
fraction dPt (a screen, a separated intake at incidence) and/or whose inlet
total temperature is higher by dTt (hot-gas ingestion). Each sector passes
its share of the flow the map gives at its own corrected speed and beta;
both discharge to the same exit pressure, which is the extra matching
equation per distorted compressor. The distorted sector runs closer to surge;
the compressor's surge margin is that of its worst sector.

Critical sector angle: a spoiled sector narrower than a critical angle
(about 60 deg of the annulus) hurts the compressor less than the same deficit
over a wider sector, and widening it beyond the critical angle adds little
(Reid 1969; the reason for the DC(60) descriptor). The flow redistributes ahead
of a narrow sector and the rotor passes it before responding. Here the deficit
the rotor sees is the nominal one scaled by min(1, theta / theta_crit)
(``critical_angle_deg``, 60 deg by default); at and above theta_crit the model is
the plain parallel compressor. The statement "widening adds little" holds at a
constant deficit relative to the face-mean total pressure (Reid's DC(theta)), which
the plain parallel compressor reproduces (its loss of surge pressure ratio then equals
the deficit at any width); at a constant ``dPt_frac`` (relative to the clean flow) the
face mean falls as the sector widens and the penalty falls beyond theta_crit. The rise
below theta_crit is the scaling above, not a prediction (tests/engine/test_distortion.py).

The sectors are computed in the gas path (:func:`.gas_path.turbofan`, one more unknown, the
distorted sector's beta, and one more residual, the equal exit pressures, per distorted face);
their exit flows are mixed (mass, air, fuel, enthalpy conserved, at the flow-weighted total
pressure) before the next component, i.e. the distortion is not carried downstream. This module
describes a distortion (:class:`Distortion`).

References
----------
W. M. Pearson, A. McKenzie, "Wakes in axial compressors", J. R. Aeronaut. Soc.
63 (1959) 415-416 (the parallel compressor idea); C. Reid, "The response of
axial flow compressors to intake flow distortion", ASME 69-GT-29, 1969.
N. A. Cumpsty, "Compressor Aerodynamics", 2nd ed., 2004, ch. 9 (inlet distortion:
parallel compressor, critical sector angle of about 60 deg). SAE ARP1420C, "Gas Turbine Engine
Inlet Flow Distortion Guidelines", 2017, and SAE AIR1419C (parallel compressor methodology, surge margin stack-up).
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.2.6.
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import OutOfRangeError

__all__ = ["Distortion"]


@dataclass(frozen=True, slots=True)
class Distortion:
    """A sector distortion at a compressor face.

    Attributes
    ----------
    sector_frac : float
        Share of the annulus that is distorted, theta/360 deg [-], in (0, 1).
    dPt_frac : float
        Total-pressure deficit of the distorted sector, relative to the clean inlet [-], in [0, 0.5).
    dTt_K : float
        Total-temperature excess of the distorted sector [K], in [0, 300].
    critical_angle_deg : float
        Critical sector angle [deg], in (0, 360]: narrower sectors act with a deficit scaled
        by their angle over this one.
    """

    sector_frac: float
    dPt_frac: float = 0.0
    dTt_K: float = 0.0
    critical_angle_deg: float = 60.0

    @property
    def attenuation(self) -> float:
        """Share of the nominal deficits the rotor sees, min(1, theta / theta_crit) [-]."""
        return min(1.0, 360.0 * self.sector_frac / self.critical_angle_deg)

    def __post_init__(self) -> None:
        if not (0.0 < self.sector_frac < 1.0):
            raise OutOfRangeError(f"distortion: sector_frac={self.sector_frac!r} is outside (0, 1)")
        if not (0.0 <= self.dPt_frac < 0.5):
            raise OutOfRangeError(f"distortion: dPt_frac={self.dPt_frac!r} is outside [0, 0.5)")
        if not (0.0 <= self.dTt_K <= 300.0):
            raise OutOfRangeError(f"distortion: dTt_K={self.dTt_K!r} is outside [0, 300] K")
        if not (0.0 < self.critical_angle_deg <= 360.0):
            raise OutOfRangeError(f"distortion: critical_angle_deg={self.critical_angle_deg!r} is outside (0, 360]")
