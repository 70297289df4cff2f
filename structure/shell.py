"""Static shell model of the diaphragm: hyperelastic membrane + calibrated bending, found by
minimising the total potential energy under the liquid-volume constraint.

For a liquid of density rho under body acceleration b filling the region below the membrane,
with the uniform pressure level p_ref (Pa, at the tank centre) as the multiplier of the volume
constraint V(x) = V*, the equilibrium of the thesis's load p = p_ref + rho b . x (Eqn 4.5
generalised; :mod:`fluid.hydrostatic`) is a stationary point of

    Pi(x) = W_membrane(x) + W_bending(x) - rho b . M1(x) - sum_i m_i b . x_i
            + W_wall(x) - p_ref (V(x) - V*),

M1 = integral of x over the liquid (first moment, m^4): moving the membrane by dx at x adds
dV of liquid there, whose potential is -rho b . x dV, exactly the work of p on the move.  M1 and
V are sums over the membrane triangles (divergence theorem, F = (x_k^2 / 2) e_k; the lower
tank wall and the equator disc add constants, as in :mod:`structure.volume`).  The tank wall
is a one-sided quadratic penalty on |x_i| > R for free nodes (stiffness ``wall_stiffness``,
N/m).  Minimisation: augmented Lagrangian on the volume, each inner problem by L-BFGS
(SciPy).  A local minimum is a stable equilibrium; the path (continuation over fills) selects
which one when folds make several.

Membrane laws: :class:`structure.hyperelastic.SaintVenantKirchhoff` (E, nu) or
:class:`structure.hyperelastic.HyperelasticLaw` (neo-Hookean / Yeoh, incompressible); bending:
:class:`structure.bending.MidedgeBending` with D = E t^3 / 12 (1 - nu^2).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy.optimize import minimize

from .bending import MidedgeBending
from .grid import triangles_from_quads
from .hyperelastic import HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane
from .kernels import first_moment
from .load import Equilibrium, Load
from .model import MembraneModel, MembraneState
from .volume import liquid_volume, liquid_volume_gradient, lower_hemisphere_volume

MEMBRANE_LAWS = ("saint-venant-kirchhoff", "neo-hookean")


@dataclass(frozen=True)
class ShellSettings:
    """Static solve settings.

    * law : one of MEMBRANE_LAWS (neo-Hookean takes mu = E / 3, incompressible);
    * bending : include the calibrated bending energy;
    * wall_stiffness : penalty stiffness of the tank wall per node (N/m);
    * volume_tolerance : |V - V*| / tank volume on the returned shape (-);
    * gradient_tolerance : L-BFGS stops when the largest free-node force is below this fraction
      of the largest pressure force rho |b| R A_node (-);
    * fill_step : continuation: the volume target moves by at most this fraction of the tank
      volume per constrained solve (-);
    * max_iterations : L-BFGS iterations per inner solve.
    """

    law: str = "saint-venant-kirchhoff"
    bending: bool = True
    wall_stiffness: float = 2.5e5
    volume_tolerance: float = 1e-6
    gradient_tolerance: float = 1e-4
    fill_step: float = 0.05
    max_iterations: int = 20000

    def __post_init__(self):
        if self.law not in MEMBRANE_LAWS:
            raise ValueError(f"shell law must be one of {MEMBRANE_LAWS}, got {self.law!r}")
        if not self.wall_stiffness > 0:
            raise ValueError(f"wall_stiffness must be > 0 N/m, got {self.wall_stiffness!r}")
        if not 0 < self.fill_step <= 1:
            raise ValueError(f"fill_step must be in (0, 1], got {self.fill_step!r}")


@dataclass(frozen=True)
class ShellModel:
    """Fixed data: the :class:`MembraneModel` grid (masses, fixed nodes, quads), its triangle
    membrane, law and bending."""

    base: MembraneModel
    membrane: TriangleMembrane
    law: object
    bending: Optional[MidedgeBending]

    @classmethod
    def from_membrane(cls, base: MembraneModel, settings: "ShellSettings",
                      bending: Optional[MidedgeBending] = None) -> "ShellModel":
        """Shell on ``base``'s grid; ``bending`` reuses an already built bending model."""
        mat = base.material
        tri = triangles_from_quads(base.face_nodes)
        membrane = TriangleMembrane(base.node_rest_position, tri, mat.thickness)
        if settings.law == "neo-hookean":
            law = HyperelasticLaw.from_youngs_modulus(mat.youngs_modulus)
        else:
            law = SaintVenantKirchhoff(mat.youngs_modulus, min(mat.poisson_ratio, 0.4999))
        if not settings.bending:
            bending = None
        elif bending is None:
            bending = MidedgeBending.build(base.node_rest_position, tri, mat.flexural_rigidity,
                                           mat.poisson_ratio)
        return cls(base, membrane, law, bending)


def _volume(base: MembraneModel, x):
    return liquid_volume(base, x), liquid_volume_gradient(base, x)


def _forces(model: ShellModel, x, density, body, wall_k):
    """Energy (J) without the volume term and its gradient (n, 3) N."""
    base = model.base
    e, g = model.membrane.energy_and_gradient(x, model.law)
    if model.bending is not None:
        eb, gb = model.bending.energy_and_gradient(x)
        e, g = e + eb, g + gb
    m1, gm1 = first_moment(x, base.face_nodes, base.volume_sign)
    e -= density * float(body @ m1) + float(base.node_mass @ (x @ body))
    g = g - density * (gm1 @ body) - base.node_mass[:, None] * body[None, :]
    r = np.sqrt(np.einsum("ij,ij->i", x, x))
    over = np.where(~base.node_fixed & (r > base.radius), r - base.radius, 0.0)
    e += 0.5 * wall_k * float(over @ over)
    g = g + (wall_k * over / np.maximum(r, 1e-300))[:, None] * x
    return e, g


def _residual(model: ShellModel, x, level, density, body, s: ShellSettings, force_scale):
    """Largest free-node residual force of Pi with the level as multiplier, over
    ``force_scale`` (-)."""
    base = model.base
    _, g = _forces(model, x, density, body, s.wall_stiffness)
    _, gv = _volume(base, x)
    return float(np.abs((g - level * gv)[~base.node_fixed]).max() / force_scale)


def solve_equilibrium(model: ShellModel, state: MembraneState, load: Load,
                      settings: ShellSettings) -> tuple[MembraneState, Equilibrium]:
    """Stable equilibrium holding ``load.volume_target`` (m^3) of liquid of
    ``load.liquid_density`` (kg/m^3) under ``load.body_acceleration`` (3,) m/s^2, from
    ``state``, the level started at ``load.pressure_level`` (Pa); the pressure is the
    hydrostatic one of that liquid (module doc). Continuation in ``fill_step`` volume
    increments.  Returns (:class:`MembraneState`, :class:`structure.load.Equilibrium` with
    the residual force_ratio: the largest free-node residual force of Pi over the pressure
    force scale)."""
    if load.volume_target is None or load.liquid_density is None:
        raise ValueError("the shell model needs a volume target and the liquid density "
                         "(load.volume_target, load.liquid_density)")
    s = settings
    density, body_acceleration = load.liquid_density, load.body_acceleration
    volume_target, pressure_level = load.volume_target, load.pressure_level
    base = model.base
    body = np.asarray(body_acceleration, dtype=float)
    free = ~base.node_fixed
    x = np.array(state.node_position, dtype=float)
    tank = 2.0 * lower_hemisphere_volume(base.radius)
    mat = base.material
    scale_e = mat.youngs_modulus * mat.thickness * model.membrane.rest_area.sum()
    area = base.node_mass / (base.material.density * base.material.thickness)
    force_scale = density * max(np.linalg.norm(body), 1.0) * base.radius * area.max()
    level = float(pressure_level)
    v0, _ = _volume(base, x)
    n_stages = max(1, int(np.ceil(abs(volume_target - v0) / (s.fill_step * tank))))
    steps = 0
    converged = False
    ratio = np.inf
    for stage in range(1, n_stages + 1):
        target = v0 + (volume_target - v0) * stage / n_stages
        penalty = 100.0 * scale_e / (s.fill_step * tank) ** 2

        for _ in range(40):
            def objective(flat, level=level, target=target, penalty=penalty):
                pos = x.copy()
                pos[free] = flat.reshape(-1, 3)
                e, g = _forces(model, pos, density, body, s.wall_stiffness)
                if not np.isfinite(e):
                    return np.inf, np.zeros_like(flat)
                v, gv = _volume(base, pos)
                c = v - target
                e += -level * c + 0.5 * penalty * c * c
                g = g + (-level + penalty * c) * gv
                return e / scale_e, g[free].ravel() / scale_e

            def follow(flat):
                if model.bending is not None:
                    pos = x.copy()
                    pos[free] = flat.reshape(-1, 3)
                    model.bending.follow(pos)

            result = minimize(objective, x[free].ravel(), jac=True, method="L-BFGS-B",
                              callback=follow,
                              options={"maxiter": s.max_iterations, "maxcor": 30,
                                       "ftol": 1e-15,
                                       "gtol": s.gradient_tolerance * force_scale / scale_e})
            steps += int(result.nit)
            x[free] = result.x.reshape(-1, 3)
            v, _ = _volume(base, x)
            level -= penalty * (v - target)
            volume_met = abs(v - target) <= s.volume_tolerance * tank
            # a restart of L-BFGS (fresh curvature pairs) continues where it stalled
            if volume_met and _residual(model, x, level, density, body, s, force_scale) <= (
                    10 * s.gradient_tolerance):
                break
            if not volume_met:
                penalty *= 4.0
    ratio = _residual(model, x, level, density, body, s, force_scale)
    v, _ = _volume(base, x)
    converged = (ratio <= 10 * s.gradient_tolerance
                 and abs(v - volume_target) <= s.volume_tolerance * tank)
    return MembraneState(x), Equilibrium(steps, converged, level, float(v), force_ratio=ratio)
