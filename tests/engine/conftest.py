"""Fixtures shared by the engine tests: the Larzac 04 preset's design point and its off-design model."""

from __future__ import annotations

import pytest

from openemss.models.engine.cycle_design import DesignPoint, design
from openemss.models.engine.design_params import load_params, preset_path
from openemss.models.engine.offdesign import TurbofanOffDesign, scaled_maps


@pytest.fixture(scope="session")
def larzac_dp() -> DesignPoint:
    """The Larzac 04 preset's design point (SLS, ISA)."""
    return design(load_params(preset_path("larzac04_sls")))


@pytest.fixture(scope="session")
def larzac_od(larzac_dp: DesignPoint) -> TurbofanOffDesign:
    """Its off-design model on the shipped (extended) maps."""
    return TurbofanOffDesign(larzac_dp, scaled_maps(larzac_dp))
