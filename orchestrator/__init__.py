"""openEMSS orchestrator: loads SSP systems of FMI 2.0 co-simulation FMUs and steps them.

It knows nothing about aircraft or engines: any FMU, any SSP system.
"""

__version__ = "0.1.0"
