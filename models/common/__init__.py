"""What every model package shares (one source): the standard atmosphere, and the one reader of
YAML and JSON text files (``safe_yaml``: duplicate keys, alias bombs, NaN refused with file:line).

Model packages import it relatively (``from ..common.atmosphere import ...``); ``build-fmus``
vendors it into each FMU whose model code imports it.
"""
