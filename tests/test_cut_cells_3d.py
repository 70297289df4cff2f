"""The 3-D cut-cell fractions (fluid.cutcell.cell_fractions_3d) where two planes cut a box.

Oracle: a plane is linear on every Kuhn tetrahedron, so the lattice's piecewise-linear
level sets are the planes themselves and each cell's liquid fraction is the exact volume of
box ∩ {a < 0} ∩ {b < 0}: the convex polytope that SciPy's half-space intersection (Qhull)
builds, its volume by ConvexHull. The closed forms of fluid.cutcell (:func:`_tet_fraction`,
:func:`_tet_fraction2`) must reproduce it for every way the planes cut the six tetrahedra.
"""
import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection

from fluid.cutcell import cell_fractions_3d

SPACING = (0.5, 0.25, 0.4)  # m, a box that is not a cube


def _polytope_volume(halfspaces: np.ndarray) -> float:
    """Volume of {x: A x + c <= 0} (rows [A, c]); 0 where it has no interior."""
    norm = np.linalg.norm(halfspaces[:, :3], axis=1)
    # Chebyshev centre: the deepest interior point (linprog maximises its radius r)
    res = linprog(c=[0, 0, 0, -1], A_ub=np.column_stack([halfspaces[:, :3], norm]),
                  b_ub=-halfspaces[:, 3], bounds=[(None, None)] * 3 + [(0, None)])
    if not res.success or res.x[3] < 1e-9:
        return 0.0
    vertices = HalfspaceIntersection(halfspaces, res.x[:3]).intersections
    return ConvexHull(vertices).volume


def _box_halfspaces(lo, hi):
    rows = []
    for axis in range(3):
        e = np.zeros(3)
        e[axis] = 1.0
        rows.append(np.append(-e, lo[axis]))   # x >= lo
        rows.append(np.append(e, -hi[axis]))   # x <= hi
    return np.array(rows)


@pytest.mark.parametrize("seed", range(2))
def test_two_planes_cut_each_cell_to_its_exact_volume(seed):
    rng = np.random.default_rng(seed)
    axes = [np.arange(4) * h for h in SPACING]  # 3 x 3 x 3 cells
    centre = np.array([a[-1] / 2 for a in axes])
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    worst, cut = 0.0, 0
    for _ in range(4):
        planes = []
        for _ in range(2):
            normal = rng.normal(size=3)
            normal /= np.linalg.norm(normal)
            # through a point near the middle, so that both planes cut several cells
            offset = -normal @ (centre + rng.uniform(-0.3, 0.3, 3))
            planes.append((normal, offset))
        phi_a, phi_b = ((grid @ n) + c for n, c in planes)
        fractions = cell_fractions_3d(*axes, phi_a, phi_b)
        for i, j, k in np.ndindex(fractions.shape):
            lo = np.array([axes[0][i], axes[1][j], axes[2][k]])
            hi = lo + SPACING
            halfspaces = np.vstack([_box_halfspaces(lo, hi)]
                                   + [np.append(n, c)[None, :] for n, c in planes])
            exact = _polytope_volume(halfspaces) / np.prod(SPACING)
            worst = max(worst, abs(fractions[i, j, k] - exact))
            cut += 0.0 < exact < 1.0
    assert cut > 40  # the planes cut many cells, in every arrangement
    assert worst < 1e-12  # measured 5.6e-16: the closed forms agree with Qhull to round-off
