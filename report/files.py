"""The names of the report's own files in a results folder, defined once.

Only the report writes them; the orchestrator knows none of them (it asks the plugin: ``output_files``,
``run_summary``), and the study reads a case's summary through :data:`SUMMARY`. This module imports nothing, so
that naming a file costs no import of the report's plotting.
"""
from __future__ import annotations

__all__ = ["SUMMARY", "PLOTS_RECORD"]

#: The summary of a mission run (:mod:`.summary`): time, fuel, limits hit, landing, every section.
SUMMARY = "summary.json"
#: What made each figure of a folder that ``emss plot`` wrote into: runs, window, variables (so that another
#: plot into the same folder does not silently replace it).
PLOTS_RECORD = "plots.json"
