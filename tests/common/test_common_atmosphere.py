"""The one atmosphere (models/common/atmosphere.py) against ISO 2533 / U.S. Standard Atmosphere 1976
tables, and the same numbers in the engine, the airframe, the FCS and the engine's compiled path."""
from __future__ import annotations

import math

import numpy as np
import pytest

from openemss.models.common import atmosphere as atm

# U.S. Standard Atmosphere 1976 (= ISO 2533:1975 to 32 km), Table I by geopotential altitude:
# H [m], T [K], p [Pa]. 5e-6: the tables' rounding and the 7th digit of R.
TABLE = [(0.0, 288.15, 101325.0), (1000.0, 281.65, 89874.6), (5000.0, 255.65, 54019.9),
         (11000.0, 216.65, 22632.06), (15000.0, 216.65, 12044.57), (20000.0, 216.65, 5474.889),
         (25000.0, 221.65, 2511.02), (32000.0, 228.65, 868.0187), (-1000.0, 294.65, 113929.0)]


@pytest.mark.parametrize("alt_m, T_K, p_Pa", TABLE)
def test_table(alt_m: float, T_K: float, p_Pa: float) -> None:
    a = atm.isa(alt_m)
    assert a.T_K == pytest.approx(T_K, abs=1e-9)
    assert a.p_Pa == pytest.approx(p_Pa, rel=5e-6)


def test_sea_level_density_sound_viscosity() -> None:
    """ISO 2533 sea level: rho 1.2250 kg/m^3, a 340.294 m/s, mu 1.7894e-5 Pa s."""
    a = atm.isa(0.0)
    assert a.rho_kg_m3 == pytest.approx(1.2250, abs=5e-5)
    assert a.a_m_s == pytest.approx(340.294, abs=5e-4)
    assert atm.sutherland_viscosity(a.T_K) == pytest.approx(1.7894e-5, rel=1e-4)


def test_continuous_at_layer_bases() -> None:
    for h in atm.LAYER_H_M[1:]:
        lo, hi = atm.isa_T_p(h - 1e-7, 0.0), atm.isa_T_p(h, 0.0)
        assert lo[0] == pytest.approx(hi[0], abs=1e-6) and lo[1] == pytest.approx(hi[1], rel=1e-9)


def test_deviation_and_range() -> None:
    a, b = atm.isa(3000.0), atm.isa(3000.0, 15.0)
    assert b.T_K - a.T_K == pytest.approx(15.0) and b.p_Pa == a.p_Pa
    for alt, dT, what in ((40000.0, 0.0, "altitude 40000.0 m"), (0.0, math.nan, "ISA deviation nan"),
                          (11000.0, -80.0, "outside the valid range 150 to 350 K")):
        with pytest.raises(atm.AtmosphereRangeError, match=what):
            atm.isa(alt, dT)
        assert what.split(" ")[0] in (atm.check(alt, dT) or "")
    assert atm.check(5000.0, 10.0) is None


def test_one_source_in_every_model() -> None:
    """Engine, airframe, FCS and the engine's compiled free stream give the common atmosphere's numbers."""
    from openemss.models.airframe.aero import isa as airframe_isa
    from openemss.models.engine import jit_kernels
    from openemss.models.engine.atmosphere import isa as engine_isa
    from openemss.models.engine.jit_freestream import _isa_T_p
    from openemss.models.fcs.atmosphere import isa as fcs_isa

    for alt in (0.0, 4321.0, 11000.0, 17500.0):
        for dT in (0.0, -12.5):
            ref = atm.isa(alt, dT)
            e, f, a = engine_isa(alt, dT), fcs_isa(alt, dT), airframe_isa(alt, dT)
            assert (e.T_K, e.P_Pa, e.rho_kg_m3, e.a_m_s) == (ref.T_K, ref.p_Pa, ref.rho_kg_m3, ref.a_m_s)
            assert f == ref
            assert a[:4] == (ref.T_K, ref.p_Pa, ref.rho_kg_m3, ref.a_m_s)
            T, p = _isa_T_p(alt, dT)                        # compiled with numba when it is there
            assert T == pytest.approx(ref.T_K, rel=1e-15) and p == pytest.approx(ref.p_Pa, rel=1e-14)
    # the compiled path is this same source compiled, not a second implementation
    assert (_isa_T_p.py_func if jit_kernels.AVAILABLE else _isa_T_p) is atm.isa_T_p
    assert np.isfinite(_isa_T_p(32000.0, 0.0)[1])
