"""The battery pack against the published data it was built from, and its limits.

References:

* the A123 ANR26650M1 data sheet's 1C discharge (data/a123_anr26650m1.yaml): a full cell starts at
  the 3.6 V charge voltage, its plateau is the 3.3 V nominal voltage, it delivers the rated 2.3 Ah to
  the 2.0 V cut-off;
* Tremblay & Dessaint (2009), eq. 1, written out here by hand for a constant-current discharge
  (i* = i after the filter has settled) -- the model must agree with its published equation;
* coulomb counting and the sum of V I dt, for the state of charge and the energy.

Tolerances: 0.06 V on the data sheet's voltages (the curve read at its characteristic points; the
generic model's fit error is of this order, Tremblay & Dessaint report under 2 % over the nominal
zone), 5 % on the capacity; 1e-12 relative where the same arithmetic is done two ways.
"""
from __future__ import annotations

import math

import pytest

from openemss.models.electric.battery import BatteryPack, cell_voltage, default_cell
from openemss.models.electric.params import PackParams

CELL = default_cell()


def _pack(ns: int = 1, npar: int = 1, soc0: float = 1.0, soc_min: float = 0.0, soc_max: float = 1.0) -> BatteryPack:
    return BatteryPack(PackParams(ns, npar, soc0, soc_min, soc_max, 1.25), CELL)


def _td_discharge(it_Ah: float, i_A: float) -> float:
    """Tremblay & Dessaint (2009) eq. 1 with i* = i, by hand."""
    E0, R, K, A, B, Q = 3.366, 0.01, 0.0076, 0.26422, 26.5487, 2.3
    return E0 - R * i_A - K * Q / (Q - it_Ah) * (it_Ah + i_A) + A * math.exp(-B * it_Ah)


def _discharge_1c(dt_s: float = 1.0) -> list[tuple[float, float]]:
    """(extracted Ah, V) of a full cell discharged at 1C (2.3 A) to the 2.0 V cut-off, current not limited."""
    b = _pack()
    b.i_filt_A = CELL.Q_Ah  # the filtered current settled at 1C, as in the data sheet's steady discharge
    out = []
    while True:
        I = CELL.Q_Ah * 1.0
        V = cell_voltage(CELL, b.it_Ah, I, b.i_filt_A)
        if V < CELL.V_cutoff_V:
            return out
        out.append((b.it_Ah, V))
        b.it_Ah += I * dt_s / 3600.0


def test_1c_discharge_against_the_data_sheet() -> None:
    curve = _discharge_1c()
    v_start = curve[0][1]
    v_mid = min(curve, key=lambda p: abs(p[0] - 0.5 * CELL.Q_Ah))[1]
    delivered = curve[-1][0]
    assert v_start == pytest.approx(CELL.V_full_V, abs=0.06)      # 3.6 V full
    assert v_mid == pytest.approx(CELL.V_nominal_V, abs=0.06)     # 3.3 V plateau
    assert delivered == pytest.approx(CELL.Q_Ah, rel=0.05)         # 2.3 Ah to 2.0 V


@pytest.mark.parametrize("it", [0.0, 0.05, 0.5, 1.15, 2.0, 2.2])
@pytest.mark.parametrize("c_rate", [0.5, 1.0, 5.0])
def test_cell_voltage_is_the_published_equation(it: float, c_rate: float) -> None:
    i = c_rate * 2.3
    assert cell_voltage(CELL, it, i, i) == pytest.approx(_td_discharge(it, i), rel=1e-12)


def test_pack_scaling() -> None:
    """82s8p: voltages x 82 at the pack current / 8 per cell; capacity x 8."""
    one, pack = _pack(soc0=0.7), _pack(82, 8, soc0=0.7)
    assert pack.capacity_Ah == pytest.approx(8 * 2.3)
    s1, sp = one.step(10.0, 1.0), pack.step(10.0 * 82 * 8, 1.0)
    assert sp.I_A == pytest.approx(8 * s1.I_A, rel=1e-12)
    assert sp.V_V == pytest.approx(82 * s1.V_V, rel=1e-12)


def test_energy_is_the_sum_of_vi_dt_and_soc_the_coulomb_count() -> None:
    b = _pack(82, 8, soc0=0.9, soc_min=0.1, soc_max=0.95)
    E, q, soc0 = 0.0, 0.0, b.soc
    for k in range(2000):
        P = 40e3 * math.sin(k / 50.0)
        s = b.step(P, 0.05)
        assert s.P_W == s.V_V * s.I_A
        E += s.V_V * s.I_A * 0.05
        q += s.I_A * 0.05 / 3600.0
    assert soc0 - b.soc == pytest.approx(q / b.capacity_Ah, rel=1e-10)


@pytest.mark.parametrize("P_W", [1e6, -1e6])
def test_limits_hold_without_overshoot(P_W: float) -> None:
    """A request far beyond every limit: current, voltage and SOC limits hold in every step, the SOC
    stops exactly on its limit."""
    b = _pack(82, 8, soc0=0.5, soc_min=0.2, soc_max=0.8)
    for _ in range(20000):
        s = b.step(P_W, 0.05)
        assert -CELL.I_charge_max_A * 8 * (1 + 1e-12) <= s.I_A <= CELL.I_discharge_max_A * 8 * (1 + 1e-12)
        assert 0.2 - 1e-12 <= s.soc <= 0.8 + 1e-12
        assert CELL.V_cutoff_V * 82 * (1 - 1e-12) <= s.V_V <= CELL.V_full_V * 82 * (1 + 1e-12)
        assert s.limited
    assert b.soc == pytest.approx(0.2 if P_W > 0 else 0.8, abs=1e-9)
