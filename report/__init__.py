"""Mission reports of openEMSS runs: ``summary.json`` and plots from a run's results folder.

An ``emss`` plugin (entry point group ``openemss.plugins``, :mod:`.plugin`): after every
``emss run`` it writes the summary and the plots of a run that recorded a mission (a
flight control system's ``section_index`` and an engine's fuel flow); ``emss plot`` draws
them again from a finished run, or two runs on one figure. The orchestrator knows nothing
about missions; this package does.
"""
