"""ssp/: SSP files and model, one part of the orchestrator.

SSP files and model: what the files say (``SystemDef``, :mod:`.model`), reading and validating them
(:mod:`.read`; ``.ssp`` archives checked and extracted by :mod:`.archive`; values as text by :mod:`.values`),
flattening nested systems, writing them (:mod:`.write`), units and conversions, and the system
bound to its FMUs (``BoundSystem``: variables, value references, composed conversions, parameter assignments).

May import: its own modules, the shared modules at the package root (``errors``, ``results``, ``__init__``).
Never ``master/``, ``fmu/``, ``scenarios/``, ``recording/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``units``, ``conversion``, ``model``, ``values``, ``archive``, ``read``, ``flatten``, ``write``,
``system_model``, ``parameters``, ``system``. The parts: orchestrator/README.md.
"""
