"""The fast frozen records (models/infra/records.py) and the FCS FMU's batched get/set fast paths.

References: a plain frozen dataclass with the same fields (the construction ``fast_init`` replaces), and
pythonfmu's own ``Fmi2Slave.get_*``/``set_*`` (one getter or setter per variable), which the FCS slave's
batched methods must match for any order or subset of value references.
"""
from __future__ import annotations

import copy
import dataclasses
import math
import pickle
import random
from pathlib import Path

import pytest
from pythonfmu import Fmi2Slave

from openemss.fmus.fcs import INPUTS, OUTPUTS, Fcs
from openemss.models.fcs.state import Targets
from openemss.models.infra.records import fast_init

ROOT = Path(__file__).resolve().parents[2]


@dataclasses.dataclass(frozen=True, slots=True)
class _Plain:
    a: float
    b: str = "x"
    c: float = math.nan


@fast_init
@dataclasses.dataclass(frozen=True, slots=True)
class _Fast:
    a: float
    b: str = "x"
    c: float = math.nan


def test_fast_init_builds_the_same_frozen_dataclass() -> None:
    for args, kw in (((1.0,), {}), ((1.0, "y"), {}), ((2.0,), {"c": 3.0}), ((), {"a": 4.0, "b": "z", "c": -1.0})):
        fast, plain = _Fast(*args, **kw), _Plain(*args, **kw)
        assert dataclasses.astuple(fast) == dataclasses.astuple(plain)
    x = _Fast(1.0, c=2.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        x.a = 2.0  # type: ignore[misc]
    assert dataclasses.replace(x, a=5.0) == _Fast(5.0, "x", 2.0)
    assert hash(_Fast(1.0, "q", 2.0)) == hash(_Fast(1.0, "q", 2.0))
    with pytest.raises(TypeError):
        _Fast()  # type: ignore[call-arg]
    with pytest.raises(TypeError):
        _Fast(1.0, "x", 2.0, 3.0)  # type: ignore[call-arg]
    assert type(x) is _Fast and isinstance(x, _Fast) and dataclasses.is_dataclass(x)
    for twin in (copy.copy(x), copy.deepcopy(x), pickle.loads(pickle.dumps(x))):
        assert type(twin) is _Fast and twin == x
    with pytest.raises(dataclasses.FrozenInstanceError):
        copy.copy(x).b = "z"  # type: ignore[misc]

    for args, kw in (((1.0,), {}), ((2.0, "y"), {"c": 3.0})):  # make: the class call without its overhead
        made = _Fast.make(*args, **kw)
        assert type(made) is _Fast and made == _Fast(*args, **kw)
        assert dataclasses.astuple(made) == dataclasses.astuple(_Plain(*args, **kw))
    with pytest.raises(dataclasses.FrozenInstanceError):
        _Fast.make(1.0).a = 2.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        _Fast.make()  # type: ignore[call-arg]

    class Sub(_Fast):  # a subclass (its own layout: a __dict__) is built by the dataclass's __init__
        pass

    s = Sub(1.0, c=2.0)
    assert type(s) is Sub and dataclasses.astuple(s) == dataclasses.astuple(_Plain(1.0, c=2.0))


def test_fast_init_keeps_the_defaults_of_targets() -> None:
    t = Targets(3, "leg", "WaypointFollowing", "TO_WP1")
    for f in dataclasses.fields(Targets)[4:]:
        v = getattr(t, f.name)
        assert v == f.default or (isinstance(v, float) and math.isnan(v) and math.isnan(f.default))


def test_fast_init_refuses_what_it_cannot_build() -> None:
    @dataclasses.dataclass(frozen=True)
    class NoSlots:
        a: float

    @dataclasses.dataclass(slots=True)
    class NotFrozen:
        a: float

    for cls in (NoSlots, NotFrozen):
        with pytest.raises(TypeError):
            fast_init(cls)


def test_batched_get_set_match_pythonfmu_for_any_order() -> None:
    s = Fcs(instance_name="t", resources=str(ROOT))
    s.exit_initialization_mode()
    s.do_step(0.0, 0.05)
    vr = {v.name: k for k, v in s.vars.items()}
    ins, outs = [vr[n] for n, _ in INPUTS], [vr[n] for n, _ in OUTPUTS]
    ints = [vr[n] for n in ("section_index", "fuel_limiter", "vnav_mode", "ils_phase")]
    bools = [vr[n] for n in ("gear_down", "mission_completed", "on_ground")]  # outputs and an input
    rng = random.Random(1)
    for _ in range(20):
        for group, get, base in ((outs + ins, s.get_real, Fmi2Slave.get_real), (ints, s.get_integer, Fmi2Slave.get_integer),
                                 (bools, s.get_boolean, Fmi2Slave.get_boolean)):
            sel = rng.sample(group, rng.randint(1, len(group)))
            assert get(sel) == base(s, sel) and get(sel) == base(s, sel)  # twice: resolved, then served
        sel = rng.sample(ins, rng.randint(1, len(ins)))
        values = [rng.uniform(-1.0, 1.0) for _ in sel]
        s.set_real(sel, values)
        assert Fmi2Slave.get_real(s, sel) == values
    s.set_real(ins, [float(k) for k in range(len(ins))])
    assert Fmi2Slave.get_real(s, ins) == [float(k) for k in range(len(ins))]
    s.set_boolean([vr["on_ground"]], [False])
    assert Fmi2Slave.get_boolean(s, [vr["on_ground"]]) == [False]


def test_clip_is_min_of_max() -> None:
    from openemss.models.fcs.clip import clip

    values = [-2.0, -1.0, -0.0, 0.0, 0.5, 1.0, 3.0, math.nan, math.inf, -math.inf, 0, 1]
    for x in values:
        for lo in values:
            for hi in values:
                ref, got = min(max(x, lo), hi), clip(x, lo, hi)
                assert (math.isnan(ref) and math.isnan(got)) or (ref == got and math.copysign(1.0, ref) ==
                                                                  math.copysign(1.0, got) and type(ref) is type(got))
