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
"""
from openemss.orchestrator.cli.api import RunResult, run
from openemss.orchestrator.scenarios.timeseries import TimeSeries, read_timeseries

__all__ = ["run", "RunResult", "read_timeseries", "TimeSeries"]
