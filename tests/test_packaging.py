"""The distribution installs every sub-package of the repository's folders."""
from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_every_package_folder_is_listed_in_pyproject() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    on_disk = set()
    mapped = {(ROOT / folder).resolve() for folder in config["package-dir"].values()}
    for namespace, folder in config["package-dir"].items():
        for init in (ROOT / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / folder).parts
            if rel and init.parent.resolve() in mapped:  # a folder mapped to a package of its own
                continue
            on_disk.add(".".join((namespace, *rel)))
    assert on_disk == listed, {"missing from pyproject": on_disk - listed, "not on disk": listed - on_disk}


def test_console_scripts_resolve() -> None:
    import importlib

    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert set(scripts) == {"emss", "build-fmus"}
    for target in scripts.values():
        module, func = target.split(":")
        assert callable(getattr(importlib.import_module(module), func))
