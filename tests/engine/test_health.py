"""Health parameters (models/engine/health.py, EngineModel.set_health): exchange rates in a plausibility band,
reversibility, checks.

Exchange rates: the band of +0.5 to +1.0 % SFC and +5 to +15 K of turbine entry temperature per 1 % loss of HP
compressor efficiency at constant thrust was entered from memory of P. P. Walsh, P. Fletcher, "Gas Turbine
Performance", 2nd ed., Blackwell, 2004 (its engine deterioration chapter). It was NOT checked against the book or
another readable published table of exchange rates (none was found in session 12): it is a plausibility band
(a sign error, a factor of two or a delta not applied would take the model out of it), not a published reference. The Larzac 04
model must fall inside it at sea level static and at cruise. The health deltas must also be reversible (the
clean engine back to round-off) and checked (one line naming the parameter and its range).
"""
from __future__ import annotations

import pytest

from openemss.models.engine.engine_model import EngineModel
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.health import HealthDeltas

#: (altitude [m], Mach [-], N1 [%]) of the clean reference point; the degraded engine gives its thrust.
POINTS = ((0.0, 0.0, 95.0), (7500.0, 0.7, 90.0))
SFC_PCT_PER_PCT_HPC_ETA = (0.5, 1.0)       # +SFC [%] per -1 % HPC eta (plausibility band, unchecked: see above)
TT4_K_PER_PCT_HPC_ETA = (5.0, 15.0)        # + turbine entry temperature [K] per -1 % HPC eta (the same)


@pytest.fixture(scope="module")
def model() -> EngineModel:
    return EngineModel("larzac04_sls")


@pytest.mark.parametrize("point", POINTS)
def test_hpc_efficiency_exchange_rate(model: EngineModel, point: tuple[float, float, float]) -> None:
    alt, mach, n1 = point
    model.set_health(HealthDeltas())
    clean = model.od.solve(alt, mach, 0.0, N1_pct=n1)
    model.set_health(HealthDeltas(hpc_eta_frac=-0.01))
    try:
        deg = model.od.solve(alt, mach, 0.0, Fn_N=clean.Fn_N, guess=clean)
    finally:
        model.set_health(HealthDeltas())
    dsfc = 100.0 * (deg.SFC_kg_N_s / clean.SFC_kg_N_s - 1.0)
    dtt4 = deg.Tt4_K - clean.Tt4_K
    print(f"alt {alt:g} m, M {mach:g}: -1 % HPC efficiency: SFC {dsfc:+.3f} %, Tt4 {dtt4:+.2f} K, "
          f"SM HPC {deg.SM_hpc - clean.SM_hpc:+.4f}")
    assert deg.Fn_N == pytest.approx(clean.Fn_N, rel=1e-7)
    assert SFC_PCT_PER_PCT_HPC_ETA[0] <= dsfc <= SFC_PCT_PER_PCT_HPC_ETA[1]
    assert TT4_K_PER_PCT_HPC_ETA[0] <= dtt4 <= TT4_K_PER_PCT_HPC_ETA[1]


def test_health_is_reversible_and_acts_on_each_component(model: EngineModel) -> None:
    model.set_health(HealthDeltas())
    ref = model.od.solve(0.0, 0.0, 0.0, N1_pct=90.0)
    for field in ("fan_eta_frac", "hpc_Wc_frac", "hpt_eta_frac", "lpt_Wc_frac"):
        model.set_health(HealthDeltas(**{field: -0.02}))
        p = model.od.solve(0.0, 0.0, 0.0, N1_pct=90.0, guess=ref)
        assert abs(p.Wf_kg_s / ref.Wf_kg_s - 1.0) > 1e-4, field      # the delta changes the engine
    model.set_health(HealthDeltas())
    back = model.od.solve(0.0, 0.0, 0.0, N1_pct=90.0)
    assert back.Wf_kg_s == pytest.approx(ref.Wf_kg_s, rel=1e-10)
    assert back.Tt4_K == pytest.approx(ref.Tt4_K, rel=1e-10)


@pytest.mark.parametrize("value", [0.25, -0.3, float("nan"), True])
def test_health_out_of_range_is_refused(value: object) -> None:
    with pytest.raises(OutOfRangeError, match=r"health_hpc_eta_frac=.*\[-0.2, 0.2\]"):
        HealthDeltas(hpc_eta_frac=value)  # type: ignore[arg-type]
