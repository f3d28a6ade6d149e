"""Helpers for tests: build SSD files around test FMUs.

Written by hand (not with the orchestrator's own SSP writer) so that the reader
is tested against independently written files.
"""
from __future__ import annotations

import shutil
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest

HEADER = ('<?xml version="1.0" encoding="UTF-8"?>\n'
          '<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" '
          'xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
          'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="{name}">\n')


@dataclass
class Comp:
    """A component: name, FMU file (in fmu_dir), connectors (name, kind, type) and inline parameters."""

    name: str
    fmu: str
    connectors: list[tuple[str, str, str]]
    params: dict[str, float | int | bool | str] = field(default_factory=dict)


def _param(name: str, value: float | int | bool | str) -> str:
    if isinstance(value, str):
        typed = f"<ssv:String value={quoteattr(value)}/>"
    elif isinstance(value, bool):
        typed = f'<ssv:Boolean value="{str(value).lower()}"/>'
    elif isinstance(value, int):
        typed = f'<ssv:Integer value="{value}"/>'
    else:
        typed = f'<ssv:Real value="{value!r}"/>'
    return f'<ssv:Parameter name={quoteattr(name)}>{typed}</ssv:Parameter>'


def write_system(folder: Path, fmu_dir: Path, comps: list[Comp], connections: list[tuple[str, str]],
                 name: str = "TestSystem", stop_time: float | None = None, copy_fmus: bool = True) -> Path:
    """Write ``folder/SystemStructure.ssd`` (and copy the FMUs to ``folder/resources``)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "resources").mkdir(exist_ok=True)
    parts = [HEADER.format(name=name), f'  <ssd:System name="{name}">\n    <ssd:Elements>\n']
    for c in comps:
        if copy_fmus and (fmu_dir / c.fmu).exists():
            shutil.copy2(fmu_dir / c.fmu, folder / "resources" / c.fmu)
        parts.append(f'      <ssd:Component name="{c.name}" source="resources/{c.fmu}">\n        <ssd:Connectors>\n')
        for cname, kind, typ in c.connectors:
            parts.append(f'          <ssd:Connector name="{cname}" kind="{kind}"><ssc:{typ}/></ssd:Connector>\n')
        parts.append("        </ssd:Connectors>\n")
        if c.params:
            parts.append('        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>'
                         '<ssv:ParameterSet version="1.0" name="inline"><ssv:Parameters>')
            parts.extend(_param(k, v) for k, v in c.params.items())
            parts.append('</ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding>'
                         '</ssd:ParameterBindings>\n')
        parts.append("      </ssd:Component>\n")
    parts.append("    </ssd:Elements>\n")
    if connections:
        parts.append("    <ssd:Connections>\n")
        for start, end in connections:
            se, sc = start.split(".", 1)
            ee, ec = end.split(".", 1)
            parts.append(f'      <ssd:Connection startElement="{se}" startConnector="{sc}" '
                         f'endElement="{ee}" endConnector="{ec}"/>\n')
        parts.append("    </ssd:Connections>\n")
    parts.append("  </ssd:System>\n")
    if stop_time is not None:
        parts.append(f'  <ssd:DefaultExperiment startTime="0" stopTime="{stop_time}"/>\n')
    parts.append("</ssd:SystemStructureDescription>\n")
    path = folder / "SystemStructure.ssd"
    path.write_text("".join(parts), encoding="utf-8")
    return path


def write_ssv(path: Path, params: dict[str, float | int | bool]) -> Path:
    """Write a parameter set file."""
    body = "".join(_param(k, v) for k, v in params.items())
    path.write_text('<?xml version="1.0" encoding="UTF-8"?>\n'
                    '<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" '
                    f'version="1.0" name="set"><ssv:Parameters>{body}</ssv:Parameters></ssv:ParameterSet>\n',
                    encoding="utf-8")
    return path


GAIN_CONNECTORS = [("u_real", "input", "Real"), ("u_int", "input", "Integer"), ("u_bool", "input", "Boolean"),
                   ("y_real", "output", "Real"), ("y_int", "output", "Integer"), ("y_bool", "output", "Boolean")]


def write_gain_pair(folder: Path, fmu_dir: Path) -> Path:
    """The system of the hostile run corpus: two Gain FMUs wired both ways (a.y_real -> b.u_real,
    b.y_int -> a.u_int), 1 s; returns its folder."""
    write_system(folder, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS), Comp("b", "Gain.fmu", GAIN_CONNECTORS)],
                 [("a.y_real", "b.u_real"), ("b.y_int", "a.u_int")], stop_time=1.0)
    return folder


def wait_for(done: Callable[[], bool], proc: subprocess.Popen[bytes], what: str, hang_bound_s: float = 300.0) -> None:
    """Poll until ``done()`` while ``proc`` runs; fail if the child ends first or hangs (``hang_bound_s``: a guard
    against a hung child that would block the suite, generous for a loaded machine, never a measurement)."""
    stop = time.monotonic() + hang_bound_s
    while not done():
        if proc.poll() is not None:
            pytest.fail(f"the child ended before {what}: {proc.communicate()}")
        if time.monotonic() > stop:
            proc.kill()
            pytest.fail(f"the child hung before {what}")
        time.sleep(0.05)
