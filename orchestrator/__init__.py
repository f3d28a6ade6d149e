"""openEMSS orchestrator: loads SSP systems of FMI 2.0 co-simulation FMUs and steps them.

It knows nothing about aircraft or engines: any FMU, any SSP system.
"""

import os

# The master is single-threaded and works on vectors of tens of elements: BLAS worker
# threads would only compete with it for the cores (and their teardown at exit has
# crashed test processes that had loaded and unloaded many FMU libraries). Set before
# numpy is imported; a value the user set wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

__version__ = "0.1.0"
