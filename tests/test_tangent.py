"""The tangent stiffness of every energy of the membrane (structure.tangent) against central
differences of its own gradient.

For each term, H v (the assembled sparse Hessian times a direction) is compared with
(g(x + h v) - g(x - h v)) / 2h on random states and on folded states (a partly inverted,
compressed hemisphere: a sharp crease ring, wrinkled and slack triangles); relative error at
most 1e-6. Each term's energy and gradient are also checked against the functions the
solvers use today (the same energy, not a new one) and its gradient against central
differences of its energy.
"""
from __future__ import annotations

import numpy as np
import pytest

from fsi import constants as C
from structure.hyperelastic import HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane
from structure.model import Material, hemisphere_model
from structure.tangent import Tangent
from structure.tangent.bending import BendingTerm
from structure.grid import triangle_edges
from structure.tangent.inertia import DampingTerm, KineticTerm
from structure.tangent.load import LiquidTerm, WallTerm
from structure.tangent.membrane import MembraneTerm, regimes
from structure.volume import (liquid_first_moment, liquid_volume, liquid_volume_gradient,
                              lower_hemisphere_volume)
from structure.xpbd.kernels import SLACK, TAUT, WRINKLED
from structure.xpbd.model import XpbdModel

TOLERANCE = 1e-6
STEP = 1e-7  # m, central-difference step (the positions are ~0.2 m)
GRID = 10


def _model(wrinkling="none"):
    material = Material(C.MEMBRANE_THICKNESS, C.MEMBRANE_DENSITY, C.MEMBRANE_YOUNGS_MODULUS,
                        0.49, wrinkling)
    return hemisphere_model(GRID, C.TANK_RADIUS, material)


def _state(model, kind, seed):
    """``random``: the rest shape with noise of a fifth of an edge on every free node;
    ``folded``: the cap below z = -R/2 mirrored up through that plane (a crease ring), the
    free nodes pulled 4 % toward the axis (wrinkled and slack triangles), small noise."""
    rng = np.random.default_rng(seed)
    x = model.node_rest_position.copy()
    free = ~model.node_fixed
    edge = C.TANK_RADIUS * np.pi / 2 / GRID
    if kind == "folded":
        cut = -0.5 * C.TANK_RADIUS
        below = x[:, 2] < cut
        x[below, 2] = 2 * cut - x[below, 2]
        x[free, :2] *= 0.96
        noise = 0.02
    else:
        noise = 0.2
    x[free] += noise * edge * rng.standard_normal((free.sum(), 3))
    return x


def _direction(rng, x, free):
    """A random direction (n, 3) moving the ``free`` nodes only (all when None)."""
    v = rng.standard_normal(x.shape)
    if free is not None:
        v[~free] = 0.0
    return v


def _check_hessian(term, x, seed, directions=3, weights=None, free=None):
    """Largest relative error of H v against central differences of the gradient of
    ``term`` (or of the weighted sum of a list of terms), H assembled by
    :class:`structure.tangent.Tangent`, along directions that move the ``free`` nodes."""
    tangent = Tangent.build(len(x), term if isinstance(term, list) else [term])

    def evaluate(y, hessian):
        return tangent.evaluate(y, weights, hessian)

    _, g, matrix = evaluate(x, True)
    dense = matrix.toarray()
    assert np.abs(dense - dense.T).max() <= 1e-12 * np.abs(dense).max()
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(directions):
        v = _direction(rng, x, free)
        hv = matrix @ v.ravel()
        plus = evaluate(x + STEP * v, False)[1]
        minus = evaluate(x - STEP * v, False)[1]
        fd = (plus - minus).ravel() / (2 * STEP)
        worst = max(worst, np.linalg.norm(fd - hv) / np.linalg.norm(hv))
        # the gradient against the energy's fourth-order central difference (step 1e-6 m)
        f = [evaluate(x + k * 1e-6 * v, False)[0] for k in (-2, -1, 1, 2)]
        de = (f[0] - 8 * f[1] + 8 * f[2] - f[3]) / 12e-6
        assert de == pytest.approx(float((g * v).sum()), rel=1e-6, abs=1e-9 * np.abs(g).sum())
    return worst


def _membrane_terms(wrinkling):
    model = _model(wrinkling)
    xpbd = XpbdModel.from_membrane(model)
    terms = {"xpbd": (MembraneTerm.from_xpbd(xpbd), xpbd.membrane_energy)}
    if wrinkling == "none":
        sheet = TriangleMembrane(model.node_rest_position, xpbd.triangles,
                                 model.material.thickness)
        for name, law in (("saint-venant-kirchhoff", SaintVenantKirchhoff(8.6e6, 0.45)),
                          ("neo-hookean", HyperelasticLaw.from_youngs_modulus(8.6e6)),
                          ("yeoh", HyperelasticLaw(1.4e6, -1e5, 2e4))):
            terms[name] = (MembraneTerm.from_triangle_membrane(sheet, law),
                           lambda x, law=law, sheet=sheet: sheet.energy_and_gradient(x, law)[0])
    return model, terms


@pytest.mark.parametrize("kind", ["random", "folded"])
@pytest.mark.parametrize("wrinkling", ["none", "tension-field"])
def test_membrane_laws_hessians_match_central_differences(wrinkling, kind):
    model, terms = _membrane_terms(wrinkling)
    x = _state(model, kind, 3)
    for name, (term, energy) in terms.items():
        assert term.evaluate(x)[0] == pytest.approx(energy(x), rel=1e-12), name
        assert _check_hessian(term, x, 5, free=~model.node_fixed) <= TOLERANCE, name


@pytest.mark.parametrize("kind", ["random", "folded"])
def test_tension_field_states_hold_every_regime_and_keep_them_under_the_step(kind):
    model, terms = _membrane_terms("tension-field")
    term = terms["xpbd"][0]
    x = _state(model, kind, 3)
    found = np.bincount(regimes(term, x), minlength=3)
    assert found[TAUT] > 0 and found[WRINKLED] > 0 and found[SLACK] > 0, found
    # the differences above cross no regime boundary (the relaxed energy is C1 there only);
    # the fixed rings' triangles sit at zero strain, on the slack boundary, and do not move
    rng = np.random.default_rng(5)
    for _ in range(3):
        v = _direction(rng, x, ~model.node_fixed)
        for s in (STEP, -STEP, 1e-6, -1e-6, 2e-6, -2e-6):
            assert np.array_equal(regimes(term, x + s * v), regimes(term, x))


@pytest.mark.parametrize("kind", ["random", "folded"])
def test_bending_hessian_matches_central_differences(kind):
    model = _model()
    bending = XpbdModel.from_membrane(model).bending
    term = BendingTerm(bending)
    x = _state(model, kind, 4)
    if kind == "folded":  # the crease: angle changes of more than 1 rad (57 degrees)
        assert np.abs(bending.angle_jacobian(x)[0]).max() > 1.0
    energy, grad, _ = term.evaluate(x)
    e_ref, g_ref = bending.energy_and_gradient(x)
    assert energy == pytest.approx(e_ref, rel=1e-12)
    assert np.allclose(grad, g_ref, rtol=0, atol=1e-12 * np.abs(g_ref).max())
    assert _check_hessian(term, x, 6, free=~model.node_fixed) <= TOLERANCE


@pytest.mark.parametrize("kind", ["random", "folded"])
def test_liquid_load_volume_and_wall_hessians_match_central_differences(kind):
    model = _model()
    x = _state(model, kind, 7)
    free = ~model.node_fixed
    x[free] *= 1.05 * model.radius / np.linalg.norm(x[free], axis=1).max()  # beyond the wall
    body = np.array([0.3, -0.2, -C.STANDARD_GRAVITY])
    level, rho = 480.0, C.WATER_DENSITY
    volume = LiquidTerm.of_model(model, volume_weight=1.0)
    load = LiquidTerm.of_model(model, volume_weight=-level, moment_weight=-rho * body)
    wall = WallTerm(~model.node_fixed, model.radius, 2.5e5)
    v, gv, _ = volume.evaluate(x)
    assert v + lower_hemisphere_volume(model.radius) == pytest.approx(liquid_volume(model, x),
                                                                      rel=1e-13)
    assert np.allclose(gv, liquid_volume_gradient(model, x), rtol=0, atol=1e-15)
    m1 = liquid_first_moment(model, x) + np.array([0.0, 0.0, 0.25 * np.pi * model.radius**4])
    assert load.evaluate(x)[0] == pytest.approx(-level * v - rho * body @ m1, rel=1e-12)
    assert (np.linalg.norm(x[free], axis=1) > model.radius).sum() > 0
    for term in (volume, load, wall):
        assert _check_hessian(term, x, 8, free=~model.node_fixed) <= TOLERANCE, term


def test_mass_and_damping_matrices_are_the_gradients_derivatives():
    model = _model()
    xpbd = XpbdModel.from_membrane(model)
    rng = np.random.default_rng(9)
    v = rng.standard_normal((len(model.node_mass), 3))
    kinetic = KineticTerm(model.node_mass)
    damping = DampingTerm(triangle_edges(xpbd.triangles), 0.7)
    for term in (kinetic, damping):
        assert _check_hessian(term, v, 10) <= TOLERANCE
    # the damping's force is c L v of the edges' graph Laplacian (structure.xpbd.damping)
    from structure.xpbd.damping import edge_laplacian
    lap = edge_laplacian(xpbd.triangles, len(v))
    assert np.allclose(-damping.evaluate(v)[1], 0.7 * (lap @ v), atol=1e-12)


def test_summed_terms_share_one_pattern_and_add_with_their_weights():
    model = _model("tension-field")
    xpbd = XpbdModel.from_membrane(model)
    x = _state(model, "folded", 11)
    terms = [MembraneTerm.from_xpbd(xpbd), BendingTerm(xpbd.bending),
             LiquidTerm.of_model(model, 1.0), WallTerm(~model.node_fixed, model.radius, 1e5)]
    tangent = Tangent.build(len(x), terms)
    weights = [1.0, 1.0, -350.0, 1.0]
    value, grad, matrix = tangent.evaluate(x, weights)
    parts = [t.evaluate(x) for t in terms]
    assert value == pytest.approx(sum(w * p[0] for w, p in zip(weights, parts)), rel=1e-12)
    dense = sum(w * Tangent.build(len(x), [t]).evaluate(x)[2].toarray()
                for w, t in zip(weights, terms))
    assert np.allclose(matrix.toarray(), dense, rtol=0, atol=1e-9 * np.abs(dense).max())
    assert _check_hessian(terms, x, 12, weights=weights, free=~model.node_fixed) <= TOLERANCE
