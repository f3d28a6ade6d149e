"""The figures README.md and docs/ state are those the shipped runs produce (issue 38 point 1).

``python docs/make.py`` runs the shipped runs (the Munich mission, the reference study, the hybrid system's runs,
the stuck aileron), writes ``docs/figures.json`` and puts each figure where the docs state it, between markers
``<!--fig:KEY-->text<!--/fig-->``. Here:

* every marker of README.md and ``docs/**/*.md`` names a figure of ``figures.json`` and holds its text exactly,
  and every figure is stated somewhere (no marker edited by hand, none left stale by a rerun of make.py);
* the Munich mission flown again (the session's build of the shipped FMUs, the shipped parameters) gives every
  Munich figure of ``figures.json``: the same text, i.e. within the digits printed (fuel to 0.01 kg, time to
  0.01 s, the conformance table to 0.1 m and Mach 0.001). The other parts (a study, six hybrid runs) take too
  long for the suite: make.py reruns them.
"""
from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[1]


def _make() -> ModuleType:
    spec = importlib.util.spec_from_file_location("docs_make", ROOT / "docs" / "make.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _figures() -> dict[str, dict]:
    return json.loads((ROOT / "docs" / "figures.json").read_text(encoding="utf-8"))


def test_every_stated_figure_is_the_generated_one() -> None:
    make = _make()
    figures = _figures()
    stated: set[str] = set()
    wrong = []
    for path in make.documents():
        for m in make.MARKER.finditer(path.read_text(encoding="utf-8")):
            key = m.group("key")
            stated.add(key)
            if key not in figures:
                wrong.append(f"{path.relative_to(ROOT)}: {key}: no such figure in docs/figures.json")
            elif m.group("text") != figures[key]["text"]:
                wrong.append(f"{path.relative_to(ROOT)}: {key}: states {m.group('text')!r}, the runs gave "
                             f"{figures[key]['text']!r} (python docs/make.py)")
    assert not wrong, "\n".join(wrong)
    assert sorted(set(figures) - stated) == [], "figures generated but stated nowhere"


def test_the_markers_are_found_where_a_figure_is_written() -> None:
    make = _make()
    text = "a <!--fig:x.y-->1.5<!--/fig--> b <!--fig:t-->\n\n| a |\n|---|\n\n<!--/fig--> c"
    assert [(m.group("key"), m.group("text")) for m in make.MARKER.finditer(text)] == [
        ("x.y", "1.5"), ("t", "\n\n| a |\n|---|\n\n")]


def test_the_munich_figures_are_what_the_shipped_run_gives(munich_run: Path) -> None:
    make = _make()
    figures = _figures()
    again = make.munich_figures(munich_run)
    assert again, "no figure from the Munich run"
    differ = {k: (figures.get(k, {}).get("text"), f["text"]) for k, f in again.items()
              if figures.get(k, {}).get("text") != f["text"]}
    assert not differ, f"stated (docs/figures.json) against flown now: {differ}"
