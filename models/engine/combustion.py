"""Burner energy balance: fuel-air ratio for a given exit temperature, and back.

The balance is written per kilogram of dry air with the sensible enthalpies
of :mod:`.gas` (zero at 298.15 K for every species) and the fuel's lower
heating value LHV, defined for liquid fuel at 298.15 K burning completely to
CO2 and water vapour:

    (1 + f3) h(Tt3, f3) + (f4 - f3) (eta_b LHV + h_fl(T_fuel)) = (1 + f4) h(Tt4, f4),

where f3 and f4 are the fuel-air ratios entering and leaving, eta_b the
combustion efficiency (the fraction of LHV released) and h_fl the sensible
enthalpy of the liquid fuel. Because (1 + f) h(T, f) = h_air(T) + f h_fuel(T)
(:meth:`.gas.GasModel.h_parts`), the balance is linear in f4 and needs no
iteration for the fuel-air ratio.

References
----------
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., Blackwell, 2004,
chapter 3 (fuel-air ratio from the enthalpy balance with LHV).
B. J. McBride, M. J. Zehe, S. Gordon, NASA/TP-2002-211556, 2002 (Jet-A(L) enthalpy).
"""

from __future__ import annotations

import math

import numpy as np

from . import jit_kernels as K
from .errors import OutOfRangeError
from .gas import DEFAULT_GAS, FUEL_LIQUID_SPECIES, GasModel
from .jit_kernels import jit
from .thermo import T_REF_K

__all__ = ["h_fuel_liquid", "far_burner", "T_burner_exit", "burner_exit_T", "burner_far"]


@jit
def burner_far(gc: np.ndarray, gs: np.ndarray, Tt3_K: float, FAR_in: float, Tt4_K: float, eta_b: float,
               h_fuel_J_kg: float, err: np.ndarray) -> float:
    """Burner exit fuel-air ratio [-] that heats the flow from Tt3 to Tt4 [K] (the closed form of
    :func:`far_burner`; h_fuel_J_kg the liquid fuel's enthalpy, gs[12] the LHV): the one implementation, called
    by :func:`far_burner` and the design mode of the gas path (:mod:`.gas_path`); ``err[0]`` set where the gas
    tables end."""
    ha3, hf3 = K.h_parts(gc, gs, Tt3_K, err)
    ha4, hf4 = K.h_parts(gc, gs, Tt4_K, err)
    return FAR_in + (ha4 - ha3 + FAR_in * (hf4 - hf3)) / (eta_b * gs[12] + h_fuel_J_kg - hf4)


@jit
def burner_exit_T(gc: np.ndarray, gs: np.ndarray, Tt3_K: float, FAR_in: float, FAR_out: float, eta_b: float,
                  h_fuel_J_kg: float, T_guess_K: float, err: np.ndarray) -> float:
    """Burner exit total temperature [K] from the energy balance of :func:`T_burner_exit` (h_fuel_J_kg: the
    liquid fuel's enthalpy, :func:`h_fuel_liquid`; gs[12] the LHV): the one implementation, compiled
    (:mod:`.gas_path`) and called by :func:`T_burner_exit`; ``err[0]`` set where the gas tables end."""
    ha3, hf3 = K.h_parts(gc, gs, Tt3_K, err)
    q = (FAR_out - FAR_in) * (eta_b * gs[12] + h_fuel_J_kg)
    return K.T_from_h(gc, gs, (ha3 + FAR_in * hf3 + q) / (1.0 + FAR_out), FAR_out, T_guess_K, err)


def h_fuel_liquid(T_fuel_K: float, gas: GasModel = DEFAULT_GAS) -> float:
    """Sensible enthalpy of the liquid fuel [J/kg] relative to 298.15 K.

    Parameters
    ----------
    T_fuel_K : float
        Fuel temperature [K], 220 K to 550 K (the range of the Jet-A(L) polynomial).
    gas : GasModel
        Supplies the species data.

    Notes
    -----
    Uses the NASA Glenn polynomial of Jet-A(L) (C12H23) per kilogram whatever
    the model's H/C ratio.
    """
    if T_fuel_K == T_REF_K:
        return 0.0
    sp = gas.data.species[FUEL_LIQUID_SPECIES]
    R_J_kgK = gas.data.gas_constant_J_molK / sp.molar_mass_kg_mol
    return R_J_kgK * (sp.H_R(T_fuel_K) - sp.H_R(T_REF_K))


def _check(where: str, gas: GasModel, eta_b: float, FAR_in: float) -> None:
    if not (0.0 < eta_b <= 1.0):
        raise OutOfRangeError(f"combustion.{where}: eta_b={eta_b!r} is outside the valid range (0, 1]")
    if not (0.0 <= FAR_in <= gas.FAR_stoich):
        raise OutOfRangeError(f"combustion.{where}: FAR_in={FAR_in!r} is outside the valid range "
                              f"0 to {gas.FAR_stoich:.6f}")


def far_burner(Tt3_K: float, Tt4_K: float, eta_b: float = 1.0, FAR_in: float = 0.0,
               T_fuel_K: float = T_REF_K, gas: GasModel = DEFAULT_GAS) -> float:
    """Burner exit fuel-air ratio [-] that heats the flow from `Tt3_K` to `Tt4_K` [K].

    Solves the balance of the module docstring in closed form:

        f4 - f3 = [h_air(Tt4) - h_air(Tt3) + f3 (h_fuel(Tt4) - h_fuel(Tt3))]
                  / [eta_b LHV + h_fl(T_fuel) - h_fuel(Tt4)].

    Parameters
    ----------
    Tt3_K, Tt4_K : float
        Burner inlet and exit total temperatures [K], 200 K to 2200 K, Tt4_K > Tt3_K.
    eta_b : float
        Combustion efficiency [-], the fraction of LHV released, in (0, 1].
    FAR_in : float
        Fuel-air ratio of the entering gas [-]; 0 for air.
    T_fuel_K : float
        Liquid fuel temperature [K], 220 K to 550 K; default 298.15 K.
    gas : GasModel
        Gas model (fuel H/C ratio and LHV); default Jet-A, 43.1 MJ/kg.

    Returns
    -------
    float
        Exit fuel-air ratio f4 [-]: total fuel burned per kilogram of dry air.

    Raises
    ------
    OutOfRangeError
        If an input is out of range, Tt4_K <= Tt3_K, or f4 would exceed the
        stoichiometric fuel-air ratio (the model is lean only).
    """
    _check("far_burner", gas, eta_b, FAR_in)
    if not (Tt4_K > Tt3_K):
        raise OutOfRangeError(f"combustion.far_burner: Tt4_K={Tt4_K!r} K must exceed Tt3_K={Tt3_K!r} K")
    gas.h_parts(Tt3_K)                               # raise with their messages if a temperature is out of range
    gas.h_parts(Tt4_K)
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    far4 = float(burner_far(gc, gs, Tt3_K, FAR_in, Tt4_K, eta_b, h_fuel_liquid(T_fuel_K, gas), err))
    if far4 > gas.FAR_stoich:
        raise OutOfRangeError(
            f"combustion.far_burner: reaching Tt4_K={Tt4_K!r} K from Tt3_K={Tt3_K!r} K needs "
            f"FAR={far4:.6f}, beyond the stoichiometric {gas.FAR_stoich:.6f} (lean model only)")
    return far4


def T_burner_exit(Tt3_K: float, FAR_out: float, eta_b: float = 1.0, FAR_in: float = 0.0,
                  T_fuel_K: float = T_REF_K, gas: GasModel = DEFAULT_GAS,
                  T_guess_K: float | None = None) -> float:
    """Burner exit total temperature [K] for an exit fuel-air ratio `FAR_out` [-].

    The balance of :func:`far_burner` solved for Tt4 (used when fuel flow is
    the input, as in the transient engine):

        h(Tt4, f4) = [h_air(Tt3) + f3 h_fuel(Tt3) + (f4 - f3)(eta_b LHV + h_fl(T_fuel))] / (1 + f4).

    Parameters are those of :func:`far_burner`; `T_guess_K` [K] warm-starts
    the Newton inversion of h.

    Raises
    ------
    OutOfRangeError
        If an input is out of range, FAR_out < FAR_in, or the exit enthalpy
        lies beyond that of 2200 K.
    """
    _check("T_burner_exit", gas, eta_b, FAR_in)
    if not (FAR_in <= FAR_out <= gas.FAR_stoich):
        raise OutOfRangeError(
            f"combustion.T_burner_exit: FAR_out={FAR_out!r} is outside the valid range "
            f"FAR_in={FAR_in!r} to {gas.FAR_stoich:.6f}")
    gas.h_parts(Tt3_K)                               # raises with its message if Tt3 is out of range
    err = np.zeros(1, np.int64)
    gc, gs = gas.kernel_arrays()
    T4 = float(burner_exit_T(gc, gs, Tt3_K, FAR_in, FAR_out, eta_b, h_fuel_liquid(T_fuel_K, gas),
                             math.nan if T_guess_K is None else T_guess_K, err))
    if err[0]:
        raise OutOfRangeError(f"combustion.T_burner_exit: the exit enthalpy at Tt3={Tt3_K!r} K, FAR_out={FAR_out!r}, "
                              f"eta_b={eta_b!r} lies beyond the gas tables ({K.T_MIN} K to {K.T_MAX} K)")
    return T4
