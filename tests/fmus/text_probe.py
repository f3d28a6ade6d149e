"""Test FMU: String parameters, one a plain text and one a file, echoed as numbers.

``label`` is any text (a name, a preset); ``table_file`` names a file (its name ends in
``_file``: the orchestrator takes a relative path given with ``--set`` from the working
directory), which must exist when given: a relative path is looked for in the FMU's resources
folder, as the project's FMUs do, and a missing one fails the initialization naming where it
looked. The outputs tell what the FMU was given: the length of each string, so a test can
compare it with the text it passed.
"""
from __future__ import annotations

from pathlib import Path

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, String


class TextProbe(Fmi2Slave):
    """Echoes the lengths of its String parameters."""

    description = "Probe of String parameters"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.label = "none"
        self.table_file = ""
        self.register_variable(String("label", causality=Fmi2Causality.parameter,
                                      variability=Fmi2Variability.tunable, description="Any text [-]"))
        self.register_variable(String("table_file", causality=Fmi2Causality.parameter,
                                      variability=Fmi2Variability.tunable, description="A file [-]"))
        self.register_variable(Integer("label_chars", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete, description="len(label) [-]",
                                       getter=lambda: len(self.label)))
        self.register_variable(Integer("table_file_chars", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete, description="len(table_file) [-]",
                                       getter=lambda: len(self.table_file)))

    def exit_initialization_mode(self) -> None:
        if self.table_file:
            p = Path(self.table_file)
            p = p if p.is_absolute() else Path(self.resources or ".") / p
            if not p.is_file():
                raise FileNotFoundError(f"table_file '{self.table_file}' not found (looked at {p})")

    def do_step(self, current_time: float, step_size: float) -> bool:
        return True
