"""Electrical power system of a hybrid-electric turbofan: machines on the spools, battery pack, DC bus, loads.

Plain Python in SI units (no FMI): :mod:`.machine` (starter-generator on the HP spool, motor-generator on
the LP spool), :mod:`.battery` (Tremblay-Dessaint equivalent circuit scaled from published cell data to a
pack), :mod:`.bus` (constant, scheduled and event-driven loads), :mod:`.ems` (the energy management law),
:mod:`.system` (all of them in one step with an exact energy ledger), :mod:`.params` (parameter files).
"""
