"""Results folders: one run at a time, nothing stale, nothing written outside, files whole.

* :func:`check_name`: a name that becomes a file or folder name (a study variant, a case) is one
  path component: not empty, not ``.`` or ``..``, no separator, no NUL, at most 255 bytes.
* :func:`atomic_write`: a file a reader may open is written to a temporary file in the same
  folder and renamed over the target, so a reader sees the old file or the new one, never a
  part; a symbolic link in its place is replaced, never followed.
* :func:`open_stream`: a file streamed row by row (timeseries.csv) is created anew, never
  through an existing link.
* :class:`ResultsFolder`: checks ``--out``, takes the folder's lock (a second run into the same
  folder is refused while the first runs), removes what earlier runs wrote there (as recorded in the
  folder's manifest, and only while unchanged) and refuses to replace anything else.
* :func:`stop_on_signals`: SIGINT and SIGTERM ask the execution to stop after the current step.
"""
from __future__ import annotations

import contextlib
import errno
import fcntl
import glob
import json
import os
import signal
import stat
import threading
import zipfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import IO, Any

from openemss.models.infra import files

from .errors import ConfigurationError, EmssError

LOCK_NAME = ".emss.lock"
#: The record of what runs wrote into a results folder: per file (a name relative to the folder), the
#: identity of the file they wrote (device, inode) and, once the run closed it, its size and modification
#: time. Only a file whose identity (and, when closed, size and time) still match is ever removed.
MANIFEST_NAME = ".emss-files.json"
MANIFEST_FORMAT = 1
#: Files of a run that the orchestrator itself writes besides its time series (whose names the run gives,
#: from its formats' registry); the plugins name theirs (``output_files``).
RUN_FILES = ("run.json", "cli_parameters.ssv")
#: Limits of a zip archive (.ssp, .fmu) before anything is extracted.
MAX_ARCHIVE_ENTRIES = 10_000
MAX_ARCHIVE_BYTES = 2 * 1024 ** 3  # total uncompressed size [bytes]
MAX_COMPRESSION_RATIO = 200  # uncompressed over compressed size of an entry larger than 1 MiB


class ResultsError(EmssError):
    """A results file or folder that cannot be written (full disk, read-only, a file in the way)."""


def os_reason(exc: OSError) -> str:
    name = errno.errorcode.get(exc.errno or 0, "")
    return f"{exc.strerror or exc}" + (f" ({name})" if name else "")


def check_name(name: str, what: str) -> str:
    """``name`` unchanged if it can be used as one file or folder name.

    Raises
    ------
    ConfigurationError
        Naming ``what`` and what is allowed.
    """
    bad = (not isinstance(name, str) or not name.strip() or name in (".", "..") or "/" in name or "\\" in name
           or "\0" in name or len(name.encode("utf-8", "surrogateescape")) > 255)
    if bad:
        raise ConfigurationError(f"{what} {name!r} cannot be a file or folder name (one path component: not "
                                 "empty, '.' or '..', no '/' or '\\', at most 255 bytes)")
    return name


def atomic_write(path: Path | str, data: str | bytes) -> Path:
    """Write ``data`` to ``path`` whole (:func:`openemss.models.infra.files.atomic_write`: a temporary
    file in the same folder, then a rename; a link in its place is replaced, not followed).

    Raises
    ------
    ResultsError
        When the file cannot be written.
    """
    check_writable(path)
    try:
        files.atomic_write(path, data)
    except OSError as exc:
        raise ResultsError(f"cannot write {path}: {os_reason(exc)}") from None
    record_written(path)
    return Path(path)


def open_stream(path: Path | str) -> IO[bytes]:
    """A new file at ``path`` for streaming (an existing file or link there is removed first, not followed)."""
    path = Path(path)
    check_writable(path)
    try:
        if path.is_symlink() or path.is_file():
            path.unlink()
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o644)
    except OSError as exc:
        raise ResultsError(f"cannot write {path}: {os_reason(exc)}") from None
    record_written(path)
    return os.fdopen(fd, "wb", buffering=0)


def archive_problems(zf: zipfile.ZipFile, archive: Path | str) -> list[tuple[str, str]]:
    """(where, what) of every limit a zip archive (.ssp, .fmu) is beyond: entry count, total size,
    compression ratio (a zip bomb), judged from its directory alone, before anything is extracted."""
    infos = zf.infolist()
    if len(infos) > MAX_ARCHIVE_ENTRIES:
        return [(str(archive), f"{len(infos)} entries, more than {MAX_ARCHIVE_ENTRIES}; refused")]
    out = []
    total = sum(i.file_size for i in infos)
    if total > MAX_ARCHIVE_BYTES:
        out.append((str(archive), f"{total / 1024 ** 2:.0f} MiB uncompressed, more than "
                                  f"{MAX_ARCHIVE_BYTES // 1024 ** 2} MiB; refused"))
    for i in infos:
        if i.file_size > 1024 ** 2 and i.file_size > MAX_COMPRESSION_RATIO * max(i.compress_size, 1):
            out.append((f"{archive}!{i.filename}", f"compressed {i.file_size // max(i.compress_size, 1)} to 1 (more "
                                                   f"than {MAX_COMPRESSION_RATIO} to 1 is refused as a zip bomb)"))
    return out


def check_archive(zf: zipfile.ZipFile, archive: Path | str) -> None:
    """Raise ConfigurationError for the first of :func:`archive_problems`."""
    problems = archive_problems(zf, archive)
    if problems:
        raise ConfigurationError(f"{problems[0][0]}: {problems[0][1]}")


def lock_file(lock: Path, where: str, busy: str) -> int:
    """The descriptor of the file ``lock``, exclusively locked (flock; released by the system if the holder
    dies). The lock file is removed by its holder when done; a lock taken on a file removed meanwhile is
    taken again. A link in its place is replaced, never followed.

    Raises
    ------
    ConfigurationError
        ``where: busy (pid N); ...`` when another process holds it (N read from the file), or when it
        cannot be created.
    """
    for _ in range(5):
        try:
            if lock.is_symlink():
                lock.unlink()
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o644)
        except OSError as exc:
            raise ConfigurationError(f"{where}: cannot create its lock file: {os_reason(exc)}") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.pread(fd, 64, 0).decode("ascii", "replace").strip() or "?"
            os.close(fd)
            raise ConfigurationError(f"{where}: {busy} (pid {holder}); wait for it to end or give another "
                                     "folder") from None
        held = os.fstat(fd)
        try:
            now = os.stat(lock, follow_symlinks=False)
        except FileNotFoundError:
            now = None
        if now is not None and (now.st_ino, now.st_dev) == (held.st_ino, held.st_dev):
            return fd
        os.close(fd)  # the previous holder removed the file between our open and our lock: again
    raise ConfigurationError(f"{where}: cannot take its lock (it keeps changing)")


class ResultsFolder:
    """The folder of one run: checked, locked for the run, cleared of what earlier runs wrote, and kept
    from replacing anything else.

    What a run writes into the folder through :func:`atomic_write`, :func:`open_stream` or
    :func:`record_written` is recorded in the folder's manifest (:data:`MANIFEST_NAME`) with the
    identity of the file written (device, inode) and, once the run is over, its size and modification
    time. The next run into the folder removes exactly those files that are still the ones recorded;
    a file of the user's, a file changed since, or a list of names copied from elsewhere (another
    folder's manifest or run.json) is never removed. While the folder is open, a write that would
    replace a file this run did not write is refused (:class:`ResultsError`), and :meth:`open` refuses
    a folder where such a file stands at a name the run will write.

    Parameters
    ----------
    path : Path
        The folder (created with its parents if missing).
    what : str
        How the user named it, for messages (``--out``).
    names : iterable of str
        Files the run will write (the time series, the plugins' ``output_files``; with ``clear``,
        :data:`RUN_FILES` too), checked free before anything runs.
    clear : bool
        Remove what earlier runs wrote (a new run); False to add to a run's folder (a report made
        again), whose recorded files may then be replaced.
    """

    def __init__(self, path: Path, what: str = "--out", names: Iterable[str] = (), clear: bool = True) -> None:
        self.path = Path(path)
        self.what = what
        self.names = tuple(dict.fromkeys((*RUN_FILES, *names) if clear else names))
        self.clear = clear
        self._fd: int | None = None
        self._key = ""
        self._folder_id: list[int] = []
        self._mine: dict[str, list[int]] = {}  # name -> identity of what this run may replace (its own)
        self._mutex = threading.Lock()  # the Parquet writer records its parts from its own thread

    def open(self) -> ResultsFolder:
        """Create, lock and clear the folder.

        Raises
        ------
        ConfigurationError
            When the folder is a file, cannot be created or written, another run holds it, or a file a
            run of ours did not write stands where this run will write.
        """
        p, what = self.path, self.what
        if p.exists() and not p.is_dir():
            raise ConfigurationError(f"{what} {p}: is a file, not a folder; give a folder for the results")
        try:
            p.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise ConfigurationError(f"{what} {p}: cannot create the results folder: {os_reason(exc)}") from None
        if not os.access(p, os.W_OK | os.X_OK):
            raise ConfigurationError(f"{what} {p}: the folder is not writable; give a folder you may write to")
        fd = self._lock(p / LOCK_NAME)
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
            st = os.stat(p)
            self._folder_id = [st.st_dev, st.st_ino]
            owned = self._read_manifest()
            if self.clear:
                owned = self._clear(owned)
            # what stays the run's to replace: with clear, nothing (a folder of ours left because a file of the
            # user's is in it is in the way); else the files earlier runs wrote, still unchanged
            self._mine = {} if self.clear else {n: e[:2] for n, e in owned.items() if self._matches(n, e)}
            self._check_free()
            self._save()
        except BaseException:
            self._unlock(fd)
            raise
        self._fd = fd
        self._key = os.path.realpath(p)
        _OPEN[self._key] = self
        return self

    def _lock(self, lock: Path) -> int:
        """The descriptor of ``lock``, exclusively locked (:func:`lock_file`)."""
        return lock_file(lock, f"{self.what} {self.path}", "the results folder is in use by another run")

    # -- the manifest ---------------------------------------------------------------------------
    def _read_manifest(self) -> dict[str, list[int]]:
        """The manifest's entries, if it is this folder's own (a manifest copied from another folder
        names other files: it is ignored, and replaced)."""
        try:
            data = json.loads((self.path / MANIFEST_NAME).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}
        if not isinstance(data, dict) or data.get("format") != MANIFEST_FORMAT or data.get("folder") != self._folder_id:
            return {}
        entries = data.get("files")
        if not isinstance(entries, dict):
            return {}
        return {n: e for n, e in entries.items() if _relative_name(n) and isinstance(e, list) and len(e) in (2, 4)
                and all(type(x) is int for x in e)}

    def _matches(self, name: str, entry: list[int]) -> bool:
        """``name`` is still the file (or folder) a run of ours wrote: same device and inode, and, for a
        file closed by its run, the same size and modification time."""
        try:
            st = os.lstat(self.path / name)
        except OSError:
            return False
        if stat.S_ISDIR(st.st_mode):
            return entry[:2] == [st.st_dev, st.st_ino]
        if not stat.S_ISREG(st.st_mode):
            return False
        return entry == ([st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns][:len(entry)])

    def _clear(self, owned: dict[str, list[int]]) -> dict[str, list[int]]:
        """Remove the files of ``owned`` that are still those a run wrote, their temporaries, and then their
        folders when empty; the entries left (changed or gone files) are returned."""
        left = dict(owned)
        folders = [n for n in owned if (self.path / n).is_dir() and not (self.path / n).is_symlink()]
        for name in sorted(owned, key=lambda n: -n.count("/")):  # a folder's files before the folder
            entry, f = owned[name], self.path / name
            try:
                if name in folders:
                    if self._matches(name, entry):
                        for tmp in f.glob(".*.tmp"):  # a half-written part in a folder of ours
                            if tmp.is_file() and not tmp.is_symlink():
                                tmp.unlink()
                        with contextlib.suppress(OSError):  # not empty: a file of the user's is in it
                            f.rmdir()
                elif self._matches(name, entry):
                    f.unlink()
                for tmp in f.parent.glob(f".{glob.escape(f.name)}.*tmp"):  # atomic_write's, of a killed run
                    if tmp.is_file() and not tmp.is_symlink():
                        tmp.unlink()
            except OSError as exc:
                raise ConfigurationError(f"{self.what} {self.path}: cannot remove {name} of an earlier run: "
                                         f"{os_reason(exc)}") from None
            if not os.path.lexists(f):
                del left[name]
        return left

    def _check_free(self) -> None:
        """Refuse the folder when something this run did not write stands where it will write."""
        in_way = [n for n in self.names if os.path.lexists(self.path / n) and n not in self._mine]
        if in_way:
            raise ConfigurationError(
                f"{self.what} {self.path}: holds {', '.join(in_way)}, not written by a run of openEMSS (or changed "
                "since); a run would replace them: move them away or give another folder")

    def _save(self) -> None:
        data = {"format": MANIFEST_FORMAT, "folder": self._folder_id, "files": self._mine,
                "note": "files written by openEMSS runs; the next run removes those still unchanged"}
        try:
            files.atomic_write(self.path / MANIFEST_NAME, json.dumps(data, indent=1) + "\n")
        except OSError as exc:
            raise ResultsError(f"cannot write {self.path / MANIFEST_NAME}: {os_reason(exc)}") from None

    # -- writes of the run ----------------------------------------------------------------------
    def check_writable(self, name: str) -> None:
        """Raise :class:`ResultsError` if ``name`` exists and is not this run's to replace."""
        if name not in self._mine and os.path.lexists(self.path / name):
            raise ResultsError(f"cannot write {self.path / name}: a file this run did not write is there "
                               "(it is left as it is); move it away or give another folder")

    def written(self, name: str) -> None:
        """Record that the run wrote ``name`` (a file or a folder, just created or replaced)."""
        try:
            st = os.lstat(self.path / name)
        except OSError:
            return
        with self._mutex:
            if self._mine.get(name) != [st.st_dev, st.st_ino]:
                self._mine[name] = [st.st_dev, st.st_ino]
                self._save()

    def close(self) -> None:
        """Record the run's files as closed (size and time), remove the lock file and release the lock."""
        if self._fd is None:
            return
        _OPEN.pop(self._key, None)
        with self._mutex:
            closed = {}
            for name, entry in self._mine.items():
                with contextlib.suppress(OSError):
                    st = os.lstat(self.path / name)
                    if [st.st_dev, st.st_ino] == entry[:2]:
                        closed[name] = entry[:2] if stat.S_ISDIR(st.st_mode) else [*entry[:2], st.st_size,
                                                                                   st.st_mtime_ns]
            self._mine = closed
            with contextlib.suppress(ResultsError):  # a full disk: the next run finds them not closed
                self._save()
        self._unlock(self._fd)
        self._fd = None

    def _unlock(self, fd: int) -> None:
        with contextlib.suppress(OSError):
            os.unlink(self.path / LOCK_NAME)
        os.close(fd)

    def __enter__(self) -> ResultsFolder:
        return self.open() if self._fd is None else self

    def __exit__(self, *exc: Any) -> None:
        self.close()


#: The results folders open in this process, by real path.
_OPEN: dict[str, ResultsFolder] = {}


def _relative_name(name: object) -> bool:
    """A manifest name: a file of the folder or of one folder in it, nothing that leaves it."""
    if not isinstance(name, str) or not name or "\\" in name or "\0" in name:
        return False
    parts = name.split("/")
    return len(parts) <= 2 and all(p not in ("", ".", "..") for p in parts)


def _owner(path: Path) -> tuple[ResultsFolder, str] | None:
    """The open results folder that ``path`` is in (directly, or in one folder of it) and its name there."""
    if not _OPEN:
        return None
    parent = os.path.realpath(path.parent)
    folder = _OPEN.get(parent)
    if folder is not None:
        return folder, path.name
    folder = _OPEN.get(os.path.dirname(parent))
    if folder is not None:
        return folder, f"{os.path.basename(parent)}/{path.name}"
    return None


def check_writable(path: Path | str) -> None:
    """Raise :class:`ResultsError` if ``path`` is in an open results folder and holds something the run did
    not write (see :class:`ResultsFolder`)."""
    owner = _owner(Path(path))
    if owner is not None:
        owner[0].check_writable(owner[1])


def record_written(path: Path | str) -> None:
    """Record a file or folder written into an open results folder (no effect elsewhere)."""
    owner = _owner(Path(path))
    if owner is not None:
        owner[0].written(owner[1])


class RunInterrupted(EmssError):  # noqa: N818 - a stop the user asked for, not an error of the run
    """The run was stopped by a signal (SIGINT, SIGTERM); ``exit_code`` is 128 + the signal number."""

    def __init__(self, signum: int, time_s: float) -> None:
        self.signum = signum
        self.exit_code = 128 + signum
        self.time_s = time_s
        super().__init__(f"interrupted by {signal.Signals(signum).name} at t = {time_s:.6g} s")


@contextlib.contextmanager
def stop_on_signals(request_stop: Callable[[int], None]) -> Iterator[None]:
    """While inside, SIGINT and SIGTERM call ``request_stop(signum)`` (the run ends after its current
    step, cleanly); a second signal of either kind has its default effect."""
    previous: dict[int, Any] = {}

    def handler(signum: int, frame: object) -> None:
        for s, h in previous.items():  # a second signal: the default (or former) behaviour
            signal.signal(s, h)
        request_stop(signum)

    try:
        for s in (signal.SIGINT, signal.SIGTERM):
            previous[s] = signal.signal(s, handler)
    except ValueError:  # not the main thread: no handlers (a Dask worker thread, a test)
        previous.clear()
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
