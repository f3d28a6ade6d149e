"""Design parameters of the turbojet and the turbofan, and their parameter files.

A parameter file is JSON: an object with ``"engine": "turbofan"`` or
``"turbojet"``, the design parameters below by name (SI units, names carry
the unit), an optional ``"bleeds"`` list of bleed objects (:class:`.bleed.BleedSpec`
fields) and free-text ``"sources"`` / ``"notes"`` entries that document where
each number comes from. Unknown keys are an error (a misspelt parameter must
not silently fall back to its default). Presets live in ``presets/``.

Every value is checked where it enters, by one function (:func:`_checked`) that both the file reader
and the dataclasses use: its type (a number, not text, a Boolean or null; an integer where one is
meant), finiteness and range; a file's error names its line.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from ..common.atmosphere import ALT_MAX_M, ALT_MIN_M
from ..infra import safe_yaml, values
from .bleed import SINKS, BleedSpec
from .errors import ModelError, OutOfRangeError
from .gas import HC_RATIO_JET_A, LHV_JET_A_J_KG
from .thermo import T_REF_K

__all__ = ["PRESETS_DIR", "TurbojetParams", "TurbofanParams", "EngineParams", "load_params",
           "preset_path", "params_from_dict"]

#: Folder of the shipped parameter files.
PRESETS_DIR: Path = Path(__file__).resolve().parent / "presets"
_DOC_KEYS = ("engine", "sources", "notes", "name")
NOZZLE_TYPES = ("convergent", "ideal")
#: Integer parameters and their ranges.
_INT_RANGES: dict[str, tuple[int, int]] = {"hpc_stages": (1, 30), "handling_bleed_stage": (1, 30)}


@dataclass(frozen=True)
class _Common:
    """Parameters shared by both engines (see the engine classes for the meaning)."""

    name: str = "engine"
    alt_m: float = 0.0
    Mach: float = 0.0
    dT_isa_K: float = 0.0
    W2_kg_s: float | None = None
    Fn_target_N: float | None = None
    inlet_pi: float = 1.0
    Tt4_K: float = 1400.0
    eta_burner: float = 1.0
    dPqP_burner: float = 0.0
    T_fuel_K: float = T_REF_K
    LHV_J_kg: float = LHV_JET_A_J_KG
    hc_ratio: float = HC_RATIO_JET_A
    nozzle_type: str = "convergent"
    bleeds: tuple[BleedSpec, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        for f in fields(self):
            try:
                _checked(f.name, str(f.type), getattr(self, f.name))
            except ValueError as exc:
                raise OutOfRangeError(f"{self.name}: {f.name}: {exc}") from None
        if (self.W2_kg_s is None) == (self.Fn_target_N is None):
            raise OutOfRangeError(f"{self.name}: give exactly one of W2_kg_s and Fn_target_N")
        if isinstance(self, TurbofanParams) and not (1 <= self.handling_bleed_stage <= self.hpc_stages):
            raise OutOfRangeError(f"{self.name}: handling_bleed_stage={self.handling_bleed_stage!r} must lie in "
                                  f"1..hpc_stages={self.hpc_stages}")


def _checked(name: str, kind: str, v: Any) -> Any:
    """The value ``v`` of parameter ``name`` (of the dataclass field type ``kind``), checked: its type, its
    finiteness, its range (:func:`_rule`); an integer given for a float as a float.

    Raises
    ------
    ValueError
        What is wrong and what is allowed (the caller names the parameter and the file).
    """
    if kind == "str":
        return values.choice(v, NOZZLE_TYPES) if name == "nozzle_type" else values.text(v, "a name (text)")
    if kind == "int":
        return values.integer(v, *_INT_RANGES.get(name, (0, 10**9)))
    if kind.startswith("tuple"):  # the bleeds: BleedSpec checks its own
        return v
    if v is None and "None" in kind:
        return None
    x = values.number(v)
    rule = _rule(name)
    if rule is not None and not rule[0](x):
        raise ValueError(f"{x!r} is outside the valid range {rule[1]}")
    return x


def _rule(name: str) -> tuple[Any, str] | None:
    """Validity rule (predicate, description) of a parameter, from its name."""
    if name.startswith("eta_") or name in ("inlet_pi", "Cv", "Cd") or name.startswith(("Cv_", "Cd_")):
        return (lambda v: 0.0 < v <= 1.0), "(0, 1]"
    if name.startswith("PR_"):
        return (lambda v: 1.0 <= v <= 100.0), "[1, 100]"
    if name.startswith("dPqP") or name.endswith("_frac"):
        return (lambda v: 0.0 <= v < 1.0), "[0, 1)"
    if name.startswith("offtake"):                 # signed: + taken from the spool, - a motor's assist
        return (lambda v: abs(v) <= 1e9), "[-1e9, 1e9] W, + taken from the spool, - delivered to it"
    if name == "BPR":
        return (lambda v: 0.0 <= v <= 100.0), "[0, 100]"
    if name.endswith("_kg_m2"):
        return (lambda v: 0.0 <= v <= 1e6), "[0, 1e6] kg m^2"
    if name == "Tt4_K":
        return (lambda v: 300.0 < v <= 2200.0), "(300, 2200] K"
    if name.endswith("_rpm"):
        return (lambda v: 0.0 < v <= 1e6), "(0, 1e6] rpm"
    if name == "T_fuel_K":
        return (lambda v: 220.0 <= v <= 550.0), "[220, 550] K"
    if name == "alt_m":
        return (lambda v: ALT_MIN_M <= v <= ALT_MAX_M), f"[{ALT_MIN_M:g}, {ALT_MAX_M:g}] m (the atmosphere's)"
    if name == "W2_kg_s":
        return (lambda v: 0.0 < v <= 1e4), "(0, 1e4] kg/s"
    if name == "Fn_target_N":
        return (lambda v: 0.0 < v <= 1e7), "(0, 1e7] N"
    if name == "LHV_J_kg":
        return (lambda v: 0.0 < v <= 2e8), "(0, 2e8] J/kg"
    return None


@dataclass(frozen=True)
class TurbojetParams(_Common):
    """Single-spool turbojet design parameters.

    Attributes
    ----------
    alt_m, Mach, dT_isa_K : float
        Flight condition: geopotential altitude [m], Mach [-], ISA deviation [K].
    W2_kg_s, Fn_target_N : float or None
        Inlet mass flow [kg/s] or net-thrust target [N] (exactly one).
    inlet_pi : float
        Inlet recovery Pt2/Pt0 without shocks [-].
    PR_c, eta_c : float
        Compressor pressure ratio [-] and isentropic efficiency [-].
    Tt4_K, eta_burner, dPqP_burner, T_fuel_K : float
        Burner exit temperature [K], combustion efficiency [-], pressure loss [-], fuel temperature [K].
    eta_t : float
        Turbine isentropic efficiency [-].
    eta_mech, offtake_W : float
        Mechanical efficiency [-] and shaft port power [W], signed: + taken from the spool (offtake), - delivered
        to it (motor assist).
    dPqP_jetpipe : float
        Pressure loss turbine exit -> nozzle [-].
    Cv, Cd : float
        Nozzle velocity and discharge coefficients [-].
    nozzle_type : str
        ``"convergent"`` or ``"ideal"`` (CD, ideally expanded).
    N_rpm : float
        Design spool speed [rpm] (for the corrected speeds of map scaling).
    LHV_J_kg, hc_ratio : float
        Fuel lower heating value [J/kg] and H/C atom ratio [-].
    bleeds : tuple of BleedSpec
        Compressor bleeds (frac_W of the compressor inlet flow).
    """

    PR_c: float = 10.0
    eta_c: float = 0.85
    eta_t: float = 0.88
    eta_mech: float = 1.0
    offtake_W: float = 0.0
    dPqP_jetpipe: float = 0.0
    Cv: float = 1.0
    Cd: float = 1.0
    N_rpm: float = 10000.0


@dataclass(frozen=True)
class TurbofanParams(_Common):
    """Two-spool separate-flow turbofan design parameters (SPEC.md).

    Attributes
    ----------
    BPR : float
        Bypass ratio W13/W21 at the splitter [-].
    PR_fan_outer, eta_fan_outer : float
        Fan bypass (outer) pressure ratio and isentropic efficiency [-].
    PR_fan_inner, eta_fan_inner : float
        Fan core (inner) pressure ratio and isentropic efficiency [-].
    PR_booster, eta_booster : float
        Booster (LPC on the LP spool, core stream) pressure ratio and efficiency [-]; PR 1 = none.
    dPqP_21_24, dPqP_24_25 : float
        Core duct losses before and after the booster [-].
    PR_hpc, eta_hpc : float
        HPC pressure ratio and isentropic efficiency [-].
    hpc_stages, handling_bleed_stage : int
        Number of HPC stages and the stage behind which the handling bleed is taken.
    handling_bleed_frac : float
        Handling bleed W/W25 [-] into the bypass (0 at design: it opens below ~60 % corrected N1).
    customer_bleed_frac : float
        Customer bleed W/W25 from the HPC exit, overboard [-].
    eta_hpt, eta_lpt : float
        Turbine isentropic efficiencies [-].
    dPqP_44_45, dPqP_5_7, dPqP_13_17 : float
        Inter-turbine duct, jet pipe and bypass duct losses [-].
    bypass_bleed_frac : float
        Overboard bleed from the bypass stream, W/W13 [-].
    eta_mech_hp, eta_mech_lp : float
        Mechanical efficiencies of the spools [-].
    offtake_hp_W, offtake_lp_W : float
        Shaft port powers [W], signed: + taken from the spool (offtake, generator), - delivered to it (motor).
    Cv_core, Cd_core, Cv_bypass, Cd_bypass : float
        Nozzle coefficients [-].
    N1_rpm, N2_rpm : float
        Design LP and HP spool speeds [rpm].
    I_lp_kg_m2, I_hp_kg_m2 : float
        Polar moments of inertia of the LP and HP spools [kg m^2] (transients; 0 = not given).
    """

    BPR: float = 1.0
    PR_fan_outer: float = 2.0
    eta_fan_outer: float = 0.86
    PR_fan_inner: float = 2.0
    eta_fan_inner: float = 0.86
    PR_booster: float = 1.0
    eta_booster: float = 1.0
    dPqP_21_24: float = 0.0
    dPqP_24_25: float = 0.0
    PR_hpc: float = 5.0
    eta_hpc: float = 0.84
    hpc_stages: int = 4
    handling_bleed_stage: int = 2
    handling_bleed_frac: float = 0.0
    customer_bleed_frac: float = 0.0
    eta_hpt: float = 0.88
    eta_lpt: float = 0.89
    dPqP_44_45: float = 0.0
    dPqP_5_7: float = 0.0
    dPqP_13_17: float = 0.0
    bypass_bleed_frac: float = 0.0
    eta_mech_hp: float = 1.0
    eta_mech_lp: float = 1.0
    offtake_hp_W: float = 0.0
    offtake_lp_W: float = 0.0
    Cv_core: float = 1.0
    Cd_core: float = 1.0
    Cv_bypass: float = 1.0
    Cd_bypass: float = 1.0
    N1_rpm: float = 10000.0
    N2_rpm: float = 20000.0
    I_lp_kg_m2: float = 0.0
    I_hp_kg_m2: float = 0.0


EngineParams = TurbojetParams | TurbofanParams


def params_from_dict(data: dict[str, Any], where: str = "parameters") -> EngineParams:
    """Engine parameters from a parsed parameter file; `where` names it in error messages (with the line of
    each key when `data` knows it, as :func:`.safe_yaml.load_json` gives it).

    Raises
    ------
    ModelError
        One line: ``where:line: 'key': what is wrong; what is allowed``.
    """
    def at(m: Any, key: str) -> str:
        line = getattr(m, "lines", {}).get(key)
        return f"{where}:{line}" if line is not None else where

    kinds = {"turbofan": TurbofanParams, "turbojet": TurbojetParams}
    try:
        kind = values.choice(data.get("engine"), kinds)
    except ValueError as exc:
        raise ModelError(f"{at(data, 'engine')}: 'engine': {exc}") from None
    cls = kinds[kind]
    types = {f.name: str(f.type) for f in fields(cls)}
    kw: dict[str, Any] = {}
    for k, v in data.items():
        if k in ("sources", "notes"):
            _doc(v, f"{at(data, k)}: '{k}'")
            continue
        if k in _DOC_KEYS and k != "name":
            continue
        if k not in types:
            raise ModelError(f"{at(data, k)}: unknown parameter {k!r} for a {kind}; allowed: "
                             f"{', '.join(sorted(types))}")
        if k == "bleeds":
            kw[k] = _bleeds(v, where, at(data, k))
            continue
        try:
            kw[k] = _checked(k, types[k], v)
        except ValueError as exc:
            raise ModelError(f"{at(data, k)}: '{k}': {exc}") from None
    try:
        return cls(**kw)
    except OutOfRangeError as exc:
        raise OutOfRangeError(f"{where}: {exc}") from None


def _doc(v: Any, where: str) -> None:
    """``sources`` and ``notes``: a text or a list of texts."""
    for item in v if isinstance(v, list) else [v]:
        try:
            values.text(item, "a text or a list of texts")
        except ValueError as exc:
            raise ModelError(f"{where}: {exc}") from None


def _bleeds(v: Any, where: str, line: str) -> tuple[BleedSpec, ...]:
    """The ``bleeds`` list of a parameter file: objects of :class:`.bleed.BleedSpec`'s fields."""
    if not isinstance(v, list):
        raise ModelError(f"{line}: 'bleeds': expected a list of bleed objects, got {values.show(v)}")
    specs = {f.name: f for f in fields(BleedSpec)}
    out = []
    for i, b in enumerate(v):
        if not isinstance(b, dict):
            raise ModelError(f"{line}: 'bleeds' item {i}: expected an object {{{', '.join(specs)}}}, "
                             f"got {values.show(b)}")
        lines = getattr(b, "lines", {})
        here = f"{where}:{min(lines.values())}" if lines else line
        kw: dict[str, Any] = {}
        for k, x in b.items():
            loc = f"{where}:{lines[k]}" if k in lines else here
            if k not in specs:
                raise ModelError(f"{loc}: bleed {i}: unknown field {k!r}; allowed: {', '.join(specs)}")
            try:
                kw[k] = (values.name(x, "a bleed name") if k == "name" else values.choice(x, SINKS) if k == "sink"
                         else values.number(x))
            except ValueError as exc:
                raise ModelError(f"{loc}: bleed {i} '{k}': {exc}") from None
        missing = [k for k, f in specs.items() if f.default is dataclasses.MISSING and k not in kw]
        if missing:
            raise ModelError(f"{here}: bleed {i}: missing field {missing[0]!r}")
        try:
            out.append(BleedSpec(**kw))
        except OutOfRangeError as exc:
            raise OutOfRangeError(f"{here}: {exc}") from None
    return tuple(out)


def load_params(path: str | Path) -> EngineParams:
    """Read a parameter file (JSON) into :class:`TurbofanParams` or :class:`TurbojetParams`."""
    p = Path(path)
    if not p.is_file():
        raise ModelError(f"parameter file {p} does not exist")
    try:  # no key twice, no NaN or Infinity, UTF-8, bounded size
        data = safe_yaml.load_json(safe_yaml.read_text(p, "parameter file"), str(p))
    except safe_yaml.YamlError as exc:
        raise ModelError(str(exc)) from None
    if not isinstance(data, dict):
        raise ModelError(f"{p}: a parameter file must hold a JSON object")
    data.setdefault("name", p.stem)
    return params_from_dict(data, str(p))


def preset_path(name: str) -> Path:
    """Path of the shipped preset `name` (file stem in ``presets/``)."""
    p = PRESETS_DIR / f"{name}.json"
    if not name or name.strip(".") == "" or "/" in name or "\\" in name or not p.is_file():
        known = sorted(q.stem for q in PRESETS_DIR.glob("*.json"))
        raise ModelError(f"no preset {name!r}; known: {', '.join(known)}")
    return p


def replace(params: EngineParams, **changes: Any) -> EngineParams:
    """A copy of `params` with some fields changed (validated again)."""
    return dataclasses.replace(params, **changes)
