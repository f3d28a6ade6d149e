"""Regenerate the figures of README.md and docs/ from the shipped runs (issue 38 point 1).

    python docs/make.py [--only munich check study hybrid faults] [--work DIR] [--hybrid-study]

runs, from the repository's root and with the ``emss`` of this interpreter:

* ``munich``: ``emss run`` (the shipped system, the Munich mission): the figures of ``docs/munich/`` and its
  ``summary.json``, the mission's fuel, time and conformance table;
* ``study``: ``emss study run studies/engine_redesign.yaml`` (the reference study): ``docs/study/``'s files and
  its figures (design-point SFC change, mission fuel of both engines and its change, fuel per section);
* ``hybrid``: the runs of ``docs/hybrid/README.md`` (the hybrid system with and without energy management,
  boost, the pulse load): its mission table, its pulse table and the figures of its text; the 3 x 3 study
  (about an hour) only with ``--hybrid-study``;
* ``check``: ``emss mission check missions/munich.yaml``: the marginal sections every run warns of;
* ``faults``: ``emss run --scenario scenarios/stuck_aileron.yaml``: the line a lost aircraft stops the run with.

Each figure is written to ``docs/figures.json`` (key -> its text as the docs state it, its value, the command
that made it), and every place README.md or a ``docs/**/*.md`` states it holds it between markers,
``<!--fig:KEY-->text<!--/fig-->``, which this script rewrites (a table is a figure whose text is the table).
``tests/test_docs_figures.py`` fails when a marked text differs from ``figures.json``, and flies the Munich
mission again to compare its figures with it. A part not run keeps its figures from the last run.

This is our own script: the docs are Markdown next to the code, and what generates their figures is the
project's own ``emss`` (no documentation generator of the field runs simulations).
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
FIGURES = DOCS / "figures.json"
#: A stated figure: ``<!--fig:KEY-->text<!--/fig-->`` (text may span lines: a table).
MARKER = re.compile(r"<!--fig:(?P<key>[\w.-]+)-->(?P<text>.*?)<!--/fig-->", re.S)
Figures = dict[str, dict[str, Any]]


def documents() -> list[Path]:
    """The files whose figures are marked: README.md and every Markdown file under docs/."""
    return [ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]


def fig(out: Figures, key: str, text: str, value: Any, command: str) -> None:
    """Record figure ``key``: its ``text`` as stated, its ``value``, the ``command`` that produced it."""
    out[key] = {"text": text, "value": value, "command": command}


def emss(*args: str) -> subprocess.CompletedProcess[str]:
    """``emss ARGS`` from the repository's root with this interpreter's ``emss`` (its output captured)."""
    exe = Path(sys.executable).parent / "emss"
    argv = [str(exe) if exe.exists() else "emss", *args]
    print("docs/make.py:", " ".join(["emss", *args]), flush=True)
    return subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, check=False)


def _ok(proc: subprocess.CompletedProcess[str]) -> None:
    if proc.returncode != 0:
        raise SystemExit(f"docs/make.py: {' '.join(proc.args[:4])} ... failed (exit {proc.returncode}): "
                         f"{proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ''}")


def _summary(run: Path) -> dict[str, Any]:
    return json.loads((run / "summary.json").read_text(encoding="utf-8"))


def _series(run: Path) -> dict[str, np.ndarray]:
    from openemss.orchestrator.recording.timeseries import read_timeseries

    return read_timeseries(run).floats()


# -- Munich -------------------------------------------------------------------------------------------------
MUNICH_PNGS = ("altitude_mach.png", "attitude.png", "fuel_burned.png", "fuel_flow_tt4.png", "ground_track.png",
               "sfc_surge_margin.png", "spool_speeds.png", "thrust.png")
_SPEED = {"mach": lambda v: f"M {v:.3f}", "cas_m_s": lambda v: f"{v:.1f} m/s", "tas_m_s": lambda v: f"{v:.1f} m/s"}
_SPEED_TARGET = {"mach": lambda v: f"M {v:.2f}", "cas_m_s": lambda v: f"{v:.0f} m/s CAS",
                 "tas_m_s": lambda v: f"{v:.0f} m/s TAS"}


def _m(x: float, digits: int = 1) -> str:
    """A length as the docs write it, the minus sign typeset [m]."""
    return f"{x:.{digits}f}".replace("-", "−") + " m"


def munich_figures(run: Path, command: str = "emss run") -> Figures:
    """The figures the docs state of a Munich run (its results folder ``run``), by key."""
    s = _summary(run)
    out: Figures = {}
    fig(out, "munich.fuel_kg", f"{s['fuel_burned_kg']:.2f}", s["fuel_burned_kg"], command)
    fig(out, "munich.fuel_kg_1", f"{s['fuel_burned_kg']:.1f}", s["fuel_burned_kg"], command)
    fig(out, "munich.time_s", f"{s['sim_time_s']:.2f}", s["sim_time_s"], command)
    fig(out, "munich.time_s_0", f"{s['sim_time_s']:.0f}", s["sim_time_s"], command)
    rows = ["| section (Munich, `emss run`) | target | at its end | worst after capture | to capture |",
            "|---|---|---|---|---|"]
    worst_end = 0.0
    for sec in s["sections"]:
        c = sec.get("conformance")
        if not c or not c.get("altitude"):
            continue
        a, v = c["altitude"], c["speed"]
        worst_end = max(worst_end, abs(a["error_at_end_m"]))
        kind = v["kind"]
        ttc = a["time_to_capture_s"]
        rows.append(f"| {sec['name']} | {a['target_m']:.0f} m, {_SPEED_TARGET[kind](v['target'])} | "
                    f"{a['achieved_m']:.1f} m, {_SPEED[kind](v['achieved'])} | {_m(a['worst_after_capture_m'])} | "
                    f"{'-' if ttc is None else f'{ttc:.0f} s'} |")
    ils = s.get("ils") or {}
    if ils.get("gs_capture_altitude_m") is not None:
        rows.append(f"| ILS {ils['runway'].split('_')[-1]} | glide slope at {ils['approach_altitude_m']:.0f} m | "
                    f"captured at {ils['gs_capture_altitude_m']:.1f} m | localizer {ils['loc_overshoot_m']:.0f} m, "
                    f"glide slope {ils['gs_overshoot_m']:.1f} m overshoot | |")
        fig(out, "munich.gs_capture_error_m", f"{abs(ils['gs_capture_error_m']):.1f}", ils["gs_capture_error_m"],
            command)
    fig(out, "munich.conformance", "\n\n" + "\n".join(rows) + "\n\n", None, command)
    fig(out, "munich.worst_end_error_m", f"{worst_end:.1f}", worst_end, command)
    from openemss.models.fcs.vertical import VNAV_MODES

    d = _series(run)
    on_path = d["fcs.vnav_mode"] == VNAV_MODES.index("PATH")
    dev = float(np.max(np.abs(d["airframe.alt_m"][on_path] - d["fcs.alt_cmd_m"][on_path]))) if on_path.any() else 0.0
    fig(out, "munich.path_deviation_m", f"{dev:.0f}", dev, command)
    life = s.get("life") or {}
    for disc in life.get("discs", []):
        key = "hp" if disc.get("spool") == "N2" else "fan"
        if disc.get("equivalent_cycles") is not None:
            fig(out, f"munich.{key}_disc_cycles", f"{disc['equivalent_cycles']:.2f}", disc["equivalent_cycles"],
                command)
    return out


def munich(work: Path, figures: Figures) -> Path:
    """Fly the Munich mission, copy its figures into docs/munich/, record its figures."""
    run = work / "munich"
    _ok(emss("run", "--out", str(run)))
    for name in MUNICH_PNGS:
        shutil.copy2(run / name, DOCS / "munich" / name)
    shutil.copy2(run / "summary.json", DOCS / "munich" / "summary.json")
    figures.update(munich_figures(run))
    return run


# -- the reference study ---------------------------------------------------------------------------------------
STUDY_FILES = {"report/report.md": "report.md", "report/fuel_burned.png": "fuel_burned.png",
               "report/section.png": "section.png", "cycle/carpet.png": "carpet.png",
               "cycle/redesign.json": "redesign.json", "study.csv": "study.csv"}


def _pct(x: float) -> str:
    return f"{x:+.1f} %".replace("+", "+" if x > 0 else "")


def study(work: Path, figures: Figures) -> None:
    """Run the reference study, copy its files into docs/study/, record its figures."""
    out = work / "study"
    cmd = "emss study run studies/engine_redesign.yaml"
    _ok(emss("study", "run", "studies/engine_redesign.yaml", "--out", str(out)))
    for src, dst in STUDY_FILES.items():
        shutil.copy2(out / src, DOCS / "study" / dst)
    rep = json.loads((out / "report" / "report.json").read_text(encoding="utf-8"))
    base, red = rep["engines"]["baseline"], rep["engines"]["redesigned"]
    fig(figures, "study.sfc_change_pct", _pct(rep["design_point_SFC_change_pct"]),
        rep["design_point_SFC_change_pct"], cmd)
    fig(figures, "study.fuel_change_pct", _pct(rep["mission_fuel_change_pct"]), rep["mission_fuel_change_pct"], cmd)
    fig(figures, "study.baseline_kg", f"{base['mission_fuel_kg']:.2f}", base["mission_fuel_kg"], cmd)
    fig(figures, "study.redesigned_kg", f"{red['mission_fuel_kg']:.2f}", red["mission_fuel_kg"], cmd)
    fig(figures, "study.time_s", f"{base['sim_time_s']:.2f} s and {red['sim_time_s']:.2f} s",
        [base["sim_time_s"], red["sim_time_s"]], cmd)
    cyc = json.loads((out / "cycle" / "redesign.json").read_text(encoding="utf-8"))
    cb, cr = cyc["baseline"], cyc["redesigned"]
    fig(figures, "study.design_sfc", f"{cr['SFC_kg_N_s'] * 1e6:.2f} mg/(N s) against {cb['SFC_kg_N_s'] * 1e6:.2f} "
        "mg/(N s)", [cr["SFC_kg_N_s"], cb["SFC_kg_N_s"]], cmd)
    fig(figures, "study.design_flow", f"{cr['W2_kg_s']:.2f} kg/s against {cb['W2_kg_s']:.2f} kg/s",
        [cr["W2_kg_s"], cb["W2_kg_s"]], cmd)
    sb, sr = (_summary(out / "cases" / rep["engines"][k]["case"]) for k in ("baseline", "redesigned"))
    rows = ["| section | baseline [kg] | redesigned [kg] | change |", "|---|---|---|---|"]
    for a, b in zip(sb["sections"], sr["sections"], strict=False):
        fa, fb = a["fuel_burned_kg"], b["fuel_burned_kg"]
        rows.append(f"| {a['index']} {a['name']} | {fa:.2f} | {fb:.2f} | {_pct(100.0 * (fb / fa - 1.0))} |")
    fig(figures, "study.sections", "\n\n" + "\n".join(rows) + "\n\n", None, cmd)
    bb, br = (x["life"]["blade"] for x in (sb, sr))
    tb, tr = (x["life"]["time_above_s"]["Tt41_K"]["1300"] for x in (sb, sr))
    fig(figures, "study.blade", f"{br['creep_damage'] / bb['creep_damage']:.1f} times as fast "
        f"({br['creep_damage']:.1e} against {bb['creep_damage']:.1e} per mission)", [br["creep_damage"],
                                                                                     bb["creep_damage"]], cmd)
    fig(figures, "study.blade_metal", f"{br['max_metal_K']:.0f} K against {bb['max_metal_K']:.0f} K, with {tr:.0f} s "
        f"of Tt41 above 1300 K against {tb:.0f} s", [br["max_metal_K"], bb["max_metal_K"], tr, tb], cmd)
    fb, fr = ([d["equivalent_cycles"] for d in x["life"]["discs"] if d["spool"] == "N1"][0] for x in (sb, sr))
    fig(figures, "study.fan_disc_cycles", f"{fr:.3f} against {fb:.3f}", [fr, fb], cmd)
    mb, mr = (x["life"]["mission"]["missions_to_life"] for x in (sb, sr))
    fig(figures, "study.missions_to_life", f"{mr:,.0f} such missions to the first life against {mb:,.0f} "
        f"({100 * (mr / mb - 1):+.1f} %)".replace(",", " "), [mr, mb], cmd)
    for label, summ in (("baseline", sb), ("redesigned", sr)):
        for disc in (summ.get("life") or {}).get("discs", []):
            if disc.get("spool") == "N2" and disc.get("equivalent_cycles") is not None:
                fig(figures, f"study.{label}_hp_disc_cycles", f"{disc['equivalent_cycles']:.3f}",
                    disc["equivalent_cycles"], cmd)


# -- the hybrid-electric system --------------------------------------------------------------------------------
HYBRID_RUNS = (  # key, label in the table, emss run arguments
    ("off", "`ssp/hybrid/`, energy management off (`ems_off.ssv`)", ("ssp/hybrid", "--params",
                                                                     "ssp/hybrid/ems_off.ssv")),
    ("noboost", "`ssp/hybrid/`, no boost (`no_boost.ssv`)", ("ssp/hybrid", "--params", "ssp/hybrid/no_boost.ssv")),
    ("default", "`ssp/hybrid/`, the default law (25 kW boost, 15 kW charge, 5.0 kWh)", ("ssp/hybrid",)),
    ("climbboost", "`ssp/hybrid/`, 40 kW boost (`scenarios/climb_boost.yaml`)",
     ("ssp/hybrid", "--scenario", "scenarios/climb_boost.yaml")),
    ("pulse", None, ("ssp/hybrid", "--scenario", "scenarios/pulse_load_7500m.yaml")),
)
#: The climb the table times: the first sample within the conformance's capture band of this altitude [m].
CLIMB_ALT_M = 5000.0


def _to_climb(run: Path) -> tuple[float, float]:
    """Time [s] and burned fuel [kg] when the run first came within the capture band of CLIMB_ALT_M."""
    from openemss.report.conformance import CAPTURE_BAND_M

    d = _series(run)
    i = int(np.argmax(d["airframe.alt_m"] >= CLIMB_ALT_M - CAPTURE_BAND_M))
    return float(d["time_s"][i]), float(d["engine.fuel_burned_kg"][i])


def _row(label: str, run: Path) -> tuple[str, dict[str, float]]:
    s = _summary(run)
    t5, f5 = _to_climb(run)
    v = {"fuel": s["fuel_burned_kg"], "time": s["sim_time_s"], "t5": t5, "f5": f5}
    e = s.get("electric")
    if e is None:
        return f"| {label} | {v['fuel']:.3f} | {v['time']:.2f} | - | - | - | - | - | {t5:.2f}, {f5:.3f} |", v
    en = e["energy_kWh"]
    v.update(soc_end=e["soc"]["end"], soc_min=e["soc"]["min"], losses=en["losses_kWh"])
    cells = [f"{v['fuel']:.3f}", f"{v['time']:.2f}", f"{e['soc']['end']:.3f}", f"{e['soc']['min']:.3f}"]
    cells += [f"{en[k]:+.3f}" for k in ("battery_kWh", "lp_shaft_kWh", "losses_kWh")]
    return f"| {label} | {' | '.join(cells)} | {t5:.2f}, {f5:.3f} |", v


def hybrid(work: Path, figures: Figures, munich_run: Path | None, grid: bool) -> None:
    """Fly the hybrid runs, write docs/hybrid's tables and figures (and the 3 x 3 study with ``grid``)."""
    runs: dict[str, Path] = {}
    for key, _, args in HYBRID_RUNS:
        runs[key] = work / f"hybrid_{key}"
        _ok(emss("run", *args, "--out", str(runs[key])))
    base = munich_run if munich_run is not None else work / "munich"
    if not (base / "summary.json").is_file():
        base = munich(work, figures)
    cmd = "python docs/make.py --only hybrid (docs/hybrid/README.md lists its runs)"
    head = ("| run | fuel [kg] | mission time [s] | final SOC | lowest SOC | battery energy [kWh] | LP shaft [kWh] | "
            "machine losses [kWh] | to 5000 m: time [s], fuel [kg] |")
    rows = [head, "|" + "---|" * 9]
    vals: dict[str, dict[str, float]] = {}
    row, vals["base"] = _row("`ssp/` (no electrical system, 2100 kg)", base)
    rows.append(row)
    for key, label, _ in HYBRID_RUNS:
        if label is not None:
            row, vals[key] = _row(label, runs[key])
            rows.append(row)
    fig(figures, "hybrid.missions", "\n\n" + "\n".join(rows) + "\n\n", None, cmd)
    b, off, nb, dl, cb = (vals[k] for k in ("base", "off", "noboost", "default", "climbboost"))
    fig(figures, "hybrid.system_cost", f"{off['fuel'] - b['fuel']:.2f} kg of fuel "
        f"({100 * (off['fuel'] / b['fuel'] - 1):.1f} %) over the mission ({off['fuel']:.2f} kg against "
        f"{b['fuel']:.2f} kg)", off["fuel"] - b["fuel"], cmd)
    fig(figures, "hybrid.boost_climb", f"{cb['f5'] - nb['f5']:+.2f} kg ({100 * (cb['f5'] / nb['f5'] - 1):+.1f} %; "
        f"{cb['f5']:.2f} kg against {nb['f5']:.2f} kg)", cb["f5"] - nb["f5"], cmd)
    fig(figures, "hybrid.boost_mission", f"{cb['fuel'] - nb['fuel']:+.2f} kg "
        f"({100 * (cb['fuel'] / nb['fuel'] - 1):+.1f} %)", cb["fuel"] - nb["fuel"], cmd)
    fig(figures, "hybrid.default_law", f"{dl['f5'] - nb['f5']:+.2f} kg to 5000 m, {dl['fuel'] - nb['fuel']:+.2f} "
        "kg over the mission", [dl["f5"] - nb["f5"], dl["fuel"] - nb["fuel"]], cmd)
    fig(figures, "hybrid.boost_losses", f"{cb['losses'] - nb['losses']:.2f} kWh", cb["losses"] - nb["losses"], cmd)
    res = _summary(runs["default"])["electric"]["balance_residual_J"]
    fig(figures, "hybrid.balances", f"machines (shaft - electrical - losses) {res['machines']:.1e} J, the bus "
        f"{res['bus']:.1e} J", [res["machines"], res["bus"]], cmd)
    window = _pulse(runs["pulse"], runs["default"], figures, cmd)
    shutil.copy2(runs["default"] / "electric.png", DOCS / "hybrid" / "electric.png")
    if window is not None:  # the pulse against the same flight without it, a minute either side
        plots = work / "hybrid_pulse_compare"
        _ok(emss("plot", str(runs["default"]), str(runs["pulse"]), "--out", str(plots), "--window",
                 f"{window[0] - 60.0:.0f}", f"{window[1] + 60.0:.0f}"))
        for name in ("fuel_flow_tt4.png", "electric.png"):
            shutil.copy2(plots / name, DOCS / "hybrid" / f"pulse_{name}")
    if grid:
        _ok(emss("study", "run", "studies/hybrid.yaml", "--out", str(work / "study-hybrid")))
        proc = subprocess.run([sys.executable, "-m", "openemss.study.grid", str(work / "study-hybrid"),
                               str(DOCS / "hybrid")], cwd=ROOT, check=False)
        if proc.returncode != 0:
            raise SystemExit("docs/make.py: python -m openemss.study.grid failed")


#: The pulse table's rows: label, column, scale to the unit shown, digits.
PULSE_ROWS = (("HP shaft offtake [kW]", "electric.offtake_hp_W", 1e-3, 2), ("N2 [%]", "engine.N2_pct", 1.0, 2),
              ("N1 [%]", "engine.N1_pct", 1.0, 2), ("Tt4 [K]", "engine.Tt4_K", 1.0, 1),
              ("HPC surge margin [-]", "engine.SM_hpc", 1.0, 3), ("fuel flow [kg/s]", "engine.Wf_kg_s", 1.0, 4),
              ("battery power [kW]", "electric.battery_W", 1e-3, 1))
PULSE_LOAD_W = 50e3  # the pulse: where the pulse load exceeds this [W]
PULSE_MEAN_S = 20.0  # means over the pulse's last seconds [s]


def _pulse(pulse: Path, without: Path, figures: Figures, cmd: str) -> tuple[float, float] | None:
    """The pulse table: means over the last PULSE_MEAN_S of the pulse, with and without it; the pulse's start
    and end [s] (None: no pulse)."""
    p, w = _series(pulse), _series(without)
    on = p["electric.pulse_W"] > PULSE_LOAD_W
    if not on.any():
        return None
    t0, t1 = float(p["time_s"][on][0]), float(p["time_s"][on][-1])
    mp = (p["time_s"] >= t1 - PULSE_MEAN_S) & (p["time_s"] <= t1)
    mw = (w["time_s"] >= t1 - PULSE_MEAN_S) & (w["time_s"] <= t1)
    rows = ["| | without | with the pulse | change |", "|---|---|---|---|"]
    for label, col, k, dg in PULSE_ROWS:
        if col not in p or col not in w:
            continue
        a, b = k * float(np.mean(w[col][mw])), k * float(np.mean(p[col][mp]))
        rows.append(f"| {label} | {a:.{dg}f} | {b:.{dg}f} | {b - a:+.{dg}f} |")
    fig(figures, "hybrid.pulse", "\n\n" + "\n".join(rows) + "\n\n", None, cmd)
    fig(figures, "hybrid.pulse_window", f"t = {t0:.2f} s to {t1:.2f} s", [t0, t1], cmd)
    after = t1 + 60.0  # from the start of the pulse to a minute after it
    fuel = [float(np.interp(after, d["time_s"], d["engine.fuel_burned_kg"])
                  - np.interp(t0, d["time_s"], d["engine.fuel_burned_kg"])) for d in (p, w)]
    fig(figures, "hybrid.pulse_fuel", f"{fuel[0]:.3f} kg against {fuel[1]:.3f} kg ({fuel[0] - fuel[1]:+.3f} kg)",
        fuel, cmd)
    lim = p["electric.hp_limited"] > 0.5
    fig(figures, "hybrid.pulse_hp_limited_s", f"{float(np.sum(np.diff(p['time_s'])[lim[:-1]])):.1f}",
        float(np.sum(np.diff(p["time_s"])[lim[:-1]])), cmd)
    fp, fw = _summary(pulse)["fuel_burned_kg"], _summary(without)["fuel_burned_kg"]
    fig(figures, "hybrid.pulse_mission", f"{fp:.3f} kg against {fw:.3f} kg ({fp - fw:+.3f} kg", fp - fw, cmd)
    return t0, t1


# -- the mission check -----------------------------------------------------------------------------------------
def check(work: Path, figures: Figures) -> None:
    """The pre-run check of the shipped mission: its marginal sections (the warning every run prints)."""
    cmd = "emss mission check missions/munich.yaml --json"
    proc = emss("mission", "check", "missions/munich.yaml", "--json")
    if proc.returncode not in (0, 1):  # 1: findings
        raise SystemExit(f"docs/make.py: {cmd} failed (exit {proc.returncode})")
    (work / "mission_check.json").write_text(proc.stdout, encoding="utf-8")
    d = json.loads(proc.stdout)
    said = []
    for sec in d["sections"]:
        if sec["verdict"] != "marginal":
            continue
        need, make = abs(sec["required_gradient"]), abs(sec["achievable_gradient"])
        said.append(f"section {sec['index']} (from {sec['alt_from_m']:.0f} m to {sec['alt_to_m']:.0f} m over "
                    f"{sec['distance_m'] / 1e3:.1f} km) is *marginal*: the aircraft makes {100 * make:.1f} % against "
                    f"the {100 * need:.1f} % needed, a margin of {100 * (make / need - 1):.0f} %")
    fig(figures, "check.marginal", "; ".join(said) if said else "no section is marginal", len(said), cmd)
    fig(figures, "check.margin_pct", f"{100 * d['margin']:.0f}", d["margin"], cmd)


# -- faults ----------------------------------------------------------------------------------------------------
def faults(work: Path, figures: Figures) -> None:
    """The stuck aileron: the line the lost aircraft stops the run with (its time and cause)."""
    cmd = "emss run --scenario scenarios/stuck_aileron.yaml"
    proc = emss("run", "--scenario", "scenarios/stuck_aileron.yaml", "--out", str(work / "stuck_aileron"))
    lost = [ln for ln in proc.stderr.splitlines() if "aircraft lost" in ln]
    if proc.returncode == 0 or not lost:
        raise SystemExit(f"docs/make.py: {cmd} did not stop with a lost aircraft (exit {proc.returncode})")
    m = re.search(r"aircraft lost at t = ([\d.]+) s: ([^,;(]+)", lost[0])
    if m is None:
        raise SystemExit(f"docs/make.py: {cmd}: no time and cause in {lost[0]!r}")
    fig(figures, "faults.stuck_aileron", f"`aircraft lost at t = {m.group(1)} s: {m.group(2).strip()}`",
        float(m.group(1)), cmd)


# -- the docs --------------------------------------------------------------------------------------------------
def rewrite(figures: Figures) -> list[str]:
    """Put every marked figure's text in place; returns the markers whose key has no figure."""
    unknown = []
    for path in documents():
        text = path.read_text(encoding="utf-8")

        def put(m: re.Match[str], path: Path = path) -> str:
            key = m.group("key")
            if key not in figures:
                unknown.append(f"{path.relative_to(ROOT)}: {key}")
                return m.group(0)
            return f"<!--fig:{key}-->{figures[key]['text']}<!--/fig-->"

        new = MARKER.sub(put, text)
        if new != text:
            path.write_text(new, encoding="utf-8")
    return unknown


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python docs/make.py", description=__doc__.split("\n\n")[0])
    parts = ("munich", "check", "study", "hybrid", "faults")
    parser.add_argument("--only", nargs="+", choices=parts, default=list(parts), help="the parts to run")
    parser.add_argument("--work", type=Path, default=None,
                        help="a new folder for the runs (default results/docs-<time>: a study resumes the cases "
                             "it finds done, so each make gets its own)")
    parser.add_argument("--hybrid-study", action="store_true", help="also run studies/hybrid.yaml (about an hour)")
    a = parser.parse_args(argv)
    work = (a.work or ROOT / "results" / f"docs-{time.strftime('%Y%m%d-%H%M%S')}").resolve()
    if work.exists() and any(work.iterdir()):
        print(f"docs/make.py: --work {work}: not empty; give a new folder (runs found there would be reused)",
              file=sys.stderr)
        return 2
    work.mkdir(parents=True, exist_ok=True)
    figures: Figures = json.loads(FIGURES.read_text(encoding="utf-8")) if FIGURES.is_file() else {}
    steps: dict[str, Callable[[], Any]] = {
        "munich": lambda: munich(work, figures), "study": lambda: study(work, figures),
        "hybrid": lambda: hybrid(work, figures, work / "munich" if "munich" in a.only else None, a.hybrid_study),
        "check": lambda: check(work, figures), "faults": lambda: faults(work, figures)}
    for part in parts:
        if part in a.only:
            steps[part]()
            FIGURES.write_text(json.dumps(figures, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    unknown = rewrite(figures)
    for u in unknown:
        print(f"docs/make.py: no figure for the marker {u}", file=sys.stderr)
    return 1 if unknown else 0


if __name__ == "__main__":
    sys.exit(main())
