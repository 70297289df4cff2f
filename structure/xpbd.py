"""XPBD membrane: Saint Venant-Kirchhoff triangles and calibrated bending as compliant
constraints (Macklin, Mueller & Chentanez 2016), stepped in small substeps (Macklin et al.
2019), with the liquid volume as a hard constraint whose multiplier is the pressure level.

Constraints, each a block of three with a compliance matrix alpha (inverse stiffness) derived
from E, t and nu only, so that the stiffness does not depend on the iteration count or the
time step (the point of XPBD over the thesis's strain limiting):

* membrane, per triangle: the Green strain (E00, E11, E01) in the triangle's reference frame,
  energy 1/2 C^T S C with S = A t E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, 2 (1 - nu)]]
  (plane stress), alpha = S^-1;
* bending, per triangle: the three dihedral-angle changes of :mod:`structure.bending`,
  alpha = K_T^-1 (K_T built from D = E t^3 / 12 (1 - nu^2) and the triangle's shape);
* volume: V(x) - V_target with alpha = 0 (the liquid is incompressible); its multiplier over
  dt^2 is the uniform pressure level (Pa) added to the hydrostatic field;
* tank wall: |x| <= R for every free node (inequality, projected).

Each substep: v += dt W f_ext (hydrostatic pressure p(x) on the node area vectors dV/dx,
gravity), x = x + dt v, then ``iterations`` Gauss-Seidel sweeps of
dlambda = -(J W J^T + alpha / dt^2)^-1 (C + alpha lambda / dt^2), x += W J^T dlambda,
and v = (x - x_start) / dt.

Warm start (statics).  Plain XPBD sets lambda = 0 each substep; with a finite number of
sweeps its steady state then carries a bias of relative size ~ dt^2 k / m (each constraint is
met against positions part-way through the sweep): measured on a Hencky disc, the membrane
looks 2.8x too soft at dt = 2 ms and 1.3x at 0.5 ms.  With ``warm_start`` each substep starts
from the previous multipliers and the positions displaced by W J^T lambda (the implicit-Euler
relation M (x - x_pred) = J^T lambda) and the velocities are removed after each substep (a
quasi-static fixed-point iteration): a steady state then has dlambda = 0 and x = x_start,
which is exactly grad(elastic energy) = f_ext + level dV/dx, whatever dt and the sweep count.
This iteration treats the constraint directions explicitly and is not robust where the
membrane is compressed and buckles (the inversion of the hemisphere): there it can collapse
triangles, and :func:`solve_equilibrium` raises :class:`XpbdDivergence`.  Without warm start
the substeps are dynamic (velocities kept) with kinetic damping (velocities removed at each
kinetic-energy peak), robust but biased as above.

Dynamics.  :func:`advance` steps one time window of a coupled run: plain substeps with the
liquid-side pressure of the window held on the nodes and the liquid volume prescribed, the
membrane's own inertia kept (its stiffness bias ~ dt^2, as measured above, sets the substep).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
from numba import njit

from .bending import MidedgeBending, _triangle
from .grid import triangles_from_quads
from .hyperelastic import TriangleMembrane
from .kernels import closed_volume_gradient, closed_volume_term, wall_collision
from .model import MembraneModel, MembraneState
from .volume import liquid_volume, liquid_volume_gradient, lower_hemisphere_volume

JIT = dict(cache=True, nogil=True)


@dataclass(frozen=True)
class XpbdModel:
    """Fixed data of the XPBD membrane built on a :class:`MembraneModel`'s grid, masses and
    fixed nodes.

    triangles (m, 3) int64 (the quads split as App. D does); rest_inverse (m, 2, 2) and
    rest_area (m,) m^2 of the reference triangles; membrane_compliance (m, 3, 3) 1/J (alpha of
    the Green-strain block); bending (:class:`MidedgeBending`); bending_compliance (m, 3, 3)
    1/(N m) (alpha of the angle block, zero rows on edges without an angle).
    """

    base: MembraneModel
    triangles: np.ndarray
    rest_inverse: np.ndarray
    rest_area: np.ndarray
    membrane_compliance: np.ndarray
    bending: MidedgeBending
    bending_compliance: np.ndarray

    @classmethod
    def from_membrane(cls, base: MembraneModel, bending_boundary: str = "clamped") -> "XpbdModel":
        """XPBD constraints for ``base``: its material's E (Pa), t (m) and nu (-, <= 0.5)."""
        mat = base.material
        if not 0.0 <= mat.poisson_ratio <= 0.5:
            raise ValueError(f"poisson_ratio must be in [0, 0.5], got {mat.poisson_ratio}")
        tri = triangles_from_quads(base.face_nodes)
        # the grid's quads wind with their normal to the gas side; orientation does not matter
        # for strains and angles
        membrane = TriangleMembrane(base.node_rest_position, tri, mat.thickness)
        nu = mat.poisson_ratio
        k = mat.youngs_modulus / (1.0 - nu * nu)
        plane_stress = k * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 2.0 * (1.0 - nu)]])
        stiffness = (mat.thickness * membrane.rest_area)[:, None, None] * plane_stress
        bending = MidedgeBending.build(base.node_rest_position, tri, mat.flexural_rigidity,
                                       nu, bending_boundary)
        return cls(base, tri, membrane.rest_inverse, membrane.rest_area,
                   np.ascontiguousarray(np.linalg.inv(stiffness)), bending,
                   np.ascontiguousarray(np.linalg.pinv(bending.stiffness, hermitian=True)))


@dataclass(frozen=True)
class XpbdSettings:
    """Substep settings.

    dt : substep (s); iterations : Gauss-Seidel sweeps per substep (-); warm_start : carry the
    multipliers between substeps, quasi-static (module doc); bending : include the bending
    block; kinetic_damping : without warm start, zero the velocities at each kinetic-energy
    peak;
    tolerance : converged when max |dx| / L_node per substep < tolerance (-);
    level_tolerance : and the level changes by less than this per substep (Pa);
    ramp_rate : the volume target moves by at most this fraction of the tank volume per substep;
    max_steps : cap on substeps per solve.
    """

    dt: float = 1e-3
    iterations: int = 1
    warm_start: bool = True
    bending: bool = True
    kinetic_damping: bool = True
    tolerance: float = 1e-6
    level_tolerance: float = 0.01
    ramp_rate: float = 1e-3
    max_steps: int = 200_000

    def __post_init__(self):
        if not self.dt > 0:
            raise ValueError(f"xpbd dt must be > 0 s, got {self.dt!r}")
        if self.iterations < 1:
            raise ValueError(f"xpbd iterations must be >= 1, got {self.iterations!r}")
        if not self.tolerance > 0:
            raise ValueError(f"xpbd tolerance must be > 0, got {self.tolerance!r}")
        if not 0 < self.ramp_rate <= 1:
            raise ValueError(f"xpbd ramp_rate must be in (0, 1], got {self.ramp_rate!r}")


@njit(**JIT, inline="always")
def _solve3(a, r, out):
    """out = a^-1 r for a symmetric 3 x 3 a (Cramer); rows with a zero diagonal are skipped."""
    for i in range(3):
        if a[i, i] == 0.0:
            a[i, i] = 1.0
            r[i] = 0.0
    c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
    c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
    c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
    det = a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02
    if det == 0.0:
        out[:] = 0.0
        return
    c10 = a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]
    c11 = a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]
    c12 = a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]
    c20 = a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]
    c21 = a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]
    c22 = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
    out[0] = (c00 * r[0] + c10 * r[1] + c20 * r[2]) / det
    out[1] = (c01 * r[0] + c11 * r[1] + c21 * r[2]) / det
    out[2] = (c02 * r[0] + c12 * r[1] + c22 * r[2]) / det


@njit(**JIT, inline="always")
def _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only, a, r,
           dlam):
    """One XPBD block update of three constraints: nodes (3, k) (-1: none), grads (3, k, 3),
    value (3,), compliance alpha (3, 3); lam[t] updated.  With apply_only, x += W J^T lam[t].
    a (3, 3), r (3,), dlam (3,) are scratch."""
    k = nodes.shape[1]
    if apply_only:
        for i in range(3):
            dlam[i] = lam[t, i]
    else:
        for i in range(3):
            for j in range(i, 3):
                s = 0.0
                for p in range(k):
                    n = nodes[i, p]
                    if n < 0:
                        continue
                    for q in range(k):
                        if nodes[j, q] == n:
                            s += inv_mass[n] * (grads[i, p, 0] * grads[j, q, 0]
                                                + grads[i, p, 1] * grads[j, q, 1]
                                                + grads[i, p, 2] * grads[j, q, 2])
                a[i, j] = s + compliance[t, i, j] * inv_dt2
                a[j, i] = a[i, j]
        for i in range(3):
            s = value[i]
            for j in range(3):
                s += compliance[t, i, j] * inv_dt2 * lam[t, j]
            r[i] = -s
        _solve3(a, r, dlam)
        for i in range(3):
            lam[t, i] += dlam[i]
    for i in range(3):
        for p in range(k):
            n = nodes[i, p]
            if n >= 0 and inv_mass[n] > 0.0:
                w = inv_mass[n] * dlam[i]
                x[n, 0] += w * grads[i, p, 0]
                x[n, 1] += w * grads[i, p, 1]
                x[n, 2] += w * grads[i, p, 2]


@njit(**JIT)
def _membrane_sweep(x, inv_mass, triangles, rest_inverse, compliance, lam, inv_dt2, apply_only):
    """Green-strain blocks of every triangle with a free node (Gauss-Seidel)."""
    nodes = np.empty((3, 3), dtype=np.int64)
    grads = np.empty((3, 3, 3))
    value = np.empty(3)
    f0 = np.empty(3)
    f1 = np.empty(3)
    a3, r3, d3 = np.empty((3, 3)), np.empty(3), np.empty(3)
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        if inv_mass[a] == 0.0 and inv_mass[b] == 0.0 and inv_mass[c] == 0.0:
            continue
        d = rest_inverse[t]
        for r in range(3):
            e1 = x[b, r] - x[a, r]
            e2 = x[c, r] - x[a, r]
            f0[r] = e1 * d[0, 0] + e2 * d[1, 0]
            f1[r] = e1 * d[0, 1] + e2 * d[1, 1]
        s0 = np.sqrt(f0[0] * f0[0] + f0[1] * f0[1] + f0[2] * f0[2])
        s1 = np.sqrt(f1[0] * f1[0] + f1[1] * f1[1] + f1[2] * f1[2])
        cos01 = (f0[0] * f1[0] + f0[1] * f1[1] + f0[2] * f1[2]) / (s0 * s1)
        value[0] = s0 - 1.0
        value[1] = s1 - 1.0
        value[2] = 0.5 * cos01
        for i in range(3):
            nodes[i, 0], nodes[i, 1], nodes[i, 2] = b, c, a
        for r in range(3):
            u0 = f0[r] / s0
            u1 = f1[r] / s1
            g0 = 0.5 * (u1 - cos01 * u0) / s0      # d value[2] / d f0
            g1 = 0.5 * (u0 - cos01 * u1) / s1      # d value[2] / d f1
            grads[0, 0, r] = u0 * d[0, 0]
            grads[0, 1, r] = u0 * d[1, 0]
            grads[1, 0, r] = u1 * d[0, 1]
            grads[1, 1, r] = u1 * d[1, 1]
            grads[2, 0, r] = g0 * d[0, 0] + g1 * d[0, 1]
            grads[2, 1, r] = g0 * d[1, 0] + g1 * d[1, 1]
            for i in range(3):
                grads[i, 2, r] = -grads[i, 0, r] - grads[i, 1, r]
        _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only,
               a3, r3, d3)


@njit(**JIT)
def _bending_sweep(x, inv_mass, triangles, flap, ghost, active, rest_angle, compliance, lam,
                   inv_dt2, apply_only):
    """Angle blocks of every triangle whose stencil has a free node (Gauss-Seidel)."""
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    value = np.empty(3)
    a3, r3, d3 = np.empty((3, 3)), np.empty(3), np.empty(3)
    for t in range(triangles.shape[0]):
        free = False
        for i in range(3):
            if inv_mass[triangles[t, i]] > 0.0 or (flap[t, i] >= 0
                                                   and inv_mass[flap[t, i]] > 0.0):
                free = True
        if not free:
            continue
        _triangle(x, triangles, flap, ghost, active, rest_angle, t, nodes, grads, value)
        _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only,
               a3, r3, d3)


@njit(**JIT)
def _volume(x, inv_mass, faces, sign, base_volume, target, lam, apply_only):
    """Hard volume constraint V(x) = target (alpha = 0, one update); lam (1,) updated."""
    grad = closed_volume_gradient(x, faces, sign)
    if apply_only:
        dlam = lam[0]
    else:
        c = base_volume + closed_volume_term(x, faces, sign) - target
        denom = 0.0
        for n in range(x.shape[0]):
            denom += inv_mass[n] * (grad[n, 0] ** 2 + grad[n, 1] ** 2 + grad[n, 2] ** 2)
        dlam = -c / denom
        lam[0] += dlam
    for n in range(x.shape[0]):
        w = inv_mass[n] * dlam
        x[n, 0] += w * grad[n, 0]
        x[n, 1] += w * grad[n, 1]
        x[n, 2] += w * grad[n, 2]


@dataclass
class XpbdMultipliers:
    """Accumulated multipliers lambda (units of constraint^-1 J s^2): membrane (m, 3),
    bending (m, 3), volume (1,); the pressure level is volume[0] / dt^2 (Pa)."""

    membrane: np.ndarray
    bending: np.ndarray
    volume: np.ndarray

    @classmethod
    def zeros(cls, m: int) -> "XpbdMultipliers":
        return cls(np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(1))


def _sweep(model: XpbdModel, x, lam: XpbdMultipliers, settings: XpbdSettings, target,
           apply_only: bool) -> None:
    """One Gauss-Seidel sweep over every block, volume and wall (in place); with
    ``apply_only`` the warm-start displacement W J^T lambda instead."""
    base = model.base
    inv_dt2 = 1.0 / settings.dt**2
    _membrane_sweep(x, base.node_inv_mass, model.triangles, model.rest_inverse,
                    model.membrane_compliance, lam.membrane, inv_dt2, apply_only)
    if settings.bending:
        b = model.bending
        _bending_sweep(x, base.node_inv_mass, b.triangles, b.flap, b.ghost, b.active,
                       b.rest_angle, model.bending_compliance, lam.bending, inv_dt2, apply_only)
    if not apply_only:
        wall_collision(x, base.node_inv_mass, base.radius, 1.0)
    if target is not None:  # last, so that each substep ends on the volume
        _volume(x, base.node_inv_mass, base.face_nodes, base.volume_sign,
                lower_hemisphere_volume(base.radius), target, lam.volume, apply_only)


def external_force(model: XpbdModel, x: np.ndarray, node_pressure: np.ndarray,
                   body_acceleration) -> np.ndarray:
    """Liquid-side pressure (n,) Pa on the node area vectors dV_liquid/dx (pointing out of the
    liquid) plus gravity on the node masses: (n, 3) N."""
    base = model.base
    area_vector = liquid_volume_gradient(base, x)
    return (node_pressure[:, None] * area_vector
            + base.node_mass[:, None] * np.asarray(body_acceleration, dtype=float)[None, :])


class XpbdDivergence(RuntimeError):
    """A substep moved a node by more than its own length, or produced non-finite positions."""


@dataclass
class XpbdState(MembraneState):
    """Positions (n, 3) m, velocities (n, 3) m/s and the multipliers of the last substep
    (None: start from zero)."""

    multipliers: Optional[XpbdMultipliers] = None


@dataclass
class XpbdInfo:
    """Outcome of one static solve: steps (substeps), converged, move_ratio (max |dx| / L_node
    of the last substep), pressure_level (Pa, NaN without a volume target unless given),
    liquid_volume (m^3)."""

    steps: int
    converged: bool
    move_ratio: float
    pressure_level: float
    liquid_volume: float


PressureField = Callable[[np.ndarray], np.ndarray]


def _substep(model: XpbdModel, x: np.ndarray, v: np.ndarray, force: np.ndarray,
             lam: XpbdMultipliers, s: XpbdSettings, target: Optional[float],
             step: int) -> np.ndarray:
    """One substep in place on x (n, 3) m and v (n, 3) m/s under ``force`` (n, 3) N: explicit
    velocity update, prediction, the constraint sweeps (warm-started when ``s.warm_start``)
    and v = (x - x_start) / dt. Returns x_start; raises :class:`XpbdDivergence` when a triangle
    collapses."""
    v += s.dt * model.base.node_inv_mass[:, None] * force
    x_start = x.copy()
    x += s.dt * v
    try:
        if s.warm_start:
            _sweep(model, x, lam, s, target, apply_only=True)
        for _ in range(s.iterations):
            _sweep(model, x, lam, s, target, apply_only=False)
    except ZeroDivisionError as err:  # a collapsed triangle or edge
        raise XpbdDivergence(f"xpbd substep {step}: a triangle collapsed "
                             f"(dt = {s.dt:g} s, warm_start = {s.warm_start})") from err
    v[:] = (x - x_start) / s.dt
    return x_start


def advance(model: XpbdModel, state: MembraneState, duration: float,
            node_pressure: np.ndarray, body_acceleration, settings: XpbdSettings,
            volume: Optional[tuple[float, float]] = None):
    """Dynamic XPBD over one time window of ``duration`` (s).

    The window is cut into the fewest equal substeps no longer than ``settings.dt``; each is
    plain XPBD (multipliers from zero, velocities kept, no damping; ``settings.warm_start``
    and ``kinetic_damping`` are ignored), so the membrane keeps its inertia.
    ``node_pressure`` (n,) Pa acts on the liquid side throughout the window, on the current
    node area vectors. With ``volume = (V_start, V_end)`` (m^3) the liquid volume is held on
    the straight line between them, substep by substep (one linearised projection each, so
    to first order in the substep's volume change), and the uniform pressure level that
    holds it is the volume multiplier over the substep squared (Pa, added to
    ``node_pressure``). Returns (:class:`XpbdState` at the window's end with its velocities,
    level in Pa of the last substep (0 without ``volume``), number of substeps).
    """
    if not duration > 0:
        raise ValueError(f"xpbd window duration must be > 0 s, got {duration!r}")
    n_sub = max(1, int(np.ceil(duration / settings.dt * (1.0 - 1e-12))))
    s = XpbdSettings(dt=duration / n_sub, iterations=settings.iterations, warm_start=False,
                     bending=settings.bending, kinetic_damping=False)
    x = np.array(state.node_position, dtype=float)
    v = np.array(state.node_velocity, dtype=float)
    node_pressure = np.asarray(node_pressure, dtype=float)
    if node_pressure.shape != (len(x),):
        raise ValueError(f"node_pressure must have shape ({len(x)},) (Pa), got "
                         f"{node_pressure.shape}")
    if not np.all(np.isfinite(node_pressure)):
        raise ValueError(f"node_pressure has {int(np.sum(~np.isfinite(node_pressure)))} "
                         f"non-finite values (Pa)")
    for k in range(1, n_sub + 1):
        force = external_force(model, x, node_pressure, body_acceleration)
        target = None
        if volume is not None:
            target = volume[0] + (volume[1] - volume[0]) * k / n_sub
        lam = XpbdMultipliers.zeros(len(model.triangles))
        _substep(model, x, v, force, lam, s, target, k)
        if not np.all(np.isfinite(x)):
            raise XpbdDivergence(f"xpbd window substep {k}: non-finite positions "
                                 f"(substep {s.dt:g} s)")
    level = lam.volume[0] / s.dt**2 if volume is not None else 0.0
    return XpbdState(x, v, multipliers=None), float(level), n_sub


def solve_equilibrium(model: XpbdModel, state: MembraneState, pressure: PressureField,
                      body_acceleration, settings: XpbdSettings,
                      volume_target: Optional[float] = None, pressure_level: float = 0.0):
    """Static equilibrium by damped XPBD substeps from ``state``.

    ``pressure(x)`` gives the liquid-side pressure (n,) Pa at the nodes without the uniform
    level.  With ``volume_target`` (m^3, ramped from the start volume at
    ``settings.ramp_rate``) the level is the volume multiplier; without, it is held at
    ``pressure_level`` (Pa).  Returns (:class:`XpbdState` with zero velocities and the final
    multipliers, :class:`XpbdInfo`).
    """
    s = settings
    base = model.base
    x = np.array(state.node_position, dtype=float)
    v = np.zeros_like(x)
    m = len(model.triangles)
    lam = getattr(state, "multipliers", None) or XpbdMultipliers.zeros(m)
    if not s.warm_start:
        lam = XpbdMultipliers.zeros(m)
    free = ~base.node_fixed
    tank = 2.0 * lower_hemisphere_volume(base.radius)
    start_volume = liquid_volume(base, x)
    ramp_steps = 0
    if volume_target is not None:
        ramp_steps = int(np.ceil(abs(volume_target - start_volume) / (s.ramp_rate * tank)))
        if lam.volume[0] == 0.0:
            lam.volume[0] = pressure_level * s.dt**2
    kinetic = 0.0
    level = pressure_level
    move = np.inf
    converged = False
    step = 0
    for step in range(1, s.max_steps + 1):
        node_pressure = pressure(x)
        if volume_target is None:
            node_pressure = node_pressure + pressure_level
        force = external_force(model, x, node_pressure, body_acceleration)
        target = None
        ramping = False
        if volume_target is not None:
            ramp = min(1.0, step / max(ramp_steps, 1))
            ramping = ramp < 1.0
            target = start_volume + ramp * (volume_target - start_volume)
        if not s.warm_start:
            lam = XpbdMultipliers.zeros(m)
        x_start = _substep(model, x, v, force, lam, s, target, step)
        if s.warm_start:
            v[:] = 0.0
        elif s.kinetic_damping:
            energy = float(np.einsum("i,ij,ij->", base.node_mass, v, v))
            if energy < kinetic:
                v[:] = 0.0
            kinetic = energy
        dx = np.sqrt(np.einsum("ij,ij->i", x - x_start, x - x_start))
        move = float(np.max(dx[free] / base.node_length_scale[free]))
        if not np.isfinite(move) or move > 1.0:
            raise XpbdDivergence(f"xpbd substep {step}: a node moved {move:.3g} of its length "
                                 f"in one substep (dt = {s.dt:g} s, warm_start = "
                                 f"{s.warm_start})")
        new_level = lam.volume[0] / s.dt**2 if volume_target is not None else pressure_level
        level_change, level = abs(new_level - level), new_level
        if not ramping and move < s.tolerance and level_change < s.level_tolerance:
            converged = True
            break
    volume = liquid_volume(base, x)
    out = XpbdState(x, np.zeros_like(x), multipliers=lam)
    return out, XpbdInfo(step, converged, move, float(level), float(volume))
