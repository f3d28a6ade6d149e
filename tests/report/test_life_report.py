"""summary.json's ``life`` (report/life.py) on synthetic runs, against hand-built references: a run of known
spool-speed cycles gives the counts and damage the life model gives for those cycles alone, the sections' shares
add up to the mission's totals (damage is conserved across the split), the blade's creep at a constant condition
is time over rupture time, the time above a threshold is the time the signal spent above it, and a run without
Tt3 has no blade figure but says why."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from synthetic_runs import BOUNDS, H_S, N, Runs

from openemss.models.life.usage import disc_lcf, load_life_spec
from openemss.report.plugin import write_report
from openemss.report.rundata import load_mission, load_run
from openemss.report.summary import summarize

T = np.arange(N) * H_S


def _life(folder: Path) -> dict:
    run = load_run(folder)
    return summarize(run, load_mission(run)[0])["life"]


def test_life_of_known_cycles(tmp_path: Path) -> None:
    # N2: 80 % -> 100 % in section 1 and back to 85 %, three 85 <-> 95 % cycles in section 2
    n2 = np.full(N, 80.0)
    n2[BOUNDS[0]:BOUNDS[1]] = 100.0
    n2[BOUNDS[1]:] = 85.0
    for k in range(3):
        a = BOUNDS[1] + 100 + 150 * k
        n2[a:a + 50] = 95.0
    n1 = 0.8 * n2
    Tt41 = np.where(n2 > 99.0, 1350.0, 1100.0)
    folder = Runs(tmp_path).make(columns={"engine.N2_pct": n2, "engine.N1_pct": n1, "engine.Tt41_K": Tt41,
                                          "engine.Tt3_K": np.full(N, 600.0)})
    life = _life(folder)
    spec = load_life_spec()
    hp = next(d for d in life["discs"] if d["spool"] == "N2")
    hp_spec = next(d for d in spec.discs if d.spool == "N2")
    # by hand (ASTM E1049-85): reversals 0 (from rest), 100, 85, 95, 85, 95, 85, 95, then 0 (the stop; the 80 and
    # the last 85 are no reversals): three full 85 <-> 95 % cycles and the flight's 0 -> 100 -> 0 as two halves
    sm85, sm95 = (hp_spec.stress_at_design_speed_Pa * (p / 100.0) ** 2 for p in (85.0, 95.0))
    ref_inner = 1.0 / float(hp_spec.material.cycles_to_failure(np.array(sm95), np.array((sm95 - sm85) / 2)))
    ref = disc_lcf(np.array([0.0, 100.0, 0.0]), hp_spec).total + 3 * ref_inner
    assert hp["miner_damage"] == pytest.approx(ref, rel=1e-9)
    assert hp["cycles_counted"] == pytest.approx(1.0 + 3.0)
    # the sections' shares add up to the totals
    per = life["per_section"]
    for d in life["discs"]:
        assert sum(p["lcf_damage"][d["name"]] for p in per) == pytest.approx(d["miner_damage"], rel=1e-12)
    assert sum(p["creep_damage"] for p in per) == pytest.approx(life["blade"]["creep_damage"], rel=1e-12)
    # the three inner cycles start in section 2
    assert per[2]["lcf_damage"][hp["name"]] >= 3 * ref_inner * (1 - 1e-9)
    # creep: Robinson's sum of dt / t_r, the sample closing each interval held over it
    b = spec.blade
    Tm = Tt41 - b.cooling_effectiveness * (Tt41 - 600.0)
    tr = b.material.rupture_time_s(b.stress_at_design_speed_Pa * (n2 / 100.0) ** 2, Tm)
    assert life["blade"]["creep_damage"] == pytest.approx(float(np.sum(H_S / tr[1:])), rel=1e-9)
    # time above: Tt41 1350 K over section 1 (15 s), above 1300 K, not above 1400 K
    assert life["time_above_s"]["Tt41_K"]["1300"] == pytest.approx((BOUNDS[1] - BOUNDS[0]) * H_S)
    assert life["time_above_s"]["Tt41_K"]["1400"] == 0.0
    assert life["mission"]["missions_to_life"] == pytest.approx(
        1.0 / max(life["mission"]["lcf_damage"], life["blade"]["creep_damage"]))
    # every material used says with the run whether its constants were checked against a source (data README)
    assert set(life["data_checked"]) == {d.material.name for d in spec.discs} | {spec.blade.material.name}
    assert all(v.strip() and v != "not said" for v in life["data_checked"].values())


def test_without_tt3_no_blade_but_a_note_and_the_figure(tmp_path: Path) -> None:
    folder = Runs(tmp_path).make(columns={"engine.Tt41_K": np.full(N, 1200.0)})
    life = _life(folder)
    assert life["blade"] is None and "Tt3_K" in life["blade_note"]
    assert life["discs"][0]["equivalent_cycles"] > 0.0           # the start-stop cycle of the flight
    written = write_report(folder)
    assert folder / "life.png" in written


def test_without_spool_speeds_no_life(tmp_path: Path) -> None:
    folder = Runs(tmp_path).make(columns={"engine.N1_pct": None, "engine.N2_pct": None})
    assert _life(folder) is None
