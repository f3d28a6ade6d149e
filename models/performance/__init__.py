"""The aircraft's performance database for the flight management, generated from the airframe and engine models.

See :mod:`.generate` (``python -m openemss.models.performance.generate``); the FCS reads the result
through :mod:`openemss.models.fcs.performance`.
"""
