"""The tangent stiffness and the lumped masses against the closed-form vibrations of the two
flat-sheet oracles (the frequency-domain form of the dynamic oracles; the time integrator is
to reproduce the same frequencies):

* a circular membrane pre-tensioned by a uniform stretch, held at its rim: the fundamental
  omega = (2.4048 / a) sqrt(S / rho), S the second Piola-Kirchhoff stress of the stretch
  (Saint Venant-Kirchhoff, plane stress: S = E (s^2 - 1) / (2 (1 - nu))), a the rest radius;
  2.4048 the first zero of J0 (e.g. Graff, *Wave Motion in Elastic Solids*, 1975, sec. 4.4);
* the clamped circular plate's fundamental, lambda^2 = omega a^2 sqrt(rho t / D) = 10.2158
  (Leissa, *Vibration of Plates*, NASA SP-160, 1969, Table 2.1).

Each within 1 % at N = 38; the plate's error falls with the grid. The
lowest out-of-plane eigenvalue of K w = omega^2 M w on the free nodes, by ARPACK in
shift-invert mode.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, \
    TANK_RADIUS
from structure.model import Material, disc_model
from structure.plate import FlatDiaphragm, ShellDisc
from structure.tangent import Tangent
from structure.tangent.bending import BendingTerm
from structure.tangent.membrane import MembraneTerm

J0_FIRST_ZERO = 2.404826
CLAMPED_PLATE_LAMBDA2 = 10.2158
POISSON = 0.3
PLATE = FlatDiaphragm(TANK_RADIUS, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, POISSON)


def _fundamental(grid_size: int, bending: bool, stretch: float = 1.0) -> float:
    """omega (rad/s) of the disc's lowest out-of-plane mode at the uniform in-plane
    ``stretch`` of its rest grid."""
    disc = ShellDisc.build(PLATE, grid_size)
    base = disc_model(grid_size, PLATE.radius, Material(
        PLATE.thickness, MEMBRANE_DENSITY, PLATE.youngs_modulus, POISSON), "simply-supported")
    assert np.allclose(base.node_rest_position, disc.node_position)
    terms = [MembraneTerm.from_triangle_membrane(disc.membrane, disc.law)]
    if bending:
        terms.append(BendingTerm(disc.bending))
    x = base.node_rest_position * np.array([stretch, stretch, 1.0])
    matrix = Tangent.build(len(x), terms).evaluate(x)[2]
    out_of_plane = np.repeat(~base.node_fixed, 3) & (np.arange(3 * len(x)) % 3 == 2)
    k = sp.csr_matrix(matrix)[out_of_plane][:, out_of_plane].tocsc()
    mass = sp.diags(base.node_mass[~base.node_fixed])
    value = eigsh(k, k=1, M=mass, sigma=0.0, which="LM", return_eigenvectors=False)[0]
    return float(np.sqrt(value))


def test_pretensioned_membrane_fundamental():
    stretch = 1.01
    s = PLATE.youngs_modulus * (stretch**2 - 1) / (2 * (1 - POISSON))
    exact = J0_FIRST_ZERO / PLATE.radius * np.sqrt(s / MEMBRANE_DENSITY)
    assert _fundamental(38, bending=False, stretch=stretch) == pytest.approx(exact, rel=0.01)


def test_clamped_plate_fundamental_converges_within_one_percent():
    scale = PLATE.radius**2 * np.sqrt(MEMBRANE_DENSITY * PLATE.thickness
                                      / PLATE.flexural_rigidity)
    errors = [abs(_fundamental(n, bending=True) * scale / CLAMPED_PLATE_LAMBDA2 - 1)
              for n in (20, 38)]
    assert errors[1] < errors[0]
    assert errors[1] <= 0.01
