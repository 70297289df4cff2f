"""A membrane state carried from a coarse grid to a finer one (:mod:`structure.prolongation`):
exact for affine maps of a flat grid, the chordal sag on the sphere, the identity on the same
grid, fixed nodes at rest."""
import numpy as np
import pytest

from fsi.setup.build import build
from fsi.scene import SceneError, load_scene

from structure.model import Material, disc_model, hemisphere_model
from structure.prolongation import locate, prolong

RADIUS = 0.20955
MATERIAL = Material(thickness=0.001778, density=1070.0, youngs_modulus=8.6e6)


def _affine(x):
    a = np.array([[1.1, 0.2, -0.1], [-0.3, 0.9, 0.05], [0.2, 0.1, 1.3]])
    return x @ a.T + np.array([0.01, -0.02, 0.03])


@pytest.mark.parametrize("coarse_n, fine_n", [(10, 26), (14, 38)])
def test_an_affine_map_of_a_flat_grid_is_carried_exactly(coarse_n, fine_n):
    coarse = disc_model(coarse_n, RADIUS, MATERIAL, "simply-supported")
    fine = disc_model(fine_n, RADIUS, MATERIAL, "simply-supported")
    out = prolong(coarse, _affine(coarse.node_rest_position), fine)
    free = ~fine.node_fixed
    np.testing.assert_allclose(out[free], _affine(fine.node_rest_position)[free], atol=1e-12)
    np.testing.assert_array_equal(out[~free], fine.node_rest_position[~free])


def test_the_same_grid_is_the_identity():
    model = hemisphere_model(14, RADIUS, MATERIAL)
    rng = np.random.default_rng(3)
    x = model.node_rest_position + 1e-3 * rng.standard_normal(model.node_rest_position.shape)
    x[model.node_fixed] = model.node_rest_position[model.node_fixed]
    np.testing.assert_allclose(prolong(model, x, model), x, atol=1e-13)


def test_the_sphere_is_carried_within_its_chordal_sag_at_second_order():
    """The rest hemisphere carried from N to 38: every fine node within the chordal sag
    R - sqrt(R^2 - rho^2) of the coarse triangle it lies in, rho its circumradius (its
    vertices lie on the sphere, so the triangle lies inside the circle its plane cuts), the
    error falling as h^2 (measured 1.93 from N = 14 to 26; asserted 1.7 to 2.3)."""
    fine = hemisphere_model(38, RADIUS, MATERIAL)
    errors = []
    for n in (14, 26):
        coarse = hemisphere_model(n, RADIUS, MATERIAL)
        out = prolong(coarse, coarse.node_rest_position, fine)
        err = np.abs(np.linalg.norm(out, axis=1) - RADIUS)
        nodes, _ = locate(coarse, fine.node_rest_position)
        x = coarse.node_rest_position[nodes]          # each fine node's coarse triangle
        a, b, c = (np.linalg.norm(x[:, (i + 1) % 3] - x[:, (i + 2) % 3], axis=1)
                   for i in range(3))
        area = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        rho = np.minimum(a * b * c / (4 * area), RADIUS)
        assert np.all(err <= RADIUS - np.sqrt(RADIUS**2 - rho**2) + 1e-15)
        errors.append(err.max())
    order = np.log(errors[0] / errors[1]) / np.log((26 - 1) / (14 - 1))
    assert 1.7 <= order <= 2.3, (errors, order)


def test_a_state_of_another_grid_shape_is_refused():
    coarse = hemisphere_model(14, RADIUS, MATERIAL)
    fine = hemisphere_model(20, RADIUS, MATERIAL)
    with pytest.raises(ValueError, match="shape"):
        prolong(coarse, fine.node_rest_position, fine)


@pytest.mark.parametrize("keys, match", [
    ({"dynamics": {"start_grid": 20}}, "from 4 to membrane.grid_size = 14"),
    ({"dynamics": {"start_grid": 7}}, "an even N0"),
    ({"dynamics": {"start_grid": 10}, "membrane": {"wrinkling": "tension-field"}},
     "no tension field"),
])
def test_a_start_grid_the_run_cannot_use_is_refused_by_name(keys, match):
    with pytest.raises(SceneError, match=r"dynamics\.start_grid") as err:
        build(load_scene("diaphragm-fill").with_keys(keys))
    assert match in str(err.value)


def test_a_start_carried_from_a_coarser_grid_is_that_grids_fold_state_at_rest_here():
    """``dynamics.start_grid`` = 10 on the N = 14 diaphragm-fill: the start is the N = 10
    start carried and polished (the shell model), then settled by the run's XPBD substeps:
    it converges, holds the start volume, and is another equilibrium than N = 14's own start;
    start_grid = grid_size is the own start, bit for bit."""
    from fsi.procedures.coupled_fill import membrane_settings, static_start
    from structure.volume import liquid_volume
    from structure.xpbd import XpbdModel

    def start(keys):
        setup = build(load_scene("diaphragm-fill").with_keys(keys))
        state, info = static_start(setup, XpbdModel.from_membrane(setup.model),
                                   membrane_settings(setup))
        return setup, state, info

    setup, own, own_info = start({})
    _, same, _ = start({"dynamics": {"start_grid": 14}})
    np.testing.assert_array_equal(same.node_position, own.node_position)
    _, carried, info = start({"dynamics": {"start_grid": 10}})
    assert info.converged
    volume = liquid_volume(setup.model, own.node_position)
    assert abs(liquid_volume(setup.model, carried.node_position) - volume) <= 1e-6 * volume
    moved = np.linalg.norm(carried.node_position - own.node_position, axis=1).max()
    assert moved > 1e-3, moved  # m: another fold state than the own start's


def test_a_polish_that_does_not_converge_is_settled_and_tried_again(monkeypatch):
    """:func:`fsi.setup.carried_start.polish`: a first minimum that converges is returned as it is
    and ``settle`` is not called; one that does not is followed by ``settle`` from the
    carried state and a second minimum from the settled state and its level."""
    import fsi.setup.carried_start as cs
    from structure.load import Equilibrium
    from structure.model import MembraneState

    setup = build(load_scene("diaphragm-fill"))
    x = setup.model.node_rest_position
    calls, settled = [], []

    def minimum(converged_first):
        def solve(shell, state, load, settings):
            calls.append((state.node_position.copy(), load.pressure_level))
            ok = converged_first or len(calls) > 1
            return state, Equilibrium(1, ok, 10.0 * len(calls), 0.0, force_ratio=0.0)
        return solve

    def settle(state, level):
        settled.append(level)
        return MembraneState(state.node_position + 1e-3), Equilibrium(1, False, 77.0, 0.0)

    monkeypatch.setattr(cs, "solve_equilibrium", minimum(True))
    _, info = cs.polish(setup, x, 0.01, 5.0, settle)
    assert info.converged and len(calls) == 1 and not settled
    calls.clear()
    monkeypatch.setattr(cs, "solve_equilibrium", minimum(False))
    state, info = cs.polish(setup, x, 0.01, 5.0, settle)
    assert settled == [5.0] and len(calls) == 2 and info.converged
    np.testing.assert_array_equal(calls[1][0], x + 1e-3)  # from the settled state
    assert calls[1][1] == 77.0                             # and its level


@pytest.mark.parametrize("keys, match", [
    ({"slosh": {"start_grid": 12}}, "from 4 to membrane.grid_size = 10"),
    ({"slosh": {"start_grid": 6}, "membrane": {"wrinkling": "tension-field"}},
     "no tension field"),
])
def test_a_slosh_start_grid_the_diaphragm_cannot_use_is_refused_by_name(keys, match):
    keys = {**keys, "membrane": {"grid_size": 10, **keys.get("membrane", {})}}
    with pytest.raises(SceneError, match=r"slosh\.start_grid") as err:
        build(load_scene("slosh-diaphragm").with_keys(keys))
    assert match in str(err.value)


@pytest.mark.slow
def test_the_slosh_start_carried_from_a_coarser_grid_is_at_rest_and_holds_its_volume():
    """``slosh.start_grid`` = 6 on the N = 10 slosh-diaphragm: the start is the N = 6 start
    carried, polished and settled at the windows' substep: it converges, holds the tank
    fraction's volume, and is another equilibrium than N = 10's own (measured: 26 mm apart,
    levels 2881 and 2391 Pa)."""
    from fsi.procedures.slosh_diaphragm import static_start
    from structure.volume import liquid_volume

    def start(keys):
        setup = build(load_scene("slosh-diaphragm").with_keys(
            {"membrane": {"grid_size": 10}, **keys}))
        return setup, static_start(setup, setup.scene["slosh"]["window"])

    setup, own = start({})
    _, carried = start({"slosh": {"start_grid": 6}})
    assert carried.info.converged
    volume = liquid_volume(setup.model, carried.state.node_position)
    assert abs(volume - carried.volume) <= 1e-6 * carried.volume
    moved = np.linalg.norm(carried.state.node_position - own.state.node_position, axis=1)
    assert moved.max() > 1e-3, moved.max()


def test_a_start_carried_by_the_minimisation_is_polished_by_it_in_the_runs_own_law(
        monkeypatch):
    """``slosh.start_solver = "minimisation"`` with ``slosh.start_grid`` = 10 on N = 14: the
    N = 10 minimisation start carried here is polished by the minimisation statics in the
    run's law, not by the shell model: it converges (force ratio within the minimisation's
    test) at the start's volume with every free node inside the wall, and moves from the
    carried state (it is not the carried state returned); the relaxation's start keeps the
    shell's polish, and the tension field, which the shell lacks, is allowed with the
    minimisation's."""
    import fsi.setup.carried_start as cs
    from fsi.setup.static_start import START_SOLVERS, carried_polish
    from structure.volume import liquid_volume, tank_volume
    from structure.xpbd import XpbdModel

    keys = {"membrane": {"grid_size": 14}, "slosh": {"start_solver": "minimisation",
                                                     "start_grid": 10}}
    setup = build(load_scene("slosh-diaphragm").with_keys(keys))
    volume = setup.scene["slosh"]["fill"] * tank_volume(setup.model.radius)
    coarse_start = {}

    def relax(coarse):
        start = START_SOLVERS["minimisation"].solve(
            coarse, XpbdModel.from_membrane(coarse.model), None, volume)
        coarse_start["x"] = prolong(coarse.model, start[0].node_position, setup.model)
        return start

    def no_shell(*args, **kwargs):
        raise AssertionError("the shell polished a minimisation start")

    monkeypatch.setattr(cs, "polish", no_shell)
    xpbd = XpbdModel.from_membrane(setup.model)
    state, info = cs.carried_start(setup, 10, volume, relax, None,
                                   carried_polish(setup, xpbd, "minimisation", volume))
    assert info.converged and info.force_ratio <= 1e-6
    assert abs(liquid_volume(setup.model, state.node_position) - volume) <= 1e-8 * volume
    free = ~setup.model.node_fixed
    assert np.all(np.linalg.norm(state.node_position[free], axis=1) < setup.model.radius)
    assert np.linalg.norm(state.node_position - coarse_start["x"], axis=1).max() > 1e-3
    assert carried_polish(setup, xpbd, "relaxation", volume) is None
    build(load_scene("slosh-diaphragm").with_keys(
        {**keys, "membrane": {"grid_size": 14, "wrinkling": "tension-field"}}))
