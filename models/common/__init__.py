"""Physics shared by every model package (one source): the standard atmosphere.

Model packages import it relatively (``from ..common.atmosphere import ...``); ``build-fmus``
vendors it into each FMU whose model code imports it.
"""
