"""Parametric mission studies on Dask: many cases of one SSP system, one at a time per worker's case process.

A study file (YAML, :mod:`.spec`) names the system, the missions, the parameter
sets, grids of parameter values and scenarios; every combination is a case
(:mod:`.case`) run by ``emss run`` in its Dask worker's case process (:mod:`.warm`: the
FMUs reset between cases instead of a new process and new instances), into its own
folder. :mod:`.runner` submits the cases to a LocalCluster or a scheduler
address, skips cases already done, retries a case whose worker died once, and
writes the study table (``study.csv``). :mod:`.redesign` is the reference study:
the cycle sweep picks the lowest-SFC engine and both engines fly the mission; with
``carpet: true`` every design of the sweep flies it (:mod:`.carpet`: the mission-fuel carpet).
"""
