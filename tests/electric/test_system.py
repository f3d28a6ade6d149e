"""The electrical system in time: the energy ledger closes to round-off, limits hold, the law's modes.

Independent references: conservation of energy (each machine: shaft = electrical + losses; the bus:
sources = loads served; the battery: its counter = the sum of V I dt computed here from its outputs),
and the limits of the parameter file (never exceeded, whatever is asked).
"""
from __future__ import annotations

import random

import pytest

from openemss.models.electric.ems import MODES
from openemss.models.electric.errors import ParameterError
from openemss.models.electric.system import FLAGS, OUTPUTS, ElectricSystem

IDX = {name: i for i, (name, _, _) in enumerate(OUTPUTS)}
DT = 0.05


def _drive(s: ElectricSystem, n: int, seed: int = 1) -> list[list[float]]:
    """Random but plausible inputs: spool speeds, lever, climb or not, ground, pulses."""
    rng = random.Random(seed)
    rows = []
    lever, vs, pulse = 1.0, 5.0, 0.0
    for k in range(n):
        if k % 200 == 0:
            lever, vs = rng.choice([(1.0, 8.0), (0.6, 0.0), (0.4, -8.0), (0.9, 3.0)])
            pulse = rng.choice([0.0, 0.0, 60e3, 150e3])
        N1, N2 = 9000.0 + 8000.0 * lever, 16000.0 + 6000.0 * lever
        rows.append(list(s.step(k * DT, DT, N1, N2, lever, k < 100, vs, pulse)) + [float(s.mode)] + s.flags)
    return rows


def test_energy_ledger_closes_to_round_off() -> None:
    s = ElectricSystem({"battery.n_parallel": 4, "battery.soc0": 0.5})
    rows = _drive(s, 6000)
    v = rows[-1]
    g = lambda n: v[IDX[n]]  # noqa: E731
    scale = max(abs(g("E_shaft_hp_J")), abs(g("E_shaft_lp_J")), abs(g("E_loads_J")))
    assert g("E_shaft_hp_J") + g("E_shaft_lp_J") - g("E_elec_hp_J") - g("E_elec_lp_J") - g("E_loss_J") == \
        pytest.approx(0.0, abs=1e-12 * scale * 6000)
    assert g("E_elec_hp_J") + g("E_elec_lp_J") + g("E_batt_J") - g("E_loads_J") + g("E_shed_J") == \
        pytest.approx(0.0, abs=1e-12 * scale * 6000)
    # the battery's counter against V I dt of its outputs, and every step's bus balance
    vi = sum(r[IDX["battery_V"]] * r[IDX["battery_A"]] * DT for r in rows)
    assert g("E_batt_J") == pytest.approx(vi, rel=1e-12)
    for r in rows:
        bal = r[IDX["hp_elec_W"]] + r[IDX["lp_elec_W"]] + r[IDX["battery_W"]] - r[IDX["load_W"]] + r[IDX["load_shed_W"]]
        assert abs(bal) <= 1e-9 * max(r[IDX["load_W"]], 1.0)
        assert r[IDX["offtake_hp_W"]] - r[IDX["hp_elec_W"]] - r[IDX["hp_loss_W"]] == pytest.approx(0.0, abs=1e-8)
        assert r[IDX["offtake_lp_W"]] - r[IDX["lp_elec_W"]] - r[IDX["lp_loss_W"]] == pytest.approx(0.0, abs=1e-8)


def test_limits_hold_without_overshoot() -> None:
    """A small pack, a large boost and pulses beyond every source: machines within power and torque,
    the battery within current and SOC, the rest shed (and said)."""
    s = ElectricSystem({"battery.n_parallel": 1, "battery.soc0": 0.4, "ems.boost_W": 1e6, "ems.charge_W": 1e6})
    rows = _drive(s, 8000, seed=3)
    hp, lp, cell = s.hp.p, s.lp.p, s.cell
    for r in rows:
        assert abs(r[IDX["offtake_hp_W"]]) <= hp.P_max_W * (1 + 1e-12) + hp.k_i_W_s * 3000 + hp.k_w_W_s3 * 3000 ** 3
        assert abs(r[IDX["offtake_lp_W"]]) <= lp.P_max_W * (1 + 1e-12) + lp.k_i_W_s * 3000 + lp.k_w_W_s3 * 3000 ** 3
        assert -cell.I_charge_max_A * (1 + 1e-12) <= r[IDX["battery_A"]] <= cell.I_discharge_max_A * (1 + 1e-12)
        assert 0.2 - 1e-12 <= r[IDX["soc"]] <= 0.95 + 1e-12
        assert r[IDX["load_shed_W"]] >= -1e-6
    assert max(r[IDX["load_shed_W"]] for r in rows) > 0.0           # 150 kW pulses cannot all be served
    assert any(r[len(OUTPUTS) + 1 + [n for n, _ in FLAGS].index("load_shed")] for r in rows)


def test_modes_of_the_law() -> None:
    s = ElectricSystem({"battery.soc0": 0.6})
    s.step(0.0, DT, 17000.0, 22000.0, 1.0, True, 0.0)
    assert MODES[s.mode] == "boost" and s.values[IDX["offtake_lp_W"]] < 0.0          # take-off roll
    s.step(DT, DT, 15000.0, 21000.0, 0.6, False, 0.0)
    assert MODES[s.mode] == "charge" and s.values[IDX["offtake_lp_W"]] > 0.0         # cruise
    s.step(2 * DT, DT, 15000.0, 21000.0, 0.6, False, 0.0, 50e3)
    assert MODES[s.mode] == "pulse" and s.values[IDX["pulse_W"]] == 50e3
    for k in range(100):  # the HP generator ramps up at its ramp rate and then carries the pulse
        s.step((3 + k) * DT, DT, 15000.0, 21000.0, 0.6, False, 0.0, 50e3)
    assert s.values[IDX["hp_elec_W"]] == pytest.approx(50e3 + s.loads.p.avionics_W, rel=1e-9)
    s.set_parameter("ems.enabled", False)
    s.step(1e3, DT, 17000.0, 22000.0, 1.0, False, 10.0)
    assert MODES[s.mode] == "generate" and abs(s.values[IDX["lp_elec_W"]]) == 0.0


def test_scheduled_pulses() -> None:
    s = ElectricSystem({"bus.pulse_start_s": 10.0, "bus.pulse_duration_s": 2.0, "bus.pulse_period_s": 5.0,
                        "bus.pulse_count": 2, "bus.pulse_W": 1e4})
    on = [t for t in (x * 0.5 for x in range(60)) if s.loads.scheduled_W(t) > 0]
    assert on == [10.0, 10.5, 11.0, 11.5, 15.0, 15.5, 16.0, 16.5]


def test_mass_by_hand() -> None:
    """Cells x 70 g x 1.25, machines at 5 kW/kg, 10 kg wiring."""
    s = ElectricSystem({"battery.n_parallel": 12})
    assert s.mass_kg == pytest.approx(82 * 12 * 0.070 * 1.25 + 80.0 / 5 + 40.0 / 5 + 10.0, rel=1e-12)
    assert s.values[IDX["added_mass_kg"]] == pytest.approx(s.mass_kg)


@pytest.mark.parametrize("name, value", [("ems.boost_W", -1.0), ("battery.n_parallel", 2.5),
                                         ("ems.nonsense", 1.0), ("ems.enabled", 3.0)])
def test_bad_parameters_say_what_and_where(name: str, value: float) -> None:
    with pytest.raises(ParameterError, match=name.split(".")[1] if "nonsense" not in name else "unknown"):
        ElectricSystem({name: value})
