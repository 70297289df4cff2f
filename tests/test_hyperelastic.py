"""Hyperelastic triangle membrane against the thin-sphere inflation law and Hencky's clamped
membrane.

Oracle: a thin sphere of radius R and wall H inflated to stretch lambda, W = W(I1) with
I1 = 2 lambda^2 + lambda^-4, holds p = 4 (H/R) W'(I1) (lambda^-1 - lambda^-7); neo-Hookean
(W' = mu/2): p = 2 mu (H/R) (lambda^-1 - lambda^-7), maximum at lambda = 7^(1/6)
(Ogden, Non-Linear Elastic Deformations, 1984, Sec. 5.3; Yeoh 1993 for W(I1)).
Hencky (1915): a clamped circular membrane (no bending) of radius a under pressure q deflects
w0 = c a (q a / (E h))^(1/3) at the centre, c = 0.6534 for nu = 0.3 (Fichter, NASA TP-3658,
1997).
"""
import numpy as np
import pytest
from conftest import clamped_disc_under_pressure

from fsi.constants import MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, TANK_RADIUS
from structure.hyperelastic import (HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane,
                                    enclosed_volume, equilibrium_at_volume, icosphere)

R, H = TANK_RADIUS, MEMBRANE_THICKNESS


def balloon_pressure(law: HyperelasticLaw, stretch: float) -> float:
    i1m3 = 2 * stretch**2 + stretch**-4 - 3
    dw = law.c10 + 2 * law.c20 * i1m3 + 3 * law.c30 * i1m3**2
    return 4 * H / R * dw * (1 / stretch - stretch**-7)


def inflate(law, stretches, subdivisions=3):
    points, triangles = icosphere(R, subdivisions)
    membrane = TriangleMembrane(points, triangles, H)
    v0, _ = enclosed_volume(points, triangles)
    x, out = points, []
    for s in stretches:
        x, p = equilibrium_at_volume(membrane, law, v0 * s**3, x)
        out.append(p)
    return np.array(out)


@pytest.mark.parametrize("law", [HyperelasticLaw(1e6, 2e4, 3e2), SaintVenantKirchhoff(3e6, 0.3)])
def test_gradient_matches_finite_differences(law):
    points, triangles = icosphere(R, 1)
    membrane = TriangleMembrane(points, triangles, H)
    x = 1.3 * points + 0.01 * np.random.default_rng(1).standard_normal(points.shape)
    _, grad = membrane.energy_and_gradient(x, law)
    for node, axis in [(0, 0), (7, 1), (30, 2)]:
        d = np.zeros_like(x)
        d[node, axis] = 1e-6
        fd = (membrane.energy_and_gradient(x + d, law)[0]
              - membrane.energy_and_gradient(x - d, law)[0]) / 2e-6
        assert fd == pytest.approx(grad[node, axis], rel=1e-6)


def test_neo_hookean_balloon_law_and_its_pressure_maximum():
    law = HyperelasticLaw.from_youngs_modulus(MEMBRANE_YOUNGS_MODULUS)
    stretches = np.array([1.05, 1.2, 1.4, 1.6, 1.8, 2.0])
    p = inflate(law, stretches)
    exact = np.array([balloon_pressure(law, s) for s in stretches])
    assert np.max(np.abs(p / exact - 1)) < 0.02
    # the pressure maximum (limit point of pressure-controlled inflation)
    fine = np.linspace(1.30, 1.46, 9)
    pf = inflate(law, fine)
    k = int(np.argmax(pf))
    a, b, _ = np.polyfit(fine[k - 1:k + 2], pf[k - 1:k + 2], 2)
    assert -b / (2 * a) == pytest.approx(7 ** (1 / 6), rel=0.01)


def test_yeoh_balloon_law():
    law = HyperelasticLaw(0.4e6, -0.01e6, 0.001e6)  # a filled-rubber-like Yeoh set (Pa)
    stretches = np.array([1.1, 1.5, 2.0])
    p = inflate(law, stretches)
    exact = np.array([balloon_pressure(law, s) for s in stretches])
    assert np.max(np.abs(p / exact - 1)) < 0.02


def test_hencky_clamped_membrane():
    a, q, n = 0.1, 68.5, 26  # w0 / a ~ 5 %: small strain, large deflection
    law = SaintVenantKirchhoff(MEMBRANE_YOUNGS_MODULUS, 0.3)
    _, x, _ = clamped_disc_under_pressure(n, a, q, law)
    w0 = x[:, 2].max()
    assert w0 == pytest.approx(0.6534 * a * (q * a / (MEMBRANE_YOUNGS_MODULUS * H)) ** (1 / 3),
                               rel=0.03)
    assert x[:, 2].min() >= -1e-9  # the pressure pushes along the normals


def test_bad_law_and_thickness_are_named():
    with pytest.raises(ValueError, match="C10"):
        HyperelasticLaw(0.0)
    with pytest.raises(ValueError, match="poisson_ratio"):
        SaintVenantKirchhoff(1e6, 0.5)
    points, triangles = icosphere(R, 0)
    with pytest.raises(ValueError, match="thickness"):
        TriangleMembrane(points, triangles, 0.0)
