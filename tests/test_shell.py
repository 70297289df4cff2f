"""Static shell model (structure/shell.py): the liquid's potential reproduces the thesis load.

Oracle: a stationary point of Pi = W - rho b . M1 - p_ref (V - V*) is the equilibrium of the
hydrostatic pressure p = p_ref + rho b . x on the membrane (thesis Eqn 4.5): moving node i of a
flat triangle by d sweeps liquid whose potential changes by -(d . A n) (2 p_i + p_j + p_k) / 12
for the linear p, so d(-rho b . M1)/dx_i must equal minus the consistent load
sum_T (A n)_T (2 p_i + p_j + p_k) / 12 exactly, for any shape.
"""
import numpy as np
import pytest

from fsi.setup.build import build
from fsi.setup.models import STRUCTURE_MODELS
from fsi.scene import parse_scene
from structure.grid import triangles_from_quads
from structure.load import Load
from structure.model import MembraneState
from structure.shell import ShellModel, ShellSettings, first_moment, solve_equilibrium


@pytest.fixture(scope="module")
def setup():
    return build(parse_scene("[structure]\nmodel = 'shell'\n[membrane]\ngrid_size = 8\n"))


def _shape(setup):
    rng = np.random.default_rng(3)
    return setup.model.node_rest_position + 0.01 * rng.normal(size=(setup.model.n_nodes, 3))


def test_first_moment_gradient_matches_finite_differences(setup):
    x, faces, sign = _shape(setup), setup.model.face_nodes, setup.model.volume_sign
    _, grad = first_moment(x, faces, sign)
    for node in (0, 17, 40, 63):
        for r in range(3):
            step = np.zeros_like(x)
            step[node, r] = 1e-7
            fd = (first_moment(x + step, faces, sign)[0]
                  - first_moment(x - step, faces, sign)[0]) / 2e-7
            assert np.allclose(fd, grad[node, r], rtol=1e-6, atol=1e-12)


def test_liquid_potential_gives_the_hydrostatic_load(setup):
    x, model, liquid = _shape(setup), setup.model, setup.liquid
    body = np.asarray(liquid.body_acceleration)
    _, gm1 = first_moment(x, model.face_nodes, model.volume_sign)
    from_energy = -liquid.density * (gm1 @ body)
    p = liquid.pressure(x)
    load = np.zeros_like(x)
    for tri in triangles_from_quads(model.face_nodes):
        area_vector = 0.5 * model.volume_sign * np.cross(x[tri[1]] - x[tri[0]],
                                                         x[tri[2]] - x[tri[0]])
        for i in range(3):
            load[tri[i]] += area_vector * (p[tri].sum() + p[tri[i]]) / 12.0
    free = ~model.node_fixed  # the rim closes the surface; only free nodes move
    assert np.abs(from_energy + load)[free].max() <= 1e-9 * np.abs(load[free]).max()


@pytest.mark.parametrize("law", ["saint-venant-kirchhoff", "neo-hookean"])
def test_equilibrium_holds_the_volume_and_balances_forces(setup, law):
    settings = ShellSettings(law=law)
    model = ShellModel.from_membrane(setup.model, settings)
    tank = 4.0 / 3.0 * np.pi * setup.model.radius**3
    load = Load(setup.liquid.pressure, setup.liquid.body_acceleration, volume_target=0.3 * tank,
                liquid_density=setup.liquid.density)
    state, info = solve_equilibrium(model, MembraneState(setup.model.node_rest_position), load,
                                    settings)
    assert info.converged
    assert info.liquid_volume == pytest.approx(0.3 * tank, rel=1e-5)
    assert info.force_ratio < 1e-3


@pytest.mark.parametrize("name", sorted(STRUCTURE_MODELS))
def test_every_model_runs_a_volume_sweep(name):
    """The thesis model needs N = 20 here: at N <= 14 every free node of its rest shape lies
    on the wall and its relaxation holds them there (docs/validation/membrane.md, 'Speed
    against accuracy, grid convergence')."""
    from fsi.procedures import PROCEDURES

    grid = 20 if name == "thesis" else 10
    scene = parse_scene(f"[structure]\nmodel = '{name}'\n[membrane]\ngrid_size = {grid}\n"
                        "[sweep]\nfills = [0.0, 0.3]\ndrain = false\n"
                        "scale = 'full-inversion'\n")
    result = PROCEDURES["volume-sweep"](build(scene), lambda f, m: None)
    frames = result.groups["frames"]
    assert result.attrs["structure_model"] == name
    assert np.allclose(frames["inversion_fraction"], [0.0, 0.3], atol=1e-3)
    assert frames["converged"].all()
