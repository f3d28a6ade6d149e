"""Files written whole: a reader (a user, a plot viewer, the next run) sees the old file or the new one,
never a part, and a symbolic link in the file's place is replaced, never followed.

The one atomic-write helper of the project; ``openemss.orchestrator.results.atomic_write`` turns its
``OSError`` into the orchestrator's one-line error.
"""
from __future__ import annotations

import contextlib
import csv
import io
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_write", "atomic_copy", "write_whole", "csv_text", "figure_bytes"]


def atomic_write(path: str | Path, data: str | bytes) -> Path:
    """Write ``data`` (text as UTF-8) to ``path``: a new temporary file in the same folder, then a rename.

    Raises
    ------
    OSError
        When it cannot be written (the temporary file is removed; ``filename`` is ``path``).
    """
    raw = data.encode("utf-8") if isinstance(data, str) else data
    return write_whole(path, lambda f: f.write(raw))


def atomic_copy(source: str | Path, path: str | Path) -> Path:
    """Copy the file ``source`` to ``path`` whole, as :func:`atomic_write` (an FMU built elsewhere, maybe on
    another file system, replacing the one a run may be reading).

    Raises
    ------
    OSError
        When it cannot be read or written (the temporary file is removed; ``path`` is left as it was).
    """
    def copy(f: IO[bytes]) -> None:
        with open(source, "rb") as src:
            shutil.copyfileobj(src, f, 1 << 20)

    return write_whole(path, copy)


def write_whole(path: str | Path, write: Callable[[IO[bytes]], object]) -> Path:
    """Write ``path`` whole with ``write(file)``: a temporary file beside it filled by ``write`` (which may
    seek: a zip archive), flushed to the disk (a full disk fails here, not later), then renamed over
    ``path``; the temporary file is removed on any failure or interruption.

    Raises
    ------
    OSError
        When it cannot be written (``filename`` is ``path``, or the file ``write`` failed to read).
    """
    path = Path(path)
    tmp: str | None = None
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        where = exc.filename if exc.filename not in (None, tmp) else str(path)
        raise OSError(exc.errno, exc.strerror, where) from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    return path


def csv_text(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """CSV text of a header and rows (for :func:`atomic_write`)."""
    buffer = io.StringIO(newline="")
    w = csv.writer(buffer)
    w.writerow(header)
    w.writerows(rows)
    return buffer.getvalue()


def figure_bytes(fig: Any, fmt: str = "png", **savefig: Any) -> bytes:
    """A matplotlib figure rendered to bytes (for :func:`atomic_write`)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format=fmt, **savefig)
    return buffer.getvalue()
