"""The flight control's performance data of the system flown (issue 32 point 4).

* A database generated for an engine other than the shipped one (``reference_study``, whose maximum thrust
  differs) through the path ``emss run`` takes (:func:`generate.ensure_cached` into the cache, then the FCS's
  :func:`performance_for` by the airframe's and engine's identities) holds that engine's thrust: compared with
  the engine model's own steady states (:class:`EngineModel`, the model the engine FMU flies, started steady at a
  mechanical fan speed; not the generator's N1c solves) at grid points. Idle: N1c 40 % (the shipped system's
  flight idle). Maximum: lever 1 (N1c 100 %) where no limit binds, else the steady point on the Tt41 limit
  (1400 K) or the N1 limit (103 %) found on the mechanical N1 of the engine model. Tolerance 0.01 N: the database keeps
  thrust to 1e-3 N, both sides are steady states of one gas-path model matched to a residual of 1e-7 and the
  bisections end below 1e-9 of a fan speed; measured: within 1e-3 N.
* The drag polar at grid points equals the trimmed airframe (JSBSim) at a third mass, between the two masses
  the polar was fitted through: the parabola CD0 + k CL^2 holds on the linear part of the lift curve.
  Tolerance 0.5 % of CD; measured within 0.05 %.
* A database that is not the system's is refused with one line naming both; unknown identities (inputs not
  connected) and a system without data are refused, naming its identities. The mass range is the aircraft's.
"""
from __future__ import annotations

import json
import math
import os
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import pytest

pytest.importorskip("jsbsim")

from openemss.models.airframe.errors import AirframeError  # noqa: E402
from openemss.models.infra.config_id import CACHE_ENV, cache_dir, database_key  # noqa: E402
from openemss.models.fcs.errors import FcsError  # noqa: E402
from openemss.models.fcs.performance import Performance, load_performance_data, performance_for  # noqa: E402
from openemss.models.performance import generate as gen  # noqa: E402

ENGINE = "reference_study"
N1C_IDLE = 40.0
T41_LIMIT_K = 1400.0  # the fuel controller's limits (models/fcs/data/fuel_control.yaml)
N1_LIMIT_PCT = 103.0


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    folder = tmp_path_factory.mktemp("perf_cache")
    held = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(folder)
    yield folder
    if held is None:
        os.environ.pop(CACHE_ENV, None)
    else:
        os.environ[CACHE_ENV] = held


@pytest.fixture(scope="module")
def airframe():  # noqa: ANN201
    from openemss.models.airframe.adapter import Airframe

    return Airframe()


@pytest.fixture(scope="module")
def system(cache: Path, airframe) -> tuple[Path, Performance, dict]:  # noqa: ANN001
    """The reference-study engine's database, generated into the cache and found by the FCS's look-up."""
    from openemss.models.airframe.identity import airframe_config_id
    from openemss.models.engine.design_params import load_params, preset_path
    from openemss.models.engine.identity import engine_config_id

    path, seconds = gen.ensure_cached(ENGINE, airframe)
    assert seconds is not None and path.parent == cache  # generated, into the cache
    assert gen.ensure_cached(ENGINE, airframe) == (path, None)  # the second time: found by its key
    ids = airframe_config_id(airframe), engine_config_id(load_params(preset_path(ENGINE)))
    data = performance_for(*ids, gen.default_limits())
    assert data.key == path.stem == database_key(*ids, gen.default_limits())
    return path, Performance(data, n1c_idle=lambda: N1C_IDLE), json.loads(path.read_text())


@pytest.fixture(scope="module")
def engine():  # noqa: ANN201
    from openemss.models.engine.engine_model import OUTPUTS, EngineInputs, EngineModel

    m = EngineModel(ENGINE)
    names = [n for n, _ in OUTPUTS]

    def steady(alt_m: float, mach: float, N1_pct: float) -> dict[str, float]:
        return dict(zip(names, list(m.start(EngineInputs(0.05, alt_m, mach), N1_pct=N1_pct)), strict=True))
    return steady


def _at_n1c(steady, alt_m: float, mach: float, n1c_pct: float) -> dict[str, float]:  # noqa: ANN001
    """The engine model's steady state at a corrected fan speed: the mechanical speed scaled until N1c is it
    (N1c is N1 over the root of the fan-face temperature ratio, fixed by the flight condition)."""
    n1 = n1c_pct
    for _ in range(8):
        n1 *= n1c_pct / steady(alt_m, mach, n1)["N1c_pct"]
    return steady(alt_m, mach, n1)


def _on_the_limits(steady, alt_m: float, mach: float) -> dict[str, float]:  # noqa: ANN001
    """The engine model's steady state at the highest fan speed within N1 103 % and Tt41 1400 K: on the N1 limit
    when Tt41 is within its own there, else on the Tt41 limit (bisection on the mechanical N1)."""
    top = steady(alt_m, mach, N1_LIMIT_PCT)
    if top["Tt41_K"] <= T41_LIMIT_K:
        return top
    lo, hi = 50.0, N1_LIMIT_PCT
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if steady(alt_m, mach, mid)["Tt41_K"] <= T41_LIMIT_K else (lo, mid)
    return steady(alt_m, mach, lo)


POINTS = ((0.0, 0.3), (3000.0, 0.5), (5000.0, 0.6), (7000.0, 0.75), (0.0, 0.85), (2000.0, 0.8))


@pytest.mark.parametrize(("alt_m", "mach"), POINTS)
def test_idle_and_maximum_thrust_are_the_engine_models(system, engine, alt_m: float, mach: float) -> None:  # noqa: ANN001
    _, perf, _ = system
    idle = _at_n1c(engine, alt_m, mach, N1C_IDLE)
    assert perf.idle_thrust_N(alt_m, mach) == pytest.approx(idle["Fn_N"], abs=0.01)
    top = _at_n1c(engine, alt_m, mach, 100.0)  # lever 1
    if top["Tt41_K"] > T41_LIMIT_K or top["N1_pct"] > N1_LIMIT_PCT:
        top = _on_the_limits(engine, alt_m, mach)
        assert top["Tt41_K"] == pytest.approx(T41_LIMIT_K, abs=1e-6) or top["N1_pct"] == pytest.approx(N1_LIMIT_PCT)
    assert perf.max_thrust_N(alt_m, mach) == pytest.approx(top["Fn_N"], abs=0.01)


def test_the_engines_own_maximum_thrust_differs_from_the_shipped_engines(system) -> None:  # noqa: ANN001
    _, perf, _ = system
    shipped = Performance(load_performance_data())
    # measured over the grid: -0.10 % (8000 m, Mach 0.15) to -1.25 % (sea level, Mach 0.85), i.e. up to 136 N:
    # far above the 0.01 N to which the database is the engine's
    diff = [abs(perf.max_thrust_N(h, m) - shipped.max_thrust_N(h, m)) for h, m in POINTS]
    assert max(diff) > 50.0


@pytest.mark.parametrize(("alt_m", "mach"), [(1000.0, 0.4), (4000.0, 0.6), (7000.0, 0.75)])
def test_the_drag_polar_is_the_trimmed_airframes(system, airframe, alt_m: float, mach: float) -> None:  # noqa: ANN001
    from openemss.models.airframe.trim import trim_level

    _, perf, doc = system
    lo, hi = doc["airframe"]["mass_range_kg"]
    assert (lo, hi) == airframe.mass_range_kg  # the aircraft's own range
    t = trim_level(alt_m, mach, 0.5 * (lo + hi), airframe=airframe)
    cd0, k = perf.polar(alt_m, mach)
    assert cd0 + k * t.CL ** 2 == pytest.approx(t.CD, rel=5e-3)


def test_a_database_of_another_system_is_refused_naming_both(system) -> None:  # noqa: ANN001
    path, _, doc = system
    shipped = load_performance_data()
    with pytest.raises(FcsError) as e:  # the shipped (Larzac) database given to a system flying the other engine
        performance_for(doc["airframe_config_id"], doc["engine_config_id"], gen.default_limits(),
                        file=gen.OUT_FILE)
    text = str(e.value)
    assert "\n" not in text and str(doc["engine_config_id"]) in text and str(shipped.engine_config_id) in text
    with pytest.raises(FcsError, match="N1_max_pct 97"):  # the same engine with other limits: another database
        performance_for(doc["airframe_config_id"], doc["engine_config_id"],
                        {**gen.default_limits(), "N1_max_pct": 97.0}, file=path)


def test_unknown_identities_and_a_system_without_data_are_refused(cache: Path) -> None:
    with pytest.raises(FcsError, match="0: unknown"):
        performance_for(0, 5, gen.default_limits())
    with pytest.raises(FcsError, match=r"no performance data for this system \(airframe_config_id 12345, "
                                       r"engine_config_id 678"):
        performance_for(12345, 678, gen.default_limits())
    bad = cache_dir() / f"{database_key(1, 2, gen.default_limits())}.json"
    bad.write_text("{not json", encoding="utf-8")
    with pytest.raises(FcsError, match="not a performance database"):
        performance_for(1, 2, gen.default_limits())


def test_the_shipped_system_flies_the_shipped_database(airframe) -> None:  # noqa: ANN001
    from openemss.models.airframe.identity import airframe_config_id
    from openemss.models.engine.design_params import load_params, preset_path
    from openemss.models.engine.identity import engine_config_id

    ids = airframe_config_id(airframe), engine_config_id(load_params(preset_path("larzac04_sls")))
    assert performance_for(*ids, gen.default_limits()).key == load_performance_data().key
    assert gen.ensure_cached("larzac04_sls", airframe) == (gen.OUT_FILE, None)


def test_the_mass_range_is_the_aircrafts_and_a_bad_one_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    stub = SimpleNamespace(mass_range_kg=(2100.0, 1500.0), geometry=SimpleNamespace(path=Path("plane.json")))
    with pytest.raises(AirframeError, match=r"plane.json: mass: operating empty 2100 kg and maximum take-off 1500 kg"):
        gen.mass_range_kg(stub)  # type: ignore[arg-type]
    for masses in ((0.0, 1500.0), (1500.0, math.inf), (math.nan, 2000.0)):
        with pytest.raises(AirframeError):
            gen.mass_range_kg(SimpleNamespace(mass_range_kg=masses, geometry=stub.geometry))  # type: ignore[arg-type]
    with pytest.raises(AirframeError):
        gen.polar_point(1000.0, 0.4, stub)  # type: ignore[arg-type]


def test_an_engine_file_has_its_own_identity_and_steady_states() -> None:
    """An engine file flown by the engine FMU (``engine_file``, ``thrust_scale``): its identity changes with the
    scale and is not the preset's; the generator's steady state at a corrected fan speed is the engine FMU's model
    (GraphEngineModel) at that corrected speed, as that model reports it (N1c to 1e-9 %, the thrust to 1e-6 N)."""
    from openemss.models.engine.engine_signals import EO, EngineInputs
    from openemss.models.engine.graph_engine import GraphEngineModel
    from openemss.models.engine.identity import engine_file_config_id

    assert engine_file_config_id("larzac04", 1.0) == engine_file_config_id("larzac04", 1.0)
    assert engine_file_config_id("larzac04", 1.0) != engine_file_config_id("larzac04", 0.5)
    eng = gen.EngineFile("larzac04", 0.5)
    assert gen._identity(eng)[0] != gen._identity("larzac04_sls")[0]
    p = gen._steady_solver(eng).solve(5000.0, 0.6, N1c_pct=70.0)
    v = GraphEngineModel("larzac04", 0.5).start(EngineInputs(0.0, 5000.0, 0.6), N1_pct=p.N1_pct)
    assert v[EO.N1c_pct] == pytest.approx(70.0, abs=1e-9)
    assert v[EO.Fn_N] == pytest.approx(p.Fn_N, abs=1e-6) and v[EO.Tt41_K] == pytest.approx(p.T41_K, abs=1e-9)
