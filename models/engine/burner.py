"""Burner (combustor): pressure loss, combustion efficiency, fuel from the energy balance.

Per kilogram of dry air (:mod:`.combustion`):

    (1 + f3) h(Tt3, f3) + (f4 - f3) (eta_b LHV + h_fl(T_fuel)) = (1 + f4) h(Tt4, f4),
    Pt4 = Pt3 (1 - dPqP),   Wf = W_air (f4 - f3),   W4 = W3 + Wf.

Energy book: W3 ht3 + Wf (LHV + h_fl) = W4 ht4 + (1 - eta_b) Wf LHV, the last
term the chemical energy left unreleased.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., 2004, sec. 5.11
(combustor pressure loss, efficiency, fuel-air ratio).
"""

from __future__ import annotations

from dataclasses import dataclass

from .combustion import T_burner_exit, far_burner, h_fuel_liquid
from .errors import OutOfRangeError
from .flow import FlowStation
from .gas import DEFAULT_GAS, GasModel
from .thermo import T_REF_K

__all__ = ["BurnerResult", "burner_to_temperature", "burner_with_fuel"]


@dataclass(frozen=True, slots=True)
class BurnerResult:
    """Result of a burner calculation.

    Attributes
    ----------
    out : FlowStation
        Burner exit, station 4.
    Wf_kg_s : float
        Fuel flow [kg/s].
    heat_released_W : float
        eta_b Wf LHV + Wf h_fl(T_fuel) [W]: energy added to the gas.
    heat_unreleased_W : float
        (1 - eta_b) Wf LHV [W].
    """

    out: FlowStation
    Wf_kg_s: float
    heat_released_W: float
    heat_unreleased_W: float


def _check(dPqP: float) -> None:
    if not (0.0 <= dPqP < 1.0):
        raise OutOfRangeError(f"burner: dPqP={dPqP!r} is outside the valid range [0, 1)")


def _result(fs3: FlowStation, f4: float, Tt4: float, eta_b: float, dPqP: float, T_fuel_K: float,
            gas: GasModel) -> BurnerResult:
    Wf = fs3.W_air_kg_s * (f4 - fs3.FAR)
    out = FlowStation(fs3.W_kg_s + Wf, Tt4, fs3.Pt_Pa * (1.0 - dPqP), f4, gas.h(Tt4, f4))
    hfl = h_fuel_liquid(T_fuel_K, gas)
    return BurnerResult(out, Wf, Wf * (eta_b * gas.LHV_J_kg + hfl), Wf * (1.0 - eta_b) * gas.LHV_J_kg)


def burner_to_temperature(fs3: FlowStation, Tt4_K: float, eta_b: float = 1.0, dPqP: float = 0.0,
                          T_fuel_K: float = T_REF_K, gas: GasModel = DEFAULT_GAS) -> BurnerResult:
    """Burner that heats `fs3` to `Tt4_K` [K]; the fuel flow follows from the energy balance.

    Parameters
    ----------
    fs3 : FlowStation
        Burner inlet (station 31).
    Tt4_K : float
        Burner exit total temperature [K], above Tt3.
    eta_b : float
        Combustion efficiency [-], (0, 1].
    dPqP : float
        Relative total-pressure loss [-], [0, 1).
    T_fuel_K : float
        Liquid fuel temperature [K].
    gas : GasModel
        Gas model (fuel H/C ratio and LHV).
    """
    _check(dPqP)
    f4 = far_burner(fs3.Tt_K, Tt4_K, eta_b, fs3.FAR, T_fuel_K, gas)
    return _result(fs3, f4, Tt4_K, eta_b, dPqP, T_fuel_K, gas)


def burner_with_fuel(fs3: FlowStation, Wf_kg_s: float, eta_b: float = 1.0, dPqP: float = 0.0,
                     T_fuel_K: float = T_REF_K, gas: GasModel = DEFAULT_GAS,
                     T_guess_K: float | None = None) -> BurnerResult:
    """Burner with a given fuel flow `Wf_kg_s` [kg/s] >= 0; Tt4 from the energy balance."""
    _check(dPqP)
    if not (Wf_kg_s >= 0.0):
        raise OutOfRangeError(f"burner: Wf_kg_s={Wf_kg_s!r} must be >= 0")
    f4 = fs3.FAR + Wf_kg_s / fs3.W_air_kg_s
    Tt4 = T_burner_exit(fs3.Tt_K, f4, eta_b, fs3.FAR, T_fuel_K, gas, T_guess_K) if Wf_kg_s > 0 else fs3.Tt_K
    return _result(fs3, f4, Tt4, eta_b, dPqP, T_fuel_K, gas)
