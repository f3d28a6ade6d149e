"""The physics every model package shares (one source): the standard atmosphere (ISO 2533) and its constants.

Model packages import it relatively (``from ..common.atmosphere import ...``); ``build-fmus`` vendors it into
each FMU whose model code imports it. What is not physics (files, YAML, typed values, parameter sets, signal
tables, compiled kernels, fast records) is in :mod:`openemss.models.infra`.
"""
