"""fmu/: FMU build and export, one part of the orchestrator.

FMU build and export: ``build-fmus`` (pythonfmu slaves to FMUs) and a bound system exported as one container
FMU.

May import: its own modules, ``ssp/``, ``master/``, the shared modules at the package root (``errors``,
``results``, ``__init__``). Never ``scenarios/``, ``recording/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``build``, ``export``, ``fmu_deps``, ``lifecycle``. The parts: orchestrator/README.md.
"""
