"""Bending of a triangulated shell, calibrated to the plate rigidity D on any mesh.

Model (linearised midedge / Morley shape operator; Morley 1968, Grinspun et al. 2006
"Computing discrete shape operators on general meshes").  For a triangle T of reference area A
with edges i = 0, 1, 2 (edge i opposite vertex i) of reference length l_i and reference in-plane
unit edge normals m_i, the constant curvature tensor of the triangle is

    H_T = sum_i  l_i (theta_i - theta0_i) / (2 A)  m_i m_i^T,

theta_i the dihedral angle at edge i (the midedge normal is the mean of the two face normals,
so the face sees half the angle) and theta0_i its reference value.  For a quadratic deflection
of a flat mesh this is the exact Hessian whenever the midedge slope is exact (Green's theorem
over the triangle: A H = sum_i l_i (slope excess at the edge midpoint) m_i m_i^T).  The energy
is the Kirchhoff-Love plate energy, per triangle,

    U_T = A D / 2 [(1 - nu) tr(H_T^2) + nu tr(H_T)^2]  =  1/2 d^T K_T d,
    K_T[i, j] = D l_i l_j [(1 - nu)(m_i . m_j)^2 + nu] / (4 A),     d = theta - theta0,

D = E t^3 / (12 (1 - nu^2)) (thesis Eqn 3.1).  Unlike the discrete-shell hinge energy
sum 3 l^2 theta^2 / A_e, whose constant is right on near-equilateral meshes only (it is 3x too
stiff on the quad-split grids of this project), K_T is built from each triangle's own shape,
so no mesh-dependent factor needs calibrating.

**Each hinge's turn.** The dihedral angle is read on the circle, in (-pi, pi]; a change
beyond pi is a sheet that has folded through itself. Because K_T couples a triangle's three
hinges, taking a change modulo 2 pi would make the energy jump where a hinge passes +-pi (its
d flips sign, the cross terms with it). Each hinge's change is therefore taken within pi of
its own reference, ``reference_change`` (zero at build: the rest shape's branch), and the
Newton, minimisation and L-BFGS solvers move the reference along with the state
(:meth:`MidedgeBending.follow` after each accepted iterate), so that along any path whose
steps turn no hinge by pi or more the energy is continuous. The reference is the one piece of
state the bending carries. XPBD reads each change on the circle (a zero reference;
:func:`structure.xpbd.substep.sweep` says why).

Boundary edges: ``clamped`` puts a fixed ghost vertex across the edge (the triangle's opposite
vertex reflected through the edge at rest), so the edge keeps its reference slope; ``free``
condenses the edge's angle out of K_T (the edge carries no moment).  Clamped edges are meant
for edges whose nodes are held fixed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

JIT = dict(cache=True, nogil=True)
SIGN = -1.0

BOUNDARY_KINDS = ("clamped", "free")


def flap_vertices(triangles: np.ndarray) -> np.ndarray:
    """(m, 3) int64: for triangle t and edge i (opposite vertex i), the vertex of the other
    triangle across that edge, or -1 on a boundary edge."""
    tri = np.asarray(triangles, dtype=np.int64)
    flap = np.full(tri.shape, -1, dtype=np.int64)
    owner = {}
    for t, (p0, p1, p2) in enumerate(tri):
        for i, (a, b) in enumerate(((p1, p2), (p2, p0), (p0, p1))):
            key = (min(a, b), max(a, b))
            if key in owner:
                s, j = owner.pop(key)
                flap[t, i] = tri[s, j]
                flap[s, j] = tri[t, i]
            else:
                owner[key] = (t, i)
    return flap


@njit(**JIT, inline="always")
def _dihedral(pos, ghost_point, a, b, c, d, grad):
    """Signed dihedral angle (rad) at edge (a, b) between triangle (c, a, b) and its flap
    (d, b, a) (d < 0: the point ``ghost_point``), zero when flat; fills grad (4, 3) with
    d theta / d (c, d, a, b) (Bridson, Marino & Fedkiw 2003, with this angle's sign)."""
    ax, ay, az = pos[a, 0], pos[a, 1], pos[a, 2]
    bx, by, bz = pos[b, 0], pos[b, 1], pos[b, 2]
    cx, cy, cz = pos[c, 0], pos[c, 1], pos[c, 2]
    if d >= 0:
        dx, dy, dz = pos[d, 0], pos[d, 1], pos[d, 2]
    else:
        dx, dy, dz = ghost_point[0], ghost_point[1], ghost_point[2]
    ex, ey, ez = bx - ax, by - ay, bz - az
    le = np.sqrt(ex * ex + ey * ey + ez * ez)
    # n1 = (c - a) x (c - b), n2 = (d - b) x (d - a)
    p1x, p1y, p1z = cx - ax, cy - ay, cz - az
    q1x, q1y, q1z = cx - bx, cy - by, cz - bz
    n1x, n1y, n1z = p1y * q1z - p1z * q1y, p1z * q1x - p1x * q1z, p1x * q1y - p1y * q1x
    p2x, p2y, p2z = dx - bx, dy - by, dz - bz
    q2x, q2y, q2z = dx - ax, dy - ay, dz - az
    n2x, n2y, n2z = p2y * q2z - p2z * q2y, p2z * q2x - p2x * q2z, p2x * q2y - p2y * q2x
    s1 = n1x * n1x + n1y * n1y + n1z * n1z
    s2 = n2x * n2x + n2y * n2y + n2z * n2z
    crx, cry, crz = n1y * n2z - n1z * n2y, n1z * n2x - n1x * n2z, n1x * n2y - n1y * n2x
    theta = np.arctan2((crx * ex + cry * ey + crz * ez) / le,
                       n1x * n2x + n1y * n2y + n1z * n2z)
    ca = (q1x * ex + q1y * ey + q1z * ez) / le
    da = (p2x * ex + p2y * ey + p2z * ez) / le
    cb = (p1x * ex + p1y * ey + p1z * ez) / le
    db = (q2x * ex + q2y * ey + q2z * ez) / le
    k1, k2 = SIGN * le / s1, SIGN * le / s2
    u1x, u1y, u1z = k1 * n1x, k1 * n1y, k1 * n1z
    u2x, u2y, u2z = k2 * n2x, k2 * n2y, k2 * n2z
    grad[0, 0], grad[0, 1], grad[0, 2] = u1x, u1y, u1z
    grad[1, 0], grad[1, 1], grad[1, 2] = u2x, u2y, u2z
    grad[2, 0] = (ca * u1x + da * u2x) / le
    grad[2, 1] = (ca * u1y + da * u2y) / le
    grad[2, 2] = (ca * u1z + da * u2z) / le
    grad[3, 0] = -(cb * u1x + db * u2x) / le
    grad[3, 1] = -(cb * u1y + db * u2y) / le
    grad[3, 2] = -(cb * u1z + db * u2z) / le
    return theta


@njit(**JIT, inline="always")
def _triangle(pos, triangles, flap, ghost, active, rest_angle, reference, t, nodes, grads,
              delta):
    """Fills delta (3,) with the angle changes (rad) at triangle t's edges, each within pi of
    its ``reference`` (m, 3) rad (module doc), nodes (3, 4) (c, d, a, b; -1 for a ghost or an
    inactive edge) and grads (3, 4, 3) = d delta_i / d x."""
    for i in range(3):
        c, a, b, d = (triangles[t, i], triangles[t, (i + 1) % 3], triangles[t, (i + 2) % 3],
                      flap[t, i])
        nodes[i, 0], nodes[i, 1], nodes[i, 2], nodes[i, 3] = c, d, a, b
        if not active[t, i]:
            nodes[i, :] = -1
            grads[i, :, :] = 0.0
            delta[i] = 0.0
            continue
        theta = _dihedral(pos, ghost[t, i], a, b, c, d, grads[i])
        change = theta - rest_angle[t, i]
        while change - reference[t, i] > np.pi:
            change -= 2.0 * np.pi
        while change - reference[t, i] < -np.pi:
            change += 2.0 * np.pi
        delta[i] = change


@njit(**JIT)
def _energy_and_gradient(pos, triangles, flap, ghost, active, rest_angle, reference,
                         stiffness):
    grad = np.zeros_like(pos)
    energy = 0.0
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    delta = np.empty(3)
    for t in range(triangles.shape[0]):
        _triangle(pos, triangles, flap, ghost, active, rest_angle, reference, t, nodes, grads,
                  delta)
        for i in range(3):
            f = 0.0
            for j in range(3):
                f += stiffness[t, i, j] * delta[j]
            energy += 0.5 * delta[i] * f
            for k in range(4):
                if nodes[i, k] >= 0:
                    for r in range(3):
                        grad[nodes[i, k], r] += f * grads[i, k, r]
    return energy, grad


@njit(**JIT)
def _angle_jacobian(pos, triangles, flap, ghost, active, rest_angle, reference):
    m = triangles.shape[0]
    delta = np.empty((m, 3))
    nodes = np.empty((m, 3, 4), dtype=np.int64)
    grads = np.empty((m, 3, 4, 3))
    for t in range(m):
        _triangle(pos, triangles, flap, ghost, active, rest_angle, reference, t, nodes[t],
                  grads[t], delta[t])
    return delta, nodes, grads


@njit(**JIT)
def _follow(pos, triangles, flap, ghost, active, rest_angle, reference):
    """reference (m, 3) rad <- the angle changes at ``pos``, each within pi of its old value."""
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    delta = np.empty(3)
    for t in range(triangles.shape[0]):
        _triangle(pos, triangles, flap, ghost, active, rest_angle, reference, t, nodes, grads,
                  delta)
        for i in range(3):
            reference[t, i] = delta[i]


def _rest_geometry(rest: np.ndarray, tri: np.ndarray):
    """Edge lengths l (m, 3) m, unit in-plane edge normals (m, 3, 3) and areas (m,) m^2."""
    x = rest[tri]                                    # (m, 3 vertices, 3)
    edge = x[:, [2, 0, 1]] - x[:, [1, 2, 0]]         # edge i runs from vertex i+1 to i+2
    length = np.linalg.norm(edge, axis=2)
    normal = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    area = 0.5 * np.linalg.norm(normal, axis=1)
    unit = normal / (2.0 * area[:, None])
    in_plane = np.cross(edge, unit[:, None, :]) / length[:, :, None]
    return length, in_plane, area


@dataclass(frozen=True)
class MidedgeBending:
    """Bending energy of a triangulated shell (module docstring).

    triangles (m, 3) int64; flap (m, 3) int64 (vertex across edge i, -1 on a boundary edge);
    ghost (m, 3, 3) m, fixed ghost vertices of clamped boundary edges; active (m, 3) bool,
    edges that carry an angle; rest_angle (m, 3) rad; stiffness (m, 3, 3) N m, the K_T.
    """

    triangles: np.ndarray
    flap: np.ndarray
    ghost: np.ndarray
    active: np.ndarray
    rest_angle: np.ndarray
    stiffness: np.ndarray
    reference_change: np.ndarray

    @classmethod
    def build(cls, rest: np.ndarray, triangles: np.ndarray, flexural_rigidity: float,
              poisson_ratio: float, boundary: str = "clamped") -> "MidedgeBending":
        """Bending of the reference shape ``rest`` (n, 3) m with plate rigidity
        ``flexural_rigidity`` (N m) and Poisson ratio ``poisson_ratio`` (-, in [0, 0.5]);
        ``boundary`` is one of BOUNDARY_KINDS."""
        if boundary not in BOUNDARY_KINDS:
            raise ValueError(f"bending boundary must be one of {BOUNDARY_KINDS}, got "
                             f"{boundary!r}")
        if not flexural_rigidity >= 0:
            raise ValueError(f"flexural rigidity must be >= 0 N m, got {flexural_rigidity}")
        if not 0.0 <= poisson_ratio <= 0.5:
            raise ValueError(f"Poisson ratio must be in [0, 0.5], got {poisson_ratio}")
        rest = np.ascontiguousarray(rest, dtype=float)
        tri = np.ascontiguousarray(triangles, dtype=np.int64)
        flap = flap_vertices(tri)
        length, in_plane, area = _rest_geometry(rest, tri)
        ghost = np.zeros(tri.shape + (3,))
        for t, i in zip(*np.nonzero(flap < 0)):
            a, b, c = rest[tri[t, (i + 1) % 3]], rest[tri[t, (i + 2) % 3]], rest[tri[t, i]]
            e = (b - a) / np.linalg.norm(b - a)
            ghost[t, i] = 2.0 * (a + np.dot(c - a, e) * e) - c
        active = (flap >= 0) | (boundary == "clamped")
        cosine = np.einsum("tir,tjr->tij", in_plane, in_plane)
        k = (flexural_rigidity * length[:, :, None] * length[:, None, :]
             * ((1.0 - poisson_ratio) * cosine**2 + poisson_ratio) / (4.0 * area[:, None, None]))
        # a clamped edge's midedge normal is the clamp's own: the face sees the whole angle to
        # its ghost, not half of it
        scale = np.where(flap < 0, 2.0, 1.0)
        k *= scale[:, :, None] * scale[:, None, :]
        for t in np.nonzero(~active.all(axis=1))[0]:
            on, off = active[t], ~active[t]
            condensed = np.zeros((3, 3))
            if on.any():
                condensed[np.ix_(on, on)] = (
                    k[t][np.ix_(on, on)] - k[t][np.ix_(on, off)]
                    @ np.linalg.solve(k[t][np.ix_(off, off)], k[t][np.ix_(off, on)]))
            k[t] = condensed
        rest_angle, _, _ = _angle_jacobian(rest, tri, flap, ghost, active, np.zeros(tri.shape),
                                           np.zeros(tri.shape))
        return cls(tri, flap, ghost, active, rest_angle, np.ascontiguousarray(k),
                   np.zeros(tri.shape))

    def follow(self, pos: np.ndarray) -> "MidedgeBending":
        """Move each hinge's reference to its angle change at ``pos`` (n, 3) m, taken within
        pi of the old reference (in place; module doc). Returns self."""
        _follow(np.ascontiguousarray(pos, dtype=float), self.triangles, self.flap, self.ghost,
                self.active, self.rest_angle, self.reference_change)
        return self

    def reset(self) -> "MidedgeBending":
        """Every hinge back on the rest shape's turn (reference zero). Returns self."""
        self.reference_change[:] = 0.0
        return self

    def energy_and_gradient(self, pos: np.ndarray):
        """Bending energy (J) and its gradient (n, 3) N at positions ``pos`` (n, 3) m."""
        return _energy_and_gradient(np.ascontiguousarray(pos, dtype=float), self.triangles,
                                    self.flap, self.ghost, self.active, self.rest_angle,
                                    self.reference_change, self.stiffness)

    def angle_jacobian(self, pos: np.ndarray):
        """Angle changes (m, 3) rad, the nodes they depend on (m, 3, 4) int64 (-1: ghost or
        inactive) and their gradients (m, 3, 4, 3) 1/m."""
        return _angle_jacobian(np.ascontiguousarray(pos, dtype=float), self.triangles,
                               self.flap, self.ghost, self.active, self.rest_angle,
                               self.reference_change)

    def stiffness_matrix(self, pos: np.ndarray):
        """Gauss-Newton stiffness sum_T J_T^T K_T J_T, (3n, 3n) sparse N/m: the exact Hessian
        where every angle equals its reference value (e.g. a flat plate at rest)."""
        from scipy.sparse import coo_matrix

        n = len(pos)
        _, nodes, grads = self.angle_jacobian(pos)
        m = len(nodes)
        valid = (nodes >= 0)[..., None]
        dof = np.where(valid, 3 * nodes[..., None] + np.arange(3), 0).reshape(m, 3, 12)
        jac = np.where(valid, grads, 0.0).reshape(m, 3, 12)
        rows, cols, vals = [], [], []
        for i in range(3):
            for j in range(3):
                kij = (self.stiffness[:, i, j, None, None] * jac[:, i, :, None]
                       * jac[:, j, None, :])
                rows.append(np.broadcast_to(dof[:, i, :, None], kij.shape).ravel())
                cols.append(np.broadcast_to(dof[:, j, None, :], kij.shape).ravel())
                vals.append(kij.ravel())
        return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(3 * n, 3 * n)).tocsr()
