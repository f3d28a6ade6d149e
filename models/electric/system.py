"""The electrical power system in one step: loads, energy management, machines, battery, exact ledger.

:class:`ElectricSystem` owns the HP starter-generator and the LP motor-generator (:mod:`.machine`), the
battery pack (:mod:`.battery`), the loads (:mod:`.bus`) and the law (:mod:`.ems`). Each step holds its
inputs (spool speeds, lever, on-ground, event pulse power) constant and resolves the bus:

1. the law's requests (LP shaft power, HP electrical target), each machine's electrical power changing
   by at most its ``ramp_W_s`` per second, and cut to its torque, power and speed limits;
2. the battery takes the rest, within its power range of this step (:meth:`BatteryPack.power_limits_W`);
3. where the battery cannot: less boost (or charging) first, then more (or less) HP power within its
   limit and ramp, and what is still missing is shed (``load_shed_W``).

The ledger adds ``P dt`` of every flow, so over any run, to round-off::

    E_shaft_hp = E_elec_hp + E_loss_hp,  E_shaft_lp = E_elec_lp + E_loss_lp       (each machine)
    E_elec_hp + E_elec_lp + E_batt = E_loads - E_shed                               (the bus)
    E_batt = sum of V I dt                                                          (the battery)

:data:`OUTPUTS` (name, unit, description) is the one table of the outputs, in the order of
:attr:`ElectricSystem.values`; :data:`INPUTS` that of the inputs.
"""
from __future__ import annotations

import dataclasses
from typing import Any

from .battery import BatteryPack, default_cell
from .bus import Loads
from .ems import EnergyManagement
from .errors import ParameterError
from .machine import ElectricMachine, MachinePoint
from .params import SECTIONS, CellParams, parameter_sets

__all__ = ["ElectricSystem", "INPUTS", "OUTPUTS", "FLAGS", "SECTIONS"]

#: Inputs: (name, unit, description).
INPUTS: tuple[tuple[str, str, str], ...] = (
    ("N1_rpm", "rpm", "LP spool speed"), ("N2_rpm", "rpm", "HP spool speed"),
    ("lever_norm", "-", "Thrust lever command, 0 to 1"), ("vs_m_s", "m/s", "Vertical speed, positive up"),
    ("pulse_load_W", "W", "Event-driven pulse load on the bus (e.g. set by a scenario)"),
)
#: Real outputs in the order of :attr:`ElectricSystem.values`: (name, unit, description).
OUTPUTS: tuple[tuple[str, str, str], ...] = (
    ("offtake_hp_W", "W", "Shaft power taken from the HP spool, < 0 delivered to it"),
    ("offtake_lp_W", "W", "Shaft power taken from the LP spool, < 0 delivered to it (boost)"),
    ("hp_elec_W", "W", "HP starter-generator power to the bus, < 0 drawn"),
    ("lp_elec_W", "W", "LP motor-generator power to the bus, < 0 drawn (boost)"),
    ("hp_loss_W", "W", "HP machine losses"), ("lp_loss_W", "W", "LP machine losses"),
    ("battery_W", "W", "Battery power to the bus, < 0 charging"),
    ("battery_V", "V", "Battery terminal voltage"), ("battery_A", "A", "Battery current, < 0 charging"),
    ("soc", "-", "Battery state of charge"),
    ("load_W", "W", "Bus load demand"), ("pulse_W", "W", "Pulse part of the bus load demand"),
    ("load_shed_W", "W", "Bus load no source could supply"),
    ("E_shaft_hp_J", "J", "Energy taken from the HP spool since the start"),
    ("E_shaft_lp_J", "J", "Energy taken from the LP spool since the start (< 0: delivered)"),
    ("E_elec_hp_J", "J", "Energy the HP machine delivered to the bus"),
    ("E_elec_lp_J", "J", "Energy the LP machine delivered to the bus"),
    ("E_loss_J", "J", "Energy lost in both machines"),
    ("E_batt_J", "J", "Energy the battery delivered to the bus, the sum of V I dt"),
    ("E_loads_J", "J", "Energy the loads demanded"), ("E_shed_J", "J", "Energy of the loads shed"),
    ("added_mass_kg", "kg", "Mass of the electrical system (pack, machines, wiring), added to the airframe"),
)
#: Boolean outputs (limits hit in the last step): (name, description).
FLAGS: tuple[tuple[str, str], ...] = (
    ("hp_limited", "The HP machine's request was cut by its torque, power, speed or ramp limit"),
    ("lp_limited", "The LP machine's request was cut by its torque, power, speed or ramp limit"),
    ("battery_limited", "The battery's request was cut by its current, voltage or SOC limit"),
    ("load_shed", "Part of the bus load was shed"),
)


class ElectricSystem:
    """HP starter-generator, LP motor-generator, battery pack, DC bus loads and the energy management law.

    Parameters
    ----------
    params : dict, optional
        Dotted parameter values ``<section>.<name>`` replacing those of ``data/electric.yaml``.
    cell : CellParams, optional
        Cell data; default the A123 ANR26650M1 of ``data/a123_anr26650m1.yaml``.
    """

    def __init__(self, params: dict[str, Any] | None = None, cell: CellParams | None = None) -> None:
        self._specs = parameter_sets()
        self._sets: dict[str, Any] = {s: spec.make() for s, spec in self._specs.items()}
        self.cell = cell if cell is not None else default_cell()
        for name, value in (params or {}).items():
            self.set_parameter(name, value)
        self.reset()

    # -- parameters by dotted name
    def parameter_names(self) -> tuple[str, ...]:
        """Every parameter as ``<section>.<name>``."""
        return tuple(f"{s}.{f.name}" for s, ps in self._sets.items() for f in dataclasses.fields(ps))

    def get_parameter(self, name: str) -> Any:
        """The value of parameter ``<section>.<name>``."""
        section, _, field = name.partition(".")
        if section not in self._sets or field not in {f.name for f in dataclasses.fields(self._sets[section])}:
            raise ParameterError(f"electric: unknown parameter '{name}' (parameters: <section>.<name> with "
                                 f"sections {', '.join(self._sets)})")
        return getattr(self._sets[section], field)

    def set_parameter(self, name: str, value: Any) -> None:
        """Set parameter ``<section>.<name>`` (checked against its range); takes effect at once, except the
        battery's layout and initial SOC, which take effect at the next :meth:`reset`."""
        self.get_parameter(name)
        section, _, field = name.partition(".")
        self._sets[section] = self._specs[section].replace(self._sets[section], f"electric.{section}",
                                                           **{field: value})
        if hasattr(self, "ems"):
            self.hp.p, self.lp.p = self._sets["hp_machine"], self._sets["lp_machine"]
            self.loads.p, self.ems.p = self._sets["bus"], self._sets["ems"]
            self.battery.pack = dataclasses.replace(self.battery.pack, soc_min=self._sets["battery"].soc_min,
                                                    soc_max=self._sets["battery"].soc_max)
            self.values[-1] = self.mass_kg

    # -- state
    def reset(self) -> None:
        """Initial state: the battery at ``battery.soc0``, the ledger at zero, the machines idle."""
        s = self._sets
        self.hp, self.lp = ElectricMachine(s["hp_machine"]), ElectricMachine(s["lp_machine"])
        self.battery = BatteryPack(s["battery"], self.cell)
        self.loads, self.ems = Loads(s["bus"]), EnergyManagement(s["ems"])
        self.mode = 0
        self.flags = [False] * len(FLAGS)
        self._hp_prev_W = 0.0
        self._lp_prev_W = 0.0
        self.values = [0.0] * len(OUTPUTS)
        self.values[9] = self.battery.soc
        self.values[7] = self.battery.V_oc_V
        self.values[-1] = self.mass_kg

    @property
    def mass_kg(self) -> float:
        """Pack, both machines and the wiring [kg], from the present parameters."""
        s = self._sets
        return (BatteryPack(s["battery"], self.cell).mass_kg + ElectricMachine(s["hp_machine"]).mass_kg
                + ElectricMachine(s["lp_machine"]).mass_kg + s["bus"].wiring_mass_kg)

    def _ramped(self, m: ElectricMachine, P_elec_W: float, prev_W: float, n_rpm: float, dt_s: float
                ) -> tuple[MachinePoint, bool]:
        """The machine's point for an electrical target, its change limited to ``ramp_W_s dt``."""
        d = m.p.ramp_W_s * dt_s
        target = min(max(P_elec_W, prev_W - d), prev_W + d)
        pt = m.at_elec(target, n_rpm)
        return pt, pt.limited or target != P_elec_W

    def step(self, t_s: float, dt_s: float, N1_rpm: float, N2_rpm: float, lever: float, on_ground: bool,
             vs_m_s: float = 0.0, pulse_event_W: float = 0.0) -> list[float]:
        """Advance by ``dt_s`` from ``t_s`` with the inputs held; returns :attr:`values` (order of OUTPUTS)."""
        load_W, pulse_W = self.loads.demand_W(t_s, pulse_event_W)
        steady_W = load_W - pulse_W
        bat = self.battery
        d = self.ems.decide(lever, on_ground, vs_m_s, bat.soc, steady_W, pulse_W)
        # LP: the law's shaft request as an electrical target (ramped); HP: its electrical target (ramped)
        lp_req = self.lp.at_shaft(d.lp_shaft_W, N1_rpm)
        lp, lp_lim = self._ramped(self.lp, lp_req.P_elec_W if d.lp_shaft_W != 0.0 else 0.0, self._lp_prev_W,
                                  N1_rpm, dt_s)
        lp_lim = lp_lim or lp_req.limited
        hp, hp_lim = self._ramped(self.hp, d.hp_elec_W, self._hp_prev_W, N2_rpm, dt_s)
        lo_W, hi_W = bat.power_limits_W(dt_s)
        need = load_W - hp.P_elec_W - lp.P_elec_W  # the battery's share
        tol = 1e-9 * max(abs(load_W), abs(lo_W), abs(hi_W), 1.0)  # round-off of the machines' inverse
        if need > hi_W + tol:  # too little: less boost, then more HP, then shed
            if lp.P_elec_W < 0.0:
                lp = self.lp.at_elec(min(lp.P_elec_W + (need - hi_W), 0.0), N1_rpm)
                lp_lim = True
            need = load_W - hp.P_elec_W - lp.P_elec_W
            if need > hi_W + tol:
                hp_max, _ = self._ramped(self.hp, self.hp.p.P_max_W * 10.0, self._hp_prev_W, N2_rpm, dt_s)
                hp = self.hp.at_elec(min(hp.P_elec_W + (need - hi_W), hp_max.P_elec_W), N2_rpm)
                hp_lim = True
        elif need < lo_W - tol:  # too much: less charging, then less HP
            if lp.P_elec_W > 0.0:
                lp = self.lp.at_elec(max(lp.P_elec_W - (lo_W - need), 0.0), N1_rpm)
                lp_lim = True
            need = load_W - hp.P_elec_W - lp.P_elec_W
            if need < lo_W - tol and hp.P_elec_W > 0.0:
                hp = self.hp.at_elec(max(hp.P_elec_W - (lo_W - need), 0.0), N2_rpm)
                hp_lim = True
        need = load_W - hp.P_elec_W - lp.P_elec_W
        b = bat.step(need, dt_s)
        shed_W = load_W - hp.P_elec_W - lp.P_elec_W - b.P_W  # > 0: unserved; the bus balances exactly
        self._hp_prev_W, self._lp_prev_W = hp.P_elec_W, lp.P_elec_W
        self.mode = d.mode
        self.flags = [hp_lim, lp_lim, b.limited, shed_W > 1e-9 * max(load_W, 1.0)]
        v = self.values
        v[0], v[1], v[2], v[3], v[4], v[5] = hp.P_shaft_W, lp.P_shaft_W, hp.P_elec_W, lp.P_elec_W, hp.P_loss_W, \
            lp.P_loss_W
        v[6], v[7], v[8], v[9], v[10], v[11], v[12] = b.P_W, b.V_V, b.I_A, b.soc, load_W, pulse_W, shed_W
        v[13] += hp.P_shaft_W * dt_s
        v[14] += lp.P_shaft_W * dt_s
        v[15] += hp.P_elec_W * dt_s
        v[16] += lp.P_elec_W * dt_s
        v[17] += (hp.P_loss_W + lp.P_loss_W) * dt_s
        v[18] += b.V_V * b.I_A * dt_s
        v[19] += load_W * dt_s
        v[20] += shed_W * dt_s
        return v
