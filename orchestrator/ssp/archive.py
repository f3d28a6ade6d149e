"""Open an ``.ssp`` archive: every entry checked before anything is extracted.

Refused, naming the archive as the user gave it (``archive.ssp!entry``): entries that would be
written outside the extraction folder (absolute paths, ``..``, drive letters, links), two entries
that would be extracted to the same file (the same name twice, or ``./a`` and ``a``: the zip
format allows it and the last would silently win), more than one ``SystemStructure.ssd`` (one at
the root and one in a sub-folder: which system is meant?), none at the root, and the limits of
:func:`..results.archive_problems` (entry count, size, zip bombs).
"""
from __future__ import annotations

import os
import tempfile
import zipfile
import zlib
from pathlib import Path, PurePosixPath

from ..errors import Problem, SystemStructureError
from ..results import archive_problems

SSD_FILE_NAME = "SystemStructure.ssd"


def _parts(name: str) -> tuple[str, ...]:
    """The path components an entry is extracted to (zipfile drops empty and ``.`` components)."""
    return tuple(p for p in PurePosixPath(name.replace("\\", "/")).parts if p not in ("", "."))


def entry_problems(zf: zipfile.ZipFile, archive: Path) -> list[Problem]:
    """Every entry of ``zf`` that is unsafe, given twice, or a second system description."""
    problems = [Problem(where, what) for where, what in archive_problems(zf, archive)]
    if problems:
        return problems
    seen: dict[str, str] = {}
    ssds: list[str] = []
    for info in zf.infolist():
        name = info.filename
        parts = _parts(name)
        is_link = (info.external_attr >> 16) & 0o170000 == 0o120000
        if name.startswith(("/", "\\")) or ".." in parts or (parts and ":" in parts[0]) or is_link:
            problems.append(Problem(f"{archive}!{name}", "unsafe archive entry (absolute path, '..' or link); "
                                                         "entries must stay inside the archive"))
            continue
        key = "/".join(parts)
        if key in seen and not info.is_dir():
            problems.append(Problem(f"{archive}!{name}", f"a second entry extracted to '{key}' (the first: "
                                                         f"'{seen[key]}'); each file must be given once"))
            continue
        seen[key] = name
        if parts and parts[-1].casefold() == SSD_FILE_NAME.casefold() and not info.is_dir():
            ssds.append(name)
    if SSD_FILE_NAME not in seen:
        problems.append(Problem(str(archive), f"archive has no {SSD_FILE_NAME} at its root"))
    if len(ssds) > 1:
        problems.append(Problem(str(archive), f"archive holds {len(ssds)} files named {SSD_FILE_NAME} "
                                              f"({', '.join(ssds)}); an .ssp holds exactly one, at its root"))
    return problems


def extract_archive(archive: Path) -> tempfile.TemporaryDirectory[str]:
    """Extract an .ssp archive into a new temporary folder, refusing unsafe entries.

    Raises
    ------
    SystemStructureError
        With every problem of :func:`entry_problems`; nothing is extracted then.
    """
    archive = Path(archive)
    try:
        zf = zipfile.ZipFile(archive)
    except (OSError, zipfile.BadZipFile) as exc:
        raise SystemStructureError([Problem(str(archive), f"not a readable .ssp (zip) archive: {exc}")]) from None
    with zf:
        problems = entry_problems(zf, archive)
        if problems:
            raise SystemStructureError(problems)
        tmp = tempfile.TemporaryDirectory(prefix="emss_ssp_")
        root = os.path.realpath(tmp.name)
        for info in zf.infolist():
            target = os.path.realpath(os.path.join(root, info.filename))
            if os.path.commonpath([root, target]) != root:  # defence in depth after the checks above
                tmp.cleanup()
                raise SystemStructureError([Problem(f"{archive}!{info.filename}", "entry escapes the archive")])
            try:
                zf.extract(info, root)
            except (zipfile.BadZipFile, zlib.error, NotImplementedError, RuntimeError, OSError) as exc:
                tmp.cleanup()  # corrupt (bad CRC), encrypted, an unknown compression, a full disk
                raise SystemStructureError([Problem(f"{archive}!{info.filename}",
                                                    f"cannot be extracted: {exc}")]) from None
    return tmp
