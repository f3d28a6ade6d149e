"""Life usage of engine parts over a mission: disc low-cycle fatigue, turbine blade creep (:mod:`.usage`).

Plain Python on recorded time series (no FMI, no engine model): the report computes it after a run.
"""
