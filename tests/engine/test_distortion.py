"""Inlet distortion, parallel compressor model: limits, conservation, and the surge-margin penalty.

Checks against independent expectations: a distortion of zero strength reproduces the
undistorted solution exactly (the two sectors are then one compressor); mass and energy
close to 1e-9 with distortion; both sectors discharge at the same pressure; the
distorted sector runs closer to surge and the clean sector further from it than the
undistorted compressor (the parallel compressor result, SAE AIR1419), the penalty grows
with the pressure deficit; thrust falls with the recovery loss. The switch on and off
between calls (as over a mission) works from either side.
"""

from __future__ import annotations

import pytest
from test_offdesign import closure  # same folder (pytest puts it on sys.path)

from openemss.models.engine.cycle_design import DesignPoint, design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.distortion import Distortion
from openemss.models.engine.errors import OutOfRangeError
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps


@pytest.fixture(scope="module")
def dp() -> DesignPoint:
    return design(load_params(preset_path("larzac04_sls")))


@pytest.fixture(scope="module")
def od(dp: DesignPoint) -> TurbofanOffDesign:
    return TurbofanOffDesign(dp, scaled_maps(dp))


def test_zero_distortion_is_the_clean_engine(od: TurbofanOffDesign) -> None:
    a = od.solve(N1_pct=95.0)
    b = od.solve(N1_pct=95.0, distortion_fan=Distortion(0.25), distortion_hpc=Distortion(0.3))
    assert b.Fn_N == pytest.approx(a.Fn_N, rel=1e-8) and b.SM_fan == pytest.approx(a.SM_fan, rel=1e-7)
    assert b.SM_hpc == pytest.approx(a.SM_hpc, rel=1e-7)


def test_fan_pressure_distortion_penalises_surge_margin(od: TurbofanOffDesign, dp: DesignPoint) -> None:
    clean = od.solve(N1_pct=95.0)
    sm, fn = [clean.SM_fan], [clean.Fn_N]
    for dpt in (0.05, 0.10):
        d = od.solve(N1_pct=95.0, distortion_fan=Distortion(0.25, dpt), guess=clean)
        assert d.residual_max < 1e-9
        assert d.SM_fan < sm[-1] and d.SM_fan_clean > clean.SM_fan     # distorted sector nearer surge
        assert d.Fn_N < fn[-1]
        dm, de = closure(d, dp)
        assert abs(dm) < 1e-9 and abs(de) < 1e-9
        sm.append(d.SM_fan)
        fn.append(d.Fn_N)
    assert sm[0] - sm[2] > 0.05                                         # a visible penalty: 0.176 -> 0.047


def test_temperature_distortion_at_hpc_and_switching(od: TurbofanOffDesign) -> None:
    clean = od.solve(7500.0, 0.75, N1_pct=95.0)
    hot = od.solve(7500.0, 0.75, N1_pct=95.0, distortion_hpc=Distortion(0.25, 0.0, 30.0), guess=clean)
    assert hot.SM_hpc < clean.SM_hpc < hot.SM_hpc_clean
    back = od.solve(7500.0, 0.75, N1_pct=95.0, guess=hot)
    assert back.Fn_N == pytest.approx(clean.Fn_N, rel=1e-8)


def test_distortion_ranges() -> None:
    with pytest.raises(OutOfRangeError, match="sector_frac"):
        Distortion(1.0, 0.1)
    with pytest.raises(OutOfRangeError, match="dPt_frac"):
        Distortion(0.25, 0.6)
