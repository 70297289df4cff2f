"""Strain and stress per triangle (:mod:`structure.stress`) against closed forms."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from conftest import clamped_disc_under_pressure

from fsi.constants import TANK_RADIUS
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


def _hencky(nu: float):
    """Hencky's clamped membrane (1915) in Foppl's small-rotation theory: the radial stress
    sigma_r = K s(r / a), K = (E q^2 a^2 / h^2)^(1/3), with s'' + 3 s' / xi + 1 / (8 s^2) = 0
    (equilibrium, sigma_r w' = -q r / (2 h), and compatibility), s'(0) = 0 and no hoop strain
    at the clamped rim, xi s'(1) + (1 - nu) s(1) = 0; shot on s(0). Returns (s as a
    function of xi, the centre deflection's coefficient c = 1/2 int_0^1 xi / s dxi in
    w0 = c a (q a / (E h))^(1/3))."""
    from scipy.integrate import quad, solve_ivp
    from scipy.optimize import brentq

    def shoot(s0):
        x0 = 1e-6
        return solve_ivp(lambda x, y: [y[1], -3 * y[1] / x - 1 / (8 * y[0] ** 2)], (x0, 1.0),
                         [s0 - x0**2 / (64 * s0**2), -x0 / (32 * s0**2)], rtol=1e-12,
                         atol=1e-14, dense_output=True)

    def rim(s0):
        y = shoot(s0).y[:, -1]
        return y[1] + (1 - nu) * y[0]

    sol = shoot(brentq(rim, 0.2, 2.0, xtol=1e-14))
    profile = lambda xi: sol.sol(np.clip(xi, 1e-6, 1.0))[0]  # noqa: E731
    return profile, 0.5 * quad(lambda x: x / profile(x), 0, 1)[0]


def test_hencky_clamped_membrane_stress_coefficients():
    """A clamped flat disc (a = 0.1 m, EPDM, 1 mm, nu = 0.3) under q = 68.5 Pa, Saint
    Venant-Kirchhoff on the App. C disc grid (N = 38), at the equilibrium the membrane
    solver finds: the radial stress against Hencky's, sigma_r = K s(r / a), whose series
    the test shoots (centre coefficient s(0) = 0.4311, rim s(1) = 0.3330; its deflection
    coefficient 0.6534 is Fichter's, NASA TP-3658, 1997): within 3 % at every triangle near
    the centre (r < 0.15 a; 0.9 % measured) and, area-weighted, over the ring of triangles at
    the rim (0.95 a < r; -1.0 % measured; single rim triangles of the distorted corner cells
    scatter by 40 %)."""
    from fsi.constants import MEMBRANE_THICKNESS as H, MEMBRANE_YOUNGS_MODULUS as E

    profile, c = _hencky(0.3)
    assert c == pytest.approx(0.6534, abs=1e-4)
    assert profile(0.0) == pytest.approx(0.4311, abs=1e-4)
    assert profile(1.0) == pytest.approx(0.3330, abs=1e-4)
    a, q = 0.1, 68.5
    law = SaintVenantKirchhoff(E, 0.3)
    membrane, x, fixed = clamped_disc_under_pressure(38, a, q, law)
    tri = membrane.triangles
    stress = triangle_stress(membrane, law, x)
    centre = x[tri].mean(axis=1)
    r = np.hypot(centre[:, 0], centre[:, 1])
    radial = np.column_stack([centre[:, 0] / r, centre[:, 1] / r, 0 * r])
    along = np.einsum("mik,mk->mi", stress.strain.direction, radial)
    sigma_r = (stress.stress * along**2).sum(axis=1)
    hencky = (E * q * q * a * a / H / H) ** (1 / 3) * profile(r / a)
    near = r < 0.15 * a
    assert np.all(np.abs(sigma_r[near] / hencky[near] - 1) < 0.03)
    held = np.zeros(len(x), dtype=bool)
    held[fixed] = True
    ring = (r > 0.95 * a) & ~held[tri].all(axis=1)
    area = membrane.rest_area[ring]
    assert np.sum(area * sigma_r[ring]) / np.sum(area * hencky[ring]) == pytest.approx(1, abs=0.03)


@pytest.mark.parametrize("law", [SaintVenantKirchhoff(5.0e6, 0.3), HyperelasticLaw(2e5, 1e4, 500.0)])
def test_the_resultants_from_a_laws_energy_are_its_closed_form_ones(law):
    """:func:`structure.stress.term_resultants` takes the resultants from the law's energy
    gradient (n = F G F^T / a, the path of the XPBD membrane's blocks): on an inflated
    balloon's triangles, bent and unequally stretched, it gives the closed-form rules'
    principal values and directions to round-off."""
    from structure.stress import term_resultants
    from structure.tangent.membrane import MembraneTerm

    points, tri = icosphere(0.1, 2)
    membrane = TriangleMembrane(points, tri, THICKNESS)
    rng = np.random.default_rng(3)
    pos = points * (1.2 + 0.05 * rng.random((len(points), 1)))
    closed = triangle_stress(membrane, law, pos)
    values, directions = term_resultants(MembraneTerm.from_triangle_membrane(membrane, law), pos)
    assert np.allclose(values, closed.resultant, rtol=1e-10, atol=1e-12 * np.abs(values).max())
    distinct = np.abs(values[:, 0] - values[:, 1]) > 1e-6 * np.abs(values).max()
    cosines = np.abs(np.einsum("mk,mk->m", directions[:, 0], closed.strain.direction[:, 0]))
    assert np.allclose(cosines[distinct], 1.0, atol=1e-8)


def _xpbd_disc_term(wrinkling: str, poisson_ratio: float = 0.5):
    """The XPBD membrane blocks of a flat disc (N = 14, a = 0.1 m, EPDM 1 mm) as a
    :class:`structure.tangent.membrane.MembraneTerm`, and its rest positions."""
    from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS
    from structure.model import Material, disc_model
    from structure.tangent.membrane import MembraneTerm
    from structure.xpbd.model import XpbdModel

    material = Material(THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, poisson_ratio,
                        wrinkling)
    model = XpbdModel.from_membrane(disc_model(14, 0.1, material))
    return MembraneTerm.from_xpbd(model), model.base.node_rest_position, MEMBRANE_YOUNGS_MODULUS


def test_a_sheared_tension_field_sheet_carries_no_compression():
    """The XPBD membrane with wrinkling = "tension-field" (Pipkin 1986) in simple shear
    x -> x + gamma y: every triangle is wrinkled, and its stress from the law's own energy is
    uniaxial along the 45-degree diagonal with n_1 = E t gamma / 2. The tension field is
    uniaxial in the block's strain (|f_j| - 1, cos / 2), not in Green's, so the minor
    resultant is zero to first order only: |n_2| < gamma n_1 (gamma / 2 measured), ten times
    smaller at a tenth of the shear; at gamma = 0.002, n_1 within 0.3 % (0.2 % measured).
    Without the tension field the same sheet carries the compression n_2 = -n_1 of plane
    shear."""
    from structure.stress import term_resultants

    term, rest, youngs = _xpbd_disc_term("tension-field")
    ratio = {}
    for gamma in (0.02, 0.002):
        sheared = rest.copy()
        sheared[:, 0] += gamma * rest[:, 1]
        values, directions = term_resultants(term, sheared)
        assert np.all(values[:, 0] > 0)
        ratio[gamma] = np.abs(values[:, 1] / values[:, 0]).max()
        assert ratio[gamma] < gamma
        diagonal = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
        assert np.all(np.abs(directions[:, 0] @ diagonal) > 1 - gamma)
    assert ratio[0.02] / ratio[0.002] == pytest.approx(10, rel=0.1)
    assert np.allclose(values[:, 0], youngs * THICKNESS * 0.002 / 2, rtol=0.003)
    term, rest, _ = _xpbd_disc_term("none")
    values, _ = term_resultants(term, sheared)
    assert np.allclose(values[:, 1], -values[:, 0], rtol=0.01)


def _plate_moments(grid_size: int):
    """The clamped Kirchhoff plate of tests/test_bending.py (D = 1 N m, nu = 0.3, q = 1 Pa,
    a = the tank radius, the linear solve on the App. C disc grid): per triangle the radial
    bending moment M_rr (N m/m) from :func:`structure.stress.bending_moments`, Timoshenko's
    M_r = q / 16 [(1 + nu) a^2 - (3 + nu) r^2] at its centroid, r / a, its area and whether
    it has a clamped edge."""
    from test_bending import NU, D, _clamped_disc

    from fsi.constants import TANK_RADIUS as a
    from structure.stress import bending_curvature, bending_moments

    w, x, bending, _, _ = _clamped_disc(grid_size, 1.0)
    pos = x.copy()
    pos[:, 2] = 1e-6 * w                                  # linear: moments scale with w
    curvature, frame = bending_curvature(bending, x, pos, NU)
    moments, directions = bending_moments(curvature / 1e-6, frame, D, NU)
    tri = bending.triangles
    centre = x[tri].mean(axis=1)
    r = np.hypot(centre[:, 0], centre[:, 1])
    radial = np.column_stack([centre[:, 0] / r, centre[:, 1] / r, 0 * r])
    m_rr = (moments * np.einsum("mik,mk->mi", directions, radial) ** 2).sum(axis=1)
    exact = a * a / 16 * ((1 + NU) - (3 + NU) * (r / a) ** 2)
    area = 0.5 * np.linalg.norm(np.cross(x[tri[:, 1]] - x[tri[:, 0]],
                                         x[tri[:, 2]] - x[tri[:, 0]]), axis=1)
    return m_rr, exact, r / a, area, bending.flap.min(axis=1) < 0


def test_a_clamped_plates_bending_moments_approach_kirchhoffs():
    """The midedge curvature of :mod:`structure.bending` as bending moments, on the clamped
    circular plate under uniform pressure at small deflection (Timoshenko &
    Woinowsky-Krieger 1959, Sec. 62: M_r = q / 16 [(1 + nu) a^2 - (3 + nu) r^2], so the rim
    stress is 6 M / t^2 = 3 q a^2 / (4 t^2)): the interior's moments, area-weighted over
    bands of r, are within 2 % of q a^2 / 8 of Kirchhoff's on N = 38 (1 % measured), and
    over the triangles with a clamped edge the error falls with the grid (+5.4 % on N = 26,
    +3.3 % on N = 38). Single triangles at the rim of the App. C grid's distorted corner
    cells scatter several-fold: a peak stress needs the ring's mean, not one triangle."""
    ring = {}
    for n in (26, 38):
        m_rr, exact, xi, area, clamped = _plate_moments(n)
        ring[n] = np.sum(area[clamped] * m_rr[clamped]) / np.sum(area[clamped] * exact[clamped])
        if n == 38:
            scale = TANK_RADIUS**2 / 8                    # q a^2 / 8, q = 1 Pa
            for lo, hi in ((0.0, 0.15), (0.15, 0.4), (0.4, 0.6), (0.6, 0.8), (0.8, 0.9)):
                band = (xi >= lo) & (xi < hi)
                mean_error = np.sum(area[band] * (m_rr[band] - exact[band])) / area[band].sum()
                assert abs(mean_error) < 0.02 * scale, (lo, hi)
    assert abs(ring[38] - 1) < abs(ring[26] - 1) < 0.06


def test_a_clamped_plates_rim_bending_stress_is_timoshenkos():
    """The rim bending stress of the clamped circular plate under uniform pressure at small
    deflection, 3 q a^2 / (4 t^2) (Timoshenko & Woinowsky-Krieger 1959, Sec. 62), as the
    result's ``bending_stress`` (:func:`structure.stress.sheet_fields`): the largest
    principal bending stress, area-weighted over the triangles with a clamped edge, is within
    3 % of it on N = 54 (-2.6 % measured; -3.2 % on N = 38, closer as the grid refines)."""
    from test_bending import NU, D, _clamped_disc

    from fsi.constants import TANK_RADIUS as a
    from structure.hyperelastic import SaintVenantKirchhoff, TriangleMembrane
    from structure.stress import sheet_fields
    from structure.tangent.membrane import MembraneTerm

    t, scale = 0.01, 1e-6                                   # linear: stresses scale with w
    youngs = 12 * (1 - NU**2) * D / t**3
    error = {}
    for n in (38, 54):
        w, x, bending, _, _ = _clamped_disc(n, 1.0)
        pos = x.copy()
        pos[:, 2] = scale * w
        term = MembraneTerm.from_triangle_membrane(TriangleMembrane(x, bending.triangles, t),
                                                   SaintVenantKirchhoff(youngs, NU))
        fields = sheet_fields(term, pos, t, None, False, bending, x, D, NU)
        sigma = np.abs(fields["bending_stress"]).max(axis=1) / scale
        tri = bending.triangles
        area = 0.5 * np.linalg.norm(np.cross(x[tri[:, 1]] - x[tri[:, 0]],
                                             x[tri[:, 2]] - x[tri[:, 0]]), axis=1)
        ring = bending.flap.min(axis=1) < 0
        rim = np.sum(area[ring] * sigma[ring]) / area[ring].sum()
        error[n] = rim / (3 * a * a / (4 * t * t)) - 1
    assert abs(error[54]) < 0.03
    assert abs(error[54]) < abs(error[38])


def test_the_fold_count_of_sheared_tension_field_bands():
    """A flat tension-field sheet (Pipkin 1986) stretched 1 % both ways and sheared by
    gamma = 0.2 in bands across it: a band's triangles are wrinkled (the minor principal
    strain 0.01 - 0.1 < -nu e_1), the rest taut, so the folds are the bands: 0, 1 and 2 of
    them, each where its band is (within a grid cell: the triangles across a band's edge are
    sheared in part)."""
    from fsi.analysis.membrane_fields import FIELD_RULES, SheetGeometry, frame_fields
    from structure.model import MEMBRANE_SHAPES, Material

    radius = 0.2
    material = Material(THICKNESS, 1000.0, 1e6, 0.5, "tension-field")
    model = MEMBRANE_SHAPES["disc"](26, radius, material, "clamped")
    rule = FIELD_RULES["xpbd"](model, None)
    geometry = SheetGeometry.of(model, rule.term.triangles)
    rest = model.node_rest_position
    y = rest[:, 1] / radius
    for bands, expected in (([], 0), ([(0.2, 0.45)], 1), ([(-0.6, -0.35), (0.2, 0.45)], 2)):
        offset = np.zeros_like(y)                      # x += gamma * (length of band below y)
        for lo, hi in bands:
            offset += 0.2 * radius * np.clip(y - lo, 0, hi - lo)
        pos = 1.01 * rest
        pos[:, 0] += offset
        fields, folds = frame_fields(rule, geometry, model, pos)
        assert fields["fold_count"] == expected == len(folds)
        centroid = rest[rule.term.triangles].mean(axis=1)[:, 1] / radius
        for fold, (lo, hi) in zip(sorted(folds, key=lambda f: centroid[f].mean()), bands):
            cell = 0.1                                 # a grid cell is about 0.08 R
            assert np.all((centroid[fold] > lo - cell) & (centroid[fold] < hi + cell))


# -- rubber: the incompressible law's stresses under every model --------------------------

def _rubber_rules(poisson_ratio: float = 0.5, grid_size: int = 6):
    """The stress rule of every structure model (:data:`fsi.analysis.membrane_fields.
    FIELD_RULES`, the shell under both its laws, the XPBD membrane with and without the
    tension field) on a flat disc (a = 0.1 m) of the thesis rubber with ``poisson_ratio``:
    name -> :class:`~fsi.analysis.membrane_fields.FieldRule`."""
    from fsi.analysis.membrane_fields import FIELD_RULES
    from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS
    from structure.model import Material, disc_model

    rules = {}
    for wrinkling in ("none", "tension-field"):
        material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS,
                            poisson_ratio, wrinkling)
        model = disc_model(grid_size, 0.1, material)
        rules[f"xpbd {wrinkling}"] = FIELD_RULES["xpbd"](model, None)
        if wrinkling == "none":
            rules["thesis"] = FIELD_RULES["thesis"](model, None)
            for law in ("saint-venant-kirchhoff", "neo-hookean"):
                rules[f"shell {law}"] = FIELD_RULES["shell"](model,
                                                             {"structure": {"shell_law": law}})
    return rules


def _stretched(rest: np.ndarray, lam1: float, lam2: float, angle: float) -> np.ndarray:
    """The flat rest positions (n, 3) m, z = 0, stretched by ``lam1`` along the direction at
    ``angle`` (rad) in the plane and by ``lam2`` across it."""
    d = np.array([np.cos(angle), np.sin(angle)])
    e = np.array([-d[1], d[0]])
    out = rest.copy()
    out[:, :2] = rest[:, :2] @ (lam1 * np.outer(d, d) + lam2 * np.outer(e, e)).T
    return out


def test_a_rubber_sheets_uniaxial_stress_is_the_incompressible_closed_form_under_every_model():
    """A sheet of nu = 0.5 in incompressible uniaxial tension (lambda, lambda^-1/2) reports
    sigma_1 = mu (lambda^2 - 1 / lambda), sigma_2 = 0 and t lambda^-1/2 (neo-Hookean, mu = E / 3;
    Ogden 1984, Sec. 4.3) under every structure model, whatever law it ran with, to
    round-off; at lambda = 1.6 Saint Venant-Kirchhoff's own plane-stress thickness,
    t sqrt(1 - 2 nu tr E / (1 - nu)), would already be zero (tr E = 0.58)."""
    from fsi.constants import MEMBRANE_THICKNESS as t, MEMBRANE_YOUNGS_MODULUS as E

    mu = E / 3
    for lam in (1.2, 1.6, 2.5):
        for name, rule in _rubber_rules().items():
            f = rule.sheet(_stretched(rule.rest, lam, lam**-0.5, 0.7))
            assert np.allclose(f["principal_stress"][:, 0], mu * (lam**2 - 1 / lam),
                               rtol=1e-10), name
            assert np.allclose(f["principal_stress"][:, 1], 0.0, atol=1e-9 * mu), name
            assert np.allclose(f["thickness"], t * lam**-0.5, rtol=1e-12), name
            assert np.allclose(f["principal_resultant"][:, 0],
                               mu * (lam**2 - 1 / lam) * t * lam**-0.5, rtol=1e-10), name
            assert "neo-hookean" in rule.law, name
    green = 0.5 * (np.array([1.6, 1.6**-0.5]) ** 2 - 1)
    assert 1 - 2 * 0.5 * green.sum() / 0.5 < 0


def test_a_tension_field_rubber_sheet_carries_no_compression():
    """With the tension field, a rubber sheet narrower than its natural width (lambda_2 <
    lambda_1^-1/2) is wrinkled and carries the uniaxial mu (lambda_1^2 - 1 / lambda_1) with
    sigma_2 = 0 (Pipkin 1986); one shorter than at rest both ways carries none; the same
    sheet without the tension field carries compression across."""
    from fsi.constants import MEMBRANE_YOUNGS_MODULUS as E

    rules = _rubber_rules()
    wrinkled = _stretched(rules["xpbd tension-field"].rest, 1.3, 0.7, 0.2)
    f = rules["xpbd tension-field"].sheet(wrinkled)
    assert np.allclose(f["principal_stress"][:, 0], E / 3 * (1.3**2 - 1 / 1.3), rtol=1e-10)
    assert np.allclose(f["principal_stress"][:, 1], 0.0, atol=1e-3)
    assert np.all(rules["xpbd none"].sheet(wrinkled)["principal_stress"][:, 1] < -1e4)
    slack = rules["xpbd tension-field"].sheet(_stretched(wrinkled, 0.9 / 1.3, 0.8 / 0.7, 0.2))
    assert np.all(slack["principal_stress"] == 0.0)


def test_the_thesis_static_drain_frame_has_finite_incompressible_stresses():
    """The thesis-static drain frame at tank fraction 0.398 (``tests/data``, the run's node
    positions): a triangle there stretches so far (tr E >= 0.5) that Saint Venant-Kirchhoff's
    plane-stress thickness at nu = 0.4999 was zero and its stress infinite (40 MPa in the
    next frame for a rubber of E = 8.6 MPa); under the incompressible law of the same E every
    field is finite, the thickness is t / (lambda_1 lambda_2) and the stresses are
    mu (lambda_i^2 - lambda_3^2) at each triangle's stretches."""
    from pathlib import Path

    from fsi.analysis.membrane_fields import FIELD_RULES
    from fsi.constants import MEMBRANE_YOUNGS_MODULUS as E, TANK_RADIUS
    from fsi.analysis.membrane_fields import TRIANGLE_FIELDS
    from structure.model import Material, hemisphere_model
    from fsi import constants as C

    frame = np.load(Path(__file__).parent / "data" / "thesis_static_drain_tank_0398.npz")
    model = hemisphere_model(26, TANK_RADIUS, Material(C.MEMBRANE_THICKNESS,
                                                       C.MEMBRANE_DENSITY, E))
    rule = FIELD_RULES["thesis"](model, None)
    f = rule.sheet(frame["node_position"])
    for name in TRIANGLE_FIELDS:
        assert np.all(np.isfinite(f[name])), name
    green = f["green_strain"]
    svk = 1 - 2 * 0.4999 * green.sum(axis=1) / (1 - 0.4999)
    assert svk.min() <= 0                                  # the artefact the frame held
    lam = np.exp(f["log_strain"])
    lam3 = 1 / lam.prod(axis=1)
    assert np.allclose(f["thickness"], C.MEMBRANE_THICKNESS * lam3, rtol=1e-12)
    assert np.allclose(f["principal_stress"], E / 3 * (lam**2 - lam3[:, None] ** 2),
                       rtol=1e-9, atol=1e-6 * E)


@settings(max_examples=60, deadline=None)
@given(lam1=st.floats(0.2, 3.0), lam2=st.floats(0.2, 3.0), angle=st.floats(0.0, np.pi),
       poisson_ratio=st.sampled_from([0.0, 0.3, 0.45, 0.5]))
def test_no_stress_field_of_any_law_is_non_finite(lam1, lam2, angle, poisson_ratio):
    """Every field of every structure model's stress rule, compressible or rubber, with and
    without the tension field, is finite for principal stretches in [0.2, 3] at any angle
    (property test)."""
    from fsi.analysis.membrane_fields import TRIANGLE_FIELDS

    for name, rule in _rules_by_poisson(poisson_ratio).items():
        f = rule.sheet(_stretched(rule.rest, lam1, lam2, angle))
        for key in TRIANGLE_FIELDS:
            assert np.all(np.isfinite(f[key])), (name, key)
        assert np.all(f["thickness"] > 0), name


_RULES: dict = {}


def _rules_by_poisson(poisson_ratio: float) -> dict:
    if poisson_ratio not in _RULES:
        _RULES[poisson_ratio] = _rubber_rules(poisson_ratio, grid_size=4)
    return _RULES[poisson_ratio]
