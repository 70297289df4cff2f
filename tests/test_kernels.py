"""numba kernels: self-collision by spatial hash (App. I), on-disk compile cache."""
import subprocess
import sys

import numpy as np

from structure.kernels import self_collision, wall_collision


def test_self_collision_separates_non_neighbours_only(model10):
    n = 10
    pos = model10.node_rest_position.copy()
    a, b = 3 * n + 4, 6 * n + 5  # far apart on the grid
    pos[b] = pos[a] + np.array([0.0, 0.0, 1e-4])
    d_min = 0.5 * model10.min_rest_edge
    before = pos.copy()
    pairs = self_collision(pos, model10.node_inv_mass, n, d_min)
    assert pairs == 1
    assert abs(np.linalg.norm(pos[b] - pos[a]) - d_min) < 1e-12
    moved = np.flatnonzero(np.any(pos != before, axis=1))
    assert set(moved) == {a, b}
    # a grid neighbour closer than d_min is left alone (the thesis's six-neighbour exclusion)
    pos = model10.node_rest_position.copy()
    pos[a + 1] = pos[a] + np.array([0.0, 0.0, 1e-4])
    assert self_collision(pos, model10.node_inv_mass, n, d_min) == 0


def test_self_collision_matches_brute_force_pair_count(model10):
    rng = np.random.default_rng(5)
    pos = model10.node_rest_position + rng.normal(scale=0.02, size=(100, 3))
    d_min = model10.min_rest_edge
    n = 10
    expected = 0
    for a in range(100):
        for b in range(a + 1, 100):
            di, dj = b // n - a // n, b % n - a % n
            if (di == 0 and abs(dj) <= 1) or (dj == 0 and abs(di) <= 1) or (di == dj and abs(di) == 1):
                continue
            if model10.node_inv_mass[a] + model10.node_inv_mass[b] == 0:
                continue
            if np.linalg.norm(pos[b] - pos[a]) < d_min:
                expected += 1
    assert self_collision(pos.copy(), model10.node_inv_mass, n, d_min) == expected


def test_wall_collision_puts_free_nodes_back_on_sphere(model10):
    pos = model10.node_rest_position * 1.01
    wall_collision(pos, model10.node_inv_mass, model10.radius, 1.001)
    free = ~model10.node_fixed
    assert np.allclose(np.linalg.norm(pos[free], axis=1), model10.radius, rtol=1e-14)


def test_second_process_loads_compiled_kernels_from_cache():
    code = ("import numpy as np\n"
            "from structure import kernels as k\n"
            "p = np.zeros((16, 3)); p[:, 0] = np.arange(16)\n"
            "k.wall_collision(p, np.ones(16), 1.0, 1.001)\n"
            "s = k.wall_collision.stats\n"
            "print(sum(s.cache_hits.values()), sum(s.cache_misses.values()))\n")
    out = None
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             check=True).stdout.split()
    hits, misses = map(int, out)
    assert hits >= 1 and misses == 0
