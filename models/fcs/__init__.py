"""Flight and propulsion control system (FCS) of openEMSS, in plain Python.

Modules (each one subject; parameters in ``data/*.yaml`` with their sources):

``geo``            great-circle geometry, WGS-84 tangent plane of a runway threshold
``atmosphere``     ISA and Mach/CAS/TAS conversions
``tunable``        the one mechanism for tunable parameters (frozen sets, get/set by name)
``fuel_control``   thrust lever -> N1c demand -> fuel flow, Tt41/N1 limiting, stp_max
``tecs``           total energy control (thrust and pitch commands)
``pitch``          pitch attitude loop to elevator
``lateral``        roll loop, yaw damper/turn coordination, heading/track hold
``guidance``       L1 path following, waypoint sequencing, orbits
``approach``       runways, ILS geometry, automatic landing to a full stop
``mission``        mission YAML format and validation; ``qgc``: QGroundControl .plan import
``state_machine``  runs mission sections with explicit completion criteria
``state``          the signals between aircraft, state machine and control laws
``fcs``            :class:`~.fcs.FlightControlSystem`, everything stepped together

Only relative imports are used inside this package (it is vendored into an FMU).
"""
