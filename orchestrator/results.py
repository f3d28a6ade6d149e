"""Results folders: one run at a time, nothing stale, nothing written outside, files whole.

* :func:`check_name`: a name that becomes a file or folder name (a study variant, a case) is one
  path component: not empty, not ``.`` or ``..``, no separator, no NUL, at most 255 bytes.
* :func:`atomic_write`: a file a reader may open is written to a temporary file in the same
  folder and renamed over the target, so a reader sees the old file or the new one, never a
  part; a symbolic link in its place is replaced, never followed.
* :func:`open_stream`: a file streamed row by row (timeseries.csv) is created anew, never
  through an existing link.
* :class:`ResultsFolder`: checks ``--out``, takes the folder's lock (a second run into the same
  folder is refused while the first runs) and removes what an earlier run left there.
* :func:`stop_on_signals`: SIGINT and SIGTERM ask the execution to stop after the current step.
"""
from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import os
import signal
import zipfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from openemss.models.common import files

from .errors import ConfigurationError, EmssError

LOCK_NAME = ".emss.lock"
#: Files of a run, removed from a reused folder before a new run (besides those its run.json lists).
RUN_FILES = ("timeseries.csv", "timeseries.mat", "run.json", "summary.json", "cli_parameters.ssv")
STALE_PATTERNS = ("*.png", "mission.*", ".*.tmp", "report*.html")
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
    """Write ``data`` to ``path`` whole (:func:`openemss.models.common.files.atomic_write`: a temporary
    file in the same folder, then a rename; a link in its place is replaced, not followed).

    Raises
    ------
    ResultsError
        When the file cannot be written.
    """
    try:
        return files.atomic_write(path, data)
    except OSError as exc:
        raise ResultsError(f"cannot write {path}: {os_reason(exc)}") from None


def open_stream(path: Path | str) -> IO[bytes]:
    """A new file at ``path`` for streaming (an existing file or link there is removed first, not followed)."""
    path = Path(path)
    try:
        if path.is_symlink() or path.is_file():
            path.unlink()
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o644)
    except OSError as exc:
        raise ResultsError(f"cannot write {path}: {os_reason(exc)}") from None
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


class ResultsFolder:
    """The folder of one run: checked, locked for the run, cleared of an earlier run's files.

    Parameters
    ----------
    path : Path
        The folder (created with its parents if missing).
    what : str
        How the user named it, for messages (``--out``).
    """

    def __init__(self, path: Path, what: str = "--out") -> None:
        self.path = Path(path)
        self.what = what
        self._fd: int | None = None

    def open(self) -> ResultsFolder:
        """Create, lock and clear the folder.

        Raises
        ------
        ConfigurationError
            When the folder is a file, cannot be created or written, or another run holds it.
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
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        self._fd = fd
        self._clear()
        return self

    def _lock(self, lock: Path) -> int:
        """The descriptor of ``lock``, exclusively locked (flock; released by the system if the run dies).
        The lock file is removed when the run ends; a lock taken on a file removed meanwhile is taken again."""
        for _ in range(5):
            try:
                if lock.is_symlink():
                    lock.unlink()
                fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o644)
            except OSError as exc:
                raise ConfigurationError(f"{self.what} {self.path}: cannot create its lock file: "
                                         f"{os_reason(exc)}") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                holder = os.pread(fd, 64, 0).decode("ascii", "replace").strip() or "?"
                os.close(fd)
                raise ConfigurationError(f"{self.what} {self.path}: the results folder is in use by another run "
                                         f"(pid {holder}); wait for it to end or give another folder") from None
            held = os.fstat(fd)
            try:
                now = os.stat(lock, follow_symlinks=False)
            except FileNotFoundError:
                now = None
            if now is not None and (now.st_ino, now.st_dev) == (held.st_ino, held.st_dev):
                return fd
            os.close(fd)  # the previous run removed the file between our open and our lock: again
        raise ConfigurationError(f"{self.what} {self.path}: cannot take the folder's lock (it keeps changing)")

    def _clear(self) -> None:
        """Remove the files an earlier run wrote here (those its run.json lists, and the usual ones)."""
        names: set[str] = set(RUN_FILES)
        try:
            listed = json.loads((self.path / "run.json").read_text(encoding="utf-8")).get("files", [])
            names.update(n for n in listed if isinstance(n, str))
        except (OSError, ValueError, AttributeError):
            pass
        stale = [self.path / n for n in names if n not in (".", "..") and "/" not in n and "\\" not in n]
        for pattern in STALE_PATTERNS:
            stale.extend(self.path.glob(pattern))
        for f in stale:
            try:
                if f.is_symlink() or f.is_file():
                    f.unlink()
            except OSError as exc:
                raise ConfigurationError(f"{self.what} {self.path}: cannot remove {f.name} of an earlier run: "
                                         f"{os_reason(exc)}") from None

    def close(self) -> None:
        """Remove the lock file and release the lock."""
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.unlink(self.path / LOCK_NAME)
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> ResultsFolder:
        return self.open() if self._fd is None else self

    def __exit__(self, *exc: Any) -> None:
        self.close()


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
