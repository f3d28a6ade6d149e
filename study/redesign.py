"""The reference study's engine redesign: the cycle sweep picks the lowest-SFC engine.

The ``redesign`` block of a study file runs the parametric cycle study of SPEC.md
(:func:`openemss.models.engine.cycle_study.cycle_study`: BPR 0.5 to 2, OPR 9 to 20,
equal thrust, equal Tt4 and jet velocity ratio) from a reference preset, takes the
design of lowest design-point SFC, and adds two variants to the study: the
baseline engine (the preset) and the redesigned one (the preset with
``design_override`` and every ``design_*`` parameter of the chosen design, whose
design mass flow gives the same thrust).

.. code-block:: yaml

    redesign:
      component: engine              # the engine component of the system (default engine)
      preset: reference_study        # the baseline engine and the sweep's reference
      bpr: {from: 0.5, to: 2.0, num: 7}
      opr: {from: 9.0, to: 20.0, num: 12}
      section: 3                     # mission section (index) whose fuel flow and Tt4 are plotted
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from openemss.models.infra import values as checked
from openemss.orchestrator.results import atomic_write

from .case import write_case_ssv
from .spec import StudyDef, StudyError, Variant, _Ctx, _grid_values, _name, _var_name

__all__ = ["RedesignConfig", "parse_redesign", "cycle_redesign", "BASELINE", "REDESIGNED"]

BASELINE = "baseline"
REDESIGNED = "redesigned"
KEYS = ("component", "preset", "bpr", "opr", "section", "section_variable", "carpet")


@dataclass(frozen=True)
class RedesignConfig:
    """The ``redesign`` block of a study file."""

    component: str = "engine"
    preset: str = "reference_study"
    bprs: tuple[float, ...] = (0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0)
    oprs: tuple[float, ...] = tuple(float(x) for x in range(9, 21))
    section: int = 3
    section_variable: str = "fcs.section_index"
    carpet: bool = False  # fly every feasible design of the sweep, not only the lowest-SFC one (:mod:`.carpet`)


def parse_redesign(study: StudyDef) -> RedesignConfig:
    """Validate the study's ``redesign`` block (one-line errors naming the field)."""
    from openemss.models.engine.design_params import PRESETS_DIR

    d = study.redesign
    ctx = _Ctx(str(study.source))
    for k in d:
        if k not in KEYS:
            raise ctx.fail(d, f"redesign.{k}", f"unknown key; allowed: {', '.join(KEYS)}")
    presets = sorted(p.stem for p in PRESETS_DIR.glob("*.json"))
    try:
        preset = checked.choice(d.get("preset", RedesignConfig.preset), presets)
    except ValueError as exc:
        raise ctx.fail(d, "redesign.preset", str(exc)) from None
    out: dict[str, Any] = {"preset": preset}
    if "component" in d:
        out["component"] = _name(ctx, d, "redesign.component", d["component"])
    for key, attr, lo, hi in (("bpr", "bprs", 0.05, 20.0), ("opr", "oprs", 1.5, 80.0)):
        if key in d:
            vals = _grid_values(ctx, d, f"redesign.{key}", d[key])
            if not all(isinstance(v, int | float) and not isinstance(v, bool) and lo <= v <= hi for v in vals):
                raise ctx.fail(d, f"redesign.{key}", f"values from {lo:g} to {hi:g} expected")
            out[attr] = tuple(float(v) for v in vals)
    if "section" in d:
        try:
            out["section"] = checked.integer(d["section"], 0, 10**6)
        except ValueError as exc:
            raise ctx.fail(d, "redesign.section", f"a section index (0 = the first): {exc}") from None
    if "carpet" in d:
        try:
            out["carpet"] = checked.flag(d["carpet"])
        except ValueError as exc:
            raise ctx.fail(d, "redesign.carpet", str(exc)) from None
    if "section_variable" in d:
        out["section_variable"] = _var_name(ctx, d, "redesign.section_variable", d["section_variable"])
    if study.variants:
        raise ctx.fail(d, "redesign", "a study with a redesign block makes its own variants (baseline, "
                                      "redesigned); remove 'variants'")
    return RedesignConfig(**out)


def cycle_redesign(study: StudyDef, cfg: RedesignConfig, out: Path | None) -> tuple[list[Variant], dict[str, Any]]:
    """Run the cycle sweep, pick the lowest-SFC design; the two engines as variants (with ``carpet``, every
    feasible design of the sweep too), and what was found.

    Writes ``out/cycle/carpet.csv``, ``carpet.png``, ``redesign.json`` and
    ``redesigned_engine.ssv`` (the redesigned engine as a parameter set for ``emss run``); nothing without
    ``out`` (the cases listed, not run).
    """
    from openemss.models.engine.cycle_design import design
    from openemss.models.engine.cycle_study import (
        cycle_study,
        lowest_sfc_design,
        plot_carpet,
        point_params,
        write_csv,
    )
    from openemss.models.engine.design_params import TurbofanParams, load_params, preset_path
    from openemss.models.engine.errors import ModelError
    from openemss.orchestrator.errors import EmssError
    from openemss.orchestrator.ssp.read import load_system
    from openemss.orchestrator.ssp.system import bind_system

    folder = out / "cycle" if out is not None else None
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)
    ref = load_params(preset_path(cfg.preset))
    if not isinstance(ref, TurbofanParams):
        raise StudyError(f"{study.source}: field 'redesign.preset': {cfg.preset} is not a turbofan")
    try:
        points = cycle_study(ref, cfg.bprs, cfg.oprs)
        dp_ref = design(ref)
    except ModelError as exc:
        raise StudyError(f"{study.source}: field 'redesign': the cycle sweep failed: {exc}") from None
    if folder is not None:
        write_csv(points, folder / "carpet.csv")
        plot_carpet(points, folder / "carpet.png", title=f"Cycle sweep from {cfg.preset}")
    try:
        chosen, best = lowest_sfc_design(ref, points)
    except ModelError:
        raise StudyError(f"{study.source}: field 'redesign': no feasible design in the sweep") from None
    dp_new = design(chosen)  # the design the engine FMU will make of these parameters (given mass flow)
    try:
        bound = bind_system(load_system(study.system), list(study.params))
        comp = bound.components[bound.index(cfg.component)]
    except (EmssError, KeyError):
        raise StudyError(f"{study.source}: field 'redesign.component': no component '{cfg.component}' in "
                         f"{study.system}") from None
    known = {f.name for f in fields(TurbofanParams)}
    design_vars = sorted(v for v in comp.variables if v.startswith("design_") and v[7:] in known)
    if "design_override" not in comp.variables or not design_vars:
        raise StudyError(f"{study.source}: field 'redesign.component': {cfg.component} has no design_override "
                         "and design_* parameters")
    c = cfg.component
    base_values: tuple[tuple[str, Any], ...] = ((f"{c}.preset", cfg.preset),)

    def engine_values(p: TurbofanParams) -> tuple[tuple[str, Any], ...]:
        return (*base_values, (f"{c}.design_override", True), *((f"{c}.{v}", float(getattr(p, v[7:])))
                                                               for v in design_vars))

    new_values = engine_values(chosen)
    if folder is not None:
        write_case_ssv(folder / "redesigned_engine.ssv", new_values)
    variants = [Variant(BASELINE, values=base_values), Variant(REDESIGNED, values=new_values)]
    carpet: list[dict[str, Any]] = []
    for p in points if cfg.carpet else ():  # every design of the sweep flown (the lowest-SFC one is REDESIGNED)
        name = None
        if math.isfinite(p.SFC_kg_N_s):
            name = REDESIGNED if (p.BPR, p.OPR) == (best.BPR, best.OPR) else f"bpr{p.BPR:g}-opr{p.OPR:g}"
            if name != REDESIGNED:
                variants.append(Variant(name, values=engine_values(point_params(ref, p))))
        carpet.append({"BPR": p.BPR, "OPR": p.OPR, "SFC_kg_N_s": p.SFC_kg_N_s if name else None,
                       "variant": name, "note": p.note})
    info = {
        "preset": cfg.preset,
        "baseline": {"BPR": ref.BPR, "OPR": dp_ref.OPR, "W2_kg_s": dp_ref.W2_kg_s, "Fn_N": dp_ref.Fn_N,
                     "SFC_kg_N_s": dp_ref.SFC_kg_N_s},
        "redesigned": {"BPR": chosen.BPR, "OPR": dp_new.OPR, "W2_kg_s": dp_new.W2_kg_s, "Fn_N": dp_new.Fn_N,
                       "SFC_kg_N_s": dp_new.SFC_kg_N_s, "PR_fan_outer": chosen.PR_fan_outer,
                       "PR_fan_inner": chosen.PR_fan_inner, "PR_hpc": chosen.PR_hpc},
        "sweep": {"bpr": list(cfg.bprs), "opr": list(cfg.oprs), "points": len(points),
                  "feasible": sum(math.isfinite(p.SFC_kg_N_s) for p in points)},
        "design_point_SFC_change_pct": 100.0 * (dp_new.SFC_kg_N_s / dp_ref.SFC_kg_N_s - 1.0),
    }
    if cfg.carpet:
        info["carpet"] = carpet
    if folder is not None:
        atomic_write(folder / "redesign.json", json.dumps(info, indent=2, default=float) + "\n")
    return variants, info


def planned_variants(study: StudyDef) -> list[Variant]:
    """The two engines :func:`cycle_redesign` will add, as far as they are known before the sweep (the
    redesigned engine's ``design_*`` values are not): so that ``emss study cases`` counts and names the
    cases that run."""
    cfg = parse_redesign(study)
    if cfg.carpet:  # which designs fly is known from the sweep alone (seconds): run it, write nothing
        return cycle_redesign(study, cfg, None)[0]
    base = ((f"{cfg.component}.preset", cfg.preset),)
    return [Variant(BASELINE, values=base), Variant(REDESIGNED, values=(*base, (f"{cfg.component}.design_override",
                                                                                True)))]
