"""Writing SSP: build a system in Python, write it, read it back, run it; other tools read it too."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from openemss.orchestrator.master.execution import Execution
from openemss.orchestrator.recording.observers import MemoryRecorder
from openemss.orchestrator.ssp.read import load_system
from openemss.orchestrator.ssp.system import bind_system
from openemss.orchestrator.ssp.write import MappingEntry, SystemBuilder, connectors_from_fmu
from thirdparty import require_libcosim, run_isolated


def build(fmu: Path) -> SystemBuilder:
    sys_ = SystemBuilder("Written").experiment(0.0, 1.0, 0.1)
    sys_.unit("degC", K=1, offset=273.15).unit("K", K=1)
    a = sys_.component("a", "resources/Gain.fmu")
    for name, kind, typ, _ in connectors_from_fmu(fmu, ["u_real", "y_real", "y_int", "y_bool"]):
        a.connector(name, kind, typ, unit="degC" if name == "y_real" else None)
    a.parameters({"k": 2.0, "u_real": 10.0})
    b = sys_.component("b", "resources/Gain.fmu")
    for name, kind, typ, _ in connectors_from_fmu(fmu, ["u_real", "u_int", "u_bool", "y_real"]):
        b.connector(name, kind, typ, unit="K" if name == "u_real" else None)
    b.parameters({"gain_percent": 50.0}, file_name="b.ssv",
                 mapping=[MappingEntry("gain_percent", "k", factor=0.01)], mapping_file="b.ssm")
    sys_.connect("a.y_real", "b.u_real", factor=1.0, offset=5.0)
    sys_.connect("a.y_int", "b.u_int", mapping=("Integer", [("1", "7")]))
    sys_.connect("a.y_bool", "b.u_bool")
    return sys_


def run(location: Path) -> dict[str, np.ndarray]:
    ex = Execution(bind_system(load_system(location)))
    rec = MemoryRecorder()
    ex.add_observer(rec)
    ex.run(1.0)
    return rec.result()


def test_round_trip_folder_and_archive(tmp_path: Path, fmu_dir: Path) -> None:
    fmu = fmu_dir / "Gain.fmu"
    folder = tmp_path / "sys"
    build(fmu).write(folder)
    (folder / "resources").mkdir()
    shutil.copy2(fmu, folder / "resources" / "Gain.fmu")
    assert sorted(p.name for p in folder.iterdir()) == ["SystemStructure.ssd", "b.ssm", "b.ssv", "resources"]
    sysdef = load_system(folder)
    assert sysdef.step_size_s == 0.1 and sysdef.stop_time_s == 1.0
    out = run(folder)
    # a: 2 * 10 degC = 20 degC; +5 degC by the transformation = 25 degC = 298.15 K into b; b.k = 50 % = 0.5
    assert out["b.u_real"][-1] == pytest.approx(298.15)
    assert out["b.y_real"][-1] == pytest.approx(0.5 * 298.15)
    assert out["b.u_int"][-1] == 7 and out["b.u_bool"][-1] == 1
    archive = build(fmu).write_archive(tmp_path / "sys.ssp", {"resources/Gain.fmu": fmu})
    again = run(archive)
    assert set(again) == set(out)
    for k in out:
        assert np.array_equal(out[k], again[k]), k


def test_written_files_are_valid_and_name_every_connector_of_the_fmu(tmp_path: Path, fmu_dir: Path) -> None:
    files = build(fmu_dir / "Gain.fmu").documents()
    ssd = files["SystemStructure.ssd"]
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    names = [c.get("name") for c in ssd.iterfind(".//ssd:Component[@name='a']/ssd:Connectors/ssd:Connector", ns)]
    assert names == ["u_real", "y_real", "y_int", "y_bool"]
    assert etree.QName(files["b.ssv"]).localname == "ParameterSet"


def test_connectors_from_fmu_refuses_unknown_names(fmu_dir: Path) -> None:
    with pytest.raises(KeyError, match="no input, output or parameter named nope"):
        connectors_from_fmu(fmu_dir / "Gain.fmu", ["nope"])


def test_libcosim_loads_what_we_write(tmp_path: Path, fmu_dir: Path) -> None:
    require_libcosim()

    fmu = fmu_dir / "Gain.fmu"
    sys_ = SystemBuilder("ForLibcosim").experiment(0.0, 1.0, 0.1)
    a = sys_.component("a", "resources/Gain.fmu")
    for k in connectors_from_fmu(fmu, ["y_real"]):
        a.connector(*k)
    a.parameters({"k": 3.0, "u_real": 2.0})
    b = sys_.component("b", "resources/Gain.fmu")
    for k in connectors_from_fmu(fmu, ["u_real"]):
        b.connector(*k)
    sys_.connect("a.y_real", "b.u_real", factor=2.0, offset=-1.0)
    folder = tmp_path / "lc"
    sys_.write(folder)
    (folder / "resources").mkdir()
    shutil.copy2(fmu, folder / "resources" / "Gain.fmu")
    out = run_isolated("libcosim_run", system=str(folder), variables=["b.u_real"], steps=2)  # step from our annotation
    assert out["values"]["b.u_real"][-1] == pytest.approx(2 * 6.0 - 1)
    assert out["time_ns"] == 200_000_000  # two steps of 0.1 s: libcosim read our step annotation
