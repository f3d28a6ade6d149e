"""openEMSS: engine mission simulation with FMI 2.0 FMUs wired by SSP.

The Python API (a notebook's entry point)::

    import openemss
    r = openemss.run(stop_time=600, set={"engine.preset": "reference_study"}, out="results/nb")
    r.df                  # the time series as a pandas DataFrame (units in r.df.attrs["units"])
    r["engine.Fn_N"]      # one column as a NumPy array
    r.summary             # summary.json of a mission run
    r.info                # run.json

``run`` is :func:`openemss.orchestrator.cli.api.run`, the code behind ``emss run``;
``read_timeseries`` reads any run's results folder back.

This file is the ``openemss`` package itself (pyproject maps the package ``openemss`` to this
folder and every sub-package to its own top-level folder).

Its names are imported on first use (PEP 562), so that ``import openemss.<anything>`` stays light: the
console scripts install their signal handling before fmpy, numpy and the models are imported
(:mod:`openemss.orchestrator.cli.entry`).
"""
from __future__ import annotations

import importlib
from typing import Any

__all__ = ["run", "RunResult", "read_timeseries", "TimeSeries"]
_WHERE = {"run": "openemss.orchestrator.cli.api", "RunResult": "openemss.orchestrator.cli.api",
          "read_timeseries": "openemss.orchestrator.recording.timeseries",
          "TimeSeries": "openemss.orchestrator.recording.timeseries"}


def __getattr__(name: str) -> Any:
    if name not in _WHERE:
        raise AttributeError(f"module 'openemss' has no attribute {name!r}")
    value = getattr(importlib.import_module(_WHERE[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
