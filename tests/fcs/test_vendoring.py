"""The FCS package works when copied under another name (as pythonfmu vendors it into an FMU):
relative imports only, data files found next to the code, no fmpy/pythonfmu imports."""

from __future__ import annotations

import importlib
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FCS = ROOT / "models" / "fcs"


def test_no_absolute_project_imports_and_no_fmi_packages() -> None:
    for py in FCS.glob("*.py"):
        text = py.read_text()
        for bad in ("import openemss", "from openemss", "import fmpy", "from fmpy", "pythonfmu"):
            assert bad not in text, f"{py.name}: {bad}"


def test_vendored_copy_flies_a_step(tmp_path: Path) -> None:
    """As build-fmus lays it out: the FCS and the models/common, models/infra and models/mission it imports
    beside it, under a package of another name."""
    dest = tmp_path / "vendored_fcs_pkg"
    dest.mkdir()
    (dest / "__init__.py").write_text("")
    shutil.copytree(FCS, dest / "fcs", ignore=shutil.ignore_patterns("__pycache__"))
    for shared in ("common", "infra", "mission"):
        shutil.copytree(ROOT / "models" / shared, dest / shared, ignore=shutil.ignore_patterns("__pycache__"))
    sys.path.insert(0, str(tmp_path))
    try:
        fcs_mod = importlib.import_module("vendored_fcs_pkg.fcs.fcs")
        mission_mod = importlib.import_module("vendored_fcs_pkg.mission.mission")
        state_mod = importlib.import_module("vendored_fcs_pkg.fcs.state")
        geo = importlib.import_module("vendored_fcs_pkg.mission.geo")
        m = mission_mod.load_mission(ROOT / "missions" / "munich.yaml")
        fcs = fcs_mod.FlightControlSystem(m, Wf0_kg_s=0.012)
        rwy = m.sections[0]["runway"]
        x = state_mod.AircraftState(rwy.point(50.0), rwy.elevation_m, 0.0, 0.0, 0.0, 0.0, 0.0, rwy.heading_rad,
                                    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2000.0, True)
        out = fcs.step(0.0, 0.05, x, state_mod.EngineState(25.0, 25.0, 800.0))
        assert out.signals()["section_name"] == "take-off roll 26R"
        assert isinstance(rwy.threshold, geo.LatLon)
        assert len(fcs.parameter_names()) > 60
    finally:
        sys.path.remove(str(tmp_path))
        for name in [n for n in sys.modules if n.startswith("vendored_fcs_pkg")]:
            del sys.modules[name]
