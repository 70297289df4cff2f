"""The meridian at rest and its discretisation: nodes graded in the rest arc length S,
cubic Hermite elements, Gauss points and the rest geometry there.

**Rest shapes** (:class:`RestShape`), S the rest arc length from the pole (S = 0, on the axis)
to the rim (S = L), R the distance from the axis and Z the height:

* ``hemisphere`` of radius a hanging below its rim at the equator: R = a sin(S / a),
  Z = -a cos(S / a), L = pi a / 2 (pole at z = -a, rim at r = a, z = 0);
* ``disc``: the flat disc of radius a in z = 0, R = S, L = a;
* ``cap``: the spherical cap of base radius a on a sphere of radius rho >= a
  (``sphere_radius``), hanging below its rim: R = rho sin(S / rho),
  Z = rho (cos alpha - cos(S / rho)), L = rho alpha, sin alpha = a / rho (the hemisphere when
  rho = a).

**State.** A state is the (4 n,) vector of nodal values [r (m), dr/dS (1), z (m), dz/dS (1)]
node after node; r and z are interpolated by :func:`structure.axisymmetric.hermite.hermite_basis`.
The rest shape is the state of its own nodal values (:attr:`Meridian.rest_state`), and the
kinematics take the rest geometry from that interpolant, not from the exact curve: the rest
state is stress-free on every grid, and S is the rest arc length up to the interpolation error
(O(h^4)). At a Gauss point the local variables u = (r, r', r'', z, z', z'') (primes d/dS) are
u = B d of the element's eight values d (:attr:`Meridian.element_dofs` order r_a, r'_a, r_b,
r'_b, z_a, z'_a, z_b, z'_b).

**Grading.** Node k of n sits at S_k = L g(k / (n - 1)) with g the cubic of g(0) = 0, g(1) = 1,
g'(0) = ``pole_ratio``, g'(1) = ``rim_ratio``: the element beside the pole (rim) is that ratio
of the uniform length (monotone for ratios in (0, 3]; 1 and 1 give the uniform grid). The
bending layer at a clamped rim is about sqrt(a t) / (3 (1 - nu^2))^(1/4) wide (15.8 mm for the
Table 4.1 diaphragm), which a rim ratio of 0.2 to 0.4 resolves with a few elements.

Gauss points are interior to the elements, so R > 0 at each of them, the pole's element
included: the hoop terms r / R and (sin phi - sin Phi) / R are finite there and tend to their
regular limits as S -> 0 (:mod:`structure.axisymmetric.kinematics`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .hermite import gauss_rule, hermite_basis

SHAPES = ("hemisphere", "disc", "cap")
"""The rest shapes of :class:`RestShape`."""
DOFS_PER_NODE = 4
"""r, dr/dS, z, dz/dS."""
R, DR, Z, DZ = range(DOFS_PER_NODE)
"""The offsets of a node's values in a state."""


@dataclass(frozen=True)
class RestShape:
    """A meridian at rest: ``kind`` one of :data:`SHAPES`, ``radius`` a (m), the rim's
    distance from the axis; ``sphere_radius`` rho (m) of a ``cap``."""

    kind: str
    radius: float
    sphere_radius: Optional[float] = None

    def __post_init__(self):
        if self.kind not in SHAPES:
            raise ValueError(f"rest shape must be one of {SHAPES}, got {self.kind!r}")
        if not self.radius > 0:
            raise ValueError(f"rest shape radius must be > 0 m, got {self.radius!r}")
        if self.kind == "cap" and not (self.sphere_radius or 0) >= self.radius:
            raise ValueError(f"a cap's sphere_radius must be >= its radius {self.radius} m, "
                             f"got {self.sphere_radius!r}")

    @property
    def _sphere(self) -> float:
        return self.sphere_radius if self.kind == "cap" else self.radius

    @property
    def length(self) -> float:
        """The meridian's rest arc length L (m) from the pole to the rim."""
        if self.kind == "disc":
            return self.radius
        return self._sphere * np.arcsin(min(self.radius / self._sphere, 1.0))

    def curve(self, arc_length: np.ndarray) -> np.ndarray:
        """(..., 6): R (m), R' (1), R'' (1/m), Z (m), Z' (1), Z'' (1/m) at rest arc lengths
        ``arc_length`` (...) m."""
        s = np.asarray(arc_length, dtype=float)
        if self.kind != "disc":
            rho = self._sphere
            base = np.sqrt(max(rho * rho - self.radius**2, 0.0))      # rho cos(alpha)
            c, n = np.cos(s / rho), np.sin(s / rho)
            return np.stack([rho * n, c, -n / rho, base - rho * c, n, c / rho], axis=-1)
        zero = np.zeros_like(s)
        return np.stack([s, zero + 1.0, zero, zero, zero, zero], axis=-1)


def graded_nodes(length: float, elements: int, pole_ratio: float = 1.0,
                 rim_ratio: float = 1.0) -> np.ndarray:
    """(elements + 1,) m: node arc lengths from 0 to ``length``, graded (module doc)."""
    if elements < 1:
        raise ValueError(f"a meridian needs at least one element, got {elements}")
    for name, ratio in (("pole_ratio", pole_ratio), ("rim_ratio", rim_ratio)):
        if not 0 < ratio <= 3:
            raise ValueError(f"{name} must be in (0, 3], got {ratio!r}")
    xi = np.linspace(0.0, 1.0, elements + 1)
    shape = hermite_basis(xi, 1.0)[:, 0]
    return length * (pole_ratio * shape[:, 1] + shape[:, 2] + rim_ratio * shape[:, 3])


@dataclass(frozen=True)
class Meridian:
    """The discretised meridian (module doc); m elements, q Gauss points each, n nodes.

    * shape : :class:`RestShape`;
    * node_arc_length : (n,) m;
    * element_dofs : (m, 8) int64, each element's entries in a state;
    * element_length : (m,) m;
    * point_arc_length : (m, q) m, the Gauss points' S;
    * point_weight : (m, q) m, Gauss weight times element length (the points' dS);
    * point_basis : (m, q, 6, 8), u = B d (module doc);
    * rest_state : (4 n,), the rest shape's nodal values;
    * point_rest : (m, q, 6), the rest shape's local variables u;
    * point_radius R : (m, q) m > 0; point_metric A = |X'| : (m, q) 1 (1 up to the
      interpolation); point_sin_angle sin Phi : (m, q) 1, Phi the rest meridian's angle to
      the r axis; point_turning dPhi/dS : (m, q) 1/m;
    * point_area : (m, q) m, 2 pi R A, the rest area per unit S.
    """

    shape: RestShape
    node_arc_length: np.ndarray
    element_dofs: np.ndarray
    element_length: np.ndarray
    point_arc_length: np.ndarray
    point_weight: np.ndarray
    point_basis: np.ndarray
    rest_state: np.ndarray
    point_rest: np.ndarray
    point_radius: np.ndarray
    point_metric: np.ndarray
    point_sin_angle: np.ndarray
    point_turning: np.ndarray
    point_area: np.ndarray

    @property
    def nodes(self) -> int:
        return len(self.node_arc_length)

    @property
    def size(self) -> int:
        """The length of a state, 4 n."""
        return DOFS_PER_NODE * self.nodes


def element_basis(xi: np.ndarray, length: np.ndarray) -> np.ndarray:
    """(..., 6, 8): the block-diagonal map B from an element's eight values to
    u = (r, r', r'', z, z', z'') at local coordinates ``xi`` (...) on elements of ``length``
    (...) m."""
    n = hermite_basis(xi, length)
    out = np.zeros(n.shape[:-2] + (6, 8))
    out[..., 0:3, 0:4] = n
    out[..., 3:6, 4:8] = n
    return out


def local_variables(meridian: Meridian, state: np.ndarray) -> np.ndarray:
    """(m, q, 6): u = (r m, r' 1, r'' 1/m, z m, z' 1, z'' 1/m) of ``state`` (4 n,) at the
    Gauss points."""
    return np.einsum("mqij,mj->mqi", meridian.point_basis, state[meridian.element_dofs])


def rest_geometry(u: np.ndarray) -> dict:
    """The rest quantities of rest local variables ``u`` (..., 6): u itself, radius R (m),
    metric A = |X'| (1), sin Phi (1), turning dPhi/dS (1/m) and area 2 pi R A (m) per unit
    S."""
    metric = np.hypot(u[..., 1], u[..., 4])
    return dict(u=u, radius=u[..., 0], metric=metric, sin_angle=u[..., 4] / metric,
                turning=(u[..., 1] * u[..., 5] - u[..., 4] * u[..., 2]) / metric**2,
                area=2.0 * np.pi * u[..., 0] * metric)


def nodal_state(r: np.ndarray, dr: np.ndarray, z: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """(4 n,): a state from nodal r (n,) m, dr/dS (n,) 1, z (n,) m and dz/dS (n,) 1."""
    return np.stack([r, dr, z, dz], axis=1).astype(float).ravel()


def build_meridian(shape: RestShape, elements: int, points: int = 4, pole_ratio: float = 1.0,
                   rim_ratio: float = 1.0) -> Meridian:
    """The meridian of ``shape`` on ``elements`` cubic Hermite elements graded by
    ``pole_ratio`` and ``rim_ratio`` (module doc), with ``points`` Gauss points each."""
    s = graded_nodes(shape.length, elements, pole_ratio, rim_ratio)
    exact = shape.curve(s)
    rest = nodal_state(exact[:, 0], exact[:, 1], exact[:, 3], exact[:, 4])
    a = np.arange(elements) * DOFS_PER_NODE
    b = a + DOFS_PER_NODE
    dofs = np.stack([a + R, a + DR, b + R, b + DR, a + Z, a + DZ, b + Z, b + DZ], axis=1)
    length = np.diff(s)
    xi, w = gauss_rule(points)
    basis = element_basis(xi[None, :], length[:, None])
    point_s = s[:-1, None] + xi[None, :] * length[:, None]
    u = np.einsum("mqij,mj->mqi", basis, rest[dofs])
    rest_geo = rest_geometry(u)
    if np.any(rest_geo["radius"] <= 0):
        raise ValueError("the rest shape's interpolant reaches the axis at a Gauss point")
    return Meridian(shape, s, dofs.astype(np.int64), length, point_s, w[None, :] * length[:, None],
                    basis, rest, u, rest_geo["radius"], rest_geo["metric"], rest_geo["sin_angle"],
                    rest_geo["turning"], rest_geo["area"])


def locate(meridian: Meridian, arc_length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(element (k,) int64, xi (k,)) of rest arc lengths ``arc_length`` (k,) m in [0, L]."""
    s = np.atleast_1d(np.asarray(arc_length, dtype=float))
    nodes = meridian.node_arc_length
    element = np.clip(np.searchsorted(nodes, s, side="right") - 1, 0, len(nodes) - 2)
    return element, (s - nodes[element]) / meridian.element_length[element]
