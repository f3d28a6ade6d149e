"""The engine's parameters in time, from ``data/engine.json``: limits, bleed valve, numerics and start.

Each section of the file fills one frozen dataclass through the models' one parameter mechanism
(:mod:`openemss.models.infra.params`: value, unit, range, note and source of every field, errors naming
``file:line``): ``limits`` :class:`.engine_signals.EngineLimits`, ``bleed_valve``
:class:`.engine_signals.BleedValve`, ``numerics`` :class:`EngineNumerics`, ``start`` :class:`EngineStart`.
The engine FMU's parameters are these entries (``engine_signals.PARAMETER_SETS`` names them), and the FMU
builds the model from the sets it collects (:func:`engine_model`), so a parameter is added in the file and
its dataclass only.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Self, TypeVar

from ..infra.params import ParamSet, parameter_set
from .errors import OutOfRangeError

__all__ = ["ENGINE_FILE", "EngineNumerics", "EngineStart", "FromEngineFile", "engine_set", "METHODS"]

#: The engine's parameter file, in this package's ``data/``.
ENGINE_FILE = "engine.json"
#: The integration methods of :class:`.engine_model.EngineModel`, by :attr:`EngineNumerics.integrator`.
METHODS: tuple[str, ...] = ("euler", "heun")
P = TypeVar("P")


def engine_set(cls: type[P], section: str) -> ParamSet[P]:
    """The parameters of ``section`` of ``data/engine.json`` for the dataclass ``cls`` (read once); a bad value
    is an :class:`.errors.OutOfRangeError` naming the parameter, its range and the file's line."""
    return parameter_set(cls, __package__ or __name__.rpartition(".")[0], ENGINE_FILE, section, OutOfRangeError)


class FromEngineFile:
    """A parameter set of ``data/engine.json``: the section it reads (:attr:`SECTION`) and :meth:`from_file`."""

    SECTION: ClassVar[str]

    @classmethod
    def from_file(cls, **overrides: Any) -> Self:
        """The set of ``data/engine.json``, section :attr:`SECTION`, with ``overrides`` (checked against its
        ranges)."""
        return engine_set(cls, cls.SECTION).make(**overrides)


@dataclass(frozen=True)
class EngineNumerics(FromEngineFile):
    """How the engine model integrates, matches and models distortion (see :class:`.engine_model.EngineModel`).

    Attributes
    ----------
    I_lp_kg_m2, I_hp_kg_m2 : float
        Spool polar inertias [kg m^2]; 0: the design parameters'.
    dt_internal_s : float
        Largest internal step [s].
    tol : float
        Gas-path matching tolerance, max |residual| [-].
    integrator : int
        Index of the method in :data:`METHODS` (0 explicit Euler, 1 Heun).
    distortion_target : int
        Distorted compressor face: 1 fan, 2 HPC, 3 both.
    critical_angle_deg : float
        Critical sector angle of the distortion model [deg].
    linear_input_frac : float
        Largest relative fuel change taken linearly at a step start [-]; 0: always matched.
    """

    SECTION: ClassVar[str] = "numerics"

    I_lp_kg_m2: float
    I_hp_kg_m2: float
    dt_internal_s: float
    tol: float
    integrator: int
    distortion_target: int
    critical_angle_deg: float
    linear_input_frac: float

    def model_options(self) -> dict[str, Any]:
        """The keyword arguments of :class:`.engine_model.EngineModel` these settings give."""
        return {"I_lp_kg_m2": self.I_lp_kg_m2 or None, "I_hp_kg_m2": self.I_hp_kg_m2 or None,
                "dt_internal_s": self.dt_internal_s, "method": METHODS[self.integrator], "tol": self.tol,
                "distortion_target": self.distortion_target, "critical_angle_deg": self.critical_angle_deg,
                "linear_input_frac": self.linear_input_frac}


@dataclass(frozen=True)
class EngineStart(FromEngineFile):
    """How the engine starts and how it meets a point it cannot match.

    Attributes
    ----------
    start_N1_pct : float
        Initial steady N1 when no start fuel flow is given [% of design].
    start_Wf_kg_s : float
        Initial steady fuel flow, used if > 0 [kg/s].
    accept_solver_failure : bool
        Fly on with the last good state held where the gas path cannot be matched.
    use_ambient : bool
        Flight condition from the ambient static pressure and temperature instead of altitude and ISA deviation.
    """

    SECTION: ClassVar[str] = "start"

    start_N1_pct: float
    start_Wf_kg_s: float
    accept_solver_failure: bool
    use_ambient: bool

