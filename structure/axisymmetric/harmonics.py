"""The stability of an axisymmetric equilibrium to each circumferential wave number n: the second
variation of the total potential for displacements

    du = U(S) cos(n theta) e_r + V(S) sin(n theta) e_theta + W(S) cos(n theta) e_z

(the semi-analytical method of BOSOR4: D. Bushnell, "Stress, stability and vibration of
complex branched shells of revolution", Computers & Structures 4, 1974, 399-435).

**The surface energy.** Away from axisymmetry the sheet is a surface x(S, theta); its energy
per unit S and theta is a function f(J) of the jet J = (x, x_S, x_theta, x_SS, x_Stheta,
x_thetatheta) (18 Cartesian entries) at a point of the rest meridian (radius R, metric A,
curvatures B_s = Phi'/A and B_t = sin Phi / R in the rest's orthonormal frame):

* the membrane: A R t W(C), C the right Cauchy-Green tensor in that frame, C_ss = x_S . x_S /
  A^2, C_st = x_S . x_theta / (A R), C_tt = x_theta . x_theta / R^2, W the sheet's law
  (:mod:`~structure.axisymmetric.laws`; incompressible Yeoh: I1 = tr C + 1 / det C);
* the bending: A R D/2 [(1 - nu) K : K + nu (tr K)^2], K = sym(U^-1 b) - B, U = C^(1/2),
  b the second fundamental form in the frame (b_ss = x_SS . n / A^2, b_st = x_Stheta . n /
  (A R), b_tt = x_thetatheta . n / R^2, n = x_S x x_theta / |x_S x x_theta|): the change of
  the rotation-based curvature, which on an axisymmetric state is exactly the meridian's
  kappa_s = (phi' - Phi') / A and kappa_t = (sin phi - sin Phi) / R
  (:mod:`~structure.axisymmetric.kinematics`), since there U^-1 b = diag(phi' / A,
  sin phi / R);
* the liquid and the pressure: -rho g m - mu v with v = -(1/2) (x, y, 0) . (x_S x x_theta) and
  m = z v, whose integrals over theta are the densities pi r^2 z' and pi r^2 z z' of V_b and
  M_b (:mod:`~structure.axisymmetric.loads`): the load stiffness of the liquid's follower
  pressure, hydrostatic gradient included;
* the wall's barrier, A R kappa b(d), d = a + d_hat - |x| (:mod:`~structure.axisymmetric.wall`).

Every term is invariant under rotations about the axis, so at an axisymmetric state the
Hessian H = d2 f / dJ2 is the same at every theta in the local frame (e_r, e_theta, e_z); there
the jet of du is cos(n theta) a + sin(n theta) b, a and b linear in q = (U, U', U'', V, V',
V'', W, W', W'') (primes d/dS) and quadratic in n, and the second variation is

    delta^2 Pi = pi Int [a^T H a + b^T H b] dS          (n >= 1; 2 pi Int a^T H a at n = 0)

The n = 0 harmonic with V = 0 is the axisymmetric Hessian of :mod:`~structure.axisymmetric.energy`
(a check). H is computed at the Gauss points by the complex step in one entry and a central
difference in the other (Squire & Trapp 1998; Lyness & Moler 1967), each entry's step 1e-5 of
its size at the point (x_theta and x_thetatheta scale with the rest radius R, which vanishes
at the pole), accurate to about 3e-10 of its scale (the steps tenfold smaller or larger move
it by 3e-10 and 3e-8); the barrier's block, whose band is far thinner than a difference step,
in closed form. The volume constraint acts on n = 0 alone (the integral of cos n theta vanishes).

**Per harmonic.** U, V and W are cubic Hermite on the meridian's elements (six values a node:
U, U', V, V', W, W'). The pole's regularity for harmonic n: n = 1, W = 0 and U + V = 0 (a
translation across the axis); n >= 2, U = V = W = 0 and W' = 0; n >= 3 also U' = V' = 0. The
rim's support: clamped, U = V = W = 0 and (U', W') along the rest tangent; simply supported,
U = V = W = 0; symmetric (a mirror plane), W = 0 and U' = V' = 0; roller, U = V = 0 (with
the liquid under the band of wall it slides over, :func:`roller_closure`). The stability of
harmonic n is the lowest eigenvalue of K_n phi = omega^2 M phi (1/s^2; M the sheet's mass,
rho_m t per rest area): negative where the equilibrium is unstable to n lobes; phi its mode.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigsh

from ..hyperelastic import HyperelasticLaw, SaintVenantKirchhoff
from ..inertia import factor_symmetric
from .energy import rest_at_points
from .laws import TAUT, WRINKLED, regimes, uniaxial_density
from .meridian import local_variables
from .model import ShellOfRevolution
from .wall import barrier

JET = 18
"""x, x_S, x_theta, x_SS, x_Stheta, x_thetatheta, three Cartesian entries each."""
FIELDS = 9
"""U, U', U'', V, V', V'', W, W', W''."""
NODE_DOFS = 6
"""U, U', V, V', W, W' at a node."""
EIGEN_TOLERANCE = 1e-10
"""ARPACK's relative accuracy of the lowest eigenvalue (its default, 0, is the machine's)."""


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _cross(a, b):
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], -1)


def _membrane(law, c11, c12, c22, regime=None, residual=0.0):
    """W (Pa) of ``law`` at C (complex-safe); relaxed by the tension field where ``regime``
    (...) is given, keeping the fraction ``residual`` of the law (:func:`_relaxed`)."""
    if regime is not None:
        return _relaxed(law, c11, c12, c22, regime, residual)
    if isinstance(law, SaintVenantKirchhoff):
        nu = law.poisson_ratio
        k = law.youngs_modulus / (1 - nu * nu)
        e11, e12, e22 = 0.5 * (c11 - 1), 0.5 * c12, 0.5 * (c22 - 1)
        tr = e11 + e22
        return 0.5 * k * (nu * tr * tr + (1 - nu) * (e11 * e11 + 2 * e12 * e12 + e22 * e22))
    if isinstance(law, HyperelasticLaw):
        x = c11 + c22 + 1.0 / (c11 * c22 - c12 * c12) - 3.0
        c1, c2, c3 = law.coefficients
        return c1 * x + c2 * x * x + c3 * x**3
    raise TypeError(f"no surface law for {type(law).__name__}")


def _relaxed(law, c11, c12, c22, regime, residual=0.0):
    """The tension field's relaxed W (Pa) at C (complex-safe), each point in the ``regime``
    (...) of the axisymmetric state it varies about (:func:`structure.axisymmetric.laws.regimes`):
    taut, the law; slack, zero; wrinkled, the uniaxial energy
    (:func:`structure.axisymmetric.laws.uniaxial_density`) at the larger principal value
    c_1 = (c11 + c22) / 2 + sqrt(((c11 - c22) / 2)^2 + c12^2) of C. A wrinkled point's
    principal values are distinct (c_2 < c_1^(-1/2) < c_1), so c_1 is analytic there and its
    second derivative in c12, 1 / (c_1 - c_2), gives the tension field's shear stiffness
    sigma_1 / (c_1 - c_2) (the wrinkles turn with the tension). The regime is held at the
    state's: the relaxed energy's Hessian jumps across a regime's boundary, and the second
    variation is the one-sided one of the state's side. ``residual``: the fraction of the
    law kept (:class:`~structure.axisymmetric.model.ShellOfRevolution`)."""
    taut = _membrane(law, c11, c12, c22)
    half = 0.5 * (c11 - c22)
    major = 0.5 * (c11 + c22) + np.sqrt(half * half + c12 * c12 + 0j)
    wrinkled = uniaxial_density(law, 0.5 * (major - 1.0))[0]
    if not np.iscomplexobj(taut):
        wrinkled = wrinkled.real
    relaxed = np.where(regime == TAUT, taut, np.where(regime == WRINKLED, wrinkled, 0.0))
    return relaxed if residual == 0.0 else (1.0 - residual) * relaxed + residual * taut


def surface_density(shell: ShellOfRevolution, jet: np.ndarray, rest: dict, liquid: float,
                    net_pressure: float) -> np.ndarray:
    """f(J) (...) J per unit S and theta (module doc) at jets ``jet`` (..., P, 18), real or
    complex, on the rest points ``rest`` (arrays (P,): radius R m, metric A, turning Phi'
    1/m, sin_angle sin Phi), under the liquid's weight density ``liquid`` rho g (N/m^3) and
    the net pressure ``net_pressure`` mu (Pa); the wall's barrier excluded
    (:func:`wall_hessian`)."""
    x, xs, xt, xss, xst, xtt = (jet[..., 3 * k:3 * k + 3] for k in range(6))
    big_r, a = rest["radius"], rest["metric"]
    c11, c12, c22 = _dot(xs, xs) / a**2, _dot(xs, xt) / (a * big_r), _dot(xt, xt) / big_r**2
    mat = shell.material
    f = mat.thickness * _membrane(shell.law, c11, c12, c22, rest.get("regime"),
                                     shell.residual_stiffness)
    cross = _cross(xs, xt)
    if shell.flexural_rigidity > 0:
        normal = cross / np.sqrt(_dot(cross, cross))[..., None]
        b11, b12, b22 = (_dot(xss, normal) / a**2, _dot(xst, normal) / (a * big_r),
                         _dot(xtt, normal) / big_r**2)
        s = np.sqrt(c11 * c22 - c12 * c12)
        tau = np.sqrt(c11 + c22 + 2 * s)
        # U^-1 = (adj C + s I) / (tau s), adj C = [[c22, -c12], [-c12, c11]]
        u11, u12, u22 = (c22 + s) / (tau * s), -c12 / (tau * s), (c11 + s) / (tau * s)
        k11 = u11 * b11 + u12 * b12 - rest["turning"] / a
        k22 = u12 * b12 + u22 * b22 - rest["sin_angle"] / big_r
        k12 = 0.5 * (u11 * b12 + u12 * b22 + u12 * b11 + u22 * b12)
        nu, d = mat.poisson_ratio, shell.flexural_rigidity
        f = f + 0.5 * d * ((1 - nu) * (k11 * k11 + 2 * k12 * k12 + k22 * k22)
                           + nu * (k11 + k22) ** 2)
    f = f * (a * big_r)
    v = -0.5 * (x[..., 0] * cross[..., 0] + x[..., 1] * cross[..., 1])
    return f - liquid * x[..., 2] * v - net_pressure * v


def _steps(radius: float, rest_radius: np.ndarray) -> np.ndarray:
    """(P, 18): the central-difference step of each jet entry at each Gauss point, 1e-5 of its
    scale: a for x, the point's rest radius R for x_theta and x_thetatheta (their size, r:
    near the pole a step of a would be far larger than they are), 1 for x_S and x_Stheta,
    1/a for x_SS."""
    big_r = np.asarray(rest_radius, dtype=float)[:, None]
    scale = np.concatenate([np.full((len(big_r), 3), radius), np.ones((len(big_r), 3)),
                            np.repeat(big_r, 3, axis=1), np.full((len(big_r), 3), 1 / radius),
                            np.ones((len(big_r), 3)), np.repeat(big_r, 3, axis=1)], axis=1)
    return 1e-5 * scale


def base_jet(shell: ShellOfRevolution, state: np.ndarray) -> np.ndarray:
    """(P, 18): the jet of the axisymmetric ``state`` (4 n,) at theta = 0 at the Gauss
    points (module doc)."""
    u = local_variables(shell.meridian, state).reshape(-1, 6)
    r, r1, r2, z, z1, z2 = u.T
    zero = np.zeros_like(r)
    return np.stack([r, zero, z, r1, zero, z1, zero, r, zero, r2, zero, z2, zero, r1, zero,
                     -r, zero, zero], -1)


def base_regime(shell: ShellOfRevolution, jet: np.ndarray, rest: dict) -> np.ndarray:
    """(P,) int: the tension field's regime (:func:`structure.axisymmetric.laws.regimes`) of
    the axisymmetric state of ``jet`` (P, 18) at the Gauss points."""
    xs, xt = jet[:, 3:6], jet[:, 6:9]
    es = 0.5 * (_dot(xs, xs) / rest["metric"] ** 2 - 1.0)
    et = 0.5 * (_dot(xt, xt) / rest["radius"] ** 2 - 1.0)
    return regimes(shell.law, es, et)


def wall_hessian(shell: ShellOfRevolution, jet: np.ndarray, rest: dict) -> np.ndarray:
    """(P, 3, 3): the barrier's Hessian in x (J/m^2 per unit S and theta) in closed form:
    A R kappa [b'' n n^T + b' (I - n n^T) / |x|], n = x / |x| (module doc)."""
    wall = shell.wall
    x = jet[:, :3]
    rho = np.linalg.norm(x, axis=1)
    d = wall.radius + wall.tolerance - rho
    _, b1, b2 = barrier(d, wall.tolerance, 2)
    n = x / rho[:, None]
    nn = n[:, :, None] * n[:, None, :]
    scale = wall.stiffness * rest["area"] / (2 * np.pi)
    return scale[:, None, None] * (b2[:, None, None] * nn
                                   - (b1 / rho)[:, None, None] * (np.eye(3) - nn))


def jet_hessian(shell: ShellOfRevolution, state: np.ndarray, liquid: float,
                net_pressure: float) -> np.ndarray:
    """(P, 18, 18): H = d2 f / dJ2 at the Gauss points of the axisymmetric ``state`` (module
    doc); its entries (i, j >= i) by complex step in i and central difference in j, the rest
    by symmetry."""
    jet = base_jet(shell, state)
    rest = rest_at_points(shell.meridian)
    if shell.tension_field:
        rest["regime"] = base_regime(shell, jet, rest)
    steps = _steps(shell.radius, rest["radius"])
    p = len(jet)
    h_complex = 1e-30
    hess = np.empty((p, JET, JET))
    for i in range(JET):                 # row i from column i on; the rest by symmetry
        probe = jet.astype(complex)
        probe[:, i] += 1j * h_complex
        half = JET - i
        ahead = np.zeros((half, p, JET))                                 # (18 - i, P, 18)
        ahead[np.arange(half), :, np.arange(i, JET)] = steps[:, i:].T
        trial = probe[None, :, :] + np.concatenate([ahead, -ahead])
        g = surface_density(shell, trial, rest, liquid, net_pressure).imag / h_complex
        hess[:, i, i:] = ((g[:half] - g[half:]) / (2 * steps[:, i:].T)).T
        hess[:, i:, i] = hess[:, i, i:]
    if shell.wall is not None:
        hess[:, :3, :3] += wall_hessian(shell, jet, rest)
    return hess


def _jet_maps(n: int) -> tuple[np.ndarray, np.ndarray]:
    """(P_a, P_b), each (3, 18, 9): the jets a and b of harmonic n as polynomials in n
    (index 0, 1, 2 the coefficients of 1, n, n^2) times q (module doc)."""
    pa, pb = np.zeros((3, JET, FIELDS)), np.zeros((3, JET, FIELDS))
    U, U1, U2, V, V1, V2, W, W1, W2 = range(FIELDS)
    # a: x (U, 0, W); x_S (U', 0, W'); x_theta (0, U + n V, 0); x_SS (U'', 0, W'');
    #    x_Stheta (0, U' + n V', 0); x_thetatheta (-((n^2 + 1) U + 2 n V), 0, -n^2 W)
    for row, col in ((0, U), (2, W), (3, U1), (5, W1), (7, U), (9, U2), (11, W2), (13, U1)):
        pa[0, row, col] = 1.0
    pa[1, 7, V] = pa[1, 13, V1] = 1.0
    pa[0, 15, U] = pa[2, 15, U] = -1.0
    pa[1, 15, V] = -2.0
    pa[2, 17, W] = -1.0
    # b: x (0, V, 0); x_S (0, V', 0); x_theta (-(n U + V), 0, -n W); x_SS (0, V'', 0);
    #    x_Stheta (-(n U' + V'), 0, -n W'); x_thetatheta (0, -(2 n U + (n^2 + 1) V), 0)
    for row, col in ((1, V), (4, V1), (10, V2)):
        pb[0, row, col] = 1.0
    pb[1, 6, U] = pb[0, 6, V] = pb[1, 8, W] = -1.0
    pb[1, 12, U1] = pb[0, 12, V1] = pb[1, 14, W1] = -1.0
    pb[1, 16, U] = -2.0
    pb[0, 16, V] = pb[2, 16, V] = -1.0
    return pa, pb


@dataclass(frozen=True)
class HarmonicStiffness:
    """The second variation of one equilibrium for every n, K_n = sum_k n^k K_k (k = 0..4,
    each (6 n_nodes, 6 n_nodes) CSR, J per unit dof^2, the pi of n >= 1 included), and the
    mass matrix M (kg per unit dof^2; pi included) on the nodal values (U, U', V, V', W, W')."""

    powers: tuple
    mass: sp.csr_matrix

    def stiffness(self, n: int) -> sp.csr_matrix:
        """K_n (n >= 1)."""
        return sum(float(n) ** k * m for k, m in enumerate(self.powers))


def _element_basis(shell: ShellOfRevolution) -> np.ndarray:
    """(m, q, 9, 12): q = B d of an element's twelve values (U_a, U'_a, U_b, U'_b, V..., W...)."""
    herm = shell.meridian.point_basis[..., 0:3, 0:4]                   # (m, q, 3, 4)
    out = np.zeros(herm.shape[:2] + (FIELDS, 12))
    for k in range(3):
        out[..., 3 * k:3 * k + 3, 4 * k:4 * k + 4] = herm
    return out


def _element_dofs(shell: ShellOfRevolution) -> np.ndarray:
    """(m, 12): the global entries of each element's twelve values."""
    m = len(shell.meridian.element_length)
    a = np.arange(m) * NODE_DOFS
    b = a + NODE_DOFS
    return np.stack([a, a + 1, b, b + 1, a + 2, a + 3, b + 2, b + 3, a + 4, a + 5, b + 4,
                     b + 5], axis=1)


def _assemble(shell: ShellOfRevolution, point: np.ndarray) -> sp.csr_matrix:
    """(6 nn, 6 nn): sum over Gauss points of w B^T point B, ``point`` (P, 9, 9)."""
    meridian = shell.meridian
    m, q = meridian.point_weight.shape
    basis = _element_basis(shell)
    per = (meridian.point_weight.ravel()[:, None, None] * point).reshape(m, q, FIELDS, FIELDS)
    element = (np.swapaxes(basis, 2, 3) @ per @ basis).sum(axis=1)
    dofs = _element_dofs(shell)
    size = NODE_DOFS * meridian.nodes
    rows = np.broadcast_to(dofs[:, :, None], element.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], element.shape).ravel()
    return sp.csr_matrix((element.ravel(), (rows, cols)), shape=(size, size))


def harmonic_stiffness(shell: ShellOfRevolution, state: np.ndarray, liquid: float,
                       net_pressure: float) -> HarmonicStiffness:
    """The second variation of ``shell`` at the axisymmetric equilibrium ``state`` (4 n,)
    under the liquid's weight density ``liquid`` rho g (N/m^3) and net pressure mu (Pa), for
    every n >= 1 (module doc)."""
    hess = jet_hessian(shell, state, liquid, net_pressure)
    pa, pb = _jet_maps(0)
    powers = []
    for k in range(5):
        point = np.zeros((len(hess), FIELDS, FIELDS))
        for i in range(3):
            j = k - i
            if 0 <= j <= 2:
                point += np.swapaxes(pa[i], 0, 1) @ hess @ pa[j]
                point += np.swapaxes(pb[i], 0, 1) @ hess @ pb[j]
        powers.append(np.pi * _assemble(shell, point))
    if shell.support == "roller":
        powers[0] = powers[0] + roller_closure(shell, state, liquid)
    rest = rest_at_points(shell.meridian)
    density = shell.material.density * shell.material.thickness * rest["area"] / (2 * np.pi)
    unit = np.zeros((FIELDS, FIELDS))
    unit[[0, 3, 6], [0, 3, 6]] = 1.0
    mass = np.pi * _assemble(shell, density[:, None, None] * unit)
    return HarmonicStiffness(tuple(powers), mass)


def roller_closure(shell: ShellOfRevolution, state: np.ndarray, liquid: float) -> sp.csr_matrix:
    """(6 nn, 6 nn): the second variation of the liquid under a ``roller`` rim's band of wall.

    The load potential closes the liquid through the rim's own plane
    (:mod:`~structure.axisymmetric.loads`), exact while the rim's height is held. A roller
    rim at radius r_0 rises by W cos(n theta) along its vertical wall, and the liquid gains
    the band of wall it uncovers: the flux of (rho g z + mu) (x, y, 0) / 2 through it,
    Int (rho g z + mu) dz r_0^2 / 2 dtheta, whose second variation in W is
    pi rho g r_0^2 W^2 / 2 (n >= 1; the first-order part integrates to zero over theta).
    Without it a flat sheet lying on the liquid would miss rho g r_0^2 / 2 of its free
    surface's stiffness pi rho g Int w^2 r dr."""
    size = NODE_DOFS * shell.meridian.nodes
    rim = size - NODE_DOFS + 4
    r0 = float(state[-4])
    return sp.csr_matrix(([0.5 * np.pi * liquid * r0 * r0], ([rim], [rim])), shape=(size, size))


def axisymmetric_hessian(shell: ShellOfRevolution, state: np.ndarray, liquid: float,
                         net_pressure: float) -> sp.csr_matrix:
    """(6 nn, 6 nn): 2 pi Int a^T H a dS at n = 0 (module doc), on the nodal values
    (U, U', V, V', W, W'): with V = 0 it is the axisymmetric Hessian of
    :func:`structure.axisymmetric.energy.evaluate` (a check of the surface energy)."""
    hess = jet_hessian(shell, state, liquid, net_pressure)
    pa, pb = _jet_maps(0)
    point = np.swapaxes(pa[0], 0, 1) @ hess @ pa[0]
    return 2 * np.pi * _assemble(shell, point)


def admissible_harmonic(shell: ShellOfRevolution, n: int) -> sp.csr_matrix:
    """(6 nn, k): the basis of the admissible nodal values of harmonic ``n`` >= 1 (module
    doc: the pole's regularity, the rim's support)."""
    size = NODE_DOFS * shell.meridian.nodes
    rim = size - NODE_DOFS
    U, U1, V, V1, W, W1 = range(NODE_DOFS)
    held = {W} if n == 1 else {U, V, W, W1}
    if n >= 3:
        held |= {U1, V1}
    columns = []
    if n == 1:                                            # U = -V at the pole
        column = np.zeros(size)
        column[[U, V]] = np.sqrt(0.5) * np.array([1.0, -1.0])
        columns.append(column)
        held |= {U, V}
    support = shell.support
    if support == "symmetric":
        rim_held = {W, U1, V1}
    elif support == "roller":
        rim_held = {U, V}
    else:
        rim_held = {U, V, W}
        if support == "clamped":
            rim_held |= {U1, W1}
            state = shell.meridian.rest_state
            tangent = state[[-3, -1]] / np.hypot(state[-3], state[-1])
            column = np.zeros(size)
            column[[rim + U1, rim + W1]] = tangent
            columns.append(column)
    held |= {rim + k for k in rim_held}
    free = np.array([k for k in range(size) if k not in held])
    rows = [np.nonzero(c)[0] for c in columns] + [free]
    cols = [np.full(len(r), j) for j, r in enumerate(rows[:-1])] \
        + [len(columns) + np.arange(len(free))]
    vals = [c[np.nonzero(c)[0]] for c in columns] + [np.ones(len(free))]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(size, len(columns) + len(free)))


@dataclass(frozen=True)
class HarmonicStability:
    """The lowest eigenvalue of each harmonic: ``wave_numbers`` (k,), ``eigenvalue`` (k,)
    1/s^2 (omega^2 of the lowest mode; negative where unstable), ``negative`` (k,) the number
    of negative eigenvalues, ``modes`` the lowest mode of each, (k, 6 nn) nodal (U, U', V, V',
    W, W') normalised to unit mass."""

    wave_numbers: np.ndarray
    eigenvalue: np.ndarray
    negative: np.ndarray
    modes: np.ndarray

    @property
    def stable(self) -> bool:
        return bool(np.all(self.negative == 0))

    @property
    def critical(self) -> int:
        """The wave number of the lowest eigenvalue."""
        return int(self.wave_numbers[int(np.argmin(self.eigenvalue))])


def _lowest(k: sp.csr_matrix, m: sp.csr_matrix, hint: Optional[float] = None,
            start: Optional[np.ndarray] = None):
    """(lowest eigenvalue, its mode, negative count) of K phi = lambda M phi, by shift-invert
    (ARPACK) at a shift sigma below the spectrum, K - sigma M positive definite by the signs
    of the pivots of its symmetric factorisation, which then serves the shift-invert too:
    sigma = -1e-9 s first (s the median of diag K / diag M; its negative pivots are the
    negative eigenvalues); where some are, from 1.25 ``hint`` (the neighbouring harmonic's
    lowest eigenvalue, when negative) or -1e-3 s, lowered fourfold until none is left.
    ``start`` seeds ARPACK (the neighbouring harmonic's mode). (Raising the shift by bisection
    toward the lowest eigenvalue, which speeds the iterations, costs more in factorisations
    than it saves: measured 2.8 s against 2.3 s for six tables.)"""
    scale = float(np.median(np.abs(k.diagonal()) / np.maximum(m.diagonal(), 1e-300)))
    sigma = -1e-9 * scale
    lu, negative = factor_symmetric(k - sigma * m)
    count = negative
    if count != 0 and hint is not None and hint < sigma:
        sigma = 1.25 * hint
        lu, count = factor_symmetric(k - sigma * m)
    while count != 0 and sigma > -1e12 * scale:
        sigma = min(4.0 * sigma, -1e-3 * scale)
        lu, count = factor_symmetric(k - sigma * m)
    seed = None if start is None or len(start) != k.shape[0] else start
    if lu is None or count != 0:
        values, vectors = eigsh(k, k=1, M=m, sigma=sigma, which="LM", tol=EIGEN_TOLERANCE,
                                v0=seed)
    else:
        inverse = LinearOperator(k.shape, matvec=lu.solve, dtype=float)
        values, vectors = eigsh(k, k=1, M=m, sigma=sigma, which="LM", OPinv=inverse,
                                tol=EIGEN_TOLERANCE, v0=seed)
    return float(values[0]), vectors[:, 0], (-1 if negative is None else negative)


def stability(shell: ShellOfRevolution, state: np.ndarray, liquid: float, net_pressure: float,
              wave_numbers: Sequence[int] = range(1, 31)) -> HarmonicStability:
    """The lowest eigenvalue of the second variation of each harmonic in ``wave_numbers``
    (n >= 1) at the axisymmetric equilibrium ``state`` (module doc)."""
    stiffness = harmonic_stiffness(shell, state, liquid, net_pressure)
    values, negatives, modes = [], [], []
    for n in wave_numbers:
        if n < 1:
            raise ValueError(f"wave numbers must be >= 1, got {n}")
        t = admissible_harmonic(shell, n)
        k = (t.T @ stiffness.stiffness(n) @ t).tocsc()
        m = (t.T @ stiffness.mass @ t).tocsc()
        value, mode, negative = _lowest(k, m, values[-1] if values else None,
                                        reduced if values else None)
        reduced = mode
        values.append(value)
        negatives.append(negative)
        modes.append(t @ mode)
    return HarmonicStability(np.asarray(list(wave_numbers)), np.array(values),
                             np.array(negatives), np.array(modes))
