"""Thesis Eqn 6.1: volume-weighted surface difference between two diaphragm shapes.

    error = 100 * sum_i |dz_i| A_i / ((4/3) pi R^3)       (%)

over the reference surface's nodes i with |x_i| < 0.8 R; dz_i is the height of the compared
surface at the reference node's (x, y) (linear interpolation over the compared surface's nodes,
as App. J's ``griddata``) minus the reference node's height; A_i the reference node's area
(each face's area split equally among its corners, which is App. D's rule on a quad grid).
Reference nodes outside the compared surface's footprint count zero, as App. J's NaN rule does.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import griddata

from fsi.constants import EQN_6_1_CENTRE_FRACTION


def node_areas(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Node areas (n,) m^2: each polygon face's area (fan triangulation) split equally among
    its corners. ``faces`` is (f, k) int, k = 3 or 4."""
    points = np.asarray(points, dtype=float)
    faces = np.asarray(faces)
    area = np.zeros(faces.shape[0])
    for c in range(1, faces.shape[1] - 1):
        a = points[faces[:, c]] - points[faces[:, 0]]
        b = points[faces[:, c + 1]] - points[faces[:, 0]]
        area += 0.5 * np.linalg.norm(np.cross(a, b), axis=1)
    out = np.zeros(points.shape[0])
    for c in range(faces.shape[1]):
        np.add.at(out, faces[:, c], area / faces.shape[1])
    return out


def eqn_6_1_error(reference_points, reference_faces, compared_points, radius: float) -> float:
    """Eqn 6.1 error (%) of ``compared_points`` (m, n_c x 3) against the reference surface."""
    ref = np.asarray(reference_points, dtype=float)
    cmp_ = np.asarray(compared_points, dtype=float)
    area = node_areas(ref, reference_faces)
    inside = np.linalg.norm(ref, axis=1) < EQN_6_1_CENTRE_FRACTION * radius
    z = griddata(cmp_[:, :2], cmp_[:, 2], ref[inside, :2], method="linear")
    dz = np.nan_to_num(np.abs(z - ref[inside, 2]), nan=0.0)
    return float(100.0 * np.sum(dz * area[inside]) / (4.0 / 3.0 * np.pi * radius**3))


def read_obj_surface(path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) and faces (f, 3 or 4) of a Wavefront .obj surface (the thesis's scan
    format), via meshio; units as stored (the caller scales)."""
    import meshio

    mesh = meshio.read(path)
    blocks = [c.data for c in mesh.cells if c.type in ("triangle", "quad")]
    if not blocks:
        raise ValueError(f"'{path}' has no triangle or quad faces")
    tris = [b for b in blocks if b.shape[1] == 3]
    quads = [b for b in blocks if b.shape[1] == 4]
    if quads:
        tris.append(np.concatenate([np.concatenate(quads)[:, [0, 1, 2]],
                                    np.concatenate(quads)[:, [0, 2, 3]]]))
    return np.asarray(mesh.points, dtype=float), np.concatenate(tris)
