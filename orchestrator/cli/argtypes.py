"""Argument types of the ``emss`` command's options, shared by the plugins' sub-commands (report, study): a value
refused where it enters, with one line saying what is allowed."""
from __future__ import annotations

import argparse
import math
from pathlib import Path

__all__ = ["finite_number", "folder_name"]


def finite_number(text: str) -> float:
    """A finite number (argparse type): NaN and infinities are refused where they enter."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def folder_name(text: str) -> Path:
    """A results folder (argparse type): not empty (an empty name would write into the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty folder name; give the results folder, e.g. --out results/run1")
    return Path(text)
