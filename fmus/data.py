"""Data files of an FMU: found beside its module, as ``build-fmus`` lays them out in the FMU's
resources (``DATA_FILES``), or in the repository (the module imported in place, ``fmus/../``)."""
from __future__ import annotations

from pathlib import Path


def data_file(name: str) -> Path:
    """The path of data file ``name`` (relative to the repository root, e.g. ``missions/munich.yaml``).

    Raises
    ------
    FileNotFoundError
        Naming both places looked at.
    """
    here = Path(__file__).resolve().parent
    for p in (here / name, here.parent / name):
        if p.is_file():
            return p
    raise FileNotFoundError(f"data file '{name}' not found beside {here} or in {here.parent}")
