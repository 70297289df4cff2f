"""XPBD membrane (structure/xpbd.py): stiffness independent of the time step.

Oracle: Hencky's clamped circular membrane, w0 = c a (q a / (E h))^(1/3), c = 0.6534 at
nu = 0.3 (Hencky 1915; Fichter, NASA TP-3658, 1997), a case with one equilibrium.  The shape
metric is the thesis's Eqn 6.1 (fsi/compare.py), taken relative to the same metric of the
deflection itself (the disc's Eqn 6.1 against the flat disc), since Eqn 6.1 divides by the
sphere volume.
"""
import numpy as np
import pytest

from fsi.compare import eqn_6_1_error
from fsi.constants import MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, TANK_RADIUS
from structure.grid import triangles_from_quads
from structure.model import Material, MembraneState, disc_model
from structure.xpbd import XpbdModel, XpbdSettings, solve_equilibrium

Q = 100.0  # Pa: w0 = 15 mm, about 8 membrane thicknesses (membrane regime)
GRID = 14


@pytest.fixture(scope="module")
def disc():
    material = Material(MEMBRANE_THICKNESS, 1070.0, MEMBRANE_YOUNGS_MODULUS, 0.3)
    return XpbdModel.from_membrane(disc_model(GRID, TANK_RADIUS, material,
                                              support="simply-supported"))


def _inflate(model, dt, warm_start):
    base = model.base
    settings = XpbdSettings(dt=dt, warm_start=warm_start, tolerance=1e-7)
    state, info = solve_equilibrium(model, MembraneState(base.node_rest_position),
                                    lambda x: np.zeros(len(x)), (0.0, 0.0, 0.0), settings,
                                    pressure_level=Q)
    assert info.converged
    return state.node_position


def _relative_eqn_6_1(model, a, b):
    faces = triangles_from_quads(model.base.face_nodes)
    flat = model.base.node_rest_position
    return eqn_6_1_error(a, faces, b, TANK_RADIUS) / eqn_6_1_error(a, faces, flat, TANK_RADIUS)


def test_equilibrium_does_not_depend_on_the_time_step(disc):
    coarse = _inflate(disc, 2e-3, warm_start=True)
    fine = _inflate(disc, 5e-4, warm_start=True)
    assert _relative_eqn_6_1(disc, fine, coarse) <= 0.01
    centre = np.argmin(np.linalg.norm(disc.base.node_rest_position[:, :2], axis=1))
    mat = disc.base.material
    stiffness = mat.youngs_modulus * mat.thickness
    hencky = 0.6534 * TANK_RADIUS * (Q * TANK_RADIUS / stiffness) ** (1 / 3)
    assert abs(fine[centre, 2]) == pytest.approx(hencky, rel=0.03)


def test_plain_xpbd_with_one_sweep_is_softer_at_larger_steps(disc):
    """Why the multipliers are carried: with lambda reset every substep and one sweep, the
    equilibrium carries a bias ~ dt^2 k / m and the membrane looks softer at larger dt."""
    coarse = _inflate(disc, 2e-3, warm_start=False)
    fine = _inflate(disc, 5e-4, warm_start=False)
    assert _relative_eqn_6_1(disc, fine, coarse) > 0.2


def test_settings_reject_bad_values():
    with pytest.raises(ValueError, match="dt"):
        XpbdSettings(dt=0.0)
    with pytest.raises(ValueError, match="iterations"):
        XpbdSettings(iterations=0)
