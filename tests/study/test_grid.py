"""Grid figures of a study: each value lands in the cell of its two grid values; failed cases are empty."""
from __future__ import annotations

import csv
from pathlib import Path

from openemss.study.grid import write_grid
from openemss.study.table import OUTCOME_COLUMNS


def test_grid_cells(tmp_path: Path) -> None:
    study = tmp_path / "study"
    study.mkdir()
    cols = ["case", "a", "b", *OUTCOME_COLUMNS]
    with open(study / "study.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for a in (1, 2, 3):
            for b in (10, 20):
                status = "failed" if (a, b) == (3, 20) else "completed"
                w.writerow({"case": f"{a}-{b}", "a": a, "b": b, "status": status,
                            "mission_completed": (a, b) != (2, 10),
                            "fuel_burned_kg": 100 * a + b, "final_soc": a / 10})
    files = write_grid(study, tmp_path / "out")
    assert [p.name for p in files] == ["grid.png", "grid.md", "study.csv"]
    md = (tmp_path / "out" / "grid.md").read_text()
    assert "| b \\ a | 1 | 2 | 3 |" in md
    assert "| 10 | 110 | 210* | 310 |" in md and "| 20 | 120 | 220 | - |" in md
    assert "| 10 | 0.1 | 0.2* | 0.3 |" in md and "a=2, b=10" in md
