"""scenarios/: scenarios, one part of the orchestrator (the run side: what acts on a run).

Scenario files (set, ramp, hold, release, ``when:``) and the manipulator that applies them where a slave's
inputs are set (libcosim's manipulators). What a run records and writes is the results side, ``recording/``.

May import: its own modules, ``ssp/``, ``master/``, the shared modules at the package root (``errors``,
``results``, ``__init__``). Never ``fmu/``, ``recording/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``manipulators``. The parts: orchestrator/README.md.
"""
