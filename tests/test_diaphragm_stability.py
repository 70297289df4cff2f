"""Partitioned schemes on the Table 4.1 diaphragm (mass ratio m / (rho_f R) = 0.009): constant
under-relaxation is stable below the added-mass bound and not above it, the explicit scheme
diverges (Causin, Gerbeau & Nobile 2005; docs/validation/coupling.md, 'On the diaphragm
itself').  The bound was measured between omega = 0.07 (converges) and 0.1 (does not) by
``benchmarks/diaphragm_stability.py``; the sphere's n = 1 estimate 2 m / (m + rho_f R) = 0.018
lies below it (safe)."""
import numpy as np
import pytest

from fsi.setup.build import build
from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, TANK_RADIUS, WATER_DENSITY
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene


def _run(coupling: dict, windows: int):
    scene = load_scene("diaphragm-fill").with_keys(
        {"coupling": coupling, "dynamics": {"end_time": windows * 0.002,
                                            "frame_interval": windows}})
    return PROCEDURES["coupled-fill"](build(scene), lambda f, m: None)


def test_constant_relaxation_converges_below_the_bound_and_not_above():
    m = MEMBRANE_DENSITY * MEMBRANE_THICKNESS
    estimate = 2 * m / (m + WATER_DENSITY * TANK_RADIUS)
    assert estimate == pytest.approx(0.018, abs=5e-4)
    below = _run(dict(acceleration="constant", relaxation=0.05, max_iterations=300), 1)
    assert below.attrs["failure"] == "" and below.groups["windows"]["converged"].all()
    above = _run(dict(acceleration="constant", relaxation=0.2, max_iterations=100), 1)
    assert "not converged after 100 iterations" in above.attrs["failure"]
    residual = float(above.attrs["failure"].split("'interface_pressure': ")[1].split(",")[0])
    assert residual > 0.5  # not slow: the iterates keep changing by their own size


def test_explicit_scheme_diverges_where_iqn_ils_does_not():
    explicit = _run(dict(scheme="explicit"), 25)
    implicit = _run(dict(), 2)
    speed = lambda r: float(np.nanmax(r.groups["frames"]["node_speed_max"]))  # noqa: E731
    assert speed(implicit) < 0.01  # m/s: the membrane follows the slow fill
    assert speed(explicit) > 100 * speed(implicit)


def test_coupled_fill_is_first_order_in_the_window():
    """Backward Euler windows: the level at t = 0.048 s from windows of 16, 8 and 4 ms (24, 12
    and 6 XPBD substeps of the same 0.667 ms, so that the membrane and its static start are
    the same) converges at observed order ~1 (measured 1.42;
    docs/notes/coupled-fill-convergence.md)."""
    levels = []
    for window in (0.016, 0.008, 0.004):
        scene = load_scene("diaphragm-fill").with_keys(
            {"dynamics": {"window": window, "substep_fraction": 0.266, "end_time": 0.048,
                          "frame_interval": 1000}})
        result = PROCEDURES["coupled-fill"](build(scene), lambda f, m: None)
        assert result.attrs["failure"] == ""
        assert result.attrs["substep"] == pytest.approx(0.002 / 3, rel=1e-12)
        levels.append(float(result.groups["windows"]["pressure_level"][-1]))
    d12, d23 = abs(levels[0] - levels[1]), abs(levels[1] - levels[2])
    order = np.log(d12 / d23) / np.log(2.0)
    assert 0.8 < order < 2.0, levels


@pytest.fixture(scope="module")
def flat_family():
    """The flat diaphragm's membrane-grid family, N = 14, 20, 26 (fsi.analysis.coupled_study)."""
    from fsi.analysis.coupled_study import FLAT, family
    return family(FLAT, 0.048)


def test_coupled_fill_of_a_flat_diaphragm_converges_in_the_membrane_grid(flat_family):
    """The coupled stack on a membrane that does not fold: ``diaphragm-fill`` with a flat
    diaphragm across the equator (``membrane.shape = "disc"``), started taut at tank
    fraction 0.52, on N = 14, 20, 26 to t = 0.048 s (fsi.analysis.coupled_study's family;
    docs/notes/flat-diaphragm.md; measured: Eqn 6.1 against N = 26 0.276 and 0.093 %,
    observed orders 1.23 (level), 1.38 (centre z), 1.04 (shape)). Every run converges, the
    differences shrink, and each order lies between 0.8 and 3; the hemispherical diaphragm's
    family, folded, has none (docs/notes/coupled-fill-convergence.md)."""
    fam = flat_family
    assert all(r["failure"] == "" and r["start_converged"] for r in fam["runs"])
    e = [r["eqn_6_1_vs_finest"] for r in fam["runs"]]
    assert e[0] > e[1] > 10 * abs(e[2]) and abs(e[2]) < 1e-12, e  # the finest against itself
    for measure in ("level", "centre_z", "shape"):
        assert 0.8 < fam["observed_order"][measure] < 3.0, fam["observed_order"]
    centre = np.array([r["centre"] for r in fam["runs"]])
    assert np.abs(centre[:, :2]).max() < 1e-4  # m: the taut sheet stays on the axis


def test_the_flat_diaphragms_grid_error_is_its_second_fixed_ring(flat_family):
    """The same family with the rim held by its ring on r = R only (``membrane.support =
    "simply-supported"``; the bending holds the rim's slope) instead of by a second ring one
    grid edge inside it, whose width shrinks with N (docs/notes/lateral-compliance.md, 'The
    flat diaphragm's second fixed ring'; measured: levels 172.5 / 171.5 / 168.4 Pa against
    255.3 / 211.5 / 190.4 Pa, Eqn 6.1 of N = 14 against N = 26 0.038 % against 0.276 %). The
    sheet's own grid error is small beside the second ring's: the levels' spread under a tenth
    of the two-ring family's, N = 14's shape error under a fifth, the centres' heights within
    0.01 mm."""
    from fsi.analysis.coupled_study import FLAT_RIM, family

    rim = family(FLAT_RIM, 0.048)
    assert all(r["failure"] == "" and r["start_converged"] for r in rim["runs"])

    def spread(fam):
        levels = [r["level"] for r in fam["runs"]]
        return max(levels) - min(levels)
    assert spread(rim) < 0.1 * spread(flat_family), (spread(rim), spread(flat_family))
    assert (rim["runs"][0]["eqn_6_1_vs_finest"]
            < 0.2 * flat_family["runs"][0]["eqn_6_1_vs_finest"])
    z = [r["centre"][2] for r in rim["runs"]]
    assert max(z) - min(z) < 1e-5, z  # m


@pytest.mark.slow
def test_coupled_fill_converges_in_the_fluid_grid_and_the_coupling_tolerance():
    """The slow members of the coupled fill's convergence study (fsi.analysis.coupled_study;
    docs/notes/coupled-fill-convergence.md, measured: fluid cells 16/24/32 shape order 1.32,
    coupling tolerance 1e-3/1e-4/1e-5 shape order 1.05): each family's shape error against
    its finest falls (observed order > 0.5), and every run converges."""
    from fsi.analysis.coupled_study import family

    for name in ("fluid cells", "coupling tolerance"):
        fam = family(name, 0.048)
        assert all(r["failure"] == "" for r in fam["runs"]), name
        e = [r["eqn_6_1_vs_finest"] for r in fam["runs"]]
        assert e[0] > e[1] > e[2] == 0.0, (name, e)
        assert fam["observed_order"]["shape"] > 0.5, (name, fam["observed_order"])
