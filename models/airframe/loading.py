"""The aircraft's loading and start against what can be: fuel within the tank, masses not negative, the
maximum take-off mass, an air start above the ground.

The limits come from the aircraft's file (:mod:`.aircraft`: empty mass, fuel tanks, the wheels and the centre
of gravity; the maximum take-off mass from its ``openemss.json``; default: UPERA). What cannot be
is refused with :class:`.errors.OutOfEnvelopeError` naming the value; a take-off mass above the maximum is
possible but outside the aircraft's certified limits, and is told (:func:`above_mtow`) by whoever reports
on the run (the mission check before it, the summary after it).
"""
from __future__ import annotations

import math

from .aircraft import Aircraft, load_aircraft
from .errors import OutOfEnvelopeError

__all__ = ["check_loading", "check_air_start", "above_mtow", "MASS_ROUNDOFF_KG"]

#: A take-off mass within this of the maximum [kg] is at it: JSBSim holds masses in slugs and pounds.
MASS_ROUNDOFF_KG = 0.1


def check_loading(fuel_kg: float, added_mass_kg: float, names: tuple[str, str] = ("fuel_kg", "added_mass_kg"),
                  engine_fed: bool = False, aircraft: Aircraft | None = None) -> float:
    """Refuse a loading that cannot be: fuel below zero (with `engine_fed`, an aircraft whose engine burns from
    its tank: no fuel at all) or above the tank's capacity, a negative added mass (:class:`OutOfEnvelopeError`,
    naming the values by ``names``); return the take-off mass [kg] (operating empty mass + fuel + added mass),
    which may exceed the maximum take-off mass (:func:`above_mtow`); ``aircraft``: default UPERA."""
    g = aircraft or load_aircraft()
    f, a = float(fuel_kg), float(added_mass_kg)
    tanks = "tank's" if len(g.tanks) == 1 else "tanks'"
    if engine_fed and f == 0.0:
        raise OutOfEnvelopeError(f"{names[0]} = {fuel_kg} kg: no fuel on board for the engine to start on; give "
                                 f"{names[0]} above 0, up to the {tanks} {g.fuel_capacity_kg:g} kg")
    if not 0.0 <= f <= g.fuel_capacity_kg:
        raise OutOfEnvelopeError(f"{names[0]} = {fuel_kg} kg: the fuel on board must be from 0 to the {tanks} "
                                 f"capacity, {g.fuel_capacity_kg:g} kg ({g.source})")
    if not 0.0 <= a <= 10000.0:
        raise OutOfEnvelopeError(f"{names[1]} = {added_mass_kg} kg: the mass added to the operating empty mass "
                                 "must be from 0 to 10000 kg")
    return g.empty_mass_kg + f + a


def check_air_start(alt_m: float, ground_elevation_m: float,
                    names: tuple[str, str] = ("alt_m", "ground_elevation_m"), aircraft: Aircraft | None = None) -> None:
    """Refuse an air start whose centre of gravity is lower above the ground than it stands on its wheels
    (:class:`OutOfEnvelopeError`, naming the values by ``names``): the aircraft would start in the ground."""
    h_cg = (aircraft or load_aircraft()).cg_height_on_wheels_m
    a, e = float(alt_m), float(ground_elevation_m)
    if not (math.isfinite(a) and math.isfinite(e)) or a < e + h_cg:
        raise OutOfEnvelopeError(
            f"air start below the ground: {names[0]} = {alt_m} m with the ground at {names[1]} = {ground_elevation_m}"
            f" m, and the centre of gravity stands {h_cg:.2f} m above the ground on the wheels; give {names[0]} >= "
            f"{e + h_cg:.2f} m, or start on the runway")


def above_mtow(takeoff_mass_kg: float, aircraft: Aircraft | None = None) -> str:
    """One line if a take-off mass [kg] is above the aircraft's maximum take-off mass, else "" (also for an
    aircraft without one); ``aircraft``: default UPERA."""
    g = aircraft or load_aircraft()
    if g.mtom_kg is None:
        return ""
    excess = float(takeoff_mass_kg) - g.mtom_kg
    if not excess > MASS_ROUNDOFF_KG:
        return ""
    return (f"take-off mass {takeoff_mass_kg:.1f} kg is {excess:.1f} kg ({100.0 * excess / g.mtom_kg:.1f} %) above the "
            f"aircraft's maximum take-off mass, {g.mtom_kg:g} kg (empty {g.empty_mass_kg:g} kg, tanks "
            f"{g.fuel_capacity_kg:g} kg: {g.source})")
