"""cli/: the command line, one part of the orchestrator.

The command line: the ``emss`` command (:mod:`.main`, also ``python -m openemss.orchestrator.cli``) and its
plugins.

May import: its own modules, ``ssp/``, ``master/``, ``fmu/``, ``scenarios/``, ``recording/``, the shared modules at the
package root (``errors``, ``results``, ``__init__``).

Modules: ``entry`` (the console scripts), ``main``, ``plugins``, ``hooks``, ``api``, ``describe``. The parts: orchestrator/README.md.
"""
