"""The slosh modes of a sheet of revolution on the liquid's potential flow
(:mod:`fsi.slosh.axisymmetric`) against two oracles:

* the limp limit: a flat massless sheet without stiffness lying on the liquid in a sphere is
  its free surface, whose lambda1 = omega^2 a / g and first slosh mass by tank fraction are the
  isoparametric P2 reference of ``benchmarks/sphere_slosh_reference.py``
  (``docs/data/sphere_slosh_reference.json``, 8 digits; Budiansky 1960 gives 1.5602 at half
  fill), and whose pendulum hinges at the sphere's centre (Dodge 2000, Sec. 3.4);
* Bauer's hydroelastic membrane: a flat membrane of uniform tension T pinned at the wall of
  an upright cylinder (H. F. Bauer's elastic cover of a liquid), its first antisymmetric
  mode as the Rayleigh-Ritz series of :mod:`fsi.analysis.membrane_series`, for
  Gamma = T / (rho g a^2) from 0.01 to 1, with and without the sheet's mass.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from fluid.section.mesh import cylinder_section
from fsi.analysis.membrane_series import pinned_membrane_limit
from fsi.slosh.axisymmetric import axisymmetric_slosh, free_surface_slosh
from structure.axisymmetric import AxisymmetricLoad, equilibrium, shell_of_revolution
from structure.axisymmetric.meridian import nodal_state
from structure.hyperelastic import SaintVenantKirchhoff
from structure.model import Material

REFERENCE = json.loads((Path(__file__).parents[1] / "docs" / "data"
                        / "sphere_slosh_reference.json").read_text())["fills"]
RHO, G = 1000.0, 9.81


def _limp(fraction: float):
    return free_surface_slosh(fraction, 1.0, RHO, G)


@pytest.mark.parametrize("fraction", [0.1, 0.3, 0.5, 0.7, 0.9])
def test_limp_sheet_is_the_free_surface(fraction):
    out = _limp(fraction)
    reference = REFERENCE[str(fraction)]
    assert out.unstable == 0
    assert out.slosh == 0
    assert out.lambda1 == pytest.approx(reference["lambda1"], rel=1e-5)
    assert out.slosh_mass_fraction == pytest.approx(reference["slosh_mass_fraction"], rel=1e-5)
    assert abs(out.hinge_height) < 1e-9


def test_half_full_limp_sheet_meets_budiansky():
    assert _limp(0.5).lambda1 == pytest.approx(1.5602, abs=1e-4)


@pytest.mark.parametrize("gamma", [0.01, 0.1, 1.0])
@pytest.mark.parametrize("mass_ratio", [0.0, 0.1])
def test_pinned_membrane_meets_bauer(gamma, mass_ratio):
    """A disc stretched by 1 % equibiaxially (Saint Venant-Kirchhoff: T = t E e / (1 - nu),
    e = (1.01^2 - 1) / 2), held at the wall a = h = 1 m."""
    stretch, thickness, nu = 1.01, 1e-3, 0.3
    strain = 0.5 * (stretch**2 - 1)
    youngs = gamma * RHO * G * (1 - nu) / (thickness * strain)
    density = mass_ratio * RHO * stretch**2 / thickness          # mu = rho_m t / stretch^2
    shell = shell_of_revolution("disc", 1.0 / stretch, Material(thickness, density, youngs, nu),
                                SaintVenantKirchhoff(youngs, nu), 32,
                                support="simply-supported", bending=False)
    rest = shell.meridian.rest_state.reshape(-1, 4)
    state = nodal_state(stretch * rest[:, 0], stretch * rest[:, 1], rest[:, 2], rest[:, 3])
    out = axisymmetric_slosh(shell, state, RHO, G, 0.0, np.pi,
                             section=lambda top: cylinder_section(1.0, 16),
                             wet=shell.meridian.shape.length, tank_radius=1.0)
    assert out.lambda1 == pytest.approx(pinned_membrane_limit(gamma, 1.0, mass_ratio),
                                        rel=5e-5)


def test_roller_rim_has_no_static_load():
    shell = shell_of_revolution("disc", 1.0, Material(1e-3, 0.0, 1.0, 0.3),
                                SaintVenantKirchhoff(1.0, 0.3), 8, support="roller",
                                bending=False)
    with pytest.raises(NotImplementedError, match="roller"):
        equilibrium(shell, AxisymmetricLoad(liquid_density=RHO, gravity=G))
