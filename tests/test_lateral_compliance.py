"""The contents' static lateral compliance (fsi.slosh.lateral_compliance) and the liquid's first
moment it is measured with (structure.volume.liquid_first_moment)."""
import numpy as np
import pytest

from fsi.slosh.lateral_compliance import (contents_centre, first_mode_bound,
                                          free_surface_compliance, modal_compliance,
                                          static_compliance)
from structure.model import Material, hemisphere_model
from structure.volume import liquid_first_moment, liquid_volume, mirrored_rest_position

R = 0.2


@pytest.fixture(scope="module")
def model():
    return hemisphere_model(26, R, Material(0.001, 1000.0, 1e6, 0.45), "clamped")


def test_first_moment_of_the_lower_hemisphere(model):
    """A flat membrane on the equator holds the lower hemisphere, whose first moment is
    (0, 0, -pi R^4 / 4) and centroid 3R/8 below the centre (exact on the faceted disc:
    its triangles add nothing at z = 0); the empty and the full tank hold no moment
    (to the hemisphere grid's faceting)."""
    flat = model.node_rest_position.copy()
    flat[:, 2] = 0.0
    m1 = liquid_first_moment(model, flat)
    assert m1 == pytest.approx([0.0, 0.0, -np.pi * R**4 / 4], abs=1e-15)
    volume = liquid_volume(model, flat)
    assert m1[2] / volume == pytest.approx(-3 * R / 8, rel=1e-12)
    for x in (model.node_rest_position, mirrored_rest_position(model)):
        assert np.abs(liquid_first_moment(model, x)).max() < 0.01 * np.pi * R**4 / 4


def test_contents_centre_weighs_the_membrane(model):
    """The contents' centre is the mass-weighted mean of the liquid's centroid and the
    membrane's node masses."""
    flat = model.node_rest_position.copy()
    flat[:, 2] = 0.0
    volume = liquid_volume(model, flat)
    c = contents_centre(model, flat, 1000.0, volume)
    liquid = 1000.0 * volume
    assert c[2] == pytest.approx(liquid * (-3 * R / 8) / (liquid + model.node_mass.sum()),
                                 rel=1e-12)


def test_static_compliance_of_a_linear_and_of_a_skewed_response():
    """C is the centred slope; the asymmetry is the mean displacement over the tilt."""
    calls = []

    def linear(b_x):
        calls.append(b_x)
        return np.array([0.002 + 3e-4 * b_x, 0.0, -0.05]), True

    c = static_compliance(linear, tilt=0.1)
    assert c.compliance == pytest.approx(3e-4) and abs(c.asymmetry) < 1e-15 and c.converged
    assert sorted(calls) == [-0.1, 0.0, 0.1]
    skewed = static_compliance(lambda b: (np.array([3e-4 * b + 1e-3 * b * b, 0, 0]), b >= 0),
                               tilt=0.1)
    assert skewed.asymmetry == pytest.approx(1e-4) and not skewed.converged
    with pytest.raises(ValueError, match="tilt"):
        static_compliance(linear, tilt=0.0)


def test_the_free_surface_first_mode_meets_the_static_limit():
    """Half-full sphere: C = 3R/(8g); Budiansky's lambda1 = 1.5602 with the first mode
    carrying the whole static response gives the slosh mass fraction lambda1 * 3/8 = 0.585
    (NASA SP-106 quotes about 0.58), and the first mode lies below the bound 1/sqrt(C)."""
    g = 9.81
    c = free_surface_compliance(-3 * R / 8, g)
    assert c == pytest.approx(3 * R / (8 * g))
    omega = np.sqrt(1.5602 * g / R)
    mass_fraction = 1.5602 * 3 / 8
    assert modal_compliance([mass_fraction * 10.0], [omega], 10.0) == pytest.approx(c)
    assert omega < first_mode_bound(c)
    assert modal_compliance([1.0, 2.0], [2.0, 4.0], 4.0) == pytest.approx((1 / 4 + 2 / 16) / 4)


@pytest.mark.slow
def test_the_flat_diaphragms_compliance_converges_when_held_by_its_rim_ring_only():
    """The flat diaphragm (``membrane.shape = "disc"``) at tank fraction 0.52, C at
    b_x = 0.01 m/s^2 from the slosh run's own static start (docs/notes/lateral-compliance.md,
    'The flat diaphragm's second fixed ring'; measured: 1.2803 / 1.2832 / 1.2695e-3 s^2 on
    N = 14 / 20 / 26 with the rim ring only, 2.440 / 4.504 / 5.836e-4 s^2 with two rings).
    Held by its rim ring on r = R only, C moves less than 1.5 % from N = 14 to 20 to 26; with
    the two-ring support N = 14's is under a third of it, because the second ring shortens
    the free disc by one grid edge."""
    from fsi.setup.build import build
    from fsi.procedures.slosh_diaphragm import start_compliance, static_start
    from fsi.scene import load_scene

    def compliance(grid_size, support):
        setup = build(load_scene("slosh-diaphragm").with_keys(
            {"membrane": {"grid_size": grid_size, "shape": "disc", "support": support},
             "slosh": {"fill": 0.52}}))
        start = static_start(setup, 0.001)
        assert start.info.converged
        c = start_compliance(setup, start, 0.01)
        assert c.converged
        return c.compliance

    rim = [compliance(n, "simply-supported") for n in (14, 20, 26)]
    assert max(rim) - min(rim) < 0.015 * min(rim), rim
    two_rings = compliance(14, "clamped")
    assert two_rings < rim[0] / 3, (two_rings, rim)
