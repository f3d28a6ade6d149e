"""The energy management law: which machine does what, from the flight phase and the battery's state.

Modes (:data:`MODES`), chosen every step in this order:

* ``pulse`` -- a pulse load is on: no boost, no charging; the HP generator takes the pulse up to its
  limit and ramp (``pulse_hp_first``), the battery buffers the rest (or, without ``pulse_hp_first``,
  the battery takes the pulse and the HP generator the steady loads);
* ``boost`` -- take-off and climb: the thrust lever at or above ``lever_boost_min`` (take-off and climb
  power) on the ground (the take-off roll) or climbing at ``climb_vs_min_m_s`` or more, with the SOC
  above ``soc_boost_min``: the LP machine motors, delivering ``boost_W`` to the LP spool from the battery;
* ``charge`` -- airborne and not climbing (cruise, descent) while the SOC is below ``soc_charge_stop``
  (resuming below ``soc_charge_stop - soc_charge_band``): the LP machine generates ``charge_W`` (shaft
  side) into the battery;
* ``generate`` -- otherwise (ground, a full battery, the law disabled): the HP generator supplies the
  loads, the LP machine is idle.

In every mode the HP generator's target is the bus load it is to carry; the battery is the bus's
slack within its limits, and :mod:`.system` resolves what the limits do not allow (less boost or
charging first, more HP power next, shedding last).

Why here and not in the flight control: the law acts on the power system's fast state (SOC, the
machines' and the battery's limits, the pulse loads) and needs from the flight only the lever, the
vertical speed and whether the aircraft is on the ground; in the electric FMU it keeps the default system (``ssp/``)
and the FCS untouched and adds no extra communication delay between law and battery.
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import EmsParams

__all__ = ["MODES", "EmsDecision", "EnergyManagement"]

MODES = ("generate", "boost", "charge", "pulse")  #: mode names by index (the FMU's ems_mode)


@dataclass(frozen=True)
class EmsDecision:
    """What the law asks for in one step.

    Attributes
    ----------
    mode : int
        Index in :data:`MODES`.
    lp_shaft_W : float
        LP machine shaft power request [W], > 0 generating (charge), < 0 motoring (boost).
    hp_elec_W : float
        HP generator electrical power target [W].
    """

    mode: int
    lp_shaft_W: float
    hp_elec_W: float


class EnergyManagement:
    """The law of the module text, with the charging hysteresis as its only state.

    Parameters
    ----------
    p : EmsParams
        Gains and limits.
    """

    def __init__(self, p: EmsParams) -> None:
        self.p = p
        self.charging = False

    def decide(self, lever: float, on_ground: bool, vs_m_s: float, soc: float, steady_W: float,
               pulse_W: float) -> EmsDecision:
        """The mode and the requests for this step.

        Parameters
        ----------
        lever : float
            Thrust lever command, 0 to 1 [-].
        on_ground : bool
            A wheel carries weight.
        vs_m_s : float
            Vertical speed, > 0 up [m/s].
        soc : float
            Battery state of charge [-].
        steady_W, pulse_W : float
            Steady (constant) and pulse parts of the bus load [W].
        """
        p = self.p
        if soc >= p.soc_charge_stop:
            self.charging = False
        elif soc < p.soc_charge_stop - p.soc_charge_band:
            self.charging = True
        if not p.enabled:
            return EmsDecision(0, 0.0, steady_W + pulse_W)
        if pulse_W > 0.0:
            return EmsDecision(3, 0.0, steady_W + (pulse_W if p.pulse_hp_first else 0.0))
        climbing = vs_m_s >= p.climb_vs_min_m_s
        if lever >= p.lever_boost_min and (on_ground or climbing) and soc > p.soc_boost_min and p.boost_W > 0.0:
            return EmsDecision(1, -p.boost_W, steady_W)
        if not on_ground and not climbing and self.charging and p.charge_W > 0.0:
            return EmsDecision(2, p.charge_W, steady_W)
        return EmsDecision(0, 0.0, steady_W)
