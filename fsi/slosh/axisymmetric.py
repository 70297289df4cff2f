"""The slosh modes of the diaphragm as a shell of revolution: its second variation in the first
circumferential harmonic coupled to the liquid's potential flow on the meridional section.

About an axisymmetric equilibrium of the sheet (:mod:`structure.axisymmetric`), small motion
in the harmonic n = 1, du = U cos(theta) e_r + V sin(theta) e_theta + W cos(theta) e_z, obeys

    K_1 q + (M + M_a) q'' = 0

on the nodal values q = (U, U', V, V', W, W') that the pole and the rim admit:

* K_1, M: the sheet's second variation in the harmonic (elasticity, bending, prestress, the
  liquid's follower load with its hydrostatic gradient, the wall's barrier) and its mass
  (:func:`structure.axisymmetric.harmonics.harmonic_stiffness`; pi of the integral over
  theta included);
* M_a = pi rho G^T A^-1 G: the liquid's added mass. The liquid below the sheet flows with the
  potential Phi(r, z) cos(theta) (:mod:`fluid.section.potential`, A on P2 triangles of the
  section between the sheet and the tank, :func:`fluid.section.mesh.sphere_section`);
  G (fluid dofs x sheet values) is the trace Int Psi_i u_n r ds of the sheet's normal
  displacement u_n = U n_r + W n_z along its wet part, n the liquid's outward normal. The
  sheet's pressure -rho Phi_t works on u_n, so the liquid's kinetic energy is
  1/2 q'^T M_a q'.

**The wet part.** The sheet is wet from its pole to the first point where its gap to the wall
falls to ``contact_gap`` a; beyond, it lies on the wall (within the barrier's band) and the
liquid there is a film, left out: the section is closed by the wall from that point, its
radius blended from the point's onto the sphere's (:func:`fluid.section.mesh.sphere_section`).
The error of the left-out film falls with the gap (measured in the validation pages).

**Modes.** The lowest few eigenpairs omega^2 of K_1 q = omega^2 (M + M_a) q by ARPACK in
shift-invert mode about a shift just below zero, on dense matrices (M_a is dense on the wet
values): negative omega^2 are directions in which the equilibrium is unstable in n = 1.
lambda = omega^2 a / g.

**Slosh mass and hinge** (NASA SP-106's pendulum). Under a lateral tank acceleration x'' the
contents feel the body force -x'': the liquid as the pressure -rho x'' r cos(theta), which
loads the sheet by pi rho b (b_k = Int r u_n,k r ds), and the sheet by its mass on the
translation r_x (U = 1, V = -1). With f = pi rho b + M r_x, mode j's slosh mass is
m_j = (q_j . f)^2 / (q_j . (M + M_a) q_j), and the lateral force on the tank omega_j^2 q_j . f.
The liquid's pressure on the sphere and the barrier's force pass through the tank's centre;
the moment about it comes from the rim alone, the support's reaction
r_j = (K_1 - omega_j^2 (M + M_a)) q_j on the held values (zero on the admitted ones) against
the rotation r_y about the centre (U = z, V = -z, W = -r): the tank feels -r_j . r_y. The
pendulum's hinge is where the lateral force acts, at the height
h_j = -(r_j . r_y) / (omega_j^2 q_j . f) above the centre, its length g / omega_j^2. With no
rim (the free surface) the hinge is the centre: Dodge (2000), Sec. 3.4, the sphere's
pendulums hinge at its centre.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, partial
from typing import Callable, Optional

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigsh

from fluid.container import SphericalTank
from fluid.section.mesh import sphere_section
from fluid.section.potential import (boundary_facets, facet_coordinate, p2_trace,
                                     section_potential)
from structure.axisymmetric.harmonics import (NODE_DOFS, admissible_harmonic,
                                              harmonic_stiffness)
from structure.axisymmetric.hermite import gauss_rule, hermite_basis
from structure.axisymmetric.meridian import locate
from structure.axisymmetric.model import ShellOfRevolution, shell_of_revolution
from structure.hyperelastic import SaintVenantKirchhoff
from structure.parallel import process_map
from structure.model import Material

CONTACT_GAP = 1e-3
"""The sheet is wet up to where its gap to the wall falls to this fraction of a (module doc)."""
FLUID_CELLS = 16
"""Cells along each side of the section's three blocks."""
FLUID_GRADING = 2.0
"""The section's grading power towards the contact point."""
MODES = 8
"""Eigenpairs found about zero, among which the slosh mode is the one of largest slosh mass."""
ON_CURVE = 1e-9
"""A mesh node within this fraction of a of the sheet lies on it."""
TRACE_POINTS = 4
"""Gauss points per piece of a facet between the sheet's nodes."""


@dataclass(frozen=True)
class SheetCurve:
    """The sheet's meridian in the section's frame: ``shell``, ``state`` (4 n,), ``offset``
    (m) added to its heights, ``wet_end`` S (m) where the wet part ends."""

    shell: ShellOfRevolution
    state: np.ndarray
    offset: float
    wet_end: float

    def local(self, arc: np.ndarray):
        """(element (k,), basis (k, 3, 4), r (k, 3), z (k, 3)): at rest arc lengths ``arc``
        the element, the Hermite basis and r, z with their first two S-derivatives."""
        meridian = self.shell.meridian
        element, xi = locate(meridian, arc)
        basis = hermite_basis(xi, meridian.element_length[element])
        values = self.state[meridian.element_dofs[element]]
        r = np.einsum("kij,kj->ki", basis, values[:, 0:4])
        z = np.einsum("kij,kj->ki", basis, values[:, 4:8])
        z[:, 0] += self.offset
        return element, basis, r, z

    def points(self, arc: np.ndarray) -> np.ndarray:
        """(2, k): (r, z) m at ``arc`` (k,)."""
        _, _, r, z = self.local(np.asarray(arc, float))
        return np.vstack([r[:, 0], z[:, 0]])

    def top(self, s: np.ndarray) -> np.ndarray:
        """The wet part as a curve of s in [0, 1] (:data:`fluid.section.mesh.Curve`)."""
        return self.points(np.asarray(s, float) * self.wet_end)

    def project(self, points: np.ndarray):
        """(S (k,), distance (k,) m): the nearest point of the wet part to each of ``points``
        (2, k), by Newton from the nearest of a dense sampling."""
        samples = np.linspace(0.0, self.wet_end, 40 * len(self.shell.meridian.element_length))
        curve = self.points(samples)
        d2 = ((points[:, :, None] - curve[:, None, :]) ** 2).sum(axis=0)
        arc = samples[np.argmin(d2, axis=1)]
        for _ in range(8):
            _, _, r, z = self.local(arc)
            dr, dz = r[:, 0] - points[0], z[:, 0] - points[1]
            g = dr * r[:, 1] + dz * z[:, 1]
            h = r[:, 1] ** 2 + z[:, 1] ** 2 + dr * r[:, 2] + dz * z[:, 2]
            arc = np.clip(arc - g / h, 0.0, self.wet_end)
        return arc, np.hypot(*(self.points(arc) - points))


def wet_end(shell: ShellOfRevolution, state: np.ndarray, contact_gap: float = CONTACT_GAP,
            offset: float = 0.0, tank_radius: Optional[float] = None) -> float:
    """S (m): the first rest arc length from the pole at which the sheet's gap to the tank
    wall (the sphere of radius a, ``tank_radius`` or the rim's, about the origin) falls to
    ``contact_gap`` a; the rim's when it never does before the rim."""
    meridian = shell.meridian
    a = shell.radius if tank_radius is None else tank_radius
    curve = SheetCurve(shell, state, offset, meridian.shape.length)
    arc = np.linspace(0.0, meridian.shape.length, 50 * len(meridian.element_length) + 1)
    gap = a - np.hypot(*curve.points(arc))
    close = np.nonzero(gap <= contact_gap * a)[0]
    if len(close) == 0 or close[0] == len(arc) - 1:
        return float(meridian.shape.length)
    k = close[0]
    lo, hi = arc[k - 1], arc[k]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if a - np.hypot(*curve.points([mid]))[0] > contact_gap * a:
            lo = mid
        else:
            hi = mid
    return float(0.5 * (lo + hi))


@dataclass(frozen=True)
class WetTrace:
    """The sheet's coupling to the liquid: ``trace`` G (fluid dofs x 6 n) CSR, m^2 per unit
    Phi and q; ``moment`` b (6 n,) m^3, Int r u_n r ds of each nodal value (module doc)."""

    trace: sp.csr_matrix
    moment: np.ndarray


def wet_trace(curve: SheetCurve, mesh, fluid_dofs: int) -> WetTrace:
    """G and b of the wet part of ``curve`` on the P2 ``mesh`` (module doc); a node within
    :data:`ON_CURVE` of the mesh's extent from the curve lies on it."""
    shell = curve.shell
    scale = float(np.ptp(mesh.doflocs, axis=1).max())
    _, dofs = boundary_facets(mesh)
    arc, distance = (v.reshape(3, -1) for v in curve.project(mesh.doflocs[:, dofs.ravel()]))
    on_curve = (distance < ON_CURVE * scale).all(axis=0)
    dofs, nodes_arc = dofs[:, on_curve], arc[:, on_curve]
    sheet_nodes = shell.meridian.node_arc_length
    xg, wg = gauss_rule(TRACE_POINTS)
    arc, weight, facet = [], [], []
    for f in range(dofs.shape[1]):
        lo, hi = np.sort(nodes_arc[[0, 2], f])
        breaks = np.concatenate([[lo], sheet_nodes[(sheet_nodes > lo) & (sheet_nodes < hi)],
                                 [hi]])
        length = np.diff(breaks)
        arc.append((breaks[:-1, None] + xg[None, :] * length[:, None]).ravel())
        weight.append((wg[None, :] * length[:, None]).ravel())
        facet.append(np.full(arc[-1].shape, f))
    arc, weight, facet = (np.concatenate(v) for v in (arc, weight, facet))
    t = facet_coordinate(arc, nodes_arc[:, facet])
    psi = p2_trace(t)                                                   # (3, k)
    element, basis, r, z = curve.local(arc)
    # u_n r ds = (U (-z') + W r') r dS (n = (-z', r') / |X'|, ds = |X'| dS)
    value = basis[:, 0, :]                                              # (k, 4)
    w_r, w_z = -z[:, 1] * r[:, 0] * weight, r[:, 1] * r[:, 0] * weight
    nodes = np.stack([element, element, element + 1, element + 1], 1) * NODE_DOFS \
        + np.array([0, 1, 0, 1])
    sheet = np.concatenate([nodes, nodes + 4], axis=1)                  # U's then W's
    coefficient = np.concatenate([value * w_r[:, None], value * w_z[:, None]], axis=1)
    rows = np.broadcast_to(dofs[:, facet].T[:, :, None], (len(arc), 3, 8))
    cols = np.broadcast_to(sheet[:, None, :], (len(arc), 3, 8))
    vals = psi.T[:, :, None] * coefficient[:, None, :]
    size = NODE_DOFS * shell.meridian.nodes
    trace = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())),
                          shape=(fluid_dofs, size))
    moment = np.bincount(sheet.ravel(), weights=(coefficient * r[:, [0]]).ravel(),
                         minlength=size)
    return WetTrace(trace, moment)


def added_mass(potential, trace: sp.csr_matrix, liquid_density: float):
    """(values (k,), block (k, k)): M_a = pi rho G^T A^-1 G on the free fluid dofs (module
    doc), kg per unit q^2, nonzero on the sheet's ``values`` (its wet part's) alone."""
    g = trace[potential.free].tocsc()
    values = np.unique(g.nonzero()[1])
    g = g[:, values]
    touched = np.unique(g.nonzero()[0])
    lu = sp.linalg.splu(potential.reduced, permc_spec="COLAMD")
    unit = np.zeros((g.shape[0], len(touched)))
    unit[touched, np.arange(len(touched))] = 1.0
    schur = lu.solve(unit)[touched]                                     # (A^-1)_bb
    gb = g[touched].toarray()
    return values, np.pi * liquid_density * gb.T @ (0.5 * (schur + schur.T)) @ gb


@dataclass(frozen=True)
class SheetOperators:
    """The sheet's side of the modes (module doc): ``stiffness`` K_1 and ``mass`` M (6 n,
    6 n) CSR, ``basis`` T (6 n, k) CSR of the admitted values, ``translation`` r_x and
    ``rotation`` r_y (6 n,)."""

    stiffness: sp.csr_matrix
    mass: sp.csr_matrix
    basis: sp.csr_matrix
    translation: np.ndarray
    rotation: np.ndarray

    @cached_property
    def reduced_stiffness(self) -> np.ndarray:
        """T^T K_1 T, a dense matrix of the admitted values' count squared."""
        return (self.basis.T @ self.stiffness @ self.basis).toarray()

    @cached_property
    def reduced_mass(self) -> np.ndarray:
        """T^T M T, a dense matrix of the admitted values' count squared."""
        return (self.basis.T @ self.mass @ self.basis).toarray()


def sheet_operators(shell: ShellOfRevolution, state: np.ndarray, liquid_weight: float,
                    net_pressure: float, centre: float = 0.0) -> SheetOperators:
    """K_1, M, T and the rigid motions of ``shell`` at ``state`` under the liquid's weight
    density ``liquid_weight`` rho g (N/m^3) and the net pressure mu (Pa), the tank's centre
    at height ``centre`` m in the sheet's frame."""
    stiffness = harmonic_stiffness(shell, state, liquid_weight, net_pressure)
    k = stiffness.stiffness(1)
    translation, rotation = rigid_vectors(shell, state, centre)
    return SheetOperators((0.5 * (k + k.T)).tocsr(), stiffness.mass,
                          admissible_harmonic(shell, 1), translation, rotation)


def rigid_vectors(shell: ShellOfRevolution, state: np.ndarray, centre: float = 0.0):
    """(translation r_x (6 n,), rotation r_y (6 n,)): the lateral translation along x and the
    rotation about the y axis through the tank's centre at height ``centre`` m, as nodal
    values of the harmonic n = 1 (module doc)."""
    nodes = shell.meridian.nodes
    nodal = state.reshape(nodes, 4)
    r, dr, z, dz = nodal.T
    translation = np.zeros((nodes, NODE_DOFS))
    translation[:, 0], translation[:, 2] = 1.0, -1.0
    rotation = np.stack([z - centre, dz, -(z - centre), -dz, -r, -dr], axis=1)
    return translation.ravel(), rotation.ravel()


@dataclass(frozen=True)
class AxisymmetricSlosh:
    """The n = 1 modes about one equilibrium: ``omega2`` (k,) 1/s^2 ascending; ``lam`` (k,)
    omega^2 a / g; ``slosh_mass`` (k,) kg; ``hinge`` (k,) m above the tank's centre;
    ``modes`` (k, 6 n) nodal values; ``slosh`` the index of the slosh mode (the largest
    slosh mass among the stable ones); ``unstable`` the count of omega^2 < 0 found;
    ``liquid_mass`` kg; ``wet_end`` m; ``fluid_dofs``."""

    omega2: np.ndarray
    lam: np.ndarray
    slosh_mass: np.ndarray
    hinge: np.ndarray
    modes: np.ndarray
    slosh: int
    unstable: int
    liquid_mass: float
    wet_end: float
    fluid_dofs: int

    @property
    def lambda1(self) -> float:
        return float(self.lam[self.slosh])

    @property
    def slosh_mass_fraction(self) -> float:
        """m_1 over the liquid's mass."""
        return float(self.slosh_mass[self.slosh] / self.liquid_mass)

    @property
    def hinge_height(self) -> float:
        return float(self.hinge[self.slosh])


def _eigenpairs(k: np.ndarray, m: np.ndarray, count: int, scale: float):
    """The ``count`` eigenpairs of K q = omega^2 M q nearest a shift 1e-6 ``scale`` below
    zero (M may be singular: a massless sheet's values that carry no liquid)."""
    sigma = -1e-6 * scale
    lu = la.lu_factor(k - sigma * m)
    inverse = LinearOperator(k.shape, matvec=lambda x: la.lu_solve(lu, x), dtype=float)
    values, vectors = eigsh(k, k=min(count, k.shape[0] - 2), M=m, sigma=sigma, which="LM",
                            OPinv=inverse, tol=1e-12)
    order = np.argsort(values)
    return values[order], vectors[:, order]


def axisymmetric_slosh(shell: ShellOfRevolution, state: np.ndarray, liquid_density: float,
                       gravity: float, net_pressure: float, liquid_volume: float,
                       section: Optional[Callable] = None, wet: Optional[float] = None,
                       offset: float = 0.0, contact_gap: float = CONTACT_GAP,
                       fluid_cells: int = FLUID_CELLS, modes: int = MODES,
                       centre: float = 0.0, tank_radius: Optional[float] = None,
                       sheet: Optional[SheetOperators] = None) -> AxisymmetricSlosh:
    """The n = 1 modes of ``shell`` at the equilibrium ``state`` (4 n,) on the liquid below it
    (module doc): ``liquid_density`` rho kg/m^3, ``gravity`` g m/s^2, ``net_pressure`` mu Pa
    (the equilibrium's), ``liquid_volume`` m^3 (for the slosh mass fraction). ``section``
    maps the wet part's curve to the liquid's P2 mesh (the sphere of radius a about the
    origin below it by default, ``fluid_cells`` cells a block); ``wet`` the wet part's end S
    (by ``contact_gap`` by default); ``offset`` m raises the sheet in the section's frame;
    ``centre`` m the height of the tank's centre there; ``tank_radius`` a m (the rim's by
    default), which scales lambda; ``sheet`` the sheet's operators when already formed
    (:func:`sheet_operators`)."""
    a = shell.radius if tank_radius is None else tank_radius
    wet = wet_end(shell, state, contact_gap, offset, a) if wet is None else wet
    curve = SheetCurve(shell, state, offset, wet)
    if section is None:
        def section(top):
            return sphere_section(top, fluid_cells, FLUID_GRADING, radius=a)
    potential = section_potential(section(curve.top), 1)
    coupling = wet_trace(curve, potential.mesh, potential.basis.N)
    if sheet is None:
        sheet = sheet_operators(shell, state, liquid_density * gravity, net_pressure,
                                centre - offset)
    values, block = added_mass(potential, coupling.trace, liquid_density)
    t = sheet.basis
    tw = t[values]                                                      # (wet, k) CSR
    k = sheet.reduced_stiffness
    m = sheet.reduced_mass + (tw.T @ (tw.T @ block).T).T
    omega2, reduced = _eigenpairs(k, m, modes, gravity / a)
    full = (t @ reduced).T                                              # (k, 6 n)
    load = np.pi * liquid_density * coupling.moment + sheet.mass @ sheet.translation
    participation = full @ load
    modal_mass = np.einsum("ki,ij,kj->k", reduced.T, m, reduced.T)
    inertia = (sheet.mass @ full.T).T
    inertia[:, values] += full[:, values] @ block
    reaction = (sheet.stiffness @ full.T).T - omega2[:, None] * inertia
    with np.errstate(divide="ignore", invalid="ignore"):
        hinge = -(reaction @ sheet.rotation) / (omega2 * participation)
    slosh_mass = participation**2 / modal_mass
    stable = omega2 > 0
    index = int(np.argmax(np.where(stable, slosh_mass, -np.inf)))
    return AxisymmetricSlosh(omega2, omega2 * a / gravity, slosh_mass, hinge, full, index,
                             int(np.sum(~stable)), liquid_density * liquid_volume, wet,
                             len(potential.free))


CONTACT_GAPS = (1e-3, 5e-4, 2.5e-4)
"""The wet part's end gaps (fraction of a) of :func:`converged_slosh`, each half the last."""


@dataclass(frozen=True)
class ConvergedSlosh:
    """The slosh mode extrapolated to a wet part that reaches the wall (gap 0) from
    :data:`CONTACT_GAPS`: ``lambda1``, ``slosh_mass_fraction``, ``hinge`` (m above the tank's
    centre), each Richardson's value over the gaps with its ``observed_order`` (of lambda1;
    None where the differences do not shrink monotonically, then the finest gap's values);
    ``by_gap`` the :class:`AxisymmetricSlosh` of each gap."""

    lambda1: float
    slosh_mass_fraction: float
    hinge: float
    observed_order: Optional[float]
    by_gap: tuple

    @property
    def unstable(self) -> int:
        """Directions of negative stiffness in n = 1 found (at the finest gap)."""
        return self.by_gap[-1].unstable


def _richardson(values, order: Optional[float]) -> float:
    f1, f2, f3 = values
    if order is None:
        return float(f3)
    return float(f3 + (f3 - f2) / (2.0**order - 1))


def converged_slosh(shell: ShellOfRevolution, state: np.ndarray, liquid_density: float,
                    gravity: float, net_pressure: float, liquid_volume: float,
                    gaps=CONTACT_GAPS, **options) -> ConvergedSlosh:
    """:func:`axisymmetric_slosh` at each wet end of ``gaps`` (three, each half the last; the
    sheet's operators formed once), extrapolated to gap 0 by Richardson at the observed order
    of lambda1 (module doc: the film left out beyond the wet end shifts lambda1 at first
    order in the gap). ``options`` go to :func:`axisymmetric_slosh`."""
    if len(gaps) != 3:
        raise ValueError(f"converged_slosh needs three gaps, got {len(gaps)}")
    sheet = sheet_operators(shell, state, liquid_density * gravity, net_pressure,
                            options.get("centre", 0.0) - options.get("offset", 0.0))
    runs = tuple(axisymmetric_slosh(shell, state, liquid_density, gravity, net_pressure,
                                    liquid_volume, contact_gap=g, sheet=sheet, **options)
                 for g in gaps)
    lam = [r.lambda1 for r in runs]
    d1, d2 = lam[1] - lam[0], lam[2] - lam[1]
    order = float(np.log(d1 / d2) / np.log(2.0)) if d1 * d2 > 0 and abs(d1) > abs(d2) \
        else None
    return ConvergedSlosh(_richardson(lam, order),
                          _richardson([r.slosh_mass_fraction for r in runs], order),
                          _richardson([r.hinge_height for r in runs], order), order, runs)


def free_surface_slosh(tank_fraction: float, tank_radius: float, liquid_density: float,
                       gravity: float, elements: int = 32,
                       fluid_cells: int = FLUID_CELLS) -> AxisymmetricSlosh:
    """The limp limit (E, D and the sheet's mass -> 0): a massless flat disc of negligible
    stiffness at the free surface's level in the sphere of ``tank_radius`` m filled to
    ``tank_fraction``, its rim on a roller (the contact line moves), on ``elements``
    meridian elements: its modes are the free surface's."""
    a = tank_radius
    volume = tank_fraction * 4.0 / 3.0 * np.pi * a**3
    level = SphericalTank(a).level_holding(volume)
    youngs = 1e-9 * liquid_density * gravity * a
    shell = shell_of_revolution("disc", float(np.sqrt(a * a - level * level)),
                                Material(1e-3 * a, 0.0, youngs, 0.3),
                                SaintVenantKirchhoff(youngs, 0.3), elements, support="roller",
                                bending=False)
    return axisymmetric_slosh(shell, shell.meridian.rest_state, liquid_density, gravity, 0.0,
                              volume, wet=shell.meridian.shape.length, offset=level,
                              tank_radius=a, fluid_cells=fluid_cells)


def fill_slosh(shell: ShellOfRevolution, equilibrium, tank_fraction: float,
               liquid_density: float, gravity: float) -> dict:
    """The slosh row of one fill's axisymmetric ``equilibrium``
    (:class:`structure.axisymmetric.solve.AxisymmetricEquilibrium`) at ``tank_fraction``:
    ``lambda1_full`` = omega^2 a / g of the slosh mode, its ``slosh_mass_fraction`` (over the
    liquid's mass) and ``hinge`` (m above the tank's centre), extrapolated in the wet part's
    gap (:func:`converged_slosh`) with ``wet_gap_order``; ``lambda1_lowest`` and
    ``lowest_slosh_mass_fraction``, the lowest stable mode's at the finest gap (NaN where
    none of the modes found is stable);
    ``unstable_n1``, the directions of negative stiffness in n = 1; ``lambda1_free`` and
    ``free_slosh_mass_fraction``, the free surface's at the same fill
    (:func:`free_surface_slosh`)."""
    a = shell.radius
    e = equilibrium
    volume = tank_fraction * 4.0 / 3.0 * np.pi * a**3
    slosh = converged_slosh(shell, e.state, liquid_density, gravity,
                            e.pressure - e.pressure_level, volume)
    finest = slosh.by_gap[-1]
    stable = finest.omega2 > 0
    lowest = int(np.argmax(stable))
    free = free_surface_slosh(tank_fraction, a, liquid_density, gravity)
    return dict(tank_fraction=float(tank_fraction), lambda1_full=slosh.lambda1,
                slosh_mass_fraction=slosh.slosh_mass_fraction, hinge=slosh.hinge,
                wet_gap_order=slosh.observed_order,
                lambda1_lowest=float(finest.lam[lowest]) if stable.any() else np.nan,
                lowest_slosh_mass_fraction=float(finest.slosh_mass[lowest] / finest.liquid_mass)
                if stable.any() else np.nan,
                unstable_n1=slosh.unstable, lambda1_free=free.lambda1,
                free_slosh_mass_fraction=free.slosh_mass_fraction)


def _fill_slosh_item(shell, liquid_density, gravity, item):
    return fill_slosh(shell, item[0], item[1], liquid_density, gravity)


def fill_slosh_table(shell: ShellOfRevolution, equilibria, tank_fractions,
                     liquid_density: float, gravity: float,
                     workers: Optional[int] = 1) -> list[dict]:
    """:func:`fill_slosh` at each of the ``equilibria`` and its tank fraction, over ``workers``
    processes (:func:`structure.parallel.process_map`; None: every core)."""
    return process_map(partial(_fill_slosh_item, shell, liquid_density, gravity),
                       list(zip(equilibria, tank_fractions)), workers)
