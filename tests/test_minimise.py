"""Statics as constrained minimisation (structure/minimise/).

Oracles: IPC's barrier b(d) = -(d - dhat)^2 ln(d / dhat) as ipc-toolkit computes it
(``ipctk.barrier`` and its derivatives; Li et al. 2020); finite differences of the wall's
energy; the geometry of a sphere (the largest step); the Newton statics' equilibria where
both converge: the thesis's flat diaphragm under 2 kPa and the Table 4.1 hemisphere at tank
fraction 0.1 (N = 14) from the same start, each within Eqn 6.1's bar of 0.05 %.
"""
import ipctk
import numpy as np
import pytest

from fsi.analysis.compare import eqn_6_1_error
from fsi.scene import load_scene
from fsi.setup.build import build
from fsi.setup.models import hydrostatic_load
from structure.load import Load
from structure.minimise import (MinimiseSettings, fill_path, inside, membrane_terms,
                                minimisation_model, xpbd_terms)
from structure.minimise.barrier import BarrierWall, barrier, stiffness_for
from structure.minimise.model import projectable
from structure.minimise.newton import Corrector, Scales, minimise_at_volume
from structure.model import MembraneState
from structure.newton import statics as S
from structure.newton.system import NewtonModel
from structure.plate import FlatDiaphragm, ShellDisc
from structure.volume import tank_volume
from structure.xpbd.model import XpbdModel

EQN_6_1_BAR = 0.05  # %


@pytest.mark.parametrize("ratio", [1e-4, 0.01, 0.1, 0.37, 0.5, 0.9, 0.999])
def test_the_barrier_is_ipc_toolkits(ratio):
    dhat = 1e-3
    d = ratio * dhat
    b, db, ddb = barrier(d, dhat)
    assert b == pytest.approx(ipctk.barrier(d, dhat), rel=1e-12)
    assert db == pytest.approx(ipctk.barrier_first_derivative(d, dhat), rel=1e-12)
    assert ddb == pytest.approx(ipctk.barrier_second_derivative(d, dhat), rel=1e-12)


def test_the_barrier_vanishes_beyond_dhat_and_is_infinite_at_the_wall():
    assert barrier(2e-3, 1e-3) == (0.0, 0.0, 0.0)
    assert barrier(0.0, 1e-3)[0] == np.inf
    assert barrier(-1e-6, 1e-3)[0] == np.inf


def _wall(n=20, seed=3):
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(n, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    radius, dhat = 0.2, 1e-3
    gap = rng.uniform(0.05, 1.5, n) * dhat           # some inside dhat, some beyond
    x = direction * (radius - gap)[:, None]
    free = np.ones(n, dtype=bool)
    free[:2] = False
    wall = BarrierWall.build(free, rng.uniform(1e-4, 2e-4, n), radius, dhat, 2000.0)
    return wall, x


def test_the_wall_gradient_and_hessian_match_finite_differences():
    wall, x = _wall()
    e, g, blocks = wall.evaluate(x)
    assert np.isfinite(e) and e > 0
    h = 1e-9
    for i in range(len(x)):
        for r in range(3):
            step = np.zeros_like(x)
            step[i, r] = h
            ep, gp, _ = wall.evaluate(x + step, hessian=False)
            em, gm, _ = wall.evaluate(x - step, hessian=False)
            assert (ep - em) / (2 * h) == pytest.approx(g[i, r], rel=1e-5, abs=1e-9 * np.abs(
                g).max())
            np.testing.assert_allclose((gp[i] - gm[i]) / (2 * h), blocks[i, 0, 0, :, r],
                                       rtol=1e-5, atol=1e-6 * np.abs(blocks).max())
    # fixed nodes carry nothing, and every node's block is positive semi-definite
    assert not g[:2].any()
    assert np.linalg.eigvalsh(blocks[:, 0, 0]).min() >= -1e-9 * np.abs(blocks).max()


def test_the_stiffness_carries_the_pressure_at_a_tenth_of_dhat():
    """A node of area A pressed by p rests where kappa A |b'(d)| = p A: at d = dhat / 10."""
    dhat, pressure = 1e-3, 2000.0
    kappa = stiffness_for(pressure, dhat)
    assert kappa * abs(barrier(0.1 * dhat, dhat)[1]) == pytest.approx(pressure, rel=1e-12)


def test_the_largest_step_stops_every_node_short_of_the_wall():
    wall, x = _wall()
    rng = np.random.default_rng(5)
    dx = rng.normal(size=x.shape) * 5e-3                # steps far longer than the gaps
    s = wall.largest_step(x, dx, fraction=0.9)
    assert 0 < s < 1
    gap_before, gap_after = wall.gaps(x), wall.gaps(x + s * dx)
    free = wall.weight > 0
    assert np.all(gap_after[free] >= 0.1 * gap_before[free] - 1e-15)
    # the node that sets it closes exactly 90 % of its gap
    assert np.min(gap_after[free] / gap_before[free]) == pytest.approx(0.1, abs=1e-9)
    # a step that stays clear of the wall is not cut
    assert wall.largest_step(x, -0.01 * x) == 1.0


def _hemisphere(grid_size: int, wrinkling: str = "none"):
    keys = {"membrane": {"grid_size": grid_size, "wrinkling": wrinkling},
            "structure": {"model": "xpbd"}}
    setup = build(load_scene("diaphragm-static").with_keys(keys))
    radius = setup.model.radius
    pressure = setup.liquid.density * 9.81 * radius
    xpbd = XpbdModel.from_membrane(setup.model)
    model, wall = minimisation_model(setup.model, xpbd_terms(xpbd), pressure)
    return setup, xpbd, model, wall


def test_the_flat_diaphragm_meets_newton_under_the_held_pressure():
    """The thesis's flat diaphragm (Ch. 3) under 2 kPa: Newton under the held pressure finds
    the equilibrium and its volume; the minimisation at that volume, from the flat sheet,
    finds the same sheet and 2 kPa as the volume's multiplier."""
    disc = ShellDisc.build(FlatDiaphragm(0.20955, 0.001778, 8.6e6, 0.5), 14)
    newton = disc.newton_model()
    base = newton.base
    start = base.node_rest_position.copy()
    start[~base.node_fixed, 2] += 1e-6  # off the flat plate's bifurcation point
    held = Load(np.zeros(len(base.node_mass)), np.zeros(3), None, 2000.0, 0.0)
    x, _, converged, _ = S.newton_at_level(newton, start, held)
    assert converged
    volume = newton.liquid_volume(x)
    model, wall = minimisation_model(base, newton.terms, 2000.0)
    load = Load(held.node_pressure, np.zeros(3), volume, 0.0, 0.0)
    ((state, eq),), report = fill_path(model, wall, MembraneState(start), load, [volume])
    assert eq.converged and len(report.steps) >= 1
    assert eq.pressure_level == pytest.approx(2000.0, rel=1e-6)
    assert eqn_6_1_error(x, base.face_nodes, state.node_position, base.radius) <= 1e-6
    assert np.abs(state.node_position - x).max() <= 1e-6 * x[:, 2].max()


def test_the_hemisphere_keeps_newtons_fold_state_at_a_tenth_of_the_tank():
    """From the Newton statics' equilibrium at tank fraction 0.1 (N = 14, the full law, the
    wall a penalty) the minimisation (the wall a barrier) stays in the same fold state:
    Eqn 6.1 within the bar (it counts the sheet off the wall, within 0.8 R of the centre)."""
    setup, xpbd, model, wall = _hemisphere(14)
    radius = setup.model.radius
    target = 0.1 * tank_volume(radius)
    load = hydrostatic_load(setup.liquid, volume_target=target)
    old = NewtonModel.from_xpbd(XpbdModel.from_membrane(setup.model), load_form="energy")
    (reference, eq, _), = S.fill_path(old, MembraneState(setup.model.node_rest_position.copy()),
                                      load, [target])
    assert eq.converged
    start = inside(wall, reference.node_position)
    model.follow(start)
    scales = Scales(model, load)
    x, level, iterations, converged, lin = minimise_at_volume(
        model, wall, start, eq.pressure_level, load, target, MinimiseSettings(), scales,
        Corrector(), projected=projectable(model))
    assert converged and iterations <= 15
    assert abs(lin.volume - target) <= 1e-9 * tank_volume(radius)
    assert eqn_6_1_error(reference.node_position, setup.model.face_nodes, x,
                         radius) <= EQN_6_1_BAR
    assert np.all(wall.gaps(x)[wall.weight > 0] > 0)


@pytest.mark.parametrize("wrinkling", ["none", "tension-field"])
def test_the_fill_path_reaches_half_the_tank_from_the_rest_shape(wrinkling):
    """Every step converged, every free node inside the wall, the volume and the residual
    held; the report counts what was done."""
    setup, _, model, wall = _hemisphere(10, wrinkling)
    radius = setup.model.radius
    targets = [0.25 * tank_volume(radius), 0.5 * tank_volume(radius)]
    load = hydrostatic_load(setup.liquid, volume_target=targets[-1])
    results, report = fill_path(model, wall,
                                MembraneState(inside(wall, setup.model.node_rest_position)),
                                load, targets)
    for target, (state, eq) in zip(targets, results):
        assert eq.converged and eq.force_ratio <= 1e-6
        assert model.liquid_volume(state.node_position) == pytest.approx(target, rel=1e-8)
        assert np.all(wall.gaps(state.node_position)[wall.weight > 0] > 0)
    assert report.steps and report.steps[-1].volume == pytest.approx(targets[-1])
    assert report.iterations >= sum(s.iterations for s in report.steps)
    assert report.factorisations >= report.iterations > 0
    assert 0 < report.factor_seconds < report.seconds


def test_a_start_on_the_wall_is_refused_by_name():
    setup, _, model, wall = _hemisphere(6)
    load = hydrostatic_load(setup.liquid, volume_target=0.1 * tank_volume(setup.model.radius))
    with pytest.raises(ValueError, match="on or beyond the tank wall"):
        fill_path(model, wall, MembraneState(setup.model.node_rest_position), load,
                  [load.volume_target])


def test_the_residual_stiffness_keeps_a_fraction_of_the_full_law():
    """W = (1 - e) W_tension_field + e W_full, gradients alike."""
    setup, xpbd_tf, _, _ = _hemisphere(8, "tension-field")
    _, xpbd_full, _, _ = _hemisphere(8)
    x = setup.model.node_rest_position * np.array([1.0, 0.97, 1.02])  # some slack, some taut
    (relaxed,) = membrane_terms(xpbd_tf, 0.0)
    (full,) = membrane_terms(xpbd_full)
    e = 0.03
    terms = membrane_terms(xpbd_tf, e)
    assert len(terms) == 2
    value = sum(t.evaluate(x, False)[0] for t in terms)
    gradient = sum(t.evaluate(x, False)[1] for t in terms)
    assert value == pytest.approx((1 - e) * relaxed.evaluate(x, False)[0]
                                  + e * full.evaluate(x, False)[0], rel=1e-12)
    np.testing.assert_allclose(gradient, (1 - e) * relaxed.evaluate(x, False)[1]
                               + e * full.evaluate(x, False)[1], rtol=1e-10,
                               atol=1e-12 * np.abs(gradient).max())
    with pytest.raises(ValueError, match="residual_stiffness"):
        membrane_terms(xpbd_tf, 1.0)


@pytest.mark.parametrize("key, value", [("volume_step", 0.0), ("step_shrink", 1.5),
                                        ("max_iterations", 0), ("pseudo_inertia", -1.0),
                                        ("min_volume_step", 0.5)])
def test_settings_out_of_range_are_refused_by_name(key, value):
    with pytest.raises(ValueError, match=key.split("_")[0]):
        MinimiseSettings(**{key: value})


def test_a_static_sweep_runs_on_the_minimisation(tmp_path):
    """``structure.model = "minimisation"``: a fill and drain sweep (N = 10) with every fill
    converged (exit 0), each fill's volume held, the levels recorded; the snaps crossed on the
    way recorded with their tank fraction (in order along the fill, within the sweep) and the
    level's jump."""
    import h5py

    from fsi.cli import main

    scene = tmp_path / "sweep.toml"
    scene.write_text("[scene]\nname = 'tiny'\nprocedure = 'volume-sweep'\n[membrane]\n"
                     "grid_size = 10\n[structure]\nmodel = 'minimisation'\n[sweep]\n"
                     "scale = 'tank'\nfills = [0.2, 0.4]\ndrain = true\n")
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) == 0
    with h5py.File(out / "result.h5") as f:
        for leg in ("frames", "drain"):
            assert np.all(f[leg]["converged"][()]), leg
            assert np.all(np.isfinite(f[leg]["pressure_level"][()])), leg
        points = f["limit_points"]
        events = [e.decode() for e in points["event"][()]]
        fills = points["tank_fraction"][()][[e.startswith("filling") for e in events]]
        assert fills.size and np.all(np.diff(fills) > 0) and 0 < fills[0] and fills[-1] <= 0.4
        assert np.all(points["pressure_level_before"][()] != points["pressure_level"][()])


def test_the_pseudo_inertia_crosses_to_an_equilibrium():
    """The path's last resort at the smallest step: proximal steps M / (2 h^2) |x - x_prev|^2
    from a state far from equilibrium (the rest shape pulled in by 5 % at its own volume) end
    on an equilibrium of the potential without the term."""
    from structure.minimise.model import projectable
    from structure.minimise.path import _cross

    setup, _, model, wall = _hemisphere(8)
    radius = setup.model.radius
    free = wall.weight > 0
    x = setup.model.node_rest_position.copy()
    x[free] *= 0.95
    load = hydrostatic_load(setup.liquid, volume_target=model.liquid_volume(x))
    model.follow(x)
    settings = MinimiseSettings()
    scales = Scales(model, load)
    x, level, iterations, converged, lin = _cross(model, wall, x, 0.0, load,
                                                  load.volume_target, settings, scales,
                                                  Corrector(), projectable(model))
    assert converged and iterations > 0
    assert abs(lin.volume - load.volume_target) <= 1e-9 * tank_volume(radius)
    assert np.abs(lin.residual[free]).max() <= settings.force_tolerance * scales.force
    assert np.all(wall.gaps(x)[free] > 0)


def test_self_contact_carries_the_pressure_at_a_tenth_of_dhat_on_any_triangle_size():
    """The pairs are area-weighted, so two parallel triangles of four times the probe's area a
    tenth of dhat apart carry the calibrating pressure, as the wall's barrier does."""
    from structure.minimise.contact import SelfContact

    dhat, pressure = 1e-3, 2000.0
    lower = 2.0 * np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    points = np.vstack([lower, lower + np.array([0.2, 0.2, 0.1 * dhat])])
    faces = np.array([[0, 1, 2], [3, 4, 5]])
    contact = SelfContact.build(points, faces, np.ones(6, dtype=bool), dhat, pressure)
    energy, grad, matrix = contact.evaluate(points)
    assert energy > 0 and matrix.shape == (18, 18)
    assert abs(grad[3:, 2].sum()) / 2.0 == pytest.approx(pressure, rel=1e-6)
    # apart by more than dhat, nothing
    apart = points + np.array([0, 0, 2 * dhat]) * (np.arange(6) >= 3)[:, None]
    assert contact.evaluate(apart)[0] == 0.0


def test_self_contact_stops_a_flap_short_of_the_sheet():
    """A triangle driven through another is stopped by the continuous collision detection
    before they meet; the wall's own limit is kept beside it."""
    from structure.minimise.contact import Obstacles, SelfContact

    lower = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]]) - 0.03
    upper = lower + np.array([0.01, 0.01, 0.002])
    upper[2, 2] += 0.004                             # tilted: the step pierces the lower one
    points = np.vstack([lower, upper])
    faces = np.array([[0, 1, 2], [3, 4, 5]])
    free = np.ones(6, dtype=bool)
    contact = SelfContact.build(points, faces, free, 1e-3, 2000.0)
    wall = BarrierWall.build(free, np.full(6, 1e-3), 0.2, 1e-3, 2000.0)
    step = np.zeros_like(points)
    step[3:, 2] = -0.004                             # through the lower triangle
    alpha = Obstacles(wall, contact).largest_step(points, step)
    assert 0 < alpha < 0.5                           # they would first touch at 0.5
    assert not contact.intersecting(points + alpha * step)
    assert contact.intersecting(points + step)


def test_the_full_law_fills_without_passing_through_itself_with_self_contact():
    """The full law's fold states pass through themselves from N = 26 without self-contact
    (docs/notes/minimisation-statics.md); with it the path reaches its fills converged and
    the sheet never intersects itself, nor does a flap fold through its neighbour."""
    from structure.minimise.contact import Obstacles, SelfContact

    setup, xpbd, model, wall = _hemisphere(10)
    radius = setup.model.radius
    contact = SelfContact.build(setup.model.node_rest_position, xpbd.triangles,
                                ~setup.model.node_fixed, 2.5e-4, 2000.0)
    targets = [0.2 * tank_volume(radius), 0.4 * tank_volume(radius)]
    load = hydrostatic_load(setup.liquid, volume_target=targets[-1])
    results, _ = fill_path(model, Obstacles(wall, contact),
                           MembraneState(inside(wall, setup.model.node_rest_position)), load,
                           targets)
    for state, eq in results:
        assert eq.converged
        assert not contact.intersecting(state.node_position)
    assert np.abs(xpbd.bending.reference_change).max() < np.pi
