"""A mission section type registered from outside the package (models/fcs/sections.py: ``register``, its
declaration going to models/mission/sections.py's registry) is read,
checked before the flight and judged after it like a shipped one, with nothing else naming it (issue 37.3).

* ``emss mission check`` runs the type's own feasibility check: a type that carries the shipped Levelling check
  gives, in the same mission, the same figures and findings as a Levelling section in its place (the check is
  found through the registry, not by the type's name); a type that carries no check is ``n/a`` with one note.
* The report's conformance follows the type's ``conformance`` kind: a ``targets`` type in place of the
  synthetic run's waypoint section gets the same capture and deviations (hand-computed in test_conformance.py:
  the altitude enters the 10 m band 14.5 s after the section's start, dips 25 m, ends 5 m high); an
  ``approach`` type in place of its landing gets the same ILS figures; a type without a kind gets none.
* ``register`` refuses a conformance kind it does not know, and a kind whose fields the type lacks.
"""
# ruff: noqa: F811  (``system`` is test_mission_check.py's fixture, imported to be used by name)
from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from synthetic_runs import H_S, MISSION, N, Runs
from test_mission_check import system  # noqa: F401  (the project's system with this session's FMUs)

from openemss.models.fcs import feasibility_sections as checks
from openemss.models.fcs.sections import Landing, Levelling, SectionType, register, unregister
from openemss.models.mission.sections import APPROACH, REGISTRY, TARGETS
from openemss.orchestrator.cli.main import main
from openemss.report.rundata import load_mission, load_run
from openemss.report.summary import summarize

T = np.arange(N) * H_S


class Cruise(SectionType):
    """The Levelling's fields and feasibility check under another name, flown to targets."""

    type_name = "Cruise"
    fields = Levelling.fields
    completion = Levelling.completion
    feasibility = staticmethod(checks.levelling)
    conformance = TARGETS


class Drift(SectionType):
    """No feasibility check, no conformance."""

    type_name = "Drift"
    speed_field = None
    completion = "``duration_s`` elapsed"
    fields = {"duration_s": ("number", True, None, (0.1, 3600.0), "duration [s]"),
              "altitude_m": ("number", False, None, (-400.0, 15000.0), "altitude [m]")}


class Glidepath(SectionType):
    """A landing's fields under another name, an ILS approach."""

    type_name = "Glidepath"
    speed_field = None
    completion = Landing.completion
    fields = Landing.fields
    conformance = APPROACH


@pytest.fixture()
def registered() -> Iterator[None]:
    for cls in (Cruise, Drift, Glidepath):
        register(cls)
    try:
        yield
    finally:
        for cls in (Cruise, Drift, Glidepath):
            unregister(cls.type_name)


CHECKED = """mission: {{name: registered types}}
places:
  runways:
    EDDM_26R: {{threshold_lat_deg: 48.366887, threshold_lon_deg: 11.821173, heading_deg: 263.42,
               elevation_m: 441.7, length_m: 4000.0, width_m: 60.0}}
sections:
  - {{type: Rolling, runway: EDDM_26R, lever: 1.0, rotate_cas_m_s: 62.0}}
  - {{type: TakeOff, runway: EDDM_26R, climb_speed: {{cas_m_s: 85.0}}, until_height_agl_m: 300.0}}
  - {{type: {level}, name: level off, altitude_m: 2500.0, speed: {{cas_m_s: 100.0}}, heading_deg: 263.0}}
  - {{type: Drift, name: drifting, duration_s: 60.0}}
  - {{type: Levelling, name: higher, altitude_m: 3000.0, speed: {{cas_m_s: 100.0}}}}
"""


def _check(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], level: str) -> tuple[int, dict]:
    f = tmp_path / f"{level}.yaml"
    f.write_text(CHECKED.format(level=level))
    code = main(["mission", "check", str(f), "--system", str(system), "--json"])
    out, err = capsys.readouterr()
    assert out, err
    return code, json.loads(out)


@pytest.mark.usefixtures("registered")
def test_mission_check_runs_the_check_the_type_carries(system: Path, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    code_a, shipped = _check(system, tmp_path, capsys, "Levelling")
    code_b, mine = _check(system, tmp_path, capsys, "Cruise")
    assert code_a == code_b == shipped["counts"]["infeasible"] == 0
    a, b = shipped["sections"], mine["sections"]
    assert b[2]["type"] == "Cruise" and a[2]["type"] == "Levelling"
    assert {**b[2], "type": "Levelling"} == a[2] and b[3:] == a[3:]
    assert b[2]["thrust_ratio"] > 1.0 and b[2]["tas_m_s"] > 100.0  # the check ran: figures filled
    drift = b[3]
    assert drift["verdict"] == "n/a" and drift["alt_to_m"] == drift["alt_from_m"] == b[2]["alt_to_m"]
    assert [f["text"] for f in drift["findings"]] == ["Drift sections have no feasibility check: not checked"]
    capsys.readouterr()
    assert main(["mission", "check", str(tmp_path / "Cruise.yaml"), "--system", str(system)]) == 0
    out = capsys.readouterr().out
    assert "Cruise" in out and "Drift" in out and "Traceback" not in out


def _altitude() -> np.ndarray:
    """test_conformance.py's altitude: 500 m climbing at 20 m/s from 15 s to 1000 m at 40 s, a 25 m dip from
    45 to 50 s (half sine), 5 m up over the last 2 s."""
    h = np.where(T < 40.0, 500.0 + 20.0 * np.maximum(T - 15.0, 0.0), 1000.0)
    dip = (T > 45.0) & (T < 50.0)
    h = np.where(dip, 1000.0 - 25.0 * np.sin(np.pi * (T - 45.0) / 5.0), h)
    return np.where(T > 58.0, 1000.0 + 2.5 * (T - 58.0), h)


def _summary(folder: Path) -> dict[str, Any]:
    run = load_run(folder)
    return summarize(run, load_mission(run)[0])


WAYPOINTS = ("  - {type: WaypointFollowing, name: out to WP1, waypoints: [WP1], altitude_m: 1000.0, "
             "speed: {mach: 0.4}}\n")
LANDING = "  - {type: Landing, name: land,"


@pytest.mark.usefixtures("registered")
def test_conformance_follows_the_kind_the_type_carries(tmp_path: Path) -> None:
    assert WAYPOINTS in MISSION and LANDING in MISSION
    cruise = MISSION.replace(WAYPOINTS, "  - {type: Cruise, name: cruise, altitude_m: 1000.0, speed: {mach: 0.4}}\n")
    runs = Runs(tmp_path)
    c = _summary(runs.make("cruise", columns={"airframe.alt_m": _altitude()}, mission=cruise))
    a = c["sections"][2]["conformance"]["altitude"]
    assert c["sections"][2]["type"] == "Cruise" and a["target_m"] == 1000.0
    assert a["time_to_capture_s"] == pytest.approx(14.5, abs=1e-9)
    assert a["worst_after_capture_m"] == pytest.approx(-25.0) and a["error_at_end_m"] == pytest.approx(5.0)
    drift = MISSION.replace(WAYPOINTS, "  - {type: Drift, name: drift, duration_s: 60.0, altitude_m: 1000.0}\n")
    d = _summary(runs.make("drift", columns={"airframe.alt_m": _altitude()}, mission=drift))
    assert d["sections"][2]["type"] == "Drift" and d["sections"][2]["conformance"] is None

    phase = np.where(T < 40.0, 2.0, np.where(T < 45.0, 3.0, 4.0))  # LOC from 40 s, GS from 45 s
    landing = _summary(runs.make("landing", columns={"fcs.ils_phase": phase}))["ils"]
    glide = _summary(runs.make("glide", columns={"fcs.ils_phase": phase},
                               mission=MISSION.replace(LANDING, "  - {type: Glidepath, name: land,")))["ils"]
    assert landing is not None and landing["loc_capture_time_s"] == pytest.approx(40.0)
    assert glide == landing
    none = _summary(runs.make("none", columns={"fcs.ils_phase": phase}, mission=MISSION.replace(
        LANDING + " runway: RWY_09, approach_altitude_m: 1000.0, approach_speed: {cas_m_s: 65.0}}",
        "  - {type: Drift, name: land, duration_s: 10.0}")))
    assert none["ils"] is None


def test_register_refuses_a_conformance_it_cannot_judge() -> None:
    unknown = type("Odd", (SectionType,), {"type_name": "Odd", "fields": Levelling.fields, "conformance": "wiggle"})
    with pytest.raises(ValueError, match="conformance 'wiggle' is not one of targets, approach"):
        register(unknown)
    bare = type("Bare", (SectionType,), {"type_name": "Bare", "fields": Drift.fields, "conformance": APPROACH})
    with pytest.raises(ValueError, match="needs the field.s. runway, approach_altitude_m"):
        register(bare)
    assert "Odd" not in REGISTRY and "Bare" not in REGISTRY
