"""The master algorithms by name: the one registry that ``emss run --algorithm``, the study files'
``algorithm:`` check, the execution and the documentation read.

An entry gives the name, one line for ``--help``, whether it repeats steps (and so needs FMUs that
can get and set their state), and a factory from the bound system and the step multiples to an
:class:`~.algorithm.Algorithm`. To add an algorithm, write its class (see orchestrator/README.md,
"Adding an algorithm") and call :func:`register` once, here.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ..errors import ConfigurationError
from ..ssp.system_model import BoundSystem
from .algorithm import Algorithm, GaussSeidel, Jacobi, step_order
from .iterative import ATOL, MAX_ITERATIONS, RTOL, IterativeGaussSeidel


@dataclass(frozen=True)
class AlgorithmEntry:
    """One registered master algorithm."""

    name: str
    summary: str  # one line: what it does
    make: Callable[[BoundSystem, Sequence[int]], Algorithm]
    needs_fmu_state: bool = False  # repeats steps of the loops: their FMUs must get and set their state


REGISTRY: dict[str, AlgorithmEntry] = {}


def register(entry: AlgorithmEntry) -> AlgorithmEntry:
    """Add an algorithm; a name is registered once."""
    if entry.name in REGISTRY:
        raise ValueError(f"algorithm '{entry.name}' is registered twice")
    REGISTRY[entry.name] = entry
    return entry


def names() -> tuple[str, ...]:
    """The registered names, in registration order (the first is the default)."""
    return tuple(REGISTRY)


def check_name(name: str, where: str) -> str:
    """``name`` if an algorithm has it, else ConfigurationError naming ``where`` and the choices."""
    if name not in REGISTRY:
        raise ConfigurationError(f"{where}: unknown algorithm {name!r} (allowed: {', '.join(REGISTRY)})")
    return name


def create(name: str, system: BoundSystem, multiples: Sequence[int], where: str = "algorithm") -> Algorithm:
    """The algorithm ``name`` for ``system`` with one step multiple per component.

    Raises
    ------
    ConfigurationError
        For an unknown name, or a system the algorithm cannot step (e.g. a loop of FMUs that
        cannot get and set their state, for an iterating algorithm).
    """
    entry = REGISTRY[check_name(name, where)]
    if entry.needs_fmu_state:
        order = step_order(system)
        unable = [system.components[i].name for c in order.cycles for i in c
                  if not system.components[i].model_description.coSimulation.canGetAndSetFMUstate]
        if unable:
            raise ConfigurationError(f"algorithm {name}: {', '.join(unable)} in a loop cannot get and set its "
                                     "FMU state (canGetAndSetFMUstate), which repeating a step needs; allowed "
                                     "for such FMUs: " + ", ".join(n for n, e in REGISTRY.items()
                                                                   if not e.needs_fmu_state))
    return entry.make(system, multiples)


def _input_names(system: BoundSystem) -> list[list[str]]:
    """Per component, ``component.variable`` of its connected inputs in exchange order (by type)."""
    out: list[list[str]] = [[] for _ in system.components]
    for t in ("Real", "Integer", "Boolean"):
        for ln in system.links:
            if ln.target_var.type_name == t:
                out[ln.target].append(f"{system.components[ln.target].name}.{ln.target_var.name}")
    return out


DEFAULT = register(AlgorithmEntry(
    "jacobi", "every component steps from the inputs of the last exchange, then all outputs are exchanged",
    lambda system, multiples: Jacobi(multiples))).name
register(AlgorithmEntry(
    "gauss-seidel", "components step one after the other in connection order, each taking the newest outputs",
    lambda system, multiples: GaussSeidel(multiples, step_order(system))))
register(AlgorithmEntry(
    "gauss-seidel-iterative", "Gauss-Seidel with every loop stepped again until its inputs agree "
    f"(rtol {RTOL:g}, atol {ATOL:g}, at most {MAX_ITERATIONS} sweeps); needs FMUs that can get and set their state",
    lambda system, multiples: IterativeGaussSeidel(multiples, step_order(system), [c.name for c in system.components],
                                                   _input_names(system)),
    needs_fmu_state=True))
