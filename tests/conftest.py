"""Shared fixtures: the thesis material and small models (SI units)."""
import pytest

from fsi import constants as C
from structure.model import Material, hemisphere_model


@pytest.fixture(scope="session")
def thesis_material():
    return Material(C.MEMBRANE_THICKNESS, C.MEMBRANE_DENSITY, C.MEMBRANE_YOUNGS_MODULUS)


@pytest.fixture(scope="session")
def model26(thesis_material):
    return hemisphere_model(26, C.TANK_RADIUS, thesis_material)


@pytest.fixture(scope="session")
def model10(thesis_material):
    return hemisphere_model(10, C.TANK_RADIUS, thesis_material)
