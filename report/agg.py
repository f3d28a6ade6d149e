"""matplotlib's Agg canvas, whatever the environment's plotting backend.

``MPLBACKEND`` (``TkAgg``, or a name matplotlib does not know) is read by ``import matplotlib``
itself: an unknown name makes that import raise, which left the report plugin unloaded and every
run without its report. The report never uses the global backend (no pyplot): its figures are
drawn on :class:`Figure`, a matplotlib figure attached to the Agg canvas when it is made, and
matplotlib is imported here with ``MPLBACKEND`` set aside for that one import (restored at once).
"""
from __future__ import annotations

import os
import sys
from typing import Any

if "matplotlib" not in sys.modules:
    _backend = os.environ.pop("MPLBACKEND", None)
    try:
        import matplotlib  # noqa: F401  (imported without the environment's backend)
    finally:
        if _backend is not None:
            os.environ["MPLBACKEND"] = _backend

from matplotlib.axes import Axes  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure as _Figure  # noqa: E402

__all__ = ["Axes", "Figure"]


class Figure(_Figure):
    """A matplotlib figure drawn and saved on the Agg canvas (PNG), never on the global backend."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        FigureCanvasAgg(self)
