"""recording/: observers and result formats, one part of the orchestrator (the results side of a run).

The observers that read a run through the one narrow interface (libcosim's observers): the recorders,
``run.json``, real-time pacing and the progress bar; the time series on disk (Parquet parts, CSV with units,
.mat) with units and descriptions, the registry of their formats (``FORMATS``, ``register_format``), and
reading them back. What acts on a run is the run side, ``scenarios/``.

May import: its own modules, ``ssp/``, ``master/``, the shared modules at the package root (``errors``,
``results``, ``__init__``). Never ``fmu/``, ``scenarios/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``observers``, ``timeseries``, ``timeseries_files``. The parts: orchestrator/README.md.
"""
