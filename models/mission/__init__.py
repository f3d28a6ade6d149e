"""The mission: what is to be flown and where, apart from how the flight control flies it.

- :mod:`.geo`: geodesy on the WGS-84 ellipsoid (positions, bearings, distances, local frames);
- :mod:`.runway`: a runway direction and its frame;
- :mod:`.weather`: winds aloft and turbulence of a mission or a weather file;
- :mod:`.marks`: the file and line of every value of a mission file, for messages;
- :mod:`.qgc`: QGroundControl ``.plan`` files converted to missions;
- :mod:`.errors`: :class:`~.errors.MissionError` (an invalid mission or weather file) and
  :class:`~.errors.GeometryError`.

Used by the FCS (``models/fcs``: the section laws fly it), the airframe FMU (the mission's start and weather),
the report and the study. It imports nothing of the other model packages (only ``models/infra``).
"""
