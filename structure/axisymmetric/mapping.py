"""An axisymmetric state carried onto a 3-D sheet: the start of a 3-D equilibrium below the onset
of folding, and above it the same start seeded with the critical harmonic's mode.

A material point of the 3-D sheet's rest (the hemisphere of radius a about the tank's centre,
or the flat disc) at rest arc length S from the pole and azimuth theta goes to

    x = r(S) e_r(theta) + z(S) e_z + A [U(S) cos(n theta) e_r + V(S) sin(n theta) e_theta
        + W(S) cos(n theta) e_z]

with (r, z) the meridian of the state and (U, V, W) a harmonic's mode
(:class:`~structure.axisymmetric.harmonics.HarmonicStability`'s ``modes``, nodal (U, U', V,
V', W, W')) scaled by A. The hemisphere's rest point at polar angle psi from its lowest point
has S = a psi; the disc's at radius rho has S = rho.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .hermite import hermite_basis
from .meridian import locate
from .model import ShellOfRevolution

__all__ = ["rest_arc_length", "meridian_values", "surface_points"]


def rest_arc_length(shell: ShellOfRevolution, rest_points: np.ndarray) -> np.ndarray:
    """(n,) m: the rest arc length S from the pole of the 3-D rest points (n, 3) m (module
    doc), within [0, L]."""
    p = np.asarray(rest_points, dtype=float)
    kind = shell.meridian.shape.kind
    if kind == "hemisphere":
        a = shell.radius
        s = a * np.arccos(np.clip(-p[:, 2] / np.linalg.norm(p, axis=1), -1.0, 1.0))
    elif kind == "disc":
        s = np.hypot(p[:, 0], p[:, 1])
    else:
        raise ValueError(f"a 3-D rest sheet is a hemisphere or a disc, not {kind!r}")
    return np.clip(s, 0.0, shell.meridian.shape.length)


def meridian_values(shell: ShellOfRevolution, nodal: np.ndarray,
                    arc_length: np.ndarray) -> np.ndarray:
    """(k, m): the cubic Hermite interpolants at rest arc lengths ``arc_length`` (k,) m of m
    fields given at the nodes by value and slope, ``nodal`` (n_nodes, 2 m) ordered (f_1,
    f_1', f_2, f_2', ...)."""
    meridian = shell.meridian
    element, xi = locate(meridian, np.asarray(arc_length, dtype=float))
    basis = hermite_basis(xi, meridian.element_length[element])[:, 0, :]     # (k, 4) values
    # an element's four entries of one field: (f_a, f_a', f_b, f_b')
    nodal = np.asarray(nodal, dtype=float).reshape(meridian.nodes, -1, 2)
    ends = np.stack([nodal[element], nodal[element + 1]], axis=1)          # (k, 2, m, 2)
    local = ends.transpose(0, 2, 1, 3).reshape(len(element), -1, 4)         # (k, m, 4)
    return np.einsum("kmj,kj->km", local, basis)


def surface_points(shell: ShellOfRevolution, state: np.ndarray, rest_points: np.ndarray,
                   mode: Optional[np.ndarray] = None, wave_number: int = 0,
                   amplitude: float = 0.0) -> np.ndarray:
    """(n, 3) m: the 3-D rest points (n, 3) carried onto the surface of revolution of
    ``state`` (4 n_nodes,), plus ``amplitude`` (m per unit of the mode) times the harmonic
    ``mode`` (6 n_nodes,) of ``wave_number`` (module doc)."""
    p = np.asarray(rest_points, dtype=float)
    s = rest_arc_length(shell, p)
    theta = np.arctan2(p[:, 1], p[:, 0])
    r, z = meridian_values(shell, np.asarray(state).reshape(-1, 4), s).T
    if mode is not None and amplitude != 0.0:
        u, v, w = (amplitude * meridian_values(shell, np.asarray(mode).reshape(-1, 6), s)).T
        c, sn = np.cos(wave_number * theta), np.sin(wave_number * theta)
        r = r + u * c
        tangential = v * sn
        z = z + w * c
    else:
        tangential = np.zeros_like(r)
    return np.stack([r * np.cos(theta) - tangential * np.sin(theta),
                     r * np.sin(theta) + tangential * np.cos(theta), z], axis=1)
