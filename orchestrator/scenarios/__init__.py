"""scenarios/: scenarios and observers, one part of the orchestrator.

Scenarios and observers: scenario files (set, ramp, hold, release, ``when:``); recorders, ``run.json``, real-
time pacing, the progress bar.

May import: its own modules, ``ssp/``, ``master/``, the shared modules at the package root (``errors``,
``results``, ``__init__``). Never ``fmu/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``manipulators``, ``observers``, ``timeseries``. The parts: orchestrator/README.md.
"""
