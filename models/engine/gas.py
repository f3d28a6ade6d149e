"""Gas properties of dry air and of its lean combustion products with kerosene.

The working fluid of the engine is dry air or the products of complete, lean
combustion of a hydrocarbon fuel CH_y in dry air, described by the fuel-air
ratio FAR [-] (kg of fuel burned per kg of dry air). Per kilogram of air the
products are

    air + FAR/M_f CH_y  ->  air - (1 + y/4) n O2 + n CO2 + (y/2) n H2O,   n = FAR/M_f,

an ideal-gas mixture of N2, O2, Ar, CO2 and H2O whose properties are the
mole-weighted NASA Glenn polynomials of the species (:mod:`.thermo`). No
dissociation is modelled, which limits the model to 2200 K; the lower limit,
200 K, is that of the polynomials.

Conventions
-----------
* ``h`` is the sensible enthalpy [J/kg]: every species' enthalpy is counted
  from 298.15 K, so h(298.15 K, FAR) = 0 at every FAR. The chemical energy of
  the fuel enters only through its lower heating value in the burner balance
  (:func:`.combustion.far_burner`). Mixing streams of different FAR conserves
  this h exactly, because the mixture is linear in the species.
* ``phi`` is the entropy function phi(T) = integral from 298.15 K to T of
  cp/T dT [J/(kg K)]; between two states s2 - s1 = phi2 - phi1 - R ln(p2/p1).
* Every property is written as (X_air(T) + FAR X_fuel(T)) / (1 + FAR), where
  X_air is per kilogram of air and X_fuel the change per kilogram of fuel
  burned; both are precomputed polynomials, so a call costs a few
  microseconds. Arguments are Python floats (scalars).

References
----------
B. J. McBride, M. J. Zehe, S. Gordon, "NASA Glenn Coefficients for Calculating
Thermodynamic Properties of Individual Species", NASA/TP-2002-211556, 2002.
S. Gordon, B. J. McBride, "Computer Program for Calculation of Complex Chemical
Equilibrium Compositions and Applications", NASA RP-1311, 1994 (dry-air
composition of the 'Air' record, after Gordon 1982).
P. P. Walsh, P. Fletcher, "Gas Turbine Performance", 2nd ed., Blackwell, 2004,
chapter 3 (working-fluid properties, burner fuel-air ratio).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from . import jit_kernels as _K
from .errors import ConvergenceError, ModelError, OutOfRangeError
from .thermo import T_REF_K, ThermoData, load_thermo_data

__all__ = [
    "T_MIN_K", "T_MAX_K", "LHV_JET_A_J_KG", "HC_RATIO_JET_A", "FUEL_LIQUID_SPECIES",
    "GasModel", "DEFAULT_GAS",
    "cp", "h", "phi", "gamma", "R", "T_from_h", "T_from_phi", "T_isentropic", "static_from_total",
]

#: Valid temperature range of the mixture model [K].
T_MIN_K: float = 200.0
T_MAX_K: float = 2200.0

#: Default lower heating value of Jet-A [J/kg], liquid fuel at 298.15 K, water
#: as vapour. 43.1 MJ/kg is the customary kerosene value of gas-turbine
#: performance work; ASTM D1655 requires at least 42.8 MJ/kg. The NASA Glenn
#: heats of formation of Jet-A(L) C12H23, CO2 and H2O in the data file give
#: 43.03 MJ/kg (checked in the tests).
LHV_JET_A_J_KG: float = 43.1e6

#: Hydrogen-to-carbon atom ratio y of the fuel CH_y: Jet-A as C12H23 (NASA CEA).
HC_RATIO_JET_A: float = 23.0 / 12.0

_SPECIES: tuple[str, ...] = ("N2", "O2", "Ar", "CO2", "H2O")
#: Species of the data file whose enthalpy stands for the liquid fuel's.
FUEL_LIQUID_SPECIES: str = "Jet-A(L)"
_MAX_ITER: int = _K.MAX_ITER
#: A scratch error flag for the kernels whose inputs were checked here (they cannot set it).
_SCRATCH = np.zeros(1, np.int64)

Coeffs = tuple[float, ...]


def _poly_coeffs(data: ThermoData, moles_per_kg: Mapping[str, float], k: int
                 ) -> tuple[Coeffs, Coeffs, Coeffs]:
    """Mass-specific cp, h and phi coefficients of a species blend in interval k.

    Returns (cp7, h8, phi8) for cp = c0/T^2 + c1/T + c2 + c3 T + ... + c6 T^4,
    h = h0/T + h1 ln T + T (h2 + T (h3 + ...)) + h7 and
    phi = s0/T^2 + s1/T + s2 ln T + T (s3 + T (s4 + ...)) + s7, zero at 298.15 K.
    """
    R_u = data.gas_constant_J_molK
    a = [0.0] * 7
    hb = sb = 0.0
    for name, n in moles_per_kg.items():
        sp = data.species[name]
        iv = sp.intervals[k]
        for j in range(7):
            a[j] += R_u * n * iv.a[j]
        hb += R_u * n * (iv.b[0] - sp.H_R(T_REF_K))
        sb += R_u * n * (iv.b[1] - sp.S_R(T_REF_K))
    cp7 = tuple(a)
    h8 = (-a[0], a[1], a[2], a[3] / 2, a[4] / 3, a[5] / 4, a[6] / 5, hb)
    s8 = (-a[0] / 2, -a[1], a[2], a[3], a[4] / 2, a[5] / 3, a[6] / 4, sb)
    return cp7, h8, s8


def _continuous(lo: tuple[Coeffs, Coeffs, Coeffs], hi: tuple[Coeffs, Coeffs, Coeffs],
                T_mid: float) -> tuple[Coeffs, Coeffs, Coeffs]:
    """Shift the high interval's constants so that h and phi are continuous at T_mid.

    The NASA fits meet at 1000 K only to their printed precision (jumps in H/R of
    the species here are below 5e-5 K, in S/R below 2e-8); without this shift
    the inverses T_from_h and T_from_phi would be ambiguous by about 1e-6 K there.
    """
    cp7, h8, s8 = hi
    h8 = h8[:7] + (h8[7] + _h(lo[1], T_mid) - _h(h8, T_mid),)
    s8 = s8[:7] + (s8[7] + _phi(lo[2], T_mid) - _phi(s8, T_mid),)
    return cp7, h8, s8


def _h(c: Coeffs, T: float) -> float:
    return (c[0] / T + c[1] * math.log(T)
            + T * (c[2] + T * (c[3] + T * (c[4] + T * (c[5] + T * c[6])))) + c[7])


def _phi(c: Coeffs, T: float) -> float:
    i = 1.0 / T
    return (i * (c[0] * i + c[1]) + c[2] * math.log(T)
            + T * (c[3] + T * (c[4] + T * (c[5] + T * c[6]))) + c[7])


@dataclass(frozen=True, slots=True)
class GasModel:
    """Dry air and its lean, complete combustion products with a CH_y fuel.

    Parameters
    ----------
    hc_ratio : float
        Hydrogen-to-carbon atom ratio y of the fuel CH_y [-], 0 < y <= 4;
        default 23/12 (Jet-A as C12H23).
    LHV_J_kg : float
        Lower heating value of the liquid fuel at 298.15 K [J/kg]; default
        :data:`LHV_JET_A_J_KG`.
    data : ThermoData
        Species data; default the bundled NASA Glenn file.

    Attributes
    ----------
    FAR_stoich : float
        Stoichiometric fuel-air ratio [-], the upper limit of FAR.
    molar_mass_air_kg_mol : float
        Molar mass of dry air [kg/mol].

    Notes
    -----
    Methods take scalars: temperatures ``T_K`` [K] in [200, 2200] and fuel-air
    ratios ``FAR`` [-] in [0, FAR_stoich]; outside these they raise
    :class:`~.errors.OutOfRangeError` (a ``ValueError``). The burner energy
    balance, which uses `LHV_J_kg`, is in :mod:`.combustion`.

    References
    ----------
    McBride, Zehe & Gordon, NASA/TP-2002-211556 (2002); Walsh & Fletcher, Gas
    Turbine Performance, 2nd ed. (2004), ch. 3.
    """

    hc_ratio: float = HC_RATIO_JET_A
    LHV_J_kg: float = LHV_JET_A_J_KG
    data: ThermoData = field(default_factory=load_thermo_data, repr=False, compare=False)
    FAR_stoich: float = field(init=False)
    molar_mass_air_kg_mol: float = field(init=False)
    _moles_air: Mapping[str, float] = field(init=False, repr=False, compare=False)
    _moles_fuel: Mapping[str, float] = field(init=False, repr=False, compare=False)
    _T_mid: float = field(init=False, repr=False, compare=False)
    _RA: float = field(init=False, repr=False, compare=False)
    _RB: float = field(init=False, repr=False, compare=False)
    _lo: tuple[Coeffs, ...] = field(init=False, repr=False, compare=False)
    _hi: tuple[Coeffs, ...] = field(init=False, repr=False, compare=False)
    _h_bounds: tuple[float, float, float, float] = field(init=False, repr=False, compare=False)
    _phi_bounds: tuple[float, float, float, float] = field(init=False, repr=False, compare=False)
    _gc: np.ndarray = field(init=False, repr=False, compare=False)
    _gs: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        y, data = self.hc_ratio, self.data
        if not (0.0 < y <= 4.0):
            raise OutOfRangeError(f"GasModel: hc_ratio={y!r} is outside the allowed range (0, 4]")
        if not (self.LHV_J_kg > 0.0):
            raise OutOfRangeError(f"GasModel: LHV_J_kg={self.LHV_J_kg!r} J/kg must be positive")
        sp = data.species
        missing = [s for s in (*_SPECIES, FUEL_LIQUID_SPECIES) if s not in sp]
        if missing:
            raise ModelError(f"GasModel: data file {data.path} lacks species {missing}")
        breaks = {tuple(iv.T_min_K for iv in sp[s].intervals) + (sp[s].T_max_K,) for s in _SPECIES}
        if len(breaks) != 1 or len(next(iter(breaks))) != 3:
            raise ModelError(f"GasModel: species {_SPECIES} in {data.path} must share two "
                             f"intervals with common breakpoints, found {sorted(breaks)}")
        (T_lo, T_mid, T_hi), = breaks
        if T_lo > T_MIN_K or T_hi < T_MAX_K:
            raise ModelError(f"GasModel: data in {data.path} cover {T_lo} K to {T_hi} K, "
                             f"less than the model range {T_MIN_K} K to {T_MAX_K} K")
        M = {s: sp[s].molar_mass_kg_mol for s in _SPECIES}
        x_air = data.air_mole_fractions
        M_air = sum(x * M[s] for s, x in x_air.items())
        moles_air = {s: x / M_air for s, x in x_air.items()}            # mol per kg air
        M_C = M["CO2"] - M["O2"]                                        # element molar masses
        M_H = (M["H2O"] - M["O2"] / 2) / 2                              # consistent with the data
        n_f = 1.0 / (M_C + y * M_H)                                     # mol CH_y per kg fuel
        moles_fuel = {"CO2": n_f, "H2O": y / 2 * n_f, "O2": -(1 + y / 4) * n_f}
        R_u = data.gas_constant_J_molK
        s = object.__setattr__
        s(self, "molar_mass_air_kg_mol", M_air)
        s(self, "FAR_stoich", moles_air["O2"] / ((1 + y / 4) * n_f))
        s(self, "_moles_air", moles_air)
        s(self, "_moles_fuel", moles_fuel)
        s(self, "_T_mid", T_mid)
        s(self, "_RA", R_u * sum(moles_air.values()))
        s(self, "_RB", R_u * sum(moles_fuel.values()))
        lo_a, lo_f = _poly_coeffs(data, moles_air, 0), _poly_coeffs(data, moles_fuel, 0)
        hi_a = _continuous(lo_a, _poly_coeffs(data, moles_air, 1), T_mid)
        hi_f = _continuous(lo_f, _poly_coeffs(data, moles_fuel, 1), T_mid)
        # per interval: (cp_air, cp_fuel, h_air, h_fuel, phi_air, phi_fuel)
        s(self, "_lo", (lo_a[0], lo_f[0], lo_a[1], lo_f[1], lo_a[2], lo_f[2]))
        s(self, "_hi", (hi_a[0], hi_f[0], hi_a[1], hi_f[1], hi_a[2], hi_f[2]))
        s(self, "_h_bounds", (_h(lo_a[1], T_MIN_K), _h(lo_f[1], T_MIN_K),
                              _h(hi_a[1], T_MAX_K), _h(hi_f[1], T_MAX_K)))
        s(self, "_phi_bounds", (_phi(lo_a[2], T_MIN_K), _phi(lo_f[2], T_MIN_K),
                                _phi(hi_a[2], T_MAX_K), _phi(hi_f[2], T_MAX_K)))
        gc = np.zeros((2, 6, 8))                 # the layout of jit_kernels (its module docstring)
        for k, iv in enumerate((self._lo, self._hi)):
            for j, c in enumerate(iv):
                gc[k, j, :len(c)] = c
        gs = np.array([T_mid, self.FAR_stoich, *self._h_bounds, *self._phi_bounds, self._RA, self._RB,
                       self.LHV_J_kg])
        s(self, "_gc", gc)
        s(self, "_gs", gs)

    # ------------------------------------------------------------------ checks
    def _T_error(self, where: str, T_K: float) -> OutOfRangeError:
        return OutOfRangeError(
            f"gas.{where}: T_K={T_K!r} K is outside the valid range {T_MIN_K} K to {T_MAX_K} K "
            f"(NASA Glenn polynomials; complete combustion without dissociation)")

    def _far_error(self, where: str, FAR: float) -> OutOfRangeError:
        return OutOfRangeError(
            f"gas.{where}: FAR={FAR!r} is outside the valid range 0 to {self.FAR_stoich:.6f} "
            f"(lean complete combustion of CH{self.hc_ratio:.4g} in dry air)")

    # -------------------------------------------------------------- properties
    # The formulas are written once, in jit_kernels (compiled by numba, or plain Python without it); the
    # methods here check the arguments, raise with the full message and call them.
    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The coefficient arrays of the compiled gas functions, (gc, gs) as :mod:`.jit_kernels` lays them out
        (gs without the liquid fuel's enthalpy, which a burner appends). Shared: not to be changed (left writeable
        so that numba compiles one signature for them and for the arrays derived from them)."""
        return self._gc, self._gs

    def R(self, FAR: float = 0.0) -> float:
        """Specific gas constant R [J/(kg K)] of the mixture at `FAR` [-]."""
        if FAR == 0.0:
            return self._RA
        if not (0.0 <= FAR <= self.FAR_stoich):
            raise self._far_error("R", FAR)
        return float(_K.R(self._gs, FAR))

    def _checked(self, where: str, T_K: float, FAR: float) -> None:
        if not (T_MIN_K <= T_K <= T_MAX_K):
            raise self._T_error(where, T_K)
        if not (0.0 <= FAR <= self.FAR_stoich):
            raise self._far_error(where, FAR)

    def cp(self, T_K: float, FAR: float = 0.0) -> float:
        """Isobaric specific heat capacity cp [J/(kg K)] at `T_K` [K] and `FAR` [-]."""
        self._checked("cp", T_K, FAR)
        return float(_K.cp(self._gc, self._gs, T_K, FAR, _SCRATCH))

    def h(self, T_K: float, FAR: float = 0.0) -> float:
        """Sensible specific enthalpy h [J/kg], zero at 298.15 K, at `T_K` [K] and `FAR` [-]."""
        self._checked("h", T_K, FAR)
        return float(_K.h(self._gc, self._gs, T_K, FAR, _SCRATCH))

    def phi(self, T_K: float, FAR: float = 0.0) -> float:
        """Entropy function phi = int_{298.15 K}^{T} cp/T dT [J/(kg K)] at `T_K` [K], `FAR` [-]."""
        self._checked("phi", T_K, FAR)
        return float(_K.phi(self._gc, self._gs, T_K, FAR, _SCRATCH))

    def gamma(self, T_K: float, FAR: float = 0.0) -> float:
        """Ratio of specific heats cp/cv [-] at `T_K` [K] and `FAR` [-]."""
        c = self.cp(T_K, FAR)
        return c / (c - self.R(FAR))

    def molar_mass(self, FAR: float = 0.0) -> float:
        """Molar mass of the mixture [kg/mol] at `FAR` [-]."""
        return self.data.gas_constant_J_molK / self.R(FAR)

    def mole_numbers(self, FAR: float = 0.0) -> dict[str, float]:
        """Moles of each species per kilogram of mixture [mol/kg] at `FAR` [-]."""
        if not (0.0 <= FAR <= self.FAR_stoich):
            raise self._far_error("mole_numbers", FAR)
        fa, ff = self._moles_air, self._moles_fuel
        return {s: (fa.get(s, 0.0) + FAR * ff.get(s, 0.0)) / (1.0 + FAR) for s in _SPECIES}

    def mass_fractions(self, FAR: float = 0.0) -> dict[str, float]:
        """Mass fraction of each species [-] at `FAR` [-]; they sum to 1."""
        sp = self.data.species
        return {s: n * sp[s].molar_mass_kg_mol for s, n in self.mole_numbers(FAR).items()}

    # ---------------------------------------------------------------- inverses
    def T_from_h(self, h_J_kg: float, FAR: float = 0.0, T_guess_K: float | None = None) -> float:
        """Temperature [K] at which the sensible enthalpy equals `h_J_kg` [J/kg].

        Newton iteration on h(T) - h_J_kg with slope cp, from `T_guess_K` [K]
        if given and in range (warm start), else from 298.15 K + h/(1100 J/(kg K)); it stops
        when a step is below 1e-5 K (error then < 1e-13 K).

        Raises
        ------
        OutOfRangeError
            If `h_J_kg` lies outside [h(200 K), h(2200 K)] or `FAR` is out of range.
        ConvergenceError
            If 30 iterations do not converge (not expected for valid inputs).
        """
        f = FAR
        if f != 0.0 and not (0.0 <= f <= self.FAR_stoich):
            raise self._far_error("T_from_h", f)
        inv = 1.0 / (1.0 + f)
        ha_min, hf_min, ha_max, hf_max = self._h_bounds
        h_min, h_max = (ha_min + f * hf_min) * inv, (ha_max + f * hf_max) * inv
        slack = 1e-12 * (h_max - h_min)       # rounding at the ends; T is clamped in the iteration
        if not (h_min - slack <= h_J_kg <= h_max + slack):
            raise OutOfRangeError(
                f"gas.T_from_h: h_J_kg={h_J_kg!r} J/kg at FAR={f!r} is outside the valid range "
                f"{h_min:.1f} J/kg to {h_max:.1f} J/kg (the enthalpies at {T_MIN_K} K and {T_MAX_K} K)")
        err = np.zeros(1, np.int64)
        T = float(_K.T_from_h(self._gc, self._gs, h_J_kg, f, math.nan if T_guess_K is None else T_guess_K, err))
        if err[0]:
            raise ConvergenceError(f"gas.T_from_h: no convergence in {_MAX_ITER} Newton steps for "
                                   f"h_J_kg={h_J_kg!r} J/kg, FAR={f!r}")
        return T

    def T_from_phi(self, phi_J_kgK: float, FAR: float = 0.0, T_guess_K: float | None = None) -> float:
        """Temperature [K] at which the entropy function equals `phi_J_kgK` [J/(kg K)].

        Newton iteration in ln T (dphi/dlnT = cp): T <- T exp(-(phi(T) - phi)/cp),
        from `T_guess_K` [K] if given; stops when a step is below 1e-5 K.

        Raises
        ------
        OutOfRangeError
            If `phi_J_kgK` lies outside [phi(200 K), phi(2200 K)] or `FAR` is out of range.
        ConvergenceError
            If 30 iterations do not converge.
        """
        f = FAR
        if f != 0.0 and not (0.0 <= f <= self.FAR_stoich):
            raise self._far_error("T_from_phi", f)
        inv = 1.0 / (1.0 + f)
        pa_min, pf_min, pa_max, pf_max = self._phi_bounds
        p_min, p_max = (pa_min + f * pf_min) * inv, (pa_max + f * pf_max) * inv
        slack = 1e-12 * (p_max - p_min)
        if not (p_min - slack <= phi_J_kgK <= p_max + slack):
            raise OutOfRangeError(
                f"gas.T_from_phi: phi_J_kgK={phi_J_kgK!r} J/(kg K) at FAR={f!r} is outside the valid "
                f"range {p_min:.3f} to {p_max:.3f} J/(kg K) (phi at {T_MIN_K} K and {T_MAX_K} K)")
        err = np.zeros(1, np.int64)
        T = float(_K.T_from_phi(self._gc, self._gs, phi_J_kgK, f, math.nan if T_guess_K is None else T_guess_K,
                                err))
        if err[0]:
            raise ConvergenceError(f"gas.T_from_phi: no convergence in {_MAX_ITER} Newton steps for "
                                   f"phi_J_kgK={phi_J_kgK!r}, FAR={f!r}")
        return T

    def T_isentropic(self, T1_K: float, pressure_ratio: float, FAR: float = 0.0,
                     T_guess_K: float | None = None) -> float:
        """Temperature [K] after an isentropic change of pressure by `pressure_ratio` = p2/p1 [-].

        Solves phi(T2) = phi(T1) + R ln(p2/p1) at constant composition.
        """
        if not (pressure_ratio > 0.0):
            raise OutOfRangeError(f"gas.T_isentropic: pressure_ratio={pressure_ratio!r} must be > 0")
        phi2 = self.phi(T1_K, FAR) + self.R(FAR) * math.log(pressure_ratio)
        return self.T_from_phi(phi2, FAR, T_guess_K)

    def static_from_total(self, Tt_K: float, Mach: float, FAR: float = 0.0) -> tuple[float, float]:
        """Static temperature [K] and static-to-total pressure ratio p/pt [-] at a Mach number.

        Solves h(Tt) = h(T) + V^2/2 with V = Mach sqrt(gamma(T) R T) (adiabatic,
        real cp), then p/pt = exp((phi(T) - phi(Tt))/R) (isentropic). Iterates
        with slope cp + Mach^2 gamma R / 2 (dgamma/dT neglected in the slope
        only), to a step below 1e-7 K.

        Raises
        ------
        OutOfRangeError
            If `Mach` < 0, or Tt or the static temperature leave 200 K to 2200 K.
        """
        if not (Mach >= 0.0):
            raise OutOfRangeError(f"gas.static_from_total: Mach={Mach!r} must be >= 0")
        self._checked("static_from_total", Tt_K, FAR)
        err = np.zeros(1, np.int64)
        T, p_pt = _K.static_from_total(self._gc, self._gs, Tt_K, Mach, FAR, err)
        if err[0]:
            raise OutOfRangeError(f"gas.static_from_total: at Tt_K={Tt_K!r} K, Mach={Mach!r}, FAR={FAR!r} the static "
                                  f"temperature leaves the valid range {T_MIN_K} K to {T_MAX_K} K (or does not "
                                  f"converge in {_MAX_ITER} steps)")
        return float(T), float(p_pt)

    # --------------------------------------------------------------- burner
    def h_parts(self, T_K: float) -> tuple[float, float]:
        """Enthalpy split (h_air, h_fuel) [J/kg] at `T_K` [K], sensible, zero at 298.15 K.

        h_air is per kilogram of dry air and h_fuel the change per kilogram of
        fuel burned, so that (1 + FAR) h(T, FAR) = h_air + FAR h_fuel. Used by
        the burner energy balance (:mod:`.combustion`).
        """
        if not (T_MIN_K <= T_K <= T_MAX_K):
            raise self._T_error("h_parts", T_K)
        ha, hf = _K.h_parts(self._gc, self._gs, T_K, _SCRATCH)
        return float(ha), float(hf)


#: The default gas: Jet-A (C12H23) products in dry air, LHV 43.1 MJ/kg.
DEFAULT_GAS: GasModel = GasModel()

# Module-level shortcuts to the default gas (bound methods, same signatures).
cp = DEFAULT_GAS.cp
h = DEFAULT_GAS.h
phi = DEFAULT_GAS.phi
gamma = DEFAULT_GAS.gamma
R = DEFAULT_GAS.R
T_from_h = DEFAULT_GAS.T_from_h
T_from_phi = DEFAULT_GAS.T_from_phi
T_isentropic = DEFAULT_GAS.T_isentropic
static_from_total = DEFAULT_GAS.static_from_total
