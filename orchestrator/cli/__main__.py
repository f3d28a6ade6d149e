"""``python -m openemss.orchestrator.cli``: the ``emss`` command (:func:`.entry.emss`: signals handled first)."""
import sys

from .entry import emss

sys.exit(emss())
