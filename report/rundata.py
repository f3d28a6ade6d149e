"""A finished (or failed) run's results folder: its time histories, run.json and mission.

Columns are found by role, never by component name: the flight control system is the
component with a ``section_index`` column, the engine the one with ``Wf_kg_s``
and ``fuel_burned_kg``, the airframe the one with ``lat_deg``, ``lon_deg``,
``alt_m`` and ``mach`` (other than the FCS, whose inputs carry some of those names), the
electrical system (if any) the one with ``soc``, ``E_batt_J`` and ``offtake_lp_W``.
"""
from __future__ import annotations

import json
import math
import zipfile
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any
from xml.etree import ElementTree

import numpy as np

from openemss.models.fcs.errors import FcsError
from openemss.models.infra import safe_yaml
from openemss.models.mission.errors import MissionError
from openemss.models.mission.mission import Mission, parse_mission
from openemss.orchestrator.recording.timeseries import (
    Column,
    TimeSeriesError,
    find_timeseries,
    read_columns,
    read_timeseries,
)

from .errors import ReportError

RUN_RECORD = "run.json"
MISSION_COPY = "mission"  # + the source's suffix: the mission as flown, kept with the results


@dataclass(frozen=True)
class Roles:
    """Component names by role (None where the run has no such component)."""

    fcs: str | None
    engine: str | None
    airframe: str | None
    electric: str | None = None


def find_roles(columns: Iterable[str]) -> Roles:
    """Assign components to roles from the recorded ``component.variable`` names."""
    by_comp: dict[str, set[str]] = {}
    for name in columns:
        comp, sep, var = name.partition(".")
        if sep:
            by_comp.setdefault(comp, set()).add(var)
    fcs = next((c for c, v in by_comp.items() if "section_index" in v), None)
    engine = next((c for c, v in by_comp.items() if {"Wf_kg_s", "fuel_burned_kg"} <= v), None)
    nav = {"lat_deg", "lon_deg", "alt_m"}
    airframe = next((c for c, v in by_comp.items() if c != fcs and nav | {"mach"} <= v), None)
    if airframe is None and fcs is not None and nav <= by_comp[fcs]:
        airframe = fcs
    electric = next((c for c, v in by_comp.items() if {"soc", "E_batt_J", "offtake_lp_W"} <= v), None)
    return Roles(fcs, engine, airframe, electric)


def read_header(folder: Path) -> list[str]:
    """Column names of a results folder's time series ([] when there is none)."""
    path = find_timeseries(Path(folder))
    return read_columns(path) if path is not None else []


@dataclass(frozen=True)
class RunData:
    """One results folder.

    Attributes
    ----------
    folder : Path
        The results folder.
    columns : dict[str, numpy.ndarray]
        ``time_s`` [s] and every recorded ``component.variable`` (values in the FMUs' units).
    info : dict
        ``run.json`` (empty when the folder has none).
    roles : Roles
        Which component is the FCS, the engine, the airframe.
    """

    folder: Path
    columns: dict[str, np.ndarray]
    info: dict[str, Any]
    roles: Roles
    note: str = ""  # what reading left out (a torn last row), '' when the file was whole
    meta: dict[str, Column] = field(default_factory=dict)  # unit and description of each column

    def unit(self, name: str) -> str:
        """The unit of a column as recorded ('' where none)."""
        c = self.meta.get(name)
        return c.unit if c is not None else ""

    @property
    def name(self) -> str:
        return self.folder.resolve().name

    @property
    def time_s(self) -> np.ndarray:
        return self.columns["time_s"]

    def get(self, role: str, variable: str) -> np.ndarray | None:
        """The column ``<component of role>.variable``, or None."""
        comp = getattr(self.roles, role)
        return None if comp is None else self.columns.get(f"{comp}.{variable}")


def load_run(folder: Path) -> RunData:
    """Read a results folder of ``emss run``.

    Raises
    ------
    ReportError
        When the folder or its time series is missing or unreadable, or holds no row.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ReportError(f"{folder}: no such results folder (give a folder written by emss run)")
    path = find_timeseries(folder)
    if path is None:
        raise ReportError(f"{folder}: no timeseries.parquet, timeseries.csv or timeseries.mat (give a folder "
                          "written by emss run)")
    try:
        ts = read_timeseries(path)
    except TimeSeriesError as exc:
        raise ReportError(str(exc)) from None
    if len(ts) == 0:
        raise ReportError(f"{path}: no rows recorded")
    info: dict[str, Any] = {}
    if (folder / RUN_RECORD).is_file():
        try:
            info = json.loads((folder / RUN_RECORD).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise ReportError(f"{folder / RUN_RECORD}: unreadable ({exc})") from None
    return RunData(folder, ts.floats(), info, find_roles(ts.names), ts.note, {c.name: c for c in ts.columns})


# -- the FCS's parameters and mission ---------------------------------------------------------
def fmu_start_values(fmu: Path) -> dict[str, str]:
    """Start values (as written) of an FMU's variables, from its modelDescription.xml ({} if unreadable)."""
    try:
        with zipfile.ZipFile(fmu) as z:
            root = ElementTree.fromstring(z.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile, ElementTree.ParseError):
        return {}
    out: dict[str, str] = {}
    for sv in root.iter("ScalarVariable"):
        for child in sv:
            if "start" in child.attrib:
                out[sv.attrib["name"]] = child.attrib["start"]
    return out


def parameter(run: RunData, component: str, name: str) -> str | None:
    """A parameter's value in the run: bound (run.json) or else the FMU's start value, as text."""
    bound = run.info.get("parameters", {}).get(f"{component}.{name}")
    if bound is not None:
        return str(bound)
    fmu = run.info.get("components", {}).get(component)
    return fmu_start_values(Path(fmu)).get(name) if fmu else None


def parameter_float(run: RunData, component: str, name: str) -> float | None:
    """A numeric parameter (see :func:`parameter`), or None."""
    text = parameter(run, component, name)
    try:
        value = float(text) if text is not None else math.nan
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _mission_source(run: RunData) -> tuple[str, str] | None:
    """(text, source) of the mission the FCS flew: the copy kept in the folder, else its
    ``mission_file`` parameter resolved as the FCS does (absolute, or relative to the FMU's
    resources folder)."""
    for copy in sorted(run.folder.glob(MISSION_COPY + ".*")):
        text = _text(copy)
        return (text, str(copy)) if text is not None else None
    fcs = run.roles.fcs
    if fcs is None:
        return None
    fmu = run.info.get("components", {}).get(fcs)
    return read_fmu_file(parameter(run, fcs, "mission_file"), Path(fmu) if fmu else None)


def read_fmu_file(value: str | None, fmu: Path | None) -> tuple[str, str] | None:
    """(text, source) of a file parameter as an FMU resolves it: an absolute path, or a path relative to
    the FMU's resources folder (read from the archive); None when it cannot be read."""
    if not value:
        return None
    path = Path(value)
    if path.is_absolute():
        text = _text(path) if path.is_file() else None
        return (text, str(path)) if text is not None else None
    if fmu is None:
        return None
    member = str(PurePosixPath("resources") / PurePosixPath(*path.parts))
    try:
        with zipfile.ZipFile(fmu) as z:
            return z.read(member).decode("utf-8"), f"{fmu}!{member}"
    except (OSError, KeyError, zipfile.BadZipFile, UnicodeDecodeError):
        return None


def _text(path: Path) -> str | None:
    """The text of a (mission) file through the project's one reader; None when it cannot be read
    (not UTF-8, too large): the FCS, which reads it too, reports why."""
    try:
        return safe_yaml.read_text(path, "mission file")
    except safe_yaml.YamlError:
        return None


def load_mission(run: RunData) -> tuple[Mission | None, str | None]:
    """The run's mission and the text it was read from, or (None, None) when it cannot be found or read."""
    found = _mission_source(run)
    if found is None:
        return None, None
    text, source = found
    try:
        if source.endswith(".plan"):
            from openemss.models.mission.qgc import plan_to_yaml

            return parse_mission(plan_to_yaml(text, source), source + " (converted)"), text
        return parse_mission(text, source), text
    except (FcsError, MissionError):
        return None, None
