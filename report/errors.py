"""Errors of the report package: bad input to ``emss plot`` or an unreadable results folder."""
from __future__ import annotations

from openemss.orchestrator.errors import EmssError


class ReportError(EmssError):
    """A results folder, window or option that cannot be reported on; the message says what and where."""
