"""Membrane Model (fixed data) and State (evolving data) of the thesis particle membrane.

The Model holds what never changes during a run: rest positions, node masses (Eqn 4.3 with the
node areas of App. D), which nodes are fixed, and the rest-length maps of App. E for the axial,
shear and bending springs.  The State holds positions and velocities.  Steppers take a Model and
a State and return a new State (warp.sim's split).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from . import grid as grid_mod
from .kernels import node_area_and_normal

SUPPORTS = {"clamped": 2, "simply-supported": 1}
"""Support type -> number of outer grid rings held fixed (App. B ``SupportType`` 1 and 2)."""

SPRING_FAMILIES = ("axial-x", "axial-y", "shear-positive", "shear-negative")
"""In-plane spring families in the order App. G relaxes them."""


@dataclass(frozen=True)
class Material:
    """Membrane material and section.

    thickness : m; density : kg/m^3; youngs_modulus : Pa; poisson_ratio : - (used by plate
    checks only; the thesis particle model has no Poisson effect); wrinkling : "none" or
    "tension-field" (the XPBD membrane carries no compression, :mod:`structure.xpbd`).
    """

    thickness: float
    density: float
    youngs_modulus: float
    poisson_ratio: float = 0.5
    wrinkling: str = "none"

    @property
    def flexural_rigidity(self) -> float:
        """Plate flexural rigidity D = E t^3 / (12 (1 - nu^2)) (N m), thesis Eqn 3.1."""
        return self.youngs_modulus * self.thickness**3 / (12.0 * (1.0 - self.poisson_ratio**2))


@dataclass(frozen=True)
class MembraneModel:
    """Fixed data of a structured N x N particle membrane.

    Its attributes (n = N*N nodes):

    * grid_size : N.
    * radius : tank / hemisphere radius (m) (disc radius for flat grids).
    * material : :class:`Material`.
    * node_rest_position : (n, 3) m.
    * node_mass : (n,) kg, rho t A_node (Eqn 4.3) with A_node of App. D at rest.
    * node_inv_mass : (n,) 1/kg, zero on fixed nodes.
    * node_fixed : (n,) bool.
    * node_length_scale : (n,) m, sqrt(A_node), the Courant length of Eqn 4.7.
    * face_nodes : (n_faces, 4) int64 quads.
    * spring_nodes : (m, 2) int64, in-plane springs, families concatenated in App. G order.
    * spring_rest_length : (m,) m.
    * spring_family_start : (5,) int64 offsets of the families in ``spring_nodes``.
    * bend_nodes : (b, 3) int64, (end, middle, end) node triples spanning two cells (App. E).
    * bend_rest_length : (b,) m, rest chord L_B between the two end nodes.
    * bend_family_start : (3,) int64 offsets of the x and y bending families.
    * bend_stiffness : (b,) N/m, K_eq = 48 E I / L_B^3 with I = L t^3 / 12, i.e. 4 E t^3 / L_B^2
      (Eqns 4.8-4.10, App. F).
    * normal_sign : +1 or -1 so that node normals point from the liquid side (rest shape: the
      outer, convex side) to the gas side (towards the sphere centre).
    * volume_sign : +1 or -1 so that the membrane's divergence-theorem volume term uses normals
      pointing out of the liquid (see :mod:`structure.volume`).
    """

    grid_size: int
    radius: float
    material: Material
    node_rest_position: np.ndarray
    node_mass: np.ndarray
    node_inv_mass: np.ndarray
    node_fixed: np.ndarray
    node_length_scale: np.ndarray
    face_nodes: np.ndarray
    spring_nodes: np.ndarray
    spring_rest_length: np.ndarray
    spring_family_start: np.ndarray
    bend_nodes: np.ndarray
    bend_rest_length: np.ndarray
    bend_family_start: np.ndarray
    bend_stiffness: np.ndarray
    normal_sign: float = 1.0
    volume_sign: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "_node_free_mass",
                           np.where(self.node_fixed, 0.0, self.node_mass))
        object.__setattr__(self, "_bend_chord_nodes",
                           np.ascontiguousarray(self.bend_nodes[:, [0, 2]]))

    @property
    def n_nodes(self) -> int:
        return self.node_rest_position.shape[0]

    @property
    def node_free_mass(self) -> np.ndarray:
        """(n,) kg: node mass, zero on fixed nodes (App. B's ``Mcorrected``)."""
        return self._node_free_mass

    @property
    def bend_chord_nodes(self) -> np.ndarray:
        """(b, 2) int64: the end nodes of each bending triple (App. H's chords)."""
        return self._bend_chord_nodes

    @property
    def total_rest_length(self) -> float:
        """Sum of in-plane rest lengths (m), App. E's ``Totaldist``."""
        return float(self.spring_rest_length.sum())

    @property
    def min_rest_edge(self) -> float:
        """Shortest axial rest edge (m); App. I's collision distance for ``Cbuffer = 1``."""
        axial = self.spring_rest_length[: self.spring_family_start[2]]
        return float(axial.min())


@dataclass
class MembraneState:
    """Evolving data: node_position (n, 3) m and node_velocity (n, 3) m/s."""

    node_position: np.ndarray
    node_velocity: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __post_init__(self):
        self.node_position = np.array(self.node_position, dtype=np.float64, order="C")
        if self.node_velocity is None:
            self.node_velocity = np.zeros_like(self.node_position)
        else:
            self.node_velocity = np.array(self.node_velocity, dtype=np.float64, order="C")

    def copy(self) -> "MembraneState":
        return replace(self, node_position=self.node_position.copy(),
                       node_velocity=self.node_velocity.copy())


def _pairs(grid_size: int, di: int, dj: int) -> np.ndarray:
    """Node pairs (i,j)-(i+di, j+dj) inside the grid, thesis loop order (i outer, j inner)."""
    n = grid_size
    out = []
    for i in range(n):
        for j in range(n):
            i2, j2 = i + di, j + dj
            if 0 <= i2 < n and 0 <= j2 < n:
                out.append((i * n + j, i2 * n + j2))
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)


def build_model(node_rest_position: np.ndarray, grid_size: int, radius: float,
                material: Material, support: str = "clamped") -> MembraneModel:
    """Build the fixed Model from rest positions (n, 3) m of an N x N structured grid.

    ``support`` is ``"clamped"`` (two outer rings fixed) or ``"simply-supported"`` (one ring).
    """
    if support not in SUPPORTS:
        raise ValueError(f"support must be one of {sorted(SUPPORTS)}, got {support!r}")
    pos = np.ascontiguousarray(node_rest_position, dtype=np.float64)
    n = grid_size
    if pos.shape != (n * n, 3):
        raise ValueError(f"node_rest_position must have shape ({n * n}, 3), got {pos.shape}")
    fixed = np.zeros(n * n, dtype=bool)
    for depth in range(SUPPORTS[support]):
        fixed[grid_mod.boundary_ring(n, depth)] = True

    # in-plane springs in App. G order: X (j+1), Y (i+1), positive shear, negative shear
    fams = [_pairs(n, 0, 1), _pairs(n, 1, 0), _pairs(n, 1, 1), _pairs(n, -1, 1)]
    spring_nodes = np.concatenate(fams)
    start = np.cumsum([0] + [len(f) for f in fams]).astype(np.int64)
    rest = np.linalg.norm(pos[spring_nodes[:, 1]] - pos[spring_nodes[:, 0]], axis=1)

    bx, by = _pairs(n, 0, 2), _pairs(n, 2, 0)
    mid_x = bx[:, 0] + 1
    mid_y = by[:, 0] + n
    bend_nodes = np.concatenate([np.stack([bx[:, 0], mid_x, bx[:, 1]], axis=1),
                                 np.stack([by[:, 0], mid_y, by[:, 1]], axis=1)])
    bend_start = np.array([0, len(bx), len(bx) + len(by)], dtype=np.int64)
    bend_rest = np.linalg.norm(pos[bend_nodes[:, 2]] - pos[bend_nodes[:, 0]], axis=1)
    E, t = material.youngs_modulus, material.thickness
    bend_k = 48.0 * E * (t**3 / 12.0) / bend_rest**2

    area, normal = node_area_and_normal(pos, n, 1.0)
    # orient normals towards the gas side: the centre of curvature for the hemisphere, +z for
    # a flat disc
    centre = np.array([0.0, 0.0, 0.0]) if np.ptp(pos[:, 2]) > 0 else np.array([0, 0, 1e9])
    inward = np.sum(normal * (centre - pos), axis=1)
    sign = 1.0 if np.median(inward) > 0 else -1.0

    # triangle (p0, p1, p2) of the first quad: right-hand normal against the oriented node normal
    q = grid_mod.quad_faces(n)[0]
    tri_normal = np.cross(pos[q[1]] - pos[q[0]], pos[q[2]] - pos[q[0]])
    volume_sign = 1.0 if tri_normal @ (sign * normal[q[0]]) > 0 else -1.0

    mass = material.density * t * area
    inv_mass = np.where(fixed, 0.0, 1.0 / mass)
    return MembraneModel(
        grid_size=n, radius=float(radius), material=material,
        node_rest_position=pos, node_mass=mass, node_inv_mass=inv_mass, node_fixed=fixed,
        node_length_scale=np.sqrt(area), face_nodes=grid_mod.quad_faces(n),
        spring_nodes=spring_nodes, spring_rest_length=rest, spring_family_start=start,
        bend_nodes=bend_nodes, bend_rest_length=bend_rest, bend_family_start=bend_start,
        bend_stiffness=bend_k, normal_sign=sign, volume_sign=volume_sign,
    )


def hemisphere_model(grid_size: int, radius: float, material: Material,
                     support: str = "clamped",
                     grading: grid_mod.Grading = grid_mod.Grading()) -> MembraneModel:
    """Model of the thesis hemisphere (App. C grid, ``grading`` as
    :class:`structure.grid.Grading`) with the given support."""
    return build_model(grid_mod.hemisphere_grid(grid_size, radius, grading), grid_size, radius,
                       material, support)


def disc_model(grid_size: int, radius: float, material: Material,
               support: str = "clamped",
               grading: grid_mod.Grading = grid_mod.Grading()) -> MembraneModel:
    """Model of a flat disc of the given radius (m) in z = 0 (plate checks; ``grading`` as
    :func:`structure.grid.disc_grid`)."""
    return build_model(grid_mod.disc_grid(grid_size, radius, grading), grid_size, radius,
                       material, support)


MEMBRANE_SHAPES = {"hemisphere": hemisphere_model, "disc": disc_model}
"""Rest shape -> ``f(grid_size, radius, material, support, grading)`` ->
:class:`MembraneModel`: the
thesis's hemisphere against the lower tank wall, or a flat disc across the equator (the
thesis's Ch. 3 flat diaphragm; liquid below it fills the lower hemisphere at rest)."""
