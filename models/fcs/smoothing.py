"""The outer loops' targets ramped between their updates (issue 38 point 4).

The navigation sections run at the outer loops' rate (``guidance.outer_period_s``, 0.5 s): their
targets (altitude and vertical speed of a managed path, flight-path angle, bank or heading, speed) are
computed once a period and held in between (:meth:`.state_machine.MissionRunner.step`). Fed to the inner
loops as they are, each update is a step of the commands, and the TECS's thrust channel answers every
step: in a managed descent the fuel flow carried a +-1.5 % sawtooth at the outer loops' rate (2 Hz).

:class:`TargetRamp` makes the commands the inner loops see continuous: at an update it starts from the
value it was giving and moves linearly to the new target over one outer period, which is when the next
update comes. A managed path's altitude moves on at the new target's vertical speed at once, and the jump
between what was given and the new target's altitude decays linearly over the period. The commands are
then continuous in time (their slope changes at the updates, where holding them stepped them). The price
is half a period more delay on average of the part of a target's change that its rate did not predict (a
first-order hold in place of a zero-order hold): 0.25 s at the shipped period.

Only targets that are continuous in the section's logic are ramped: a value that appears or disappears
(a target given as None before or after), a speed given in another kind, a new section or a target of
a section that is not held (:attr:`.sections.SectionType.outer_rate` False) is taken at once, as before.

This is our own code: it is the hold of the control law's own sampled outer loop (a first-order hold,
e.g. Franklin, Powell, Workman, *Digital Control of Dynamic Systems*, 3rd ed., 1998, section 6.3.2).
"""

from __future__ import annotations

import math

from ..mission.geo import wrap_pi
from .state import Targets

__all__ = ["RampedTargets", "TargetRamp"]

#: The continuous targets of :class:`.state.Targets` the ramp moves (angles wrapped: ``heading_cmd_rad``).
RAMPED_FIELDS = ("alt_cmd_m", "hdot_ff_m_s", "gamma_cmd_rad", "phi_cmd_rad", "heading_cmd_rad")


class RampedTargets:
    """The continuous targets as the inner loops get them at one instant (None: no such target).

    Attributes
    ----------
    alt_cmd_m : float or None
        Altitude command, a managed path's moved on at its vertical speed [m].
    hdot_ff_m_s : float
        Vertical speed of the commanded altitude [m/s].
    gamma_cmd_rad, phi_cmd_rad, heading_cmd_rad : float or None
        Flight-path angle, bank and heading commands [rad].
    speed_value : float or None
        The speed command's value in its kind's unit (Mach [-] or airspeed [m/s]).
    """

    __slots__ = ("alt_cmd_m", "hdot_ff_m_s", "gamma_cmd_rad", "phi_cmd_rad", "heading_cmd_rad", "speed_value")

    def __init__(self) -> None:
        self.alt_cmd_m: float | None = None
        self.hdot_ff_m_s = 0.0
        self.gamma_cmd_rad: float | None = None
        self.phi_cmd_rad: float | None = None
        self.heading_cmd_rad: float | None = None
        self.speed_value: float | None = None


def _blend(a: float | None, b: float | None, w: float) -> float | None:
    """``a`` moved by ``w`` of the way to ``b``; ``b`` when either is None (a target that appears or goes)."""
    return b if a is None or b is None else a + w * (b - a)


class TargetRamp:
    """Ramps held targets from one update to the next over one outer period (see the module).

    Call :meth:`step` every inner step with the runner's targets and the time they were computed: a new
    time is an update.
    """

    __slots__ = ("_section", "_speed_kind", "_t_tg_s", "_t0_s", "_period_s", "_from", "_to", "out")

    def __init__(self) -> None:
        self._section = -2  # section index of the last update's targets
        self._speed_kind: object = None  # the kind of their speed command (None: none)
        self._t_tg_s = math.nan  # when the last update's targets were computed [s]
        self._t0_s = 0.0  # time of the last update [s]
        self._period_s = 0.0  # the ramp's duration: the outer period then in force (0: no ramp) [s]
        self._from = RampedTargets()  # the values given at the last update
        self._to = RampedTargets()  # the update's targets, the altitude at the update's time
        #: the values of the last :meth:`step`
        self.out = RampedTargets()

    def step(self, t_s: float, tg: Targets, t_tg_s: float, period_s: float) -> RampedTargets:
        """The targets for the inner loops at time ``t_s`` [s].

        Parameters
        ----------
        t_s : float
            Time of the step [s].
        tg : Targets
            The runner's targets.
        t_tg_s : float
            When ``tg`` was computed [s] (the same while they are held).
        period_s : float
            How long ``tg`` is held [s]: the outer period for a held section, 0 for targets of every step.
        """
        if t_tg_s != self._t_tg_s:
            self._update(t_s, tg, t_tg_s, period_s)
        return self._at(t_s)

    def _at(self, t_s: float) -> RampedTargets:
        """The ramped values at ``t_s`` [s] (into :attr:`out`)."""
        out, a, b = self.out, self._from, self._to
        dt = t_s - self._t0_s
        w = 1.0 if self._period_s <= 0.0 else min(max(dt / self._period_s, 0.0), 1.0)
        out.hdot_ff_m_s = a.hdot_ff_m_s + w * (b.hdot_ff_m_s - a.hdot_ff_m_s)
        # the new target moved on at its vertical speed, less what remains of the jump at the update
        out.alt_cmd_m = None if b.alt_cmd_m is None else b.alt_cmd_m + b.hdot_ff_m_s * dt + (
            0.0 if a.alt_cmd_m is None else (1.0 - w) * (a.alt_cmd_m - b.alt_cmd_m))
        out.gamma_cmd_rad = _blend(a.gamma_cmd_rad, b.gamma_cmd_rad, w)
        out.phi_cmd_rad = _blend(a.phi_cmd_rad, b.phi_cmd_rad, w)
        out.speed_value = _blend(a.speed_value, b.speed_value, w)
        hb = b.heading_cmd_rad
        out.heading_cmd_rad = hb if a.heading_cmd_rad is None or hb is None else \
            wrap_pi(a.heading_cmd_rad + w * wrap_pi(hb - a.heading_cmd_rad))
        return out

    def _update(self, t_s: float, tg: Targets, t_tg_s: float, period_s: float) -> None:
        """A new update: ramp from what was given at ``t_s`` to ``tg`` if both are of the same held section."""
        kind = None if tg.speed is None else tg.speed.kind
        ramp = period_s > 0.0 and self._period_s > 0.0 and self._section == tg.section_index
        a, b = self._from, self._to
        if ramp:
            out = self._at(t_s)  # what the old ramp gives at t_s (the last step ran at its value then)
            a.alt_cmd_m, a.hdot_ff_m_s = out.alt_cmd_m, out.hdot_ff_m_s
            a.gamma_cmd_rad, a.phi_cmd_rad, a.heading_cmd_rad = out.gamma_cmd_rad, out.phi_cmd_rad, \
                out.heading_cmd_rad
            a.speed_value = out.speed_value if kind is not None and kind == self._speed_kind else None
        # the new targets, the altitude at t_s (computed at t_tg_s, moved on at its vertical speed)
        b.alt_cmd_m = None if tg.alt_cmd_m is None else tg.alt_cmd_m + tg.hdot_ff_m_s * (t_s - t_tg_s)
        b.hdot_ff_m_s = tg.hdot_ff_m_s
        b.gamma_cmd_rad, b.phi_cmd_rad, b.heading_cmd_rad = tg.gamma_cmd_rad, tg.phi_cmd_rad, tg.heading_cmd_rad
        b.speed_value = None if tg.speed is None else tg.speed.value
        if not ramp:
            a.alt_cmd_m, a.hdot_ff_m_s, a.gamma_cmd_rad, a.phi_cmd_rad, a.heading_cmd_rad, a.speed_value = \
                b.alt_cmd_m, b.hdot_ff_m_s, b.gamma_cmd_rad, b.phi_cmd_rad, b.heading_cmd_rad, b.speed_value
        self._section, self._speed_kind = tg.section_index, kind
        self._t_tg_s, self._t0_s, self._period_s = t_tg_s, t_s, period_s
