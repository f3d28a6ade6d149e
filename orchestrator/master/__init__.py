"""master/: the master (slaves, exchange, algorithms, execution), one part of the orchestrator.

The master: one FMU instance with batched I/O (the slave) and the pool that keeps instances warm between runs
of one process (fmi2Reset); the exchange vectors, transfers, input modifiers and the probe; the algorithms and
their registry; conditions and the stop condition; the execution (time, initialization, the run loop).

May import: its own modules, ``ssp/``, the shared modules at the package root (``errors``, ``results``,
``__init__``). Never ``fmu/``, ``scenarios/``, ``recording/``, ``cli/`` (tests/test_import_graph.py checks it).

Modules: ``transfer``, ``pool``, ``slave``, ``exchange``, ``algorithm``, ``iterative``, ``algorithm_registry``,
``condition``, ``execution``. The parts: orchestrator/README.md.
"""
