"""``python -m openemss.orchestrator.cli``: the ``emss`` command (:mod:`.main`)."""
import sys

from .main import main

sys.exit(main())
