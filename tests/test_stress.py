"""Strain and stress per triangle (:mod:`structure.stress`) against closed forms."""
from __future__ import annotations

import numpy as np
import pytest

from structure.hyperelastic import (HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane,
                                    equilibrium_at_volume, icosphere)
from structure.stress import triangle_strain, triangle_stress

THICKNESS = 1.0e-3


def _sheet():
    """A flat square sheet in a tilted plane (rest positions (n, 3) m, triangles), and the
    plane's in-plane axes (2, 3)."""
    g = np.linspace(0.0, 0.1, 5)
    x, y = np.meshgrid(g, g, indexing="ij")
    flat = np.column_stack([x.ravel(), y.ravel()])
    axes = np.array([[np.cos(0.4), 0.0, np.sin(0.4)], [0.0, 1.0, 0.0]])
    idx = np.arange(25).reshape(5, 5)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    tri = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                          np.stack([a, c, d], -1).reshape(-1, 3)])
    return flat, flat @ axes, tri, axes


@pytest.mark.parametrize("angle", [0.0, 0.5236, 1.2])
def test_a_uniaxial_stretch_has_its_principal_values_and_directions_exactly(angle):
    """A flat sheet stretched by lambda along a direction at ``angle`` in its plane and by
    lambda^-1/2 across it (incompressible uniaxial tension): every triangle's principal
    stretches are (lambda, lambda^-1/2), its principal direction the stretch's, at rest and
    now, to round-off; a neo-Hookean sheet then carries sigma_1 = mu (lambda^2 - 1 / lambda)
    and sigma_2 = 0 exactly (Ogden 1984, Sec. 4.3), its von Mises stress sigma_1; a Saint
    Venant-Kirchhoff sheet the resultants of S = Y / (1 - nu^2) [nu tr E + (1 - nu) E]."""
    flat, rest, tri, axes = _sheet()
    lam = 1.4
    d = np.array([np.cos(angle), np.sin(angle)])
    e = np.array([-d[1], d[0]])
    stretch = lam * np.outer(d, d) + lam**-0.5 * np.outer(e, e)
    pos = (flat @ stretch.T) @ axes
    membrane = TriangleMembrane(rest, tri, THICKNESS)
    strain = triangle_strain(membrane, pos)
    assert np.allclose(strain.stretch, [lam, lam**-0.5], atol=1e-12, rtol=0)
    along = d @ axes
    assert np.allclose(np.abs(strain.direction[:, 0] @ along), 1.0, atol=1e-12)
    assert np.allclose(np.abs(strain.rest_direction[:, 0] @ along), 1.0, atol=1e-12)
    assert np.allclose(strain.green, 0.5 * (np.array([lam, lam**-0.5]) ** 2 - 1), atol=1e-12)
    mu = 4.0e5
    rubber = triangle_stress(membrane, HyperelasticLaw.neo_hookean(mu), pos)
    assert np.allclose(rubber.stress[:, 0], mu * (lam**2 - 1 / lam), rtol=1e-12)
    assert np.allclose(rubber.stress[:, 1], 0.0, atol=1e-9 * mu)
    assert np.allclose(rubber.von_mises, rubber.stress[:, 0], rtol=1e-12)
    assert np.allclose(rubber.thickness, THICKNESS / (lam * lam**-0.5), rtol=1e-12)
    youngs, nu = 5.0e6, 0.3
    svk = triangle_stress(membrane, SaintVenantKirchhoff(youngs, nu), pos)
    green = 0.5 * (np.array([lam, lam**-0.5]) ** 2 - 1)
    piola = youngs / (1 - nu**2) * (nu * green.sum() + (1 - nu) * green)
    expected = THICKNESS * np.array([lam, lam**-0.5]) ** 2 * piola / (lam * lam**-0.5)
    assert np.allclose(svk.resultant, expected, rtol=1e-12)


def test_an_inflated_balloons_stress_is_laplaces():
    """A neo-Hookean sphere (R0 = 0.1 m, t = 1 mm, icosphere of 1280 triangles) inflated to
    twice its volume, at the equilibrium the membrane solver finds: every triangle's two
    principal stresses are p R / (2 t_now) within 1 % (Laplace's law for a thin sphere; R the
    inflated radius, t_now = t lambda_3 the thinned wall, p the solver's pressure)."""
    points, tri = icosphere(0.1, 3)
    membrane = TriangleMembrane(points, tri, THICKNESS)
    law = HyperelasticLaw.neo_hookean(4.0e5)
    volume = 2.0 * 4.0 / 3.0 * np.pi * 0.1**3
    pos, pressure = equilibrium_at_volume(membrane, law, volume, points * 1.25)
    stress = triangle_stress(membrane, law, pos)
    radius = np.linalg.norm(pos, axis=1).mean()
    laplace = pressure * radius / (2 * stress.thickness)
    assert np.all(np.abs(stress.stress / laplace[:, None] - 1) < 0.01)


def test_a_law_without_a_stress_rule_is_named():
    flat, rest, tri, _ = _sheet()
    with pytest.raises(ValueError, match="no stress rule for the law object.*HyperelasticLaw"):
        triangle_stress(TriangleMembrane(rest, tri, THICKNESS), object(), rest)
