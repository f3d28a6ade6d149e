"""A finished (or failed) run's results folder: its time histories, run.json and mission.

Columns are found by role, never by component name: the flight control system is the
component with a ``section_index`` column, the engine the one with ``fuel_flow_kg_s``
and ``fuel_burned_kg``, the airframe the one with ``lat_deg``, ``lon_deg``,
``alt_msl_m`` and ``mach`` (other than the FCS, whose inputs carry some of those names), the
electrical system (if any) the one with ``soc``, ``E_batt_J`` and ``offtake_lp_W``.
"""
from __future__ import annotations

import json
import math
import zipfile
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any
from xml.etree import ElementTree

import numpy as np

from openemss.models.common import safe_yaml
from openemss.models.fcs.errors import FcsError
from openemss.models.fcs.mission import Mission, parse_mission

from .errors import ReportError

TIMESERIES = "timeseries.csv"
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
    engine = next((c for c, v in by_comp.items() if {"fuel_flow_kg_s", "fuel_burned_kg"} <= v), None)
    nav = {"lat_deg", "lon_deg", "alt_msl_m"}
    airframe = next((c for c, v in by_comp.items() if c != fcs and nav | {"mach"} <= v), None)
    if airframe is None and fcs is not None and nav <= by_comp[fcs]:
        airframe = fcs
    electric = next((c for c, v in by_comp.items() if {"soc", "E_batt_J", "offtake_lp_W"} <= v), None)
    return Roles(fcs, engine, airframe, electric)


def read_header(folder: Path) -> list[str]:
    """Column names of a results folder's ``timeseries.csv`` ([] when there is none)."""
    try:
        with open(Path(folder) / TIMESERIES, encoding="utf-8") as f:
            return f.readline().strip().split(",")
    except OSError:
        return []


def _read_table(path: Path) -> tuple[list[str], np.ndarray, str]:
    """Names, rows and a note on the file's end ('' or what was left out: a torn last row).

    A run killed while writing may leave its last row incomplete: it is left out and the note says
    so. An incomplete or unreadable row before the last is an error naming its line.
    """
    try:
        lines = path.read_bytes().decode("utf-8", "replace").split("\n")
    except OSError as exc:
        raise ReportError(f"{path}: cannot read: {exc.strerror}") from None
    if not lines or not lines[0].startswith("time_s"):
        raise ReportError(f"{path}: not a timeseries of emss run (the first column must be time_s)")
    names = lines[0].split(",")
    complete = lines[-1] == ""  # every row written whole ends with a newline
    body = lines[1:-1] if complete else lines[1:]
    note = ""
    if not complete and body:
        note = (f"{path}: the last row (line {len(lines)}) is torn, {len(body[-1].split(','))} of {len(names)} "
                "values (the run stopped while writing it); it is left out")
        body = body[:-1]
    for i, line in enumerate(body, start=2):
        if line.count(",") != len(names) - 1:
            raise ReportError(f"{path}:{i}: {line.count(',') + 1} values for {len(names)} columns; the file is "
                              "damaged")
    try:
        data = np.loadtxt(body, delimiter=",", ndmin=2) if body else np.empty((0, len(names)))
    except ValueError as exc:
        raise ReportError(f"{path}: unreadable row ({exc})") from None
    return names, data, note


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
        When the folder or its ``timeseries.csv`` is missing or unreadable, or holds no row.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ReportError(f"{folder}: no such results folder (give a folder written by emss run)")
    if not (folder / TIMESERIES).is_file():
        raise ReportError(f"{folder}: no {TIMESERIES} (give a folder written by emss run)")
    names, data, note = _read_table(folder / TIMESERIES)
    if len(data) == 0:
        raise ReportError(f"{folder / TIMESERIES}: no rows recorded")
    info: dict[str, Any] = {}
    if (folder / RUN_RECORD).is_file():
        try:
            info = json.loads((folder / RUN_RECORD).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise ReportError(f"{folder / RUN_RECORD}: unreadable ({exc})") from None
    columns = {n: data[:, j] for j, n in enumerate(names)}
    return RunData(folder, columns, info, find_roles(names), note)


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
            from openemss.models.fcs.qgc import plan_to_yaml

            return parse_mission(plan_to_yaml(text, source), source + " (converted)"), text
        return parse_mission(text, source), text
    except FcsError:
        return None, None
