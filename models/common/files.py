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
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

__all__ = ["atomic_write", "csv_text", "figure_bytes"]


def atomic_write(path: str | Path, data: str | bytes) -> Path:
    """Write ``data`` (text as UTF-8) to ``path``: a new temporary file in the same folder, then a rename.

    Raises
    ------
    OSError
        When it cannot be written (the temporary file is removed; ``filename`` is ``path``).
    """
    path = Path(path)
    raw = data.encode("utf-8") if isinstance(data, str) else data
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise OSError(exc.errno, exc.strerror, str(path)) from None
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
