"""Data files of an FMU: found through the instance's own resources folder, where ``build-fmus`` lays them out
(``DATA_FILES``), or in the repository when the slave runs in place (no resources folder given).

Never beside the module: a host may import the module once and create later instances from other extractions
of the FMU (whose folders it may remove); each instance reads its own copy.
"""
from __future__ import annotations

from pathlib import Path

#: The repository's root, for a slave imported in place (``fmus/../``)
REPOSITORY = Path(__file__).resolve().parent.parent


def data_file(name: str, resources: str | Path | None) -> Path:
    """The path of data file ``name`` (relative to the repository root, e.g. ``missions/munich.yaml``).

    Parameters
    ----------
    name : str
        The file, as listed in the slave's ``DATA_FILES``.
    resources : str or Path or None
        The instance's resources folder (pythonfmu's ``resources`` argument); None for a slave run in place.

    Raises
    ------
    FileNotFoundError
        Naming the path looked at.
    """
    p = (Path(resources) if resources else REPOSITORY) / name
    if not p.is_file():
        where = f"the FMU's resources folder {resources}" if resources else f"the repository {REPOSITORY}"
        raise FileNotFoundError(f"data file '{name}' not found in {where} (looked at {p})")
    return p
