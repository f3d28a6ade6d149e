"""The hostile corpus, data loss (issue 33 point 1): a run, a plot or a summary never deletes or replaces
a file it did not write.

Each case plants files of "the user's" in a folder, runs ``emss`` into it and compares the planted files
byte for byte afterwards (the reference is the bytes the test wrote, not anything the code computed).
A run removes only what a run of ours wrote and recorded in the folder's manifest, and only while it is
unchanged; everything else is left, and a file that stands where a run would write is refused before
anything runs, in one line naming it.
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from openemss.orchestrator.cli.main import main
from openemss.orchestrator.errors import ConfigurationError
from openemss.orchestrator.results import LOCK_NAME, MANIFEST_NAME, ResultsError, ResultsFolder, atomic_write
from systems import wait_for, write_gain_pair


@pytest.fixture()
def system(tmp_path: Path, fmu_dir: Path) -> Path:
    return write_gain_pair(tmp_path / "sys", fmu_dir)


def emss(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, list[str]]:
    try:
        rc = main(list(argv))
    except SystemExit as exc:
        rc = int(exc.code or 0)
    return rc, [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]


def refused(rc: int, err: list[str], *fragments: str) -> None:
    assert rc != 0 and len(err) == 1, err
    assert "Traceback" not in err[0] and "internal error" not in err[0], err
    for f in fragments:
        assert f in err[0], (f, err[0])


def plant(folder: Path, names: list[str]) -> dict[Path, bytes]:
    """Files of the user's: each with its own content; returns what each must still hold."""
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for n in names:
        f = folder / n
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_bytes(f"the user's {n}\n".encode())
        out[f] = f.read_bytes()
    return out


def untouched(planted: dict[Path, bytes]) -> None:
    for f, content in planted.items():
        assert f.is_file() and f.read_bytes() == content, f


def run_ok(capsys: pytest.CaptureFixture[str], system: Path, out: Path, *more: str) -> None:
    rc, err = emss(capsys, "run", str(system), "--out", str(out), *more)
    assert rc == 0, err


# -- the user's files beside a run -----------------------------------------------------------------
@pytest.mark.parametrize("names", [
    ["photo.png", "mission.yaml", "report_v2.html", "notes.txt"],  # the patterns an earlier version cleared
    [".draft.tmp", ".timeseries.csv.x1.tmp", "mission.qgc.plan"],  # hidden temporaries of a look-alike name
    ["results/ground_track.png", "timeseries.parquet.bak/part-00000.parquet"],  # in folders of the user's
])
def test_a_run_beside_the_users_files_keeps_them(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                 names: list[str]) -> None:
    out = tmp_path / "out"
    planted = plant(out, names)
    run_ok(capsys, system, out)
    untouched(planted)
    run_ok(capsys, system, out)  # and again: the second run removes the first's files, not the user's
    untouched(planted)
    assert (out / "timeseries.parquet").is_dir() and not (out / LOCK_NAME).exists()


@pytest.mark.parametrize("name", ["run.json", "timeseries.csv", "timeseries.mat", "summary.json", "report.html",
                                  "ground_track.png", "cli_parameters.ssv"])
def test_a_file_where_a_run_writes_is_refused_before_the_run(system: Path, tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str], name: str) -> None:
    out = tmp_path / "out"
    planted = plant(out, [name])
    rc, err = emss(capsys, "run", str(system), "--out", str(out), "--set", "a.k=2")
    refused(rc, err, str(out), name, "not written by a run of openEMSS", "move them away")
    untouched(planted)
    assert sorted(p.name for p in out.iterdir()) == [name]  # nothing run: no lock, manifest or run.json left


def test_a_folder_in_the_place_of_the_parquet_dataset_is_refused(system: Path, tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    planted = plant(out, ["timeseries.parquet/part-00000.parquet", "timeseries.parquet/mine.txt"])
    rc, err = emss(capsys, "run", str(system), "--out", str(out))
    refused(rc, err, "timeseries.parquet", "not written by a run")
    untouched(planted)


def test_a_copied_run_json_deletes_nothing(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """An earlier version removed every file a run.json in the folder listed."""
    out = tmp_path / "out"
    planted = plant(out, ["thesis.tex", "data.csv", "figure.png"])
    (out / "run.json").write_text(json.dumps({"status": "completed", "files": ["thesis.tex", "data.csv",
                                                                              "figure.png", "../outside.txt"]}))
    outside = plant(tmp_path, ["outside.txt"])
    rc, err = emss(capsys, "run", str(system), "--out", str(out))
    refused(rc, err, "run.json")
    untouched(planted)
    untouched(outside)


def test_a_copied_manifest_deletes_nothing(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A manifest copied from another results folder names that folder's files: it is not this folder's."""
    first = tmp_path / "first"
    run_ok(capsys, system, first, "--format", "csv")
    second = tmp_path / "second"
    planted = plant(second, ["timeseries.csv.keep", "data.txt"])
    shutil.copy2(first / MANIFEST_NAME, second / MANIFEST_NAME)
    for n in ("timeseries.csv", "run.json"):  # the same names, copied: not what a run wrote here
        shutil.copy2(first / n, second / n)
    copies = {second / n: (second / n).read_bytes() for n in ("timeseries.csv", "run.json")}
    rc, err = emss(capsys, "run", str(system), "--out", str(second), "--format", "csv")
    refused(rc, err, "timeseries.csv", "run.json")
    untouched(planted)
    untouched(copies)


def test_a_manifest_naming_files_outside_the_folder_is_not_followed(system: Path, tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    run_ok(capsys, system, out)
    outside = plant(tmp_path, ["outside.txt", "deep/er.txt"])
    manifest = json.loads((out / MANIFEST_NAME).read_text())
    for name in ("../outside.txt", "/etc/hostname", "../deep/er.txt", "a/b/c", ""):
        manifest["files"][name] = [0, 0]
    (out / MANIFEST_NAME).write_text(json.dumps(manifest))
    run_ok(capsys, system, out)
    untouched(outside)


# -- files of a run changed by the user -------------------------------------------------------------
@pytest.mark.parametrize("edit", ["append", "replace", "touch"])
def test_a_run_file_changed_since_is_not_replaced(system: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                  edit: str) -> None:
    out = tmp_path / "out"
    run_ok(capsys, system, out, "--format", "csv")
    f = out / "timeseries.csv"
    if edit == "append":
        with open(f, "a") as h:
            h.write("# my annotation\n")
    elif edit == "replace":  # an editor's save: a new file renamed over the old one
        tmp = out / "edited.tmp"
        tmp.write_bytes(f.read_bytes().replace(b"time_s", b"t"))
        os.replace(tmp, f)
    else:
        st = f.stat()
        os.utime(f, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    kept = {f: f.read_bytes()}
    rc, err = emss(capsys, "run", str(system), "--out", str(out), "--format", "csv")
    refused(rc, err, "timeseries.csv", "or changed since")
    untouched(kept)


def test_a_run_killed_hard_is_cleared_by_the_next(system: Path, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """kill -9: the run never closed its files; they are still the files it wrote, and the next run removes
    them (and the user's file beside them stays)."""
    out = tmp_path / "out"
    planted = plant(out, ["notes.txt"])
    proc = subprocess.Popen([sys.executable, "-m", "openemss.orchestrator.cli", "run", str(system), "--out", str(out),
                             "--stop-time", "120", "--realtime", "1", "--rate", "100", "--format", "csv"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    csv = out / "timeseries.csv"
    wait_for(lambda: csv.is_file() and csv.read_bytes().count(b"\n") > 5, proc, "rows are written")
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    run_ok(capsys, system, out, "--format", "parquet")
    assert not (out / "timeseries.csv").exists()
    untouched(planted)


# -- emss plot and emss summary ---------------------------------------------------------------------
def test_plot_into_a_folder_of_the_users_refuses_their_files(system: Path, tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    run = tmp_path / "run"
    run_ok(capsys, system, run)
    mine = tmp_path / "mine"
    planted = plant(mine, ["plot_a-y_real.png", "plot_a-y_real.html", "notes.txt"])
    rc, err = emss(capsys, "plot", str(run), "a.y_real", "--out", str(mine))
    refused(rc, err, "plot_a-y_real.png", "not written by a run")  # before anything is drawn
    untouched(planted)
    planted.update(plant(mine, ["thrust.png"]))  # a name the report writes: refused before anything is drawn
    rc, err = emss(capsys, "plot", str(run), "a.y_real", "--out", str(mine))
    refused(rc, err, "thrust.png", "not written by a run")
    untouched(planted)


def test_plot_again_replaces_its_own_figures_only(system: Path, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    run = tmp_path / "run"
    run_ok(capsys, system, run)
    planted = plant(run, ["notes.txt"])
    for _ in range(2):  # the second plot replaces the first's files: recorded as written in the folder
        rc, err = emss(capsys, "plot", str(run), "a.y_real")
        assert rc == 0, err
        assert (run / "plot_a-y_real.png").stat().st_size > 0
    untouched(planted)
    run_ok(capsys, system, run)  # the next run removes the plots too: they were ours
    assert not (run / "plot_a-y_real.png").exists()
    untouched(planted)


# -- the guard itself -------------------------------------------------------------------------------
def test_a_write_over_a_file_the_run_did_not_write_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "out"
    with ResultsFolder(out):
        planted = plant(out, ["late.txt"])  # appears while the run goes (another program)
        with pytest.raises(ResultsError, match="did not write"):
            atomic_write(out / "late.txt", "mine")
        atomic_write(out / "own.txt", "1")
        atomic_write(out / "own.txt", "2")  # its own file: replaced
    untouched(planted)
    assert (out / "own.txt").read_text() == "2"
    with ResultsFolder(out):
        pass
    assert not (out / "own.txt").exists()
    untouched(planted)


def test_an_interrupted_open_leaves_no_lock(tmp_path: Path) -> None:
    out = tmp_path / "out"
    plant(out, ["run.json"])
    with pytest.raises(ConfigurationError, match="run.json"):
        ResultsFolder(out).open()
    assert not (out / LOCK_NAME).exists()
    with ResultsFolder(out, names=["other.json"], clear=False) as folder:  # and the lock is free again
        assert folder.path == out
