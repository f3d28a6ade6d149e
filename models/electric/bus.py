"""Loads on the DC bus: constant avionics, a scheduled pulse train and event-driven pulses.

The bus is an ideal node (one voltage, the battery's): in every step the sources (the HP generator, the
LP motor-generator, the battery) and the loads balance exactly,
``P_hp_elec + P_lp_elec + P_batt = P_loads - P_shed`` (:mod:`.system`). What no source can supply is shed
and reported (``P_shed``), never lost silently.
"""
from __future__ import annotations

import math

from .params import BusParams

__all__ = ["Loads"]


class Loads:
    """The bus's load demand over time.

    Parameters
    ----------
    p : BusParams
        Constant load and the scheduled pulse train: ``pulse_count`` pulses of ``pulse_W`` lasting
        ``pulse_duration_s`` every ``pulse_period_s`` from ``pulse_start_s`` (none if that is < 0).
    """

    def __init__(self, p: BusParams) -> None:
        self.p = p

    def scheduled_W(self, t_s: float) -> float:
        """Power of the scheduled pulse train at time ``t_s`` [W] (pulses are ``[start, start + duration)``)."""
        p = self.p
        if p.pulse_start_s < 0.0 or p.pulse_count <= 0 or p.pulse_W == 0.0 or t_s < p.pulse_start_s:
            return 0.0
        rel = t_s - p.pulse_start_s
        k = math.floor(rel / p.pulse_period_s) if p.pulse_period_s > 0.0 else 0
        if k >= p.pulse_count:
            return 0.0
        return p.pulse_W if rel - k * p.pulse_period_s < p.pulse_duration_s else 0.0

    def demand_W(self, t_s: float, event_W: float) -> tuple[float, float]:
        """``(total, pulse)`` demand at ``t_s`` [W]: the constant load plus the scheduled and the
        event-driven pulses (``event_W``, an input set by a scenario); ``pulse`` is their pulse part."""
        pulse = self.scheduled_W(t_s) + max(event_W, 0.0)
        return self.p.avionics_W + pulse, pulse
