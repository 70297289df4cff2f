"""Model checks: masses (thesis Eqn 4.3), supports, rest lengths (App. E)."""
import numpy as np
import pytest

from fsi import constants as C
from structure.grid import boundary_ring
from structure.model import hemisphere_model
from structure.statics import strain_error


def test_total_mass_is_rho_t_hemisphere_area(model26):
    expected = C.MEMBRANE_DENSITY * C.MEMBRANE_THICKNESS * 2 * np.pi * C.TANK_RADIUS**2
    assert model26.node_mass.sum() == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("support,rings", [("clamped", 2), ("simply-supported", 1)])
def test_support_fixes_rings(thesis_material, support, rings):
    n = 10
    m = hemisphere_model(n, C.TANK_RADIUS, thesis_material, support)
    expected = np.concatenate([boundary_ring(n, d) for d in range(rings)])
    assert set(np.flatnonzero(m.node_fixed)) == set(expected)
    assert np.all(m.node_inv_mass[m.node_fixed] == 0.0)
    assert np.all(m.node_inv_mass[~m.node_fixed] > 0.0)


def test_unknown_support_raises(thesis_material):
    with pytest.raises(ValueError, match="support"):
        hemisphere_model(10, C.TANK_RADIUS, thesis_material, "glued")


def test_spring_maps_match_thesis_counts_and_rest_is_unstrained(model26):
    n = 26
    fam = np.diff(model26.spring_family_start)
    assert list(fam) == [n * (n - 1), n * (n - 1), (n - 1) ** 2, (n - 1) ** 2]
    assert np.diff(model26.bend_family_start).tolist() == [n * (n - 2), n * (n - 2)]
    assert strain_error(model26, model26.node_rest_position) == (0.0, 0.0)
    # K_eq = 48 E (t^3/12) / L_B^2 (App. F)
    k = 4 * C.MEMBRANE_YOUNGS_MODULUS * C.MEMBRANE_THICKNESS**3 / model26.bend_rest_length**2
    assert np.allclose(model26.bend_stiffness, k, rtol=1e-12)


def test_rest_normals_point_to_centre(model26):
    from structure.kernels import node_area_and_normal
    area, normal = node_area_and_normal(model26.node_rest_position, 26, model26.normal_sign)
    inward = -model26.node_rest_position / np.linalg.norm(model26.node_rest_position, axis=1)[:, None]
    # free nodes only: at the four grid corners (fixed rim) the two grid tangents are collinear
    free = ~model26.node_fixed
    assert np.min(np.sum(normal * inward, axis=1)[free]) > 0.99
    assert np.allclose(area, model26.node_mass / (C.MEMBRANE_DENSITY * C.MEMBRANE_THICKNESS))
