"""Study files: YAML, validated with one-line errors that name the file, line and field.

A study names one SSP system and what varies; every combination of a variant, a
grid point, a mission and a scenario is one case (:func:`expand_cases`).

.. code-block:: yaml

    study: engine_redesign            # name [A-Za-z0-9_.-]
    description: text                 # optional
    system: ../ssp                    # folder with SystemStructure.ssd, an .ssd or an .ssp (relative to this file)
    stop_time_s: 4000                 # optional, default: the SSD's DefaultExperiment
    rate_hz: 20                       # optional communication rate [Hz]
    algorithm: jacobi                 # optional: a name of orchestrator/master/algorithm_registry.py (emss run --help)
    record: [engine.*, fcs.section_index]   # optional: variables to record (default: every connector)
    record_every: 1                   # optional
    pre_run: false                    # optional: the plugins' pre-run checks (a mission's feasibility) before
                                      # each case, into its stderr.log (seconds of set-up per case; the table
                                      # has what each case flew)
    figures: false                    # optional: each case draws its figures (plots, report.html) as emss run
                                      # does (seconds per case); without, emss plot DIR/cases/<case> draws them
    params: [../ssp/engine_reference_study.ssv]   # parameter sets applied to every case
    values: {engine.use_ambient: false}            # parameter values applied to every case
    missions: {munich: ../missions/munich.yaml}    # optional: each case flies each mission
    mission_parameter: fcs.mission_file            # default: fcs.mission_file
    variants:                         # optional: named parameter sets and values
      - {name: baseline, params: [a.ssv], values: {engine.preset: reference_study}}
    grid:                             # optional: every combination of the value lists
      engine.design_BPR: [1.0, 1.5]
      engine.design_PR_hpc: {from: 4.0, to: 6.0, num: 3}
    scenarios: {nominal: null, bleed: bleed.yaml}  # optional: each case runs each scenario (null: none)

Parameter values are typed by the FMU variable they set (Real, Integer,
Boolean, String); a variable that does not exist or a value of the wrong kind
is refused before any case runs. Every value of the file is typed where it is read
(:mod:`openemss.models.infra.values`: no Boolean, null, list or mapping where one value
is, numbers finite and in range); nothing is taken twice silently: two missions or
scenarios of one name, a file listed twice, one grid value twice, or a variable set by
two of ``values``, a variant, the grid and ``mission_parameter`` are refused.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import yaml

from openemss.models.infra import safe_yaml
from openemss.models.infra import values as checked
from openemss.orchestrator.errors import ConfigurationError
from openemss.orchestrator.master import algorithm_registry
from openemss.orchestrator.results import check_name

__all__ = ["StudyError", "Variant", "StudyDef", "load_study", "parse_study"]

ValueT = float | int | bool | str
NAME_RE = re.compile(r"^[A-Za-z0-9_.=+-]+$")
TOP_KEYS = ("study", "description", "system", "stop_time_s", "rate_hz", "algorithm", "record", "record_every",
            "pre_run", "figures", "params", "values", "missions", "mission_parameter", "variants", "grid", "scenarios",
            "redesign")
MAX_GRID_POINTS = 100_000
MAX_RECORD_EVERY = 10**9  #: most steps between two recorded samples


class StudyError(ValueError):
    """A study file or study run that cannot be used: the message is one line naming file, line and field."""


class _Lines(dict):  # type: ignore[type-arg]
    """A mapping that remembers the line of each key (1-based)."""

    lines: dict[Any, int]


class _Loader(yaml.SafeLoader):
    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> _Lines:  # type: ignore[override]
        out = _Lines(super().construct_mapping(node, deep=True))
        out.lines = {self.construct_object(k, deep=True): k.start_mark.line + 1 for k, _ in node.value}
        return out


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _Loader.construct_mapping)


@dataclass(frozen=True)
class Variant:
    """A named set of parameter files [.ssv] and values (``component.variable`` -> value)."""

    name: str
    params: tuple[Path, ...] = ()
    values: tuple[tuple[str, ValueT], ...] = ()


@dataclass(frozen=True)
class StudyDef:
    """A validated study file; paths are absolute."""

    name: str
    source: Path
    system: Path
    description: str = ""
    stop_time_s: float | None = None
    rate_hz: float | None = None
    algorithm: str = algorithm_registry.DEFAULT
    record: tuple[str, ...] = ()
    record_every: int = 1
    pre_run: bool = False
    figures: bool = False
    params: tuple[Path, ...] = ()
    values: tuple[tuple[str, ValueT], ...] = ()
    missions: tuple[tuple[str, Path], ...] = ()
    mission_parameter: str = "fcs.mission_file"
    variants: tuple[Variant, ...] = ()
    grid: tuple[tuple[str, tuple[ValueT, ...]], ...] = ()
    scenarios: tuple[tuple[str, Path | None], ...] = ()
    redesign: dict[str, Any] = field(default_factory=dict)
    #: the line of each field that sets a variable ('values.k', 'variants[i].values.k', 'grid.k', 'system',
    #: 'mission_parameter'), for the errors of the checks against the system (:mod:`.plan`)
    lines: tuple[tuple[str, int], ...] = ()

    def where(self, label: str) -> str:
        """``file:line: field 'label'`` (the line where known)."""
        line = dict(self.lines).get(label)
        return f"{self.source}{f':{line}' if line else ''}: field '{label}'"


class _Ctx:
    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, where: Any, label: str, message: str) -> StudyError:
        """The error for field ``label``, located at the line of its key in the mapping ``where``."""
        lines: dict[Any, int] = getattr(where, "lines", {})
        line = None
        rest = label
        while rest:  # the key is a suffix of the label: 'grid.engine.design_BPR' -> 'engine.design_BPR'
            if rest in lines:
                line = lines[rest]
                break
            cut = min((i for i in (rest.find("."), rest.find("].")) if i >= 0), default=-1)
            rest = rest[cut + (2 if rest[cut:cut + 2] == "]." else 1):] if cut >= 0 else ""
        loc = f"{self.source}:{line}" if line else self.source
        return StudyError(f"{loc}: field '{label}': {message}")


def _path(ctx: _Ctx, base: Path, doc: Any, key: str, label: str, value: Any, must_exist: bool = True) -> Path:
    if not isinstance(value, str) or not value.strip():
        raise ctx.fail(doc, label, "expected a file or folder path (relative to the study file)")
    try:
        p = (base / Path(value).expanduser()).resolve()
    except (OSError, RuntimeError) as exc:  # a symlink loop, an unreadable folder
        raise ctx.fail(doc, label, f"'{value}' cannot be resolved: {exc}") from None
    if must_exist and not p.exists():
        raise ctx.fail(doc, label, f"'{value}' does not exist (looked at {p})")
    return p


def _name(ctx: _Ctx, doc: Any, label: str, value: Any) -> str:
    """A name that becomes a folder of the study's results: one path component (not '.' or '..')."""
    try:
        text = checked.name(value)
    except ValueError as exc:
        raise ctx.fail(doc, label, f"{exc}; a name of letters, digits and _ . = + - is expected") from None
    if not NAME_RE.match(text):
        raise ctx.fail(doc, label, f"{text!r}: a name of letters, digits and _ . = + - is expected")
    try:
        return check_name(text, "the name")
    except ConfigurationError as exc:
        raise ctx.fail(doc, label, str(exc)) from None


def _number(ctx: _Ctx, doc: Any, label: str, value: Any, lo: float, hi: float) -> float:
    try:
        return checked.number(value, lo, hi)
    except ValueError as exc:
        raise ctx.fail(doc, label, str(exc)) from None


def _typed(ctx: _Ctx, doc: Any, key: str, check: Callable[[Any], Any], default: Any) -> Any:
    """The value of ``key`` of ``doc`` through ``check`` (``default`` when absent or empty)."""
    value = doc.get(key)
    if value is None:
        return default
    try:
        return check(value)
    except ValueError as exc:
        raise ctx.fail(doc, key, str(exc)) from None


def _scalar(ctx: _Ctx, doc: Any, label: str, value: Any) -> ValueT:
    try:
        return checked.scalar(value)
    except ValueError as exc:
        raise ctx.fail(doc, label, str(exc)) from None


def _var_name(ctx: _Ctx, doc: Any, label: str, value: Any) -> str:
    if not isinstance(value, str) or "." not in value.strip(".") or " " in value:
        raise ctx.fail(doc, label, f"{value!r}: expected component.variable")
    return value


def _values(ctx: _Ctx, doc: Any, key: str, value: Any) -> tuple[tuple[str, ValueT], ...]:
    if value is None:
        return ()
    if not isinstance(value, dict):
        raise ctx.fail(doc, key, "expected a mapping of component.variable: value")
    return tuple((_var_name(ctx, value, f"{key}.{k}", k), _scalar(ctx, value, f"{key}.{k}", v))
                 for k, v in value.items())


def _paths(ctx: _Ctx, base: Path, doc: Any, key: str, value: Any) -> tuple[Path, ...]:
    if value is None:
        return ()
    items = value if isinstance(value, list) else [value]
    return tuple(_path(ctx, base, doc, key, f"{key}[{i}]", v) for i, v in enumerate(items))


def _named_files(ctx: _Ctx, base: Path, doc: Any, key: str, value: Any,
                 allow_none: bool) -> tuple[tuple[str, Path | None], ...]:
    """Named files (missions, scenarios): a mapping name -> file, or a list of files named by their stems
    (two files of one stem by as much of their folders as tells them apart). A file given twice is refused."""
    if value is None:
        return ()
    if isinstance(value, list):
        if not value:
            raise ctx.fail(doc, key, "expected a mapping name: file (or a list of files), got an empty list")
        return _listed_files(ctx, base, doc, key, value, allow_none)
    if not isinstance(value, dict) or not value:
        raise ctx.fail(doc, key, f"expected a mapping name: file (or a list of files), got {checked.show(value)}")
    out: list[tuple[str, Path | None]] = []
    for k, v in value.items():
        label = f"{key}.{k}"
        name = _name(ctx, value, label, k)
        out.append((name, None if v is None and allow_none else _path(ctx, base, value, k, label, v)))
    _distinct(ctx, doc, key, out)
    return tuple(out)


def _listed_files(ctx: _Ctx, base: Path, doc: Any, key: str, items: list[Any],
                  allow_none: bool) -> tuple[tuple[str, Path | None], ...]:
    paths = [None if v is None and allow_none else _path(ctx, base, doc, key, f"{key}[{i}]", v)
             for i, v in enumerate(items)]
    _distinct(ctx, doc, key, [(str(v), p) for v, p in zip(items, paths, strict=True) if p is not None])
    parts = [p.parts if p is not None else ("none",) for p in paths]
    depth = 1
    while True:  # the shortest tail of the path that names each file apart (the stem, then its folders)
        names = ["_".join((*part[-depth:-1], Path(part[-1]).stem)) if part != ("none",) else "none"
                 for part in parts]
        if len(set(names)) == len(names) or depth >= max(len(part) for part in parts):
            break
        depth += 1
    out = [(_name(ctx, doc, f"{key}[{i}]", n), p) for i, (n, p) in enumerate(zip(names, paths, strict=True))]
    _distinct(ctx, doc, key, out)
    return tuple(out)


def _distinct(ctx: _Ctx, doc: Any, key: str, named: list[tuple[str, Path | None]]) -> None:
    """Refuse a name or a file given twice: each would run the same case twice, or one hide the other."""
    seen: dict[Any, str] = {}
    for name, path in named:
        for what in (("name", name.lower()), ("file", path)):
            if what[1] is None:
                continue
            if what in seen:
                given = f"the file {path}" if what[0] == "file" else f"the name '{name}'"
                raise ctx.fail(doc, key, f"{given} is given twice (as '{seen[what]}' and '{name}'); give each "
                               "once")
            seen[what] = name


def _grid_values(ctx: _Ctx, doc: Any, label: str, value: Any) -> tuple[ValueT, ...]:
    """The values of one grid axis: a list, or a range {from, to, num}; each finite, none twice."""
    if isinstance(value, dict):
        unknown = set(value) - {"from", "to", "num"}
        if unknown or not {"from", "to", "num"} <= set(value):
            raise ctx.fail(doc, label, "a range is {from: X, to: Y, num: N}")
        a = _number(ctx, value, label + ".from", value["from"], -math.inf, math.inf)
        b = _number(ctx, value, label + ".to", value["to"], -math.inf, math.inf)
        try:
            n = checked.integer(value["num"], 1, MAX_GRID_POINTS)
        except ValueError as exc:
            raise ctx.fail(value, label + ".num", str(exc)) from None
        # a (1 - t) + b t, not a + (b - a) t: b - a overflows from -1e308 to 1e308 (NaN cases)
        vals: tuple[ValueT, ...] = tuple(a * (1.0 - i / (n - 1)) + b * (i / (n - 1)) if n > 1 else a
                                         for i in range(n))
        if not all(math.isfinite(v) for v in vals):  # type: ignore[arg-type]
            raise ctx.fail(value, label, f"the range from {a:g} to {b:g} gives values that are not finite numbers")
    elif isinstance(value, list) and value:
        vals = tuple(_scalar(ctx, doc, label, v) for v in value)
    else:
        raise ctx.fail(doc, label, f"expected a non-empty list of values or {{from, to, num}}, got "
                       f"{checked.show(value)}")
    seen: set[tuple[type, ValueT]] = set()
    for v in vals:
        key = (bool if isinstance(v, bool) else str if isinstance(v, str) else float, v)
        if key in seen:
            raise ctx.fail(doc, label, f"the value {v!r} is given twice (each case would run twice); give each "
                           "value once")
        seen.add(key)
    return vals


def _variants(ctx: _Ctx, base: Path, doc: Any, value: Any) -> tuple[Variant, ...]:
    if value is None:
        return ()
    if not isinstance(value, list) or not value:
        raise ctx.fail(doc, "variants", "expected a non-empty list of {name, params, values}")
    out: list[Variant] = []
    for i, v in enumerate(value):
        label = f"variants[{i}]"
        if not isinstance(v, dict):
            raise ctx.fail(doc, "variants", f"{label}: expected a mapping {{name, params, values}}")
        unknown = set(v) - {"name", "params", "values"}
        if unknown:
            raise ctx.fail(v, sorted(unknown)[0], f"{label}: unknown key; allowed: name, params, values")
        if "name" not in v:
            raise ctx.fail(doc, "variants", f"{label}: 'name' is required")
        out.append(Variant(_name(ctx, v, "name", v["name"]), _paths(ctx, base, v, f"{label}.params", v.get("params")),
                           _values(ctx, v, f"{label}.values", v.get("values"))))
    names = [v.name for v in out]
    dup = next((n for n in names if names.count(n) > 1), None)
    if dup:
        raise ctx.fail(doc, "variants", f"two variants are named '{dup}'; names must be unique")
    return tuple(out)


def parse_study(doc: Any, source: Path) -> StudyDef:
    """Validate a parsed study document (from :func:`load_study`); paths relative to ``source``'s folder."""
    ctx = _Ctx(str(source))
    base = source.parent
    if not isinstance(doc, dict):
        raise StudyError(f"{source}: a study file is a mapping with at least 'study' and 'system'")
    for k in doc:
        if k not in TOP_KEYS:
            raise ctx.fail(doc, str(k), f"unknown key; allowed: {', '.join(TOP_KEYS)}")
    for k in ("study", "system"):
        if k not in doc:
            raise StudyError(f"{source}: field '{k}' is required")
    try:
        algorithm = checked.choice(doc.get("algorithm", algorithm_registry.DEFAULT), algorithm_registry.names())
    except ValueError as exc:
        raise ctx.fail(doc, "algorithm", str(exc)) from None
    record = doc.get("record") or []
    if isinstance(record, str):
        record = [record]
    if not isinstance(record, list) or not all(isinstance(r, str) and r.strip() for r in record):
        raise ctx.fail(doc, "record", "expected a list of component.variable patterns")
    every = _typed(ctx, doc, "record_every", lambda v: checked.integer(v, 1, MAX_RECORD_EVERY), 1)
    description = _typed(ctx, doc, "description", checked.text, "")
    pre_run = _typed(ctx, doc, "pre_run", checked.flag, False)
    figures = _typed(ctx, doc, "figures", checked.flag, False)
    grid_doc = doc.get("grid") or _Lines()
    if not isinstance(grid_doc, dict):
        raise ctx.fail(doc, "grid", "expected a mapping component.variable: [values] or {from, to, num}")
    grid = tuple((_var_name(ctx, grid_doc, f"grid.{k}", k), _grid_values(ctx, grid_doc, f"grid.{k}", v))
                 for k, v in grid_doc.items())
    if math.prod(len(v) for _, v in grid) > MAX_GRID_POINTS:
        raise ctx.fail(doc, "grid", f"more than {MAX_GRID_POINTS} grid points")
    redesign = doc.get("redesign") or {}
    if not isinstance(redesign, dict):
        raise ctx.fail(doc, "redesign", "expected a mapping (see studies/engine_redesign.yaml)")
    stop = doc.get("stop_time_s")
    rate = doc.get("rate_hz")
    study = StudyDef(
        name=_name(ctx, doc, "study", doc["study"]), source=source.resolve(),
        system=_path(ctx, base, doc, "system", "system", doc["system"]),
        description=description,
        stop_time_s=None if stop is None else _number(ctx, doc, "stop_time_s", stop, 1e-9, 1e9),
        rate_hz=None if rate is None else _number(ctx, doc, "rate_hz", rate, 0.1, 100.0),
        algorithm=algorithm, record=tuple(record), record_every=every, pre_run=pre_run,
        figures=figures,
        params=_paths(ctx, base, doc, "params", doc.get("params")),
        values=_values(ctx, doc, "values", doc.get("values")),
        missions=tuple((n, p) for n, p in _named_files(ctx, base, doc, "missions", doc.get("missions"), False)
                       if p is not None),
        mission_parameter=_var_name(ctx, doc, "mission_parameter", doc.get("mission_parameter", "fcs.mission_file")),
        variants=_variants(ctx, base, doc, doc.get("variants")),
        grid=grid,
        scenarios=_named_files(ctx, base, doc, "scenarios", doc.get("scenarios"), True),
        redesign=redesign,  # keeps the line of each key for errors
    )
    _set_once(ctx, doc, study)
    return replace(study, lines=tuple(_field_lines(doc)))


def _field_lines(doc: Any) -> list[tuple[str, int]]:
    """The line of each field that names a variable or the system (see :attr:`StudyDef.lines`)."""
    def line(m: Any, key: Any) -> int | None:
        return getattr(m, "lines", {}).get(key)

    out = [(k, line(doc, k)) for k in ("system", "mission_parameter", "missions")]
    for key in ("values", "grid"):
        m = doc.get(key)
        if isinstance(m, dict):
            out += [(f"{key}.{k}", line(m, k) or line(doc, key)) for k in m]
    variants = doc.get("variants")
    for i, v in enumerate(variants if isinstance(variants, list) else []):
        m = v.get("values") if isinstance(v, dict) else None
        if isinstance(m, dict):
            out += [(f"variants[{i}].values.{k}", line(m, k) or line(v, "values")) for k in m]
    return [(label, n) for label, n in out if n is not None]


def _set_once(ctx: _Ctx, doc: Any, study: StudyDef) -> None:
    """Refuse a variable that two parts of the study set (one would silently replace the other in a case):
    ``values``, the grid, the missions (``mission_parameter``); a variant's values may replace the study's
    ``values`` (defaults of every case; the variant is the documented exception), not the grid's or the
    missions'."""
    setters: list[tuple[str, Any, str]] = [("values", doc.get("values"), k) for k, _ in study.values]
    variants = doc.get("variants") if isinstance(doc.get("variants"), list) else []
    for i, v in enumerate(study.variants):
        setters += [(f"variants[{i}].values", variants[i].get("values"), k) for k, _ in v.values]
    setters += [("grid", doc.get("grid"), k) for k, _ in study.grid]
    if study.missions:
        setters.append(("missions", doc, study.mission_parameter))
    first: dict[str, str] = {}
    for part, where, var in setters:
        earlier = first.get(var)
        if earlier is not None and not ((earlier == "values" or earlier.startswith("variants["))
                                        and part.startswith("variants[")):
            raise ctx.fail(where if isinstance(where, dict) else doc, var if part != "missions" else "missions",
                           f"'{var}' is set by both {earlier} and {part}: one would replace the other in every case; "
                           "set it in one place")
        first.setdefault(var, part)


def load_study(path: str | Path) -> StudyDef:
    """Read and validate a study file.

    Raises
    ------
    StudyError
        One line naming the file, the line and the field, and what is allowed.
    """
    p = Path(path)
    try:  # the project's one YAML reader: duplicate keys, alias bombs, NaN refused with file:line
        doc = safe_yaml.load(safe_yaml.read_text(p, "study file"), str(p), loader=_Loader)
    except safe_yaml.YamlError as exc:
        raise StudyError(str(exc)) from None
    return parse_study(doc, p)
