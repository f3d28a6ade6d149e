"""The fuel the tanks can deliver to the engine over a step: fuel starvation and its flame-out.

The tank is the airframe's. The engine reads what it holds (its input ``fuel_kg``, the airframe's
output of the same name) and burns over a step no more than the tank can deliver: when the fuel its
fuel system meters for the step (the command raised to the minimum-flow stops, held to the
deceleration limit: :meth:`.engine_model.EngineModel.metered_fuel_kg_s`) is more than that, the
burner is starved and flames out (:meth:`.engine_model.EngineModel.flame_out`): it burns nothing
more, and the engine cannot be stepped on (there is no windmilling model).

In a co-simulation the tank's content lags the engine's burn: under a Jacobi master the airframe
takes the fuel flow the engine published at the start of a step off the tank during that step, so
that flow times the step is still owed to the tank when the engine reads it. What the engine may
burn over a step (:meth:`FuelSupply.available_kg`) is the lesser of

* the tank's content less that owed fuel, and
* the tank's content when the engine first read it less all the engine has burned since, so that no
  master's lag, however long, lets it burn more than the tank held.

Under a Jacobi master the first is exactly what the tank will hold after the owed fuel is taken off,
so the engine flames out with less than one step's metered fuel left in the tank and the tank never
runs below zero; under a Gauss-Seidel master that steps the airframe after the engine the tank owes
nothing and the first is one step conservative. Either way the fuel the engine burned is fuel that
left the tank.

A reading of 0 kg before any positive one is taken as a tank not fed yet, not as an empty one: FMPy's SSP
runner starts every input at 0 and feeds the connections from its second step on (the airframe refuses to
start without fuel, so a run of ours never starts on an empty tank). A host that connects no tank leaves
``fuel_kg`` at its start value, :data:`.engine_signals.FUEL_UNLIMITED_KG`: the
engine is then not limited (it neither starves nor is fed by a tank it does not know).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .engine_signals import EO

if TYPE_CHECKING:
    from .engine_model import EngineModel

__all__ = ["FuelSupply"]

@dataclass
class FuelSupply:
    """What the tanks can deliver to one engine, from their content as the engine reads it.

    Attributes
    ----------
    ref_kg : float or None
        The tank's content when the engine first read it plus what the engine had burned then [kg]
        (None before the first reading).
    """

    ref_kg: float | None = None

    def available_kg(self, tank_kg: float, burned_kg: float, owed_kg: float) -> float:
        """The fuel [kg] the engine may burn over the coming step.

        Parameters
        ----------
        tank_kg : float
            The tanks' content as the engine reads it [kg].
        burned_kg : float
            The fuel the engine has burned since its start [kg].
        owed_kg : float
            The fuel the engine last published as burning over a step, times the coming step [kg]: what
            a lagging tank may still owe (see the module).

        Returns
        -------
        float
            The lesser of ``tank_kg - owed_kg`` and the first reading's content less what was burned
            since [kg]; may be negative (nothing can be delivered). NaN reads as nothing; a first reading
            of 0 or less as a tank not fed yet (infinite).
        """
        if self.ref_kg is None:
            if tank_kg <= 0.0:  # not fed yet: a host that starts every input at 0 (see the module)
                return math.inf
            self.ref_kg = tank_kg + burned_kg
        a = tank_kg - owed_kg
        b = self.ref_kg - burned_kg
        a = a if a < b else b
        return a if not math.isnan(a) else -math.inf

    def starves(self, model: EngineModel, tank_kg: float, Wf_cmd_kg_s: float, dt_s: float) -> bool:
        """Whether the tanks cannot deliver the fuel the engine's fuel system meters over the coming step of
        `dt_s` [s] for the command `Wf_cmd_kg_s` [kg/s]; if so the engine flames out in that step
        (:meth:`.engine_model.EngineModel.flame_out`, with the figures in its message).

        Parameters
        ----------
        model : EngineModel
            The started engine; its last published fuel flow is what the tank may still owe.
        tank_kg : float
            The tanks' content as the engine reads it [kg].
        """
        avail = self.available_kg(tank_kg, model.fuel_burned_kg, model.values[EO.Wf_kg_s] * dt_s)
        metered = model.metered_fuel_kg_s(Wf_cmd_kg_s, dt_s)
        if metered * dt_s <= avail:
            return False
        model.flame_out(dt_s, f"fuel tank empty: the tanks hold {tank_kg:.6g} kg, of which {max(avail, 0.0):.6g} kg "
                              f"can be delivered over the step, less than the {metered * dt_s:.6g} kg the fuel system "
                              f"meters ({metered:.6g} kg/s for {dt_s:g} s)")
        return True
