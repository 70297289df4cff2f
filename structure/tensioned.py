"""A flat membrane of uniform tension on a lattice of nodes, pinned on a circle: the
prestressed sheet whose small transverse motion is linear,

    mu w_tt = T lap(w) + q,      w = 0 on the circle r = a,      int w dA = 0,

with w (m) the displacement along z, mu (kg/m^2) the areal density, T (N/m) the tension and
q (Pa) the pressure on it from below; the last condition holds the liquid's volume under it,
its multiplier a uniform pressure.

Space: the nodes of a square lattice of spacing h inside the circle, each carrying the area
of its cell inside the circle A_i (m^2). The energy T/2 int |grad w|^2 dA is
T/2 w^T G w with G the finite-difference form: the squared difference across each edge
between two inside nodes, and for an edge that leaves the circle w^2 / theta, theta h the
distance to the circle along it (Shortley-Weller; at least ``THETA_MIN``). The same form as
the modes rung's tensioned surface (:func:`fluid.modes.membrane_stiffness`).

Time: Newmark's average acceleration (the trapezoidal rule), unconditionally stable and
free of numerical damping, second order; each step solves the bordered system
[4 M / dt^2 + T G, A; A^T, 0] with one SuperLU factorisation per step size
(:func:`newmark_step`). A stateless step on a fixed :class:`TensionedMembrane` and an evolving
:class:`MembraneMotion`.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

#: the smallest fraction of an edge between a node and the circle (Shortley-Weller)
THETA_MIN = 0.05
#: sub-samples per cell side for the cells' area inside the circle
AREA_SAMPLES = 16


@dataclass(frozen=True)
class TensionedMembrane:
    """The fixed model: ``plan`` (n, 2) m the nodes, ``area`` (n,) m^2 each node's cell inside
    the circle, ``energy_form`` (n, n) sparse G (1), ``tension`` T (N/m), ``areal_density``
    mu (kg/m^2), ``radius`` a (m) and ``spacing`` h (m)."""

    plan: np.ndarray
    area: np.ndarray
    energy_form: sparse.csr_matrix
    tension: float
    areal_density: float
    radius: float
    spacing: float
    _factors: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def n_nodes(self) -> int:
        return len(self.area)

    def stiffness(self) -> sparse.csr_matrix:
        """(n, n) N/m: T G."""
        return self.tension * self.energy_form

    def mass(self) -> np.ndarray:
        """(n,) kg: mu A_i."""
        return self.areal_density * self.area

    def factor(self, dt: float):
        """SuperLU of the bordered Newmark matrix for step ``dt`` (s), kept per step size."""
        key = float(dt)
        if key not in self._factors:
            n = self.n_nodes
            lhs = sparse.bmat([[sparse.diags(4.0 * self.mass() / dt**2) + self.stiffness(),
                                sparse.csr_matrix(self.area[:, None])],
                               [sparse.csr_matrix(self.area[None, :]), None]], format="csc")
            if lhs.shape != (n + 1, n + 1):
                raise RuntimeError("the bordered Newmark matrix has the wrong shape")
            self._factors[key] = splu(lhs)
        return self._factors[key]


@dataclass(frozen=True)
class MembraneMotion:
    """The evolving state: ``displacement`` w (n,) m, ``velocity`` (n,) m/s,
    ``acceleration`` (n,) m/s^2, ``multiplier`` (Pa) the uniform pressure that holds the
    volume, ``time`` (s)."""

    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    multiplier: float = 0.0
    time: float = 0.0


def _inside_area(x: np.ndarray, y: np.ndarray, h: float, radius: float) -> np.ndarray:
    offsets = (np.arange(AREA_SAMPLES) + 0.5) / AREA_SAMPLES - 0.5
    dx, dy = np.meshgrid(offsets * h, offsets * h, indexing="ij")
    px = x[:, None] + dx.ravel()
    py = y[:, None] + dy.ravel()
    return (px**2 + py**2 < radius**2).mean(axis=1) * h * h


def _wall_fraction(p: np.ndarray, q: np.ndarray, radius: float) -> float:
    """t in (0, 1]: where the segment p -> q (2,) first meets the circle of ``radius``."""
    d = q - p
    a, b, c = d @ d, 2 * p @ d, p @ p - radius**2
    return float((-b + np.sqrt(max(b * b - 4 * a * c, 0.0))) / (2 * a))


def tensioned_membrane(lattice_x: np.ndarray, lattice_y: np.ndarray, radius: float,
                       tension: float, areal_density: float) -> TensionedMembrane:
    """The membrane on the nodes of the lattice ``lattice_x`` (nx,), ``lattice_y`` (ny,) m
    (uniform spacing) whose position is inside the circle of ``radius`` (m) about the
    origin; ``tension`` T > 0 N/m, ``areal_density`` mu > 0 kg/m^2."""
    if not tension > 0:
        raise ValueError(f"tension: above 0 N/m, got {tension}")
    if not areal_density > 0:
        raise ValueError(f"areal_density: above 0 kg/m^2, got {areal_density}")
    h = float(lattice_x[1] - lattice_x[0])
    x, y = np.meshgrid(lattice_x, lattice_y, indexing="ij")
    inside = x**2 + y**2 < radius**2
    index = -np.ones(x.shape, dtype=int)
    index[inside] = np.arange(int(inside.sum()))
    plan = np.column_stack([x[inside], y[inside]])
    rows, cols, values = [], [], []
    nx, ny = x.shape
    for i, j in zip(*np.nonzero(inside)):
        a = index[i, j]
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            k, m = i + di, j + dj
            b = index[k, m] if 0 <= k < nx and 0 <= m < ny else -1
            if b >= 0:
                if b > a:  # each inside edge once
                    rows += [a, b, a, b]
                    cols += [a, b, b, a]
                    values += [1.0, 1.0, -1.0, -1.0]
                continue
            p = plan[a]
            theta = _wall_fraction(p, p + h * np.array([di, dj], dtype=float), radius)
            rows.append(a)
            cols.append(a)
            values.append(1.0 / max(theta, THETA_MIN))
    n = len(plan)
    form = sparse.csr_matrix((values, (rows, cols)), shape=(n, n))
    return TensionedMembrane(plan, _inside_area(plan[:, 0], plan[:, 1], h, radius), form,
                             float(tension), float(areal_density), float(radius), h)


def at_rest(model: TensionedMembrane, displacement: np.ndarray | None = None,
            pressure: np.ndarray | None = None) -> MembraneMotion:
    """The membrane released from rest at ``displacement`` (n,) m (default flat; its
    volume's share removed, so that int w dA = 0) under ``pressure`` q (n,) Pa (default 0),
    with the acceleration those give it."""
    w = np.zeros(model.n_nodes) if displacement is None else np.asarray(displacement, float)
    w = w - model.area * (model.area @ w) / (model.area @ model.area)
    force = -(model.stiffness() @ w)
    if pressure is not None:
        force = force + model.area * np.asarray(pressure, dtype=float)
    lam = -(model.area @ (force / model.mass())) / (model.area @ (model.area / model.mass()))
    return MembraneMotion(w, np.zeros_like(w), (force + model.area * lam) / model.mass(), lam)


def newmark_step(model: TensionedMembrane, state: MembraneMotion, pressure: np.ndarray,
                 dt: float) -> MembraneMotion:
    """One step of ``dt`` (s) under ``pressure`` q (n,) Pa at the step's end (module doc)."""
    m = model.mass()
    w, v, a = state.displacement, state.velocity, state.acceleration
    rhs = model.area * np.asarray(pressure, dtype=float) + m * (4.0 / dt**2 * w + 4.0 / dt * v + a)
    solution = model.factor(dt).solve(np.concatenate([rhs, [0.0]]))
    w1, lam = solution[:-1], float(solution[-1])
    a1 = 4.0 / dt**2 * (w1 - w) - 4.0 / dt * v - a
    v1 = v + 0.5 * dt * (a + a1)
    return replace(state, displacement=w1, velocity=v1, acceleration=a1, multiplier=-lam,
                   time=state.time + dt)


def energy(model: TensionedMembrane, state: MembraneMotion) -> float:
    """J: the sheet's kinetic and elastic energy, 1/2 mu A v^2 + T/2 w^T G w."""
    w, v = state.displacement, state.velocity
    return float(0.5 * model.mass() @ (v * v) + 0.5 * w @ (model.stiffness() @ w))
