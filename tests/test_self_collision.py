"""Folding without interpenetration (thesis App. I self-collision by spatial hash) at 50 % fill.

Oracle: the collision distance itself, d = collision_buffer x the shortest rest edge (App. I's
Cbuffer): with self-collision on, no two non-neighbouring nodes (grid indices more than one
apart in i or j, App. I's exclusion) may end closer than d.  Without it the folds
interpenetrate, which the second case measures so that the first cannot pass vacuously.
"""
import numpy as np
from scipy.spatial import cKDTree

from fsi.setup.build import build
from fsi.setup.fill import full_inversion
from fsi.scene import parse_scene
from structure.load import Load
from structure.model import MembraneState
from structure.statics import solve_equilibrium

GRID, BUFFER = 20, 0.2  # d = 4.4 mm, 2.5 membrane thicknesses


def _closest_non_neighbours(self_collision: bool) -> float:
    setup = build(parse_scene(
        f"[structure]\nmodel = 'thesis'\n[membrane]\ngrid_size = {GRID}\n"
        f"[constraints]\nself_collision = {str(self_collision).lower()}\n"
        f"collision_buffer = {BUFFER}\n"))
    model = setup.model
    target = float(full_inversion(setup).scale.volume(0.5))
    state, info = solve_equilibrium(model, MembraneState(model.node_rest_position),
                                    Load(setup.liquid.pressure, setup.liquid.body_acceleration,
                                         volume_target=target), setup.relaxation)
    assert info.converged
    x = state.node_position
    d = BUFFER * model.min_rest_edge
    i, j = np.divmod(np.arange(model.n_nodes), GRID)
    pairs = cKDTree(x).query_pairs(1.5 * d, output_type="ndarray")
    apart = (np.abs(i[pairs[:, 0]] - i[pairs[:, 1]]) > 1) | (np.abs(j[pairs[:, 0]]
                                                                    - j[pairs[:, 1]]) > 1)
    pairs = pairs[apart]
    if len(pairs) == 0:
        return np.inf
    return float(np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1).min() / d)


def test_no_non_neighbours_closer_than_the_collision_distance_at_half_fill():
    assert _closest_non_neighbours(True) >= 1.0 - 1e-4


def test_without_self_collision_the_folds_interpenetrate():
    assert _closest_non_neighbours(False) < 0.9
