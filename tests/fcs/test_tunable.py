"""Parameter files and the shared Tunable mechanism.

Every parameter file names its sources; every entry has a value, a unit and a note,
and lies within its own stated range; every field of every parameter class is in a file.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
import yaml

from openemss.models.fcs.approach import ApproachParams
from openemss.models.fcs.errors import ParameterError
from openemss.models.fcs.fuel_control import FuelControlParams
from openemss.models.fcs.guidance import GuidanceParams, L1Guidance
from openemss.models.fcs.lateral import LateralParams
from openemss.models.fcs.pitch import PitchParams
from openemss.models.fcs.tecs import Tecs, TecsParams

DATA = Path(__file__).resolve().parents[2] / "models" / "fcs" / "data"
CLASSES = (FuelControlParams, TecsParams, PitchParams, LateralParams, GuidanceParams, ApproachParams)


@pytest.mark.parametrize("path", sorted(DATA.glob("*.yaml")), ids=lambda p: p.name)
def test_parameter_files_are_documented(path: Path) -> None:
    doc = yaml.safe_load(path.read_text())
    for section, entries in doc.items():
        assert isinstance(entries.get("source"), str) and len(entries["source"]) > 40, section
        for name, e in entries.items():
            if name == "source":
                continue
            assert {"value", "unit", "note"} <= set(e), f"{path.name}:{section}.{name}"
            if not isinstance(e["value"], bool):
                assert e.get("min", -1e300) <= e["value"] <= e.get("max", 1e300), f"{section}.{name}"


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_field_loads_from_its_file(cls: type) -> None:
    p = cls.from_file()
    assert dataclasses.is_dataclass(p)
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(p, dataclasses.fields(p)[0].name, 0.0)


def test_set_parameter_replaces_the_frozen_set() -> None:
    t = Tecs()
    before = t.parameters
    t.set_parameter("k_h_1_s", 0.1)
    assert before.k_h_1_s == 0.08 and t.parameters.k_h_1_s == 0.1  # the old set is untouched
    with pytest.raises(ParameterError, match="tecs: unknown parameter 'k_h'; valid names: k_h_1_s"):
        t.set_parameter("k_h", 1.0)
    with pytest.raises(ParameterError, match=r"tecs.gamma_max_rad: value 2.0 outside the allowed range \[0.0, 0.5\] rad "
                       r"\(see models/fcs/data/tecs.yaml:\d+\)"):
        t.set_parameter("gamma_max_rad", 2.0)


def test_overrides_are_range_checked() -> None:
    with pytest.raises(ParameterError, match=r"fuel_control.yaml:fuel_control.stp_max_kg_s: value -1.0 outside"):
        FuelControlParams.from_file(stp_max_kg_s=-1.0)


def test_boolean_parameter() -> None:
    g = L1Guidance()
    g.set_parameter("wp_fly_by", True)
    assert g.parameters.wp_fly_by is True


def test_text_value_is_refused() -> None:
    with pytest.raises(ParameterError, match="write a number without quotes; YAML reads 1e5 and 1.0e5 as text"):
        TecsParams.from_file(thrust_sls_N="1.0e6")  # type: ignore[arg-type]
