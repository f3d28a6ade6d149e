"""The hostile corpus, system values (issue 33 points 3, 4 and 5): ``--set``, .ssv files, .ssp archives,
the noise before an error, and the report under a hostile ``MPLBACKEND``.

Each case builds its system (Gain and TextProbe test FMUs) and asserts the behaviour: one line naming
the option or the file and line the user gave (an archive as ``archive.ssp!entry``, never the temporary
folder it was extracted into), a non-zero exit, ``emss validate`` counting every problem, nothing of
the user's touched. The references are independent of the code under test: line numbers are counted
in the text the test writes, values are those the test passed.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import warnings
import zipfile
from pathlib import Path

import pytest
from test_hostile_runs import assert_one_line as one_line
from test_hostile_runs import run_cli as emss

import openemss
from openemss.orchestrator.cli import api
from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError, SystemStructureError
from systems import GAIN_CONNECTORS, Comp, write_gain_pair, write_ssv, write_system

SSV_HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet '
            'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p">\n'
            '<ssv:Parameters>\n')
SSV_TAIL = "</ssv:Parameters></ssv:ParameterSet>\n"
TEXT_CONNECTORS = [("label_chars", "output", "Integer"), ("table_file_chars", "output", "Integer")]


@pytest.fixture()
def system(tmp_path: Path, fmu_dir: Path) -> Path:
    """Two Gain FMUs, a -> b -> a (the system of the run corpus)."""
    return write_gain_pair(tmp_path / "sys", fmu_dir)


def line_of(text: str, fragment: str, nth: int = 1) -> int:
    """1-based line of the nth line of ``text`` holding ``fragment`` (the independent reference)."""
    return [i for i, ln in enumerate(text.splitlines(), start=1) if fragment in ln][nth - 1]


# -- --set: every value checked where it enters, never the last of two ----------------------------
SET_CASES: dict[str, tuple[list[str], list[str]]] = {
    "twice": (["a.k=1", "a.k=2"], ["--set 'a.k=2'", "given twice", "--set 'a.k=1'"]),
    "twice_spaced": (["a.k=1", " a.k =2"], ["given twice", "--set 'a.k=1'"]),
    "boolean_two": (["a.u_bool=2"], ["--set 'a.u_bool=2'", "not a Boolean", "true, false, 1, 0"]),
    "boolean_empty": (["a.u_bool="], ["--set 'a.u_bool='", "not a Boolean"]),
    "integer_401_digits": (["a.u_int=" + "9" * 401], ["--set 'a.u_int=999", "outside the range of an FMI Integer"]),
    "integer_underscore": (["a.u_int=1_000"], ["--set 'a.u_int=1_000'", "not an integer"]),
    "integer_arabic_digits": (["a.u_int=\u0663"], ["not an integer"]),
    "integer_fraction": (["a.u_int=2.5"], ["--set 'a.u_int=2.5'", "not an integer"]),
    "integer_empty": (["a.u_int="], ["--set 'a.u_int='", "not an integer"]),
    "real_nan": (["a.k=NaN"], ["--set 'a.k=NaN'", "not a finite number"]),
    "real_1e999": (["a.k=1e999"], ["--set 'a.k=1e999'", "not a finite number"]),
    "real_underflow": (["a.k=1e-999"], ["--set 'a.k=1e-999'", "it would be 0"]),
    "real_empty": (["a.k="], ["--set 'a.k='", "not a number"]),
    "real_401_digit_exponent": (["a.k=1e" + "9" * 401], ["not a finite number"]),
}


@pytest.mark.parametrize("case", sorted(SET_CASES))
def test_hostile_set(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    items, fragments = SET_CASES[case]
    out = tmp_path / "out"
    rc, err = emss(capsys, "run", str(system), "--set", *items, "--out", str(out))
    line = one_line(rc, err, *fragments)
    assert len(line) < 400, line  # a 401-digit value is shown cut, not whole
    assert not (out / "timeseries.csv").exists() and not (out / api.SETTINGS_FILE).exists()
    rc, err = emss(capsys, "validate", str(system), "--set", *items)
    assert rc == 1, err  # validate lists it as one problem
    assert err == ["1 problem(s) found in " + str(system)], err


def test_validate_counts_every_set_problem_and_writes_nothing(system: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = {p.name for p in Path(tempfile.gettempdir()).glob("emss-set-*")}
    rc = main(["validate", str(system), "--set", "a.k", "a.u_int=x", "b.nothing=1", "a.u_bool=true", "a.u_bool=0"])
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert rc == 1 and "4 problem(s)" in captured.err, captured
    assert sorted(ln.split(":")[0] for ln in lines) == ["--set 'a.k'", "--set 'a.u_bool=0'", "--set 'a.u_int=x'",
                                                        "--set 'b.nothing=1'"], lines
    assert {p.name for p in Path(tempfile.gettempdir()).glob("emss-set-*")} == before  # no temporary copy


def test_python_api_settings_twice_and_booleans(system: Path, tmp_path: Path) -> None:
    with pytest.raises(ConfigurationError, match="given twice"):
        openemss.run(system, set=["a.k=1", "a.k=1"], out=tmp_path / "a")
    with pytest.raises(ConfigurationError, match="not a Boolean"):
        openemss.run(system, set={"a.u_bool": 2}, out=tmp_path / "b")
    with pytest.raises(ConfigurationError, match="not a number"):
        openemss.run(system, set={"a.k": True}, out=tmp_path / "c")  # a Python bool is no Real
    r = openemss.run(system, set={"a.u_bool": True, "a.k": 2.5}, out=tmp_path / "d", stop_time=0.2, rate=10.0,
                     format="csv")
    assert r.status == "completed" and r.info["parameters"]["a.k"] == 2.5 and r.info["parameters"]["a.u_bool"] is True


def test_a_string_stays_as_given_unless_it_is_a_file(tmp_path: Path, fmu_dir: Path,
                                                     monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "tsys"
    write_system(folder, fmu_dir, [Comp("t", "TextProbe.fmu", TEXT_CONNECTORS)], [], stop_time=0.2)
    work = tmp_path / "work"
    work.mkdir()
    (work / "reference_study").write_text("a file that happens to have a preset's name\n")
    monkeypatch.chdir(work)
    out = tmp_path / "out"
    assert main(["run", str(folder), "--set", "t.label=reference_study", "t.table_file=reference_study",
                 "--out", str(out), "--rate", "10", "--format", "csv"]) == 0, capsys.readouterr().err
    given = json.loads((out / "run.json").read_text())["parameters"]
    assert given["t.label"] == "reference_study"
    assert given["t.table_file"] == str(work / "reference_study")
    rows = (out / "timeseries.csv").read_text().splitlines()
    header, last = rows[0].split(","), rows[-1].split(",")
    assert int(last[header.index("t.label_chars")]) == len("reference_study")
    assert int(last[header.index("t.table_file_chars")]) == len(str(work / "reference_study"))


@pytest.mark.parametrize("value", ["a\udcffb", "bell\x07", "nul\x00"])
def test_a_string_that_is_no_text(tmp_path: Path, fmu_dir: Path, capsys: pytest.CaptureFixture[str],
                                  value: str) -> None:
    """Bytes of a command line that are not UTF-8 (a lone surrogate), control characters, NUL: an FMI String
    (UTF-8, NUL-terminated) would fail at run time or be cut silently; refused where they enter."""
    folder = tmp_path / "tsys"
    write_system(folder, fmu_dir, [Comp("t", "TextProbe.fmu", TEXT_CONNECTORS)], [], stop_time=0.2)
    if "\x00" in value:  # no command line holds a NUL: the Python API does
        with pytest.raises(ConfigurationError, match="not text an FMU can take"):
            openemss.run(folder, set={"t.label": value}, out=tmp_path / "out")
        return
    rc, err = emss(capsys, "run", str(folder), "--set", f"t.label={value}", "--out", str(tmp_path / "out"))
    one_line(rc, err, "--set 't.label=", "not text an FMU can take")


def test_step_multiple_twice_and_stop_time_not_a_number(system: Path, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    rc, err = emss(capsys, "run", str(system), "--step-multiple", "a=2", "a=3", "--out", str(tmp_path / "o"))
    one_line(rc, err, "--step-multiple 'a=3'", "given twice")
    rc, err = emss(capsys, "run", str(system), "--step-multiple", "a=\u00b2", "--out", str(tmp_path / "o"))
    one_line(rc, err, "--step-multiple", "an integer N")
    for bad in (float("nan"), "1", True):
        with pytest.raises(ConfigurationError, match="--stop-time"):
            openemss.run(system, stop_time=bad, out=tmp_path / "o")  # type: ignore[arg-type]
        assert not (tmp_path / "o" / "run.json").exists()  # refused before anything runs


# -- .ssv files ----------------------------------------------------------------------------------
SSV_CASES: dict[str, tuple[str, str, list[str]]] = {
    "parameter_twice": ('<ssv:Parameter name="a.k"><ssv:Real value="1"/></ssv:Parameter>\n'
                        '<ssv:Parameter name="a.k"><ssv:Real value="2"/></ssv:Parameter>\n',
                        'value="2"', ["given twice", "first at {ssv}:{first}"]),
    "boolean_two": ('<ssv:Parameter name="a.u_bool"><ssv:Boolean value="2"/></ssv:Parameter>\n', 'value="2"',
                    ["ssv:Boolean", "'2'"]),
    "integer_401_digits": (f'<ssv:Parameter name="a.u_int"><ssv:Integer value="{"9" * 401}"/></ssv:Parameter>\n',
                           'Integer value', ["ssv:Integer"]),
    "real_underflow": ('<ssv:Parameter name="a.k"><ssv:Real value="1e-999"/></ssv:Parameter>\n', 'value="1e-999"',
                       ["Real value='1e-999'", "it would be 0"]),
    "real_empty": ('<ssv:Parameter name="a.k"><ssv:Real value=""/></ssv:Parameter>\n', 'value=""',
                   ["ssv:Real"]),
}


@pytest.mark.parametrize("case", sorted(SSV_CASES))
def test_hostile_ssv(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    body, marker, fragments = SSV_CASES[case]
    ssv = tmp_path / "p.ssv"
    text = SSV_HEAD + body + SSV_TAIL
    ssv.write_text(text)
    lines = {"ssv": str(ssv), "first": line_of(text, 'value="1"') if case == "parameter_twice" else 0}
    rc, err = emss(capsys, "run", str(system), "--params", str(ssv), "--out", str(tmp_path / "out"))
    one_line(rc, err, f"{ssv}:{line_of(text, marker)}:", *(f.format(**lines) for f in fragments))
    assert ssv.read_text() == text


def test_mapping_two_names_onto_one_variable(system: Path, tmp_path: Path) -> None:
    """Two parameters of one set mapped to the same variable: the second is refused, not silently kept."""
    ssd = system / "SystemStructure.ssd"
    write_ssv(system / "p.ssv", {"gain": 2.0, "k": 3.0})
    (system / "p.ssm").write_text('<?xml version="1.0" encoding="UTF-8"?>\n<ssm:ParameterMapping '
                                  'xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping" '
                                  'version="1.0"><ssm:MappingEntry source="gain" target="k"/></ssm:ParameterMapping>\n')
    text = ssd.read_text().replace('</ssd:Connectors>\n      </ssd:Component>', (
        '</ssd:Connectors>\n        <ssd:ParameterBindings><ssd:ParameterBinding source="p.ssv">'
        '<ssd:ParameterMapping source="p.ssm"/></ssd:ParameterBinding></ssd:ParameterBindings>\n'
        '      </ssd:Component>'), 1)
    ssd.write_text(text)
    with pytest.raises(SystemStructureError, match="parameter 'k': given twice"):
        api.load(system)


# -- .ssp archives: confined, one system, named as the user gave them -----------------------------
def make_ssp(path: Path, ssd: str, fmu: Path, extra: dict[str, str] | None = None) -> Path:
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("SystemStructure.ssd", ssd)
        z.write(fmu, "resources/Gain.fmu")
        for name, text in (extra or {}).items():
            z.writestr(name, text)
    return path


@pytest.mark.parametrize("source", ["../../outside/Gain.fmu", "ABSOLUTE", "resources/../../outside/Gain.fmu"])
def test_ssp_component_outside_the_archive(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                           source: str) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    fmu = shutil.copy2(system / "resources" / "Gain.fmu", outside / "Gain.fmu")
    raw = Path(fmu).read_bytes()
    source = str(fmu) if source == "ABSOLUTE" else source
    text = (system / "SystemStructure.ssd").read_text().replace('source="resources/Gain.fmu"', f'source="{source}"', 1)
    archive = make_ssp(tmp_path / "sys.ssp", text, system / "resources" / "Gain.fmu")
    out = tmp_path / "out"
    rc, err = emss(capsys, "run", str(archive), "--out", str(out))
    one_line(rc, err, f"{archive}!SystemStructure.ssd:{line_of(text, source)}:", "outside the archive", source)
    assert not (out / "run.json").exists() and Path(fmu).read_bytes() == raw
    rc, err = emss(capsys, "validate", str(archive))
    assert rc == 1, err


def test_ssp_parameter_set_outside_the_archive(system: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    write_ssv(tmp_path / "secret.ssv", {"k": 5.0})
    text = (system / "SystemStructure.ssd").read_text().replace(
        '</ssd:Connectors>\n      </ssd:Component>', '</ssd:Connectors>\n        <ssd:ParameterBindings>'
        '<ssd:ParameterBinding source="../secret.ssv"/></ssd:ParameterBindings>\n      </ssd:Component>', 1)
    archive = make_ssp(tmp_path / "sys.ssp", text, system / "resources" / "Gain.fmu")
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    one_line(rc, err, f"{archive}!SystemStructure.ssd:{line_of(text, 'secret.ssv')}:", "'../secret.ssv'",
             "outside the archive")


def test_ssp_errors_name_the_archive_not_its_extraction(system: Path, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    text = (system / "SystemStructure.ssd").read_text().replace('endConnector="u_real"', 'endConnector="nope"', 1)
    archive = make_ssp(tmp_path / "sys.ssp", text, system / "resources" / "Gain.fmu")
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    line = one_line(rc, err, f"{archive}!SystemStructure.ssd:{line_of(text, 'nope')}:", "no connector 'nope'")
    assert "emss_ssp_" not in line and tempfile.gettempdir() + "/" not in line.replace(str(tmp_path), "")
    bad_xml = text.replace("</ssd:Connections>", "</ssd:Connection>")
    archive = make_ssp(tmp_path / "xml.ssp", bad_xml, system / "resources" / "Gain.fmu")
    rc = main(["validate", str(archive)])
    printed = capsys.readouterr().out.splitlines()
    where = f"{archive}!SystemStructure.ssd:{line_of(bad_xml, '</ssd:Connection>')}:"
    assert rc == 1 and printed[0].startswith(where), printed


def test_ssp_with_two_system_descriptions(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = (system / "SystemStructure.ssd").read_text()
    archive = make_ssp(tmp_path / "two.ssp", text, system / "resources" / "Gain.fmu",
                       {"variant/SystemStructure.ssd": text.replace("TestSystem", "Other")})
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    one_line(rc, err, str(archive), "2 files named SystemStructure.ssd", "variant/SystemStructure.ssd")


@pytest.mark.parametrize("second", ["SystemStructure.ssd", "./SystemStructure.ssd", "resources/Gain.fmu"])
def test_ssp_holding_one_entry_twice(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     second: str) -> None:
    text = (system / "SystemStructure.ssd").read_text()
    archive = tmp_path / "dup.ssp"
    with zipfile.ZipFile(archive, "w") as z, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zipfile warns of a duplicate name, and writes it
        z.writestr("SystemStructure.ssd", text)
        z.write(system / "resources" / "Gain.fmu", "resources/Gain.fmu")
        z.writestr(second, text.replace('endConnector="u_real"', 'endConnector="y_real"'))
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    one_line(rc, err, f"{archive}!{second}", "a second entry", "given once")


def test_ssp_holding_a_zip_bomb_fmu(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """An FMU of the archive beyond the limits of an archive: refused before anything runs, named inside
    the archive the user gave."""
    fmu = tmp_path / "Gain.fmu"
    with zipfile.ZipFile(system / "resources" / "Gain.fmu") as src, \
            zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            dst.writestr(info, src.read(info))
        dst.writestr("resources/zeros.bin", b"\0" * (8 * 2 ** 20))  # 8 MiB of zeros: about 1000 to 1
    archive = make_ssp(tmp_path / "bomb.ssp", (system / "SystemStructure.ssd").read_text(), fmu)
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    one_line(rc, err, f"{archive}!resources/Gain.fmu!resources/zeros.bin", "zip bomb")
    assert not (tmp_path / "out" / "run.json").exists()


@pytest.mark.parametrize("packed", [False, True])
def test_an_fmu_error_names_the_fmu_not_its_extraction(tmp_path: Path, fmu_dir: Path,
                                                       capsys: pytest.CaptureFixture[str], packed: bool) -> None:
    """A file an FMU looks for in its resources: the error names the FMU as the user gave it (inside the
    archive, for an .ssp), not the temporary folder it was extracted into (removed when the run ends)."""
    folder = tmp_path / "tsys"
    write_system(folder, fmu_dir, [Comp("t", "TextProbe.fmu", TEXT_CONNECTORS)], [], stop_time=0.2)
    system = folder
    if packed:
        system = tmp_path / "t.ssp"
        with zipfile.ZipFile(system, "w") as z:
            z.write(folder / "SystemStructure.ssd", "SystemStructure.ssd")
            z.write(folder / "resources" / "TextProbe.fmu", "resources/TextProbe.fmu")
    rc, err = emss(capsys, "run", str(system), "--set", "t.table_file=nope.csv", "--out", str(tmp_path / "out"))
    fmu = f"{system}!resources/TextProbe.fmu" if packed else str(folder / "resources" / "TextProbe.fmu")
    line = one_line(rc, err, "component 't'", f"(looked at {fmu}!resources/nope.csv)")
    assert "emss_fmu_" not in line and "emss_ssp_" not in line


def test_ssp_corrupt_entry(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    archive = make_ssp(tmp_path / "bad.ssp", (system / "SystemStructure.ssd").read_text(),
                       system / "resources" / "Gain.fmu", {"resources/notes.txt": "x" * 5000})
    data = bytearray(archive.read_bytes())
    at = data.rfind(b"x" * 100)  # stored uncompressed: change one byte, the CRC no longer matches
    data[at] = ord("y")
    archive.write_bytes(bytes(data))
    rc, err = emss(capsys, "run", str(archive), "--out", str(tmp_path / "out"))
    one_line(rc, err, f"{archive}!resources/notes.txt", "cannot be extracted")


# -- noise: the error line alone; up-to-date FMUs say nothing; warn= hears the rest --------------
def test_only_the_error_line_and_warnings_to_the_callback(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                          capsys: pytest.CaptureFixture[str], fmu_dir: Path) -> None:
    root = tmp_path / "project"
    (root / "fmus").mkdir(parents=True)
    shutil.copy2(Path(__file__).parent / "fmus" / "gain.py", root / "fmus" / "gain.py")
    folder = root / "ssp"
    write_system(folder, fmu_dir, [Comp("a", "Gain.fmu", GAIN_CONNECTORS)], [], stop_time=0.2, copy_fmus=False)
    monkeypatch.setattr(api, "PACKAGE_ROOT", root)  # a project of its own: its FMUs are built by the run
    heard: list[str] = []
    r = openemss.run(folder, out=tmp_path / "r1", rate=10.0, format="csv", warn=heard.append)
    assert r.status == "completed" and capsys.readouterr().err == ""
    assert heard == [f"built: {folder / 'resources' / 'Gain.fmu'}"], heard
    heard.clear()
    openemss.run(folder, out=tmp_path / "r2", rate=10.0, format="csv", warn=heard.append)
    assert heard == [] and capsys.readouterr().err == ""  # up to date: nothing said
    rc, err = emss(capsys, "run", str(folder), "--set", "a.k=nan", "--out", str(tmp_path / "r3"))
    one_line(rc, err, "--set 'a.k=nan'")
    rc, err = emss(capsys, "info", str(folder), "--set", "a.k=1", "a.k=2")
    one_line(rc, err, "given twice")


# -- the report whatever MPLBACKEND says -----------------------------------------------------------
@pytest.mark.parametrize("backend", ["nonsense", "TkAgg", "module://no.such.backend"])
def test_report_plots_whatever_mplbackend_says(tmp_path: Path, backend: str) -> None:
    code = ("import sys; from openemss.orchestrator.cli.plugins import plugins, load_problems; "
            "names = [m.__name__ for m in plugins()]; "
            "from openemss.report.plots import Figure; from openemss.models.infra.files import figure_bytes; "
            "f = Figure(); f.add_subplot().plot([0, 1], [1, 0]); "
            "open(sys.argv[1], 'wb').write(figure_bytes(f, 'png')); print(load_problems, names)")
    png = tmp_path / "f.png"
    env = {**os.environ, "MPLBACKEND": backend}
    proc = subprocess.run([sys.executable, "-c", code, str(png)], capture_output=True, text=True, env=env,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("[]") and "openemss.report.plugin" in proc.stdout, proc.stdout  # loaded
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
