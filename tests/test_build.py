"""build-fmus: self-contained FMUs with vendored model code under collision-free names."""
from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest

from openemss.orchestrator.fmu.build import build_fmu, built_hash, ensure_built, main
from openemss.orchestrator.errors import BuildError

SLAVE = textwrap.dedent('''
    """A slave that needs model code and a helper module beside it."""
    from pythonfmu import Fmi2Causality, Fmi2Slave, Real

    import helper_mod
    from helper_mod import VALUE
    from openemss.models import engine as engine_pkg

    REQUIREMENTS = ["numpy>=1.24"]


    class VendorProbe(Fmi2Slave):
        """ok = 1 when the model package and the helper came from inside this FMU."""

        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            self.ok = 0.0
            self.register_variable(Real("ok", causality=Fmi2Causality.output, description="Check [-]"))

        def do_step(self, current_time, step_size):
            inside = engine_pkg.__name__.startswith("emss_") and helper_mod.__name__.startswith("emss_")
            self.ok = 1.0 if inside and VALUE == 42 else -1.0
            return True
''')


@pytest.fixture()
def slave_dir(tmp_path: Path) -> Path:
    src = tmp_path / "src"
    src.mkdir()
    (src / "vendor_probe.py").write_text(SLAVE)
    (src / "helper_mod.py").write_text("VALUE = 42\n")
    return src


def test_model_code_and_helpers_are_vendored_under_a_unique_name(slave_dir: Path, tmp_path: Path) -> None:
    fmu = build_fmu(slave_dir / "vendor_probe.py", tmp_path / "out")
    names = zipfile.ZipFile(fmu).namelist()
    digest = built_hash(fmu)
    assert digest is not None
    lib = f"resources/emss_vendor_probe_{digest[:10]}_lib"
    assert f"{lib}/models/engine/__init__.py" in names and f"{lib}/helper_mod.py" in names
    assert f"resources/emss_vendor_probe_{digest[:10]}.py" in names
    assert not any(n.startswith(("resources/models/", "resources/helper_mod")) for n in names)
    z = zipfile.ZipFile(fmu)
    assert z.read("resources/requirements.txt").decode().split() == ["numpy>=1.24", "pythonfmu>=0.6.5"]
    assert json.loads(z.read("resources/openemss_build.json"))["source"] == "vendor_probe.py"


def test_fmu_runs_where_openemss_cannot_be_imported(slave_dir: Path, tmp_path: Path) -> None:
    fmu = build_fmu(slave_dir / "vendor_probe.py", tmp_path / "out")
    code = ("import sys; sys.modules['openemss'] = None\n"  # any import of openemss now fails
            "from fmpy import simulate_fmu\n"
            f"r = simulate_fmu({str(fmu)!r}, stop_time=0.2, step_size=0.1, output=['ok'])\n"
            "print(r['ok'][-1])")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert float(proc.stdout.split()[-1]) == 1.0


def test_rebuild_only_when_a_source_changes(slave_dir: Path, tmp_path: Path) -> None:
    messages: list[str] = []
    out = tmp_path / "out"
    ensure_built(slave_dir, out, report=messages.append)
    ensure_built(slave_dir, out, report=messages.append)
    assert messages[0].startswith("built:") and messages[1].startswith("up to date:")
    first = built_hash(out / "VendorProbe.fmu")
    (slave_dir / "helper_mod.py").write_text("VALUE = 42  # changed\n")
    ensure_built(slave_dir, out, report=messages.append)
    assert messages[2].startswith("built:") and built_hash(out / "VendorProbe.fmu") != first


def test_slave_may_not_depend_on_the_orchestrator(tmp_path: Path) -> None:
    (tmp_path / "bad.py").write_text("from openemss.orchestrator import cli\nfrom pythonfmu import Fmi2Slave\n"
                                     "class Bad(Fmi2Slave):\n    def do_step(self, t, h):\n        return True\n")
    with pytest.raises(BuildError, match="may depend only on openemss.models"):
        build_fmu(tmp_path / "bad.py", tmp_path / "out")


def test_command_line_unknown_name_is_one_line(slave_dir: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["--src", str(slave_dir), "--out", str(tmp_path / "o"), "nothing_here"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "available: vendor_probe" in err[0]


def test_data_files_travel_in_the_resources(tmp_path: Path) -> None:
    src = tmp_path / "src"
    src.mkdir()
    (src / "reader.py").write_text(textwrap.dedent('''
        from pathlib import Path
        from pythonfmu import Fmi2Causality, Fmi2Slave, Real

        DATA_FILES = ["missions/README.md"]


        class DataReader(Fmi2Slave):
            """size = bytes of the data file found in the resources."""

            def __init__(self, **kwargs):
                super().__init__(**kwargs)
                self.size = float(len((Path(self.resources) / "missions" / "README.md").read_bytes()))
                self.register_variable(Real("size", causality=Fmi2Causality.output, description="Size [B]"))

            def do_step(self, current_time, step_size):
                return True
    '''))
    fmu = build_fmu(src / "reader.py", tmp_path / "out")
    root = Path(__file__).resolve().parent.parent
    data = zipfile.ZipFile(fmu).read("resources/missions/README.md")
    assert data == (root / "missions" / "README.md").read_bytes()
    (src / "bad.py").write_text("from pythonfmu import Fmi2Slave\nDATA_FILES = ['../etc/passwd']\n"
                                "class Bad(Fmi2Slave):\n    def do_step(self, t, h):\n        return True\n")
    with pytest.raises(BuildError, match="DATA_FILES entry '../etc/passwd'"):
        build_fmu(src / "bad.py", tmp_path / "out")
