"""The mission section types as a mission file declares them: each one class with its fields, registered once.

:data:`REGISTRY` maps a section's ``type`` to its declaration: the mission reader (:mod:`.mission`) takes the
fields and their checks from it, the report its conformance kind (what it compares after the flight), the
documentation its completion:

=================  ==============================================================
type               complete when
=================  ==============================================================
Rolling            calibrated airspeed >= ``rotate_cas_m_s``
TakeOff            height above the runway >= ``until_height_agl_m`` (after lift-off)
WaypointFollowing  every waypoint passed (fly-over within ``wp_accept_m`` or abeam;
                   fly-by at the turn anticipation distance), and a planned hold at
                   the constraint's waypoint flown
Orbiting           ``turns`` full turns swept around the centre after capture
GTurns             ``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed
Levelling          ``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``
Landing            stopped on the runway (ground speed < ``v_stop_m_s``)
Custom             ``duration_s`` elapsed
=================  ==============================================================

How the flight control flies each type, and how the mission check judges it before the flight, is the FCS's
(``openemss.models.fcs.sections``: one class per type deriving from its declaration here, registered there with
its flight law). A new section type is one class deriving from ``openemss.models.fcs.sections.SectionType``
registered with that module's ``register``: its declaration is registered here by the same call.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

from .geo import LatLon

if TYPE_CHECKING:
    from .mission import Section

__all__ = ["Field", "SectionSpec", "REGISTRY", "register", "section_label", "CONFORMANCE", "TARGETS", "APPROACH"]

#: A field of a section type: (kind, required, default, (min, max) or choices, unit and help).
Field = tuple[str, bool, Any, Any, str]

#: :attr:`SectionSpec.conformance` of a section flown to an altitude (and a speed): the report compares them with
#: the flown altitude and speed (``openemss.report.conformance.section_conformance``).
TARGETS = "targets"
#: :attr:`SectionSpec.conformance` of an ILS approach to a runway: its phases are the approach's (the FCS's
#: ``ils_phase``) and the report measures the localizer and glide slope captures
#: (``openemss.report.conformance.ils_conformance``).
APPROACH = "approach"
#: Each conformance kind and the fields a section type of that kind must have.
CONFORMANCE: dict[str, tuple[str, ...]] = {TARGETS: ("altitude_m",), APPROACH: ("runway", "approach_altitude_m")}


class SectionSpec:
    """A mission section type as a mission file declares it.

    Class attributes
    ----------------
    type_name : str
        The ``type`` of the mission file.
    fields : dict
        Field name -> (kind, required, default, (min, max) or choices, unit and help), read by
        :func:`.mission.parse_mission`.
    completion : str
        When a section of this type is complete (the documentation and ``emss`` read it).
    speed_field : str or None
        The field holding the speed the section leaves the aircraft at (the next section's
        descent holds it until its deceleration).
    departs_from_runway : bool
        A ground run on the section's ``runway``: a mission that begins with it starts there, on the ground,
        and the aircraft must not leave the runway on the ground; the mission check starts there too.
    conformance : str or None
        What the report compares after the flight: :data:`TARGETS` (altitude and speed targets),
        :data:`APPROACH` (the ILS captures), or None (nothing); :data:`CONFORMANCE` lists the fields each needs.
    """

    type_name: ClassVar[str] = ""
    fields: ClassVar[dict[str, Field]] = {}
    completion: ClassVar[str] = ""
    speed_field: ClassVar[str | None] = "speed"
    departs_from_runway: ClassVar[bool] = False
    conformance: ClassVar[str | None] = None

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        """A problem among the validated field ``values`` that no single field shows, as (field or
        None, what is wrong), or None; ``raw`` is the section as the file gives it."""
        return None

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        """Where a section of this type begins, for the turn anticipation of the fly-by waypoint before it."""
        return None


def section_label(sec: Section) -> str:
    """A section as messages name it: ``section 0 (Rolling 'take-off roll')``."""
    return f"section {sec.index} ({sec.type} '{sec.name}')"


#: The section types by their ``type`` name, in the order of the documentation: the one registry of the
#: declarations, which the mission reader, the report and the documentation read.
REGISTRY: dict[str, type[SectionSpec]] = {}


def register(cls: type[SectionSpec]) -> type[SectionSpec]:
    """Class decorator: register a section type's declaration under its :attr:`~SectionSpec.type_name` (once).

    Raises
    ------
    ValueError
        When the name is empty or taken, or the type's :attr:`~SectionSpec.conformance` is not a kind of
        :data:`CONFORMANCE` or its fields lack those the kind needs.
    """
    if not cls.type_name or cls.type_name in REGISTRY:
        raise ValueError(f"section type {cls.__name__}: type_name {cls.type_name!r} is empty or taken")
    if cls.conformance is not None:
        needs = CONFORMANCE.get(cls.conformance)
        if needs is None:
            raise ValueError(f"section type {cls.__name__}: conformance {cls.conformance!r} is not one of "
                             f"{', '.join(CONFORMANCE)} (or None)")
        if missing := [f for f in needs if f not in cls.fields]:
            raise ValueError(f"section type {cls.__name__}: conformance {cls.conformance!r} needs the field(s) "
                             f"{', '.join(missing)}")
    REGISTRY[cls.type_name] = cls
    return cls


@register
class Rolling(SectionSpec):
    """Rolling section; completes when calibrated airspeed >= ``rotate_cas_m_s``."""

    type_name = "Rolling"
    speed_field = None
    departs_from_runway = True
    completion = "calibrated airspeed >= ``rotate_cas_m_s``"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "runway of the take-off roll"),
        "lever": ("number", False, 1.0, (0.0, 1.0), "thrust lever [-]"),
        "rotate_cas_m_s": ("number", True, None, (20.0, 150.0), "ends at this calibrated airspeed [m/s]"),
    }


@register
class TakeOff(SectionSpec):
    """TakeOff section; completes when height above the runway >= ``until_height_agl_m`` (after lift-off)."""

    type_name = "TakeOff"
    speed_field = "climb_speed"
    departs_from_runway = True
    completion = "height above the runway >= ``until_height_agl_m`` (after lift-off)"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "runway (centre line and elevation)"),
        "lever": ("number", False, 1.0, (0.0, 1.0), "thrust lever [-]"),
        "pitch_deg": ("number", False, 10.0, (2.0, 20.0), "rotation pitch attitude [deg]"),
        "rotation_rate_deg_s": ("number", False, 3.0, (0.5, 10.0), "rotation rate [deg/s]"),
        "climb_speed": ("speed", True, None, None, "initial climb speed"),
        "until_height_agl_m": ("number", False, 300.0, (20.0, 3000.0), "ends at this height above the runway [m]"),
    }


@register
class WaypointFollowing(SectionSpec):
    """WaypointFollowing section; completes when every waypoint passed (fly-over within ``wp_accept_m`` or abeam;
    fly-by at the turn anticipation distance), and a planned hold at the constraint's waypoint flown."""

    type_name = "WaypointFollowing"
    conformance = TARGETS
    completion = ("every waypoint passed (fly-over within ``wp_accept_m`` or abeam; fly-by at the turn anticipation "
                  "distance), and a planned hold at the constraint's waypoint flown")
    fields: ClassVar[dict[str, Field]] = {
        "waypoints": ("waypoints", True, None, None, "names of waypoints, in order"),
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude [m]"),
        "speed": ("speed", True, None, None, "speed"),
        "fly_by": ("bool", False, False, None, "fly-by (true) or fly-over (false) waypoints"),
        "altitude_at": ("waypoint", False, None, None, "the waypoint of the section the altitude is due at "
                        "(default: the last); descents are planned to it, the altitude held after it"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        at = values["altitude_at"]
        if "altitude_at" in raw and at not in values["waypoints"]:
            return "altitude_at", (f"{raw['altitude_at']!r} is not one of the section's waypoints "
                                   f"({', '.join(map(str, raw['waypoints']))})")
        return None

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        return sec["waypoints"][0]


@register
class Orbiting(SectionSpec):
    """Orbiting section; completes when ``turns`` full turns swept around the centre after capture."""

    type_name = "Orbiting"
    conformance = TARGETS
    completion = "``turns`` full turns swept around the centre after capture"
    fields: ClassVar[dict[str, Field]] = {
        "center": ("waypoint", True, None, None, "waypoint at the centre"),
        "radius_m": ("number", True, None, (200.0, 100000.0), "radius [m]"),
        "direction": ("choice", False, "clockwise", ("clockwise", "counterclockwise"), "direction"),
        "turns": ("number", True, None, (0.1, 100.0), "turns after capture [-]"),
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude [m]"),
        "speed": ("speed", True, None, None, "speed"),
    }


@register
class GTurns(SectionSpec):
    """GTurns section; completes when ``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed."""

    type_name = "GTurns"
    conformance = TARGETS
    completion = "``|heading change|`` >= ``heading_change_deg``, or ``duration_s`` elapsed"
    fields: ClassVar[dict[str, Field]] = {
        "load_factor": ("number", True, None, (1.02, 6.0), "load factor of the level turn [g]"),
        "direction": ("choice", False, "right", ("right", "left"), "turn direction"),
        "heading_change_deg": ("number", False, None, (1.0, 3600.0), "ends after this heading change [deg]"),
        "duration_s": ("number", False, None, (1.0, 36000.0), "or after this time [s]"),
        "altitude_m": ("number", False, None, (-400.0, 15000.0), "altitude [m] (default: at entry)"),
        "speed": ("speed", False, None, None, "speed (default: at entry)"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        if ("heading_change_deg" in raw) == ("duration_s" in raw):
            return None, "give exactly one of 'heading_change_deg' or 'duration_s'"
        return None


@register
class Levelling(SectionSpec):
    """Levelling section; completes when ``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``."""

    type_name = "Levelling"
    conformance = TARGETS
    completion = "``|h - altitude_m|`` < ``tolerance_m`` continuously for ``hold_s``"
    fields: ClassVar[dict[str, Field]] = {
        "altitude_m": ("number", True, None, (-400.0, 15000.0), "altitude to capture [m]"),
        "speed": ("speed", True, None, None, "speed"),
        "heading_deg": ("number", False, None, (0.0, 360.0), "true heading to hold [deg] (default: at entry)"),
        "tolerance_m": ("number", False, 10.0, (0.1, 500.0), "altitude band counted as captured [m]"),
        "hold_s": ("number", False, 20.0, (0.0, 3600.0), "time to stay in the band [s]"),
    }


@register
class Landing(SectionSpec):
    """Landing section; completes when stopped on the runway (ground speed < ``v_stop_m_s``)."""

    type_name = "Landing"
    conformance = APPROACH
    speed_field = None
    completion = "stopped on the runway (ground speed < ``v_stop_m_s``)"
    fields: ClassVar[dict[str, Field]] = {
        "runway": ("runway", True, None, None, "landing runway"),
        "approach_altitude_m": ("number", True, None, (0.0, 6000.0), "altitude held until glide slope capture [m]"),
        "approach_speed": ("speed", True, None, None, "final approach speed"),
    }

    @classmethod
    def entry_fix(cls, sec: Section) -> LatLon | None:
        return sec["runway"].threshold  # the turn onto the localizer: towards the threshold along the centre line


@register
class Custom(SectionSpec):
    """Custom section; completes when ``duration_s`` elapsed."""

    type_name = "Custom"
    speed_field = None
    completion = "``duration_s`` elapsed"
    fields: ClassVar[dict[str, Field]] = {
        "duration_s": ("number", True, None, (0.1, 36000.0), "duration [s]"),
        "commands": ("commands", True, None, None, "time points {t_s, lever, pitch_deg, bank_deg}, held between"),
    }

    @classmethod
    def check(cls, values: dict[str, Any], raw: dict[str, Any]) -> tuple[str | None, str] | None:
        if values["commands"][0][0] != 0.0:
            return "commands", "the first command must be at t_s = 0"
        return None
