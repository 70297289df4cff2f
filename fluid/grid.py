"""Fixed tank grids: a FiPy mesh plus the structured lattice behind it.

Two kinds, both uniform with square (cubic) cells:

- axisymmetric: FiPy ``CylindricalGrid2D`` over r in [0, Lr], z in [z0, z0 + Lz] (axes r, z);
  FiPy measures cell volumes as r dr dz and face areas as r ds (per radian);
- cartesian: FiPy ``Grid3D`` over a box (axes x, y, z).

The vertical (gravity) axis is z: axis 1 of the axisymmetric grid, axis 2 of the 3-D grid.
Lattice arrays (level sets, fractions) are indexed [i, j(, k)]; the maps below take them to
FiPy's cell and face numbering without assuming that numbering.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import fipy as fp
import numpy as np


@dataclass(eq=False)
class TankGrid:
    """A uniform FiPy grid and its lattice maps.

    lower: (dim,) m, lattice origin; spacing: m, cell size (equal on every axis);
    shape: (dim,) cells per axis; axisymmetric: r-z grid (dim 2) or 3-D box (dim 3).
    """

    lower: tuple
    spacing: float
    shape: tuple
    axisymmetric: bool

    def __post_init__(self):
        dim = 2 if self.axisymmetric else 3
        if len(self.shape) != dim or len(self.lower) != dim:
            raise ValueError(f"{'axisymmetric' if self.axisymmetric else 'cartesian'} grid "
                             f"needs {dim} cell counts and lower corner, got shape={self.shape}, "
                             f"lower={self.lower}")
        if min(self.shape) < 2:
            raise ValueError(f"grid shape must have >= 2 cells per axis, got {self.shape}")
        if not self.spacing > 0:
            raise ValueError(f"grid spacing must be > 0 m, got {self.spacing}")
        h = float(self.spacing)
        if self.axisymmetric:
            if self.lower[0] != 0.0:
                raise ValueError("an axisymmetric grid starts at r = 0 (lower[0] must be 0)")
            self.mesh = fp.CylindricalGrid2D(dr=h, dz=h, nr=self.shape[0], nz=self.shape[1],
                                             origin=((0.0,), (float(self.lower[1]),)))
        else:
            nx, ny, nz = self.shape
            self.mesh = fp.Grid3D(dx=h, dy=h, dz=h, nx=nx, ny=ny, nz=nz) + \
                tuple((float(v),) for v in self.lower)
        self._build_maps()

    @property
    def dim(self) -> int:
        return len(self.shape)

    @property
    def vertical_axis(self) -> int:
        """Index of the z axis (gravity direction of an upright tank)."""
        return self.dim - 1

    @property
    def n_cells(self) -> int:
        return int(self.mesh.numberOfCells)

    @property
    def n_faces(self) -> int:
        return int(self.mesh.numberOfFaces)

    @cached_property
    def vertex_axes(self) -> tuple:
        """Vertex coordinates per axis, ((shape[a] + 1),) m each."""
        return tuple(self.lower[a] + self.spacing * np.arange(self.shape[a] + 1)
                     for a in range(self.dim))

    @cached_property
    def centre_axes(self) -> tuple:
        """Cell-centre coordinates per axis, (shape[a],) m each."""
        return tuple(self.lower[a] + self.spacing * (np.arange(self.shape[a]) + 0.5)
                     for a in range(self.dim))

    @cached_property
    def face_above(self) -> np.ndarray:
        """(n_faces,) the face of the same axis one cell up (+z) from each face; -1 where
        there is none (the grid's top face, the side faces of its top layer of cells)."""
        up = self.vertical_axis
        out = np.full(self.n_faces, -1, dtype=np.int64)
        for a in range(self.dim):
            sel = np.flatnonzero(self.face_axis == a)
            shape = list(self.shape)
            shape[a] += 1
            lookup = np.full(int(np.prod(shape)), -1, dtype=np.int64)
            lookup[self.face_lattice[sel]] = sel
            index = self.face_index[sel].copy()
            index[:, up] += 1
            inside = index[:, up] < shape[up]
            index[~inside] = 0
            out[sel] = np.where(inside, lookup[np.ravel_multi_index(tuple(index.T), shape)], -1)
        return out

    @cached_property
    def face_below(self) -> np.ndarray:
        """(n_faces,) the face of the same axis one cell down (-z) from each face; -1 where
        there is none (the inverse of :attr:`face_above`)."""
        above = self.face_above
        out = np.full(self.n_faces, -1, dtype=np.int64)
        has = above >= 0
        out[above[has]] = np.flatnonzero(has)
        return out

    def _build_maps(self):
        mesh, h, dim = self.mesh, self.spacing, self.dim
        lower = np.asarray(self.lower, dtype=float)
        centres = np.asarray(mesh.cellCenters).T  # (n_cells, dim)
        idx = np.floor((centres - lower) / h).astype(np.int64)
        #: (n_cells,) index of each FiPy cell in the C-order ravel of a lattice cell array
        self.cell_lattice = np.ravel_multi_index(tuple(idx.T), self.shape)
        #: (n_cells, dim) lattice index of each FiPy cell
        self.cell_index = idx
        normals = np.asarray(mesh.faceNormals).T  # (n_faces, dim)
        self.face_axis = np.argmax(np.abs(normals), axis=1)
        #: sign of FiPy's face normal along its axis (+1 / -1)
        self.face_sign = np.sign(normals[np.arange(len(normals)), self.face_axis])
        fc = np.asarray(mesh.faceCenters).T
        self.face_index = np.empty((self.n_faces, dim), dtype=np.int64)
        self.face_lattice = np.empty(self.n_faces, dtype=np.int64)
        for a in range(dim):
            sel = self.face_axis == a
            shape = list(self.shape)
            shape[a] += 1
            fidx = np.empty((sel.sum(), dim), dtype=np.int64)
            for b in range(dim):
                if b == a:
                    fidx[:, b] = np.rint((fc[sel, b] - lower[b]) / h)
                else:
                    fidx[:, b] = np.floor((fc[sel, b] - lower[b]) / h)
            self.face_index[sel] = fidx
            self.face_lattice[sel] = np.ravel_multi_index(tuple(fidx.T), tuple(shape))
        ids = np.asarray(mesh.faceCellIDs.filled(-1)) if np.ma.isMaskedArray(mesh.faceCellIDs) \
            else np.asarray(mesh.faceCellIDs)
        #: (2, n_faces) adjacent cells, -1 where the face is on the grid boundary
        self.face_cells = np.where(np.ma.getmaskarray(mesh.faceCellIDs), -1, ids)
        self.exterior = np.asarray(mesh.exteriorFaces, dtype=bool)
        self.face_area = np.asarray(mesh._faceAreas, dtype=float)
        self.face_distance = np.asarray(mesh._cellDistances, dtype=float)
        self.cell_volume = np.asarray(mesh.cellVolumes, dtype=float)
        self.cell_centre = centres
        self.face_centre = fc

    @cached_property
    def lattice_cell(self) -> np.ndarray:
        """(prod(shape),) the FiPy cell at each C-order lattice position (the inverse of
        :attr:`cell_lattice`)."""
        out = np.full(int(np.prod(self.shape)), -1, dtype=np.int64)
        out[self.cell_lattice] = np.arange(len(self.cell_lattice))
        return out

    def cell_of(self, points: np.ndarray) -> np.ndarray:
        """The cell (n,) holding each of ``points`` (n, 3) m, -1 outside the grid; on an
        axisymmetric grid a point (x, y, z) is taken at (hypot(x, y), z)."""
        points = np.asarray(points, dtype=float)
        coords = np.stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]], axis=1) \
            if self.axisymmetric else points
        idx = np.floor((coords - np.asarray(self.lower)) / self.spacing).astype(np.int64)
        inside = np.all((idx >= 0) & (idx < np.asarray(self.shape)), axis=1)
        out = np.full(len(points), -1, dtype=np.int64)
        out[inside] = self.lattice_cell[np.ravel_multi_index(tuple(idx[inside].T), self.shape)]
        return out

    def lattice_to_cells(self, values: np.ndarray) -> np.ndarray:
        """(shape) lattice cell array -> (n_cells,) in FiPy order."""
        return np.asarray(values).reshape(-1)[self.cell_lattice]

    def lattice_to_faces(self, per_axis: tuple) -> np.ndarray:
        """Per-axis face lattice arrays (axis a has shape[a] + 1 along a) -> (n_faces,)."""
        out = np.empty(self.n_faces)
        for a in range(self.dim):
            sel = self.face_axis == a
            out[sel] = np.asarray(per_axis[a]).reshape(-1)[self.face_lattice[sel]]
        return out

    def volume_factor(self) -> float:
        """Multiply FiPy volumes/areas by this to get m^3 / m^2 (2 pi for axisymmetric)."""
        return 2.0 * np.pi if self.axisymmetric else 1.0

    def boundary_faces(self, side: str) -> np.ndarray:
        """Exterior faces on one side of the box: 'bottom' / 'top' (z), 'axis'/'outer' (r) ..."""
        sides = {"bottom": (self.vertical_axis, 0), "top": (self.vertical_axis, 1)}
        if side not in sides:
            raise ValueError(f"port side must be one of {sorted(sides)}, got {side!r}")
        axis, upper = sides[side]
        value = self.lower[axis] + (self.shape[axis] * self.spacing if upper else 0.0)
        return self.exterior & (self.face_axis == axis) & \
            np.isclose(self.face_centre[:, axis], value, atol=1e-9 * self.spacing)


def axisymmetric_grid(r_max: float, z_min: float, z_max: float, n_r: int) -> TankGrid:
    """Axisymmetric grid with ``n_r`` square cells over r in [0, r_max] and as many as fit
    over [z_min, z_max] (the top is moved up to a whole cell)."""
    h = r_max / n_r
    n_z = int(np.ceil((z_max - z_min) / h - 1e-9))
    return TankGrid(lower=(0.0, z_min), spacing=h, shape=(n_r, n_z), axisymmetric=True)


def cartesian_grid(lower, upper, n_x: int) -> TankGrid:
    """3-D grid with ``n_x`` cubic cells along x and as many as fit along y and z."""
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    h = (upper[0] - lower[0]) / n_x
    shape = tuple([n_x] + [int(np.ceil((upper[a] - lower[a]) / h - 1e-9)) for a in (1, 2)])
    return TankGrid(lower=tuple(lower), spacing=h, shape=shape, axisymmetric=False)
