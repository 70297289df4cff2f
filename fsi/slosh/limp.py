"""The limp membrane: a diaphragm that carries no pressure jump, seen as the liquid's free surface.

A slack membrane of negligible mass and bending stiffness lies on the liquid and transmits the
gas pressure unchanged; where the liquid climbs the wall above the clamped rim, the slack
membrane lines the wall and the wall carries the liquid's pressure through it, so the liquid's
edge moves along the wall as a free surface's contact line does. Its dynamics is therefore the
free surface's: p = p_gas on it (:mod:`fluid.free_surface`) and it moves with the liquid.

The surface is a height function z = eta(x, y) with one node over the centre of each vertical
column of fluid cells (and one ring of columns beyond the grid), moved by the liquid's volume
flux through each column's surface faces (:func:`fluid.free_surface.column_rates`), second order
in time and without numerical damping (:func:`advance_heights`). Columns with no surface face (outside the tank) take the mean rate
of their neighbours, so the surface stays smooth where it crosses the wall. A uniform shift
each window returns the liquid volume to its start (the lagged volume error over the surface
area; it is reported). The surface is closed by a box below it, outside the tank, so that the
fluid takes the liquid side from its winding number (:mod:`fluid.interface`).
"""
from __future__ import annotations

import numpy as np

from fluid.interface import Interface, is_closed

#: the nodes sit this fraction of a cell off the column centres: the winding number's vertical
#: rays through the cell centres must not pass exactly through a node
NODE_OFFSET = (1.3e-3, 0.7e-3)
#: sweeps of neighbour averaging that extend the rates past the columns with surface faces
EXTENSION_SWEEPS = 8


class HeightSurface:
    """z = eta(x, y) over the columns of a 3-D fluid ``grid``, closed by a box down to
    ``bottom`` (m, below the grid).

    ``heights`` arrays are (nx + 2, ny + 2) m: the grid's columns and one ring beyond."""

    def __init__(self, grid, bottom: float):
        if grid.axisymmetric:
            raise ValueError("a height surface needs a 3-D grid")
        h = grid.spacing
        xs, ys = (np.concatenate([[c[0] - h], c, [c[-1] + h]]) for c in grid.centre_axes[:2])
        x, y = np.meshgrid(xs + NODE_OFFSET[0] * h, ys + NODE_OFFSET[1] * h, indexing="ij")
        self.shape = x.shape
        self.plan = np.stack([x.ravel(), y.ravel()], axis=1)
        n_i, n_j = self.shape
        idx = np.arange(n_i * n_j).reshape(self.shape)
        a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
        top = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                              np.stack([a, c, d], -1).reshape(-1, 3)])
        ring = np.concatenate([idx[:, 0], idx[-1, 1:], idx[-2::-1, -1], idx[0, -2:0:-1]])
        m, nb = len(ring), n_i * n_j
        k = np.arange(m)
        side = np.concatenate([np.stack([ring[(k + 1) % m], ring[k], nb + k], 1),
                               np.stack([ring[(k + 1) % m], nb + k, nb + (k + 1) % m], 1)])
        cap = np.stack([nb + (k + 1) % m, nb + k, np.full(m, nb + m)], 1)
        self.faces = np.concatenate([top, side, cap])
        if not is_closed(self.faces):
            raise RuntimeError("the height surface's box is not closed")
        base = np.column_stack([self.plan[ring], np.full(m, bottom)])
        self.fixed = np.concatenate([base, [[x.mean(), y.mean(), bottom]]])
        self.n_nodes = nb

    def flat(self, level: float) -> np.ndarray:
        """Heights (m) of a level surface at z = ``level``."""
        return np.full(self.shape, float(level))

    def points(self, heights: np.ndarray) -> np.ndarray:
        """(n_nodes, 3) m: the surface nodes."""
        return np.column_stack([self.plan, np.asarray(heights, dtype=float).ravel()])

    def interface(self, heights: np.ndarray, velocities: np.ndarray | None = None) -> Interface:
        """The closed surface as the fluid sees it; ``velocities`` (n_nodes, 3) m/s of the
        nodes (the box is at rest)."""
        nodes = self.points(heights)
        vel = np.zeros((len(nodes), 3)) if velocities is None else np.asarray(velocities)
        return Interface(np.concatenate([nodes, self.fixed]), self.faces,
                         np.concatenate([vel, np.zeros_like(self.fixed)]))

    def node_rates(self, column_rate: np.ndarray, has_surface: np.ndarray) -> np.ndarray:
        """(nx + 2, ny + 2) m/s: the grid columns' rates (nx, ny) on the nodes, extended to
        the nodes without a surface face by neighbour averaging."""
        rate = np.zeros(self.shape)
        known = np.zeros(self.shape, dtype=bool)
        rate[1:-1, 1:-1] = column_rate
        known[1:-1, 1:-1] = has_surface
        for _ in range(EXTENSION_SWEEPS):
            if known.all():
                break
            value = np.pad(np.where(known, rate, 0.0), 1)
            count = np.pad(known.astype(float), 1)
            total = value[:-2, 1:-1] + value[2:, 1:-1] + value[1:-1, :-2] + value[1:-1, 2:]
            n = count[:-2, 1:-1] + count[2:, 1:-1] + count[1:-1, :-2] + count[1:-1, 2:]
            new = ~known & (n > 0)
            rate[new] = total[new] / n[new]
            known |= new
        return rate


def advance_heights(heights: np.ndarray, rate: np.ndarray, dt: float,
                    shift: float = 0.0) -> np.ndarray:
    """eta^{n+1} = eta^n + dt r^n + shift (m): the surface moves by the face fluxes of the
    liquid's last step, then the liquid steps under it (its velocity from the pressure at
    eta^{n+1}). That pairing is Stormer-Verlet's (positions and velocities staggered by half
    a step): second order in phase and free of numerical damping. Adams-Bashforth 2 in its
    place damps the mode at zeta = omega dt / 4 (its amplification has |xi|^2 =
    1 - (omega dt)^2 / 2 per step)."""
    return heights + dt * rate + shift
