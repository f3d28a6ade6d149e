"""The literal arrays of a pyCycle map module, read with :mod:`ast` (never imported or executed).

Kept free of imports of this package so that ``maps/transcribe_pycycle.py``, a script, loads it by its path;
:mod:`.map_pycycle` builds maps from it.
"""

from __future__ import annotations

import ast
from typing import Any

__all__ = ["parse_map_module"]


def parse_map_module(text: str) -> dict[str, Any]:
    """The ``X.attr = np.array(literal)``, ``X.attr = number`` and ``X.defaults[...] = literal`` of a module."""
    out: dict[str, Any] = {"defaults": {}}
    for node in ast.parse(text).body:
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1):
            continue
        target, value = node.targets[0], node.value
        if isinstance(target, ast.Attribute):
            if isinstance(value, ast.Call) and getattr(value.func, "attr", "") == "array" and value.args:
                out[target.attr] = ast.literal_eval(value.args[0])
            elif isinstance(value, ast.Constant) and isinstance(value.value, int | float):
                out[target.attr] = value.value
        elif (isinstance(target, ast.Subscript) and isinstance(target.value, ast.Attribute)
              and target.value.attr == "defaults"):
            out["defaults"][ast.literal_eval(target.slice)] = ast.literal_eval(value)
    return out
