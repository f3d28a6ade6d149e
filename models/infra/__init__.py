"""The infrastructure of the model packages, apart from their physics: no equation of the aircraft, engine or
control lives here.

- :mod:`.files`: files written whole (atomic), figures as bytes, CSV text;
- :mod:`.safe_yaml`: the one reader of YAML and JSON text files (duplicate keys, alias bombs, NaN refused with
  file:line);
- :mod:`.values`: typed values of the files users write, one check per kind;
- :mod:`.params`: the one parameter mechanism (parameter files, frozen parameter sets, FMU parameters);
- :mod:`.signals`: signal tables (name, causality, unit, description) and SI unit text;
- :mod:`.jit`: compiled kernels with numba, cached on disk by content;
- :mod:`.records`: frozen records built fast.

It sits under ``models/`` because an FMU carries only ``openemss.models`` packages (``build-fmus`` vendors the
model packages a slave imports, and their siblings, with their relative imports); the orchestrator, the report
and the study use the same files, YAML and value checks. It imports nothing of the other model packages.
"""
