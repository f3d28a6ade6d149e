"""The mission: what is to be flown and where, apart from how the flight control flies it.

- :mod:`.mission`: mission files (YAML, or QGroundControl ``.plan`` through :mod:`.qgc`) read and validated
  with file:line errors: :class:`~.mission.Mission`, :class:`~.mission.Section`, ``load_mission``;
- :mod:`.sections`: the section types as a mission file declares them (fields, completion, conformance kind),
  the one registry of the declarations; the FCS's flight law of each type derives from its declaration;
- :mod:`.speed`: a speed target (Mach, calibrated or true airspeed) and its true airspeed at an altitude;
- :mod:`.geo`: geodesy on the WGS-84 ellipsoid (positions, bearings, distances, local frames);
- :mod:`.runway`: a runway direction and its frame;
- :mod:`.weather`: winds aloft and turbulence of a mission or a weather file;
- :mod:`.marks`: the file and line of every value of a mission file, for messages;
- :mod:`.errors`: :class:`~.errors.MissionError` (an invalid mission or weather file) and
  :class:`~.errors.GeometryError`.

Used by the FCS (``models/fcs``: the section laws fly it), the airframe FMU (the mission's start and weather),
the report and the study. It imports nothing of the other model packages but the shared physics
(``models/common``) and the infrastructure (``models/infra``).
"""
