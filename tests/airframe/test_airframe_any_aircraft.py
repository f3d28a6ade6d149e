"""Any JSBSim aircraft flies on our engines (issue 32 point 1): two stock aircraft of the jsbsim package.

The T-38 (two turbojets) and the 737 (two turbofans), their engines replaced by thrust forces at the
thrusters (models/airframe/aircraft.py). Checked against the aircraft's own file (read here with
ElementTree, not through our reader) and against Newton: the empty mass and CG the file states, the CG
with fuel as the tanks' positions give it, the thrust's moments about the CG from the thrusters'
positions, at rest on the runway with no thrust, and F = m a at low speed (two thrusts from rest: the
difference of the accelerations is the difference of the thrusts over the mass, friction and drag being
the same at the same speed).
"""
from __future__ import annotations

import math
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

jsbsim = pytest.importorskip("jsbsim")

from openemss.models.airframe.adapter import Airframe  # noqa: E402
from openemss.models.airframe.aircraft import load_aircraft  # noqa: E402
from openemss.models.airframe.errors import AirframeError  # noqa: E402

STOCK = Path(jsbsim.get_default_root_dir()) / "aircraft"
AIRCRAFT = ("T38", "737")
IN_M, LB_KG, LBF_N, FT_M = 0.0254, 0.45359237, 4.4482216152605, 0.3048
EDDM = (48.366887, 11.821173, 263.42, 453.0)


def _file(name: str) -> ET.Element:
    return ET.parse(STOCK / name / f"{name}.xml").getroot()


def _xyz_in(el: ET.Element) -> tuple[float, ...]:
    assert el.get("unit") == "IN"  # both files give their locations in inches
    return tuple(float(el.find(c).text) for c in "xyz")  # type: ignore[union-attr,arg-type]


@pytest.mark.parametrize("name", AIRCRAFT)
def test_mass_and_cg_as_the_file_states(name: str) -> None:
    root = _file(name)
    mb = root.find("mass_balance")
    empty_lb = float(mb.find("emptywt").text)  # type: ignore[union-attr,arg-type]
    cg = _xyz_in(mb.find("location"))  # type: ignore[arg-type]
    tanks = [(_xyz_in(t.find("location")), float(t.find("capacity").text))  # type: ignore[arg-type,union-attr]
             for t in root.find("propulsion").findall("tank")]  # type: ignore[union-attr]
    af = Airframe(aircraft=name)
    af.start_air(3000.0, 120.0, 0.0, fuel_kg=0.0)
    assert af.mass_kg == pytest.approx(empty_lb * LB_KG, rel=1e-7)  # JSBSim: lb / 32.174049 slug
    for c, v in zip("xyz", cg, strict=True):
        assert af.get_property(f"inertia/cg-{c}-in") == pytest.approx(v, abs=1e-6)
    cap_lb = sum(c for _, c in tanks)
    fuel_kg = 0.5 * cap_lb * LB_KG
    af.start_air(3000.0, 120.0, 0.0, fuel_kg=fuel_kg)  # half of every tank (fuel in proportion to the capacity)
    m_lb = empty_lb + 0.5 * cap_lb
    assert af.mass_kg == pytest.approx(m_lb * LB_KG, rel=1e-7)
    for k, c in enumerate("xyz"):
        expect = (empty_lb * cg[k] + sum(0.5 * cap * loc[k] for loc, cap in tanks)) / m_lb
        assert af.get_property(f"inertia/cg-{c}-in") == pytest.approx(expect, abs=1e-6)
    af.set_payload(1000.0)
    af.step(1.0 / af.rate_hz)
    assert af.mass_kg == pytest.approx(m_lb * LB_KG + 1000.0, rel=1e-7)


@pytest.mark.parametrize("name", AIRCRAFT)
def test_thrust_acts_at_each_thruster(name: str) -> None:
    """Thrust of one engine only: the force along the body x axis, and the yawing and pitching moments about the
    CG from the thruster's lateral and vertical offsets in the file (r x F)."""
    root = _file(name)
    thrusters = [_xyz_in(e.find("thruster").find("location"))  # type: ignore[union-attr,arg-type]
                 for e in root.find("propulsion").findall("engine")]  # type: ignore[union-attr]
    af = Airframe(aircraft=name)
    assert af.engines == len(thrusters) == 2
    af.start_air(3000.0, 120.0, 0.0, fuel_kg=1000.0)
    f_n = 20000.0
    for k, (_, y, z) in enumerate(thrusters):
        for j in range(af.engines):
            af.set_thrust(f_n if j == k else 0.0, j)
        af.step(1.0 / af.rate_hz)
        f_lb = f_n / LBF_N
        dy_ft = (y - af.get_property("inertia/cg-y-in")) / 12.0
        dz_ft = (z - af.get_property("inertia/cg-z-in")) / 12.0
        assert af.get_property("forces/fbx-external-lbs") == pytest.approx(f_lb, rel=1e-9)
        # body axes: y right as the structural frame, z down against its z up
        assert af.get_property("moments/n-external-lbsft") == pytest.approx(-dy_ft * f_lb, rel=1e-6)
        assert af.get_property("moments/m-external-lbsft") == pytest.approx(-dz_ft * f_lb, rel=1e-6, abs=1e-6)


@pytest.mark.parametrize("name", AIRCRAFT)
def test_rests_on_the_runway_and_accelerates_as_f_equals_m_a(name: str) -> None:
    af = Airframe(aircraft=name)
    s0 = af.start_runway(*EDDM, fuel_kg=1500.0)
    assert s0.on_ground and abs(s0.vs_m_s) < 0.05 and abs(math.degrees(s0.theta_rad)) < 3.0
    af.step(5.0)  # no thrust, brakes off: it stays
    s = af.state()
    assert s.on_ground and s.gs_m_s < 0.05 and math.dist((s.lat_deg, s.lon_deg), EDDM[:2]) < 1e-6
    m = af.mass_kg
    acc = []
    g = 9.80665
    for f_each in (0.1 * m * g, 0.2 * m * g):  # a total thrust of 0.2 g and 0.4 g
        af = Airframe(aircraft=name)
        af.start_runway(*EDDM, fuel_kg=1500.0)
        for j in range(af.engines):
            af.set_thrust(f_each, j)
        af.step(0.5)
        v0 = af.state().gs_m_s
        af.step(1.0)
        acc.append(af.state().gs_m_s - v0)  # [m/s^2] over one second, below 6 m/s
        assert af.state().on_ground and af.fuel_kg == 1500.0  # no fuel burned by JSBSim's engines
    assert acc[1] - acc[0] == pytest.approx(2 * 0.1 * g, rel=0.02)
    assert 0.8 * 0.2 * g < acc[0] < 0.2 * g  # less the rolling friction and the drag


def test_fuel_burnt_from_all_tanks_in_proportion() -> None:
    af = Airframe(aircraft="737")
    af.start_air(3000.0, 120.0, 0.0, fuel_kg=8000.0)
    m0 = af.mass_kg
    af.set_fuel_flow(2.0)
    af.step(10.0)
    assert af.fuel_kg == pytest.approx(7980.0, rel=1e-9) and af.mass_kg == pytest.approx(m0 - 20.0, rel=1e-9)
    ac = af.aircraft
    for i, (k, tank) in enumerate(zip(ac.fuel_tank_indices, ac.tanks, strict=True)):
        assert af.get_property(f"propulsion/tank[{k}]/contents-lbs") * LB_KG == pytest.approx(
            7980.0 * tank.capacity_kg / ac.fuel_capacity_kg, rel=1e-9), i


def test_the_users_folder_and_the_aircraft_file_stay_as_they_were(tmp_path: Path) -> None:
    src = tmp_path / "mine"
    shutil.copytree(STOCK / "T38", src)
    before = {p.name: p.read_bytes() for p in src.iterdir()}
    ac = load_aircraft(str(src))
    assert ac.name == "T38" and len(ac.thrusters) == 2 and not str(ac.root).startswith(str(tmp_path))
    assert {p.name: p.read_bytes() for p in src.iterdir()} == before


@pytest.mark.parametrize(("make", "fragments"), [
    (lambda d: "no_such_aircraft", ("'no_such_aircraft' is neither a folder nor a known aircraft", "737")),
    (lambda d: str(d / "missing_folder"), ("folder", "not found")),
    (lambda d: (d / "empty").mkdir() or str(d / "empty"), ("holds no JSBSim aircraft file", "empty.xml")),
    (lambda d: _without_engines(d), ("no engine (propulsion/engine)",)),
    (lambda d: _write(d, "broken", "<fdm_config><metrics>"), ("not valid XML",)),
])
def test_bad_aircraft_is_one_line(tmp_path: Path, make, fragments: tuple[str, ...]) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(AirframeError) as exc:
        load_aircraft(make(tmp_path))
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("aircraft: ")
    for f in fragments:
        assert f in msg


def _write(d: Path, name: str, text: str) -> str:
    (d / name).mkdir()
    (d / name / f"{name}.xml").write_text(text, encoding="utf-8")
    return str(d / name)


def _without_engines(d: Path) -> str:
    root = _file("T38")
    prop = root.find("propulsion")
    for e in prop.findall("engine"):  # type: ignore[union-attr]
        prop.remove(e)  # type: ignore[union-attr]
    return _write(d, "glider", ET.tostring(root, encoding="unicode"))


@pytest.mark.parametrize(("name", "alt_m", "mach", "mass_kg"), [("737", 10000.0, 0.75, 50000.0),
                                                                ("T38", 6000.0, 0.7, 5000.0)])
def test_trims_in_level_flight(name: str, alt_m: float, mach: float, mass_kg: float) -> None:
    """Level flight from JSBSim's own tables (no model of ours): lift carries the weight less the thrust's share
    (T sin alpha), the thrust along the body axis balances the drag (T cos alpha = D), both engines alike."""
    from openemss.models.airframe.trim import trim_level

    af = Airframe(aircraft=name)
    r = trim_level(alt_m, mach, mass_kg, airframe=af)
    w = mass_kg * 9.80665
    assert r.residual < 1e-6 and abs(r.elevator) < 1.0 and 0.0 < r.alpha_rad < 0.2
    assert r.lift_N + r.Fn_N * math.sin(r.alpha_rad) == pytest.approx(w, rel=0.01)
    assert r.Fn_N * math.cos(r.alpha_rad) == pytest.approx(r.drag_N, rel=0.01)
    assert af.get_property("external_reactions/thrust/magnitude") == af.get_property(
        "external_reactions/thrust_2/magnitude") == pytest.approx(r.Fn_N / 2.0 / LBF_N, rel=1e-12)
