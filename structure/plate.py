"""Flat clamped circular diaphragm under a uniform pressure: the closed forms of thesis Ch. 3.

A flat disc of radius a, thickness t, Young's modulus E and Poisson ratio nu, clamped and held
at its rim (no rotation, no radial motion), under a uniform pressure q (Pa).  The centre
deflection w0 (m) and the profile w(r) by three estimates, each valid in its own range:

* ``small`` -- Kirchhoff plate, linear (Timoshenko & Woinowsky-Krieger, *Theory of Plates and
  Shells*, 1959, Sec. 62; thesis Eqn 3.2):  w(r) = q (a^2 - r^2)^2 / (64 D),
  D = E t^3 / (12 (1 - nu^2)) (thesis Eqn 3.1).  Valid while the mid-surface does not stretch,
  w0 below about t / 5 (thesis Sec. 3.1.1).
* ``large`` -- the plate with mid-surface stretching, by the energy method (Timoshenko &
  Woinowsky-Krieger Sec. 96; Roark's Formulas for Stress and Strain, 7th ed., Sec. 11.11,
  circular plate fixed and held, uniform pressure)::

      q a^4 / (E t^4) = K1 (w0 / t) + K2 (w0 / t)^3,  K1 = 16 / (3 (1 - nu^2)),
      K2 = 2.6 / (1 - nu^2);

  the profile keeps the plate's shape w0 (1 - r^2 / a^2)^2.  The thesis (Sec. 3.1.1, after
  Eaton et al.) takes it as valid up to w0 of about 3 t.
* ``hencky`` -- the membrane (no bending) with mid-surface stretching, Hencky (1915)::

      w0 = c(nu) a (q a / (E t))^(1/3),

  c(nu) and the profile from the axisymmetric membrane equations, solved here by shooting
  (c(0.3) = 0.6534, Fichter, NASA TP-3658, 1997).  Valid once bending no longer matters,
  w0 many times t.

The thesis's point (Sec. 3.1.4): the diaphragm of a propellant tank deflects far beyond every
range, so the closed forms bound trends, not shapes.  Where each stops being right is measured
against the shell model on a flat disc (``benchmarks/plate_estimates.py``;
docs/validation/membrane.md, 'The closed forms against the shell model').
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from .bending import MidedgeBending
from .grid import boundary_ring, disc_grid, quad_faces, triangles_from_quads
from .hyperelastic import SaintVenantKirchhoff, TriangleMembrane, equilibrium_under_pressure

SMALL_DEFLECTION_LIMIT = 0.2
"""w0 / t up to which the linear plate holds (thesis Sec. 3.1.1: "1/5 the plate thickness")."""
LARGE_DEFLECTION_LIMIT = 3.0
"""w0 / t up to which the large-deflection plate holds (thesis Sec. 3.1.1, Eaton et al.)."""
ROARK_CUBIC = 2.6
"""Roark's K2 (1 - nu^2) for the clamped and held plate (7th ed., Sec. 11.11)."""


@dataclass(frozen=True)
class FlatDiaphragm:
    """A flat clamped circular diaphragm: radius (m), thickness (m), youngs_modulus (Pa),
    poisson_ratio (-, in [0, 0.5])."""

    radius: float
    thickness: float
    youngs_modulus: float
    poisson_ratio: float = 0.5

    def __post_init__(self):
        for name in ("radius", "thickness", "youngs_modulus"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        if not 0.0 <= self.poisson_ratio <= 0.5:
            raise ValueError(f"poisson_ratio must be in [0, 0.5], got {self.poisson_ratio!r}")

    @property
    def flexural_rigidity(self) -> float:
        """D = E t^3 / (12 (1 - nu^2)) (N m), thesis Eqn 3.1."""
        nu = self.poisson_ratio
        return self.youngs_modulus * self.thickness**3 / (12.0 * (1.0 - nu * nu))

    def load_number(self, pressure: float) -> float:
        """q a^4 / (E t^4) (-), the plate's dimensionless load."""
        return pressure * self.radius**4 / (self.youngs_modulus * self.thickness**4)


def small_deflection_centre(plate: FlatDiaphragm, pressure: float) -> float:
    """w0 = q a^4 / (64 D) (m)."""
    return pressure * plate.radius**4 / (64.0 * plate.flexural_rigidity)


def large_deflection_centre(plate: FlatDiaphragm, pressure: float) -> float:
    """w0 (m) solving q a^4 / (E t^4) = K1 (w0/t) + K2 (w0/t)^3 (one real root: the right side
    increases with w0)."""
    nu2 = 1.0 - plate.poisson_ratio**2
    k1, k2 = 16.0 / (3.0 * nu2), ROARK_CUBIC / nu2
    load = plate.load_number(abs(pressure))
    # Cardano for k2 y^3 + k1 y - load = 0 (depressed cubic, positive discriminant)
    p, qc = k1 / k2, -load / k2
    root = np.sqrt(qc * qc / 4.0 + p**3 / 27.0)
    y = np.cbrt(-qc / 2.0 + root) + np.cbrt(-qc / 2.0 - root)
    return float(np.sign(pressure) * y * plate.thickness)


@dataclass(frozen=True)
class HenckySolution:
    """Hencky's membrane for one Poisson ratio: centre constant c (w0 / (a Q^(1/3)),
    Q = q a / (E t)), centre radial stress constant (N_r(0) / (E t Q^(2/3))) and the profile
    shape w(rho) / w0 on rho = r / a in [0, 1] (callable, 1 at the centre, 0 at the rim)."""

    poisson_ratio: float
    centre_constant: float
    centre_stress_constant: float
    shape: Callable[[np.ndarray], np.ndarray]


def _hencky_shot(s0: float, edge: float = 1.0):
    """Integrate 3 s' + rho s'' = -rho / (8 s^2), s(0) = s0, s'(0) = 0, with
    v' = rho / (2 s) (the slope integral), from the centre's series to ``edge``."""
    rho0 = 1e-6
    y0 = [s0 - rho0**2 / (64.0 * s0**2), -rho0 / (32.0 * s0**2), rho0**2 / (4.0 * s0)]

    def rhs(rho, y):
        s, ds, _ = y
        return [ds, (-rho / (8.0 * s * s) - 3.0 * ds) / rho, rho / (2.0 * s)]

    def slack(rho, y):
        return y[0] - 1e-3 * s0
    slack.terminal = True
    return solve_ivp(rhs, (rho0, edge), y0, rtol=1e-11, atol=1e-13, dense_output=True,
                     events=slack)


@lru_cache(maxsize=16)
def hencky(poisson_ratio: float) -> HenckySolution:
    """Hencky's clamped, held membrane: the radial stress resultant N_r = E t Q^(2/3) s(rho)
    solves r (3 N_r' + r N_r'') = -E t w'^2 / 2 with w' = -q r / (2 N_r) (in-plane
    compatibility and vertical equilibrium), regular at the centre, and a held rim:
    eps_theta(a) = 0, i.e. (1 - nu) s(1) + s'(1) = 0.  The centre value s0 is found by
    shooting (Brent)."""
    nu = float(poisson_ratio)
    if not 0.0 <= nu <= 0.5:
        raise ValueError(f"poisson_ratio must be in [0, 0.5], got {nu!r}")

    def edge_condition(s0):
        sol = _hencky_shot(s0)
        if sol.status == 1:  # the stress went slack before the rim: s0 far too small
            return -1.0
        s, ds, _ = sol.y[:, -1]
        return (1.0 - nu) * s + ds

    s0 = brentq(edge_condition, 0.05, 5.0, xtol=1e-13, rtol=1e-13)
    sol = _hencky_shot(s0)
    total = float(sol.y[2, -1])

    def shape(rho):
        rho = np.clip(np.asarray(rho, dtype=float), 1e-6, 1.0)
        return (total - sol.sol(rho)[2]) / total

    return HenckySolution(nu, total, s0, shape)


def hencky_centre(plate: FlatDiaphragm, pressure: float) -> float:
    """w0 = c(nu) a (q a / (E t))^(1/3) (m)."""
    c = hencky(plate.poisson_ratio).centre_constant
    q = pressure * plate.radius / (plate.youngs_modulus * plate.thickness)
    return float(c * plate.radius * np.cbrt(q))


def plate_shape(rho: np.ndarray) -> np.ndarray:
    """The clamped plate's profile w / w0 = (1 - rho^2)^2 on rho = r / a."""
    rho = np.asarray(rho, dtype=float)
    return (1.0 - rho * rho) ** 2


@dataclass(frozen=True)
class Estimate:
    """One closed form: centre(plate, q) -> w0 (m), shape(rho) -> w / w0, and its validity
    range in w0 / t (lower, upper)."""

    name: str
    description: str
    centre: Callable[[FlatDiaphragm, float], float]
    shape: Callable[[FlatDiaphragm], Callable[[np.ndarray], np.ndarray]]
    valid_range: tuple[float, float]

    def profile(self, plate: FlatDiaphragm, pressure: float, radius: np.ndarray) -> np.ndarray:
        """w(r) (m) at radii ``radius`` (m, 0..a)."""
        return self.centre(plate, pressure) * self.shape(plate)(np.asarray(radius) / plate.radius)

    def valid(self, plate: FlatDiaphragm, pressure: float) -> bool:
        """Whether w0 / t of this estimate lies in its validity range."""
        lo, hi = self.valid_range
        return lo <= abs(self.centre(plate, pressure)) / plate.thickness <= hi


ESTIMATES: dict[str, Estimate] = {}


def register_estimate(estimate: Estimate) -> Estimate:
    ESTIMATES[estimate.name] = estimate
    return estimate


register_estimate(Estimate(
    "small", "Kirchhoff plate, linear (thesis Eqn 3.2)", small_deflection_centre,
    lambda plate: plate_shape, (0.0, SMALL_DEFLECTION_LIMIT)))
register_estimate(Estimate(
    "large", "plate with stretching, energy method (Roark 11.11, fixed and held)",
    large_deflection_centre, lambda plate: plate_shape, (0.0, LARGE_DEFLECTION_LIMIT)))
register_estimate(Estimate(
    "hencky", "membrane, no bending (Hencky 1915)", hencky_centre,
    lambda plate: hencky(plate.poisson_ratio).shape, (LARGE_DEFLECTION_LIMIT, np.inf)))


@dataclass(frozen=True)
class ShellDisc:
    """The shell model's energies on a flat disc grid: the numerical reference of the closed
    forms.  Saint Venant-Kirchhoff membrane (nu capped at 0.4999, as :mod:`structure.shell`)
    plus the calibrated mid-edge bending with a clamped rim; the outer grid ring is held
    (clamped and held).  ``node_position`` (n, 3) m is the flat rest grid, ``centre`` the node
    nearest the axis."""

    plate: FlatDiaphragm
    grid_size: int
    node_position: np.ndarray
    membrane: TriangleMembrane
    law: SaintVenantKirchhoff
    bending: MidedgeBending
    fixed: np.ndarray
    centre: int

    @classmethod
    def build(cls, plate: FlatDiaphragm, grid_size: int) -> "ShellDisc":
        x = disc_grid(grid_size, plate.radius)
        tri = triangles_from_quads(quad_faces(grid_size))
        up = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 2]
        if up.mean() < 0:  # the pressure pushes along +z
            tri = tri[:, ::-1]
        membrane = TriangleMembrane(x, tri, plate.thickness)
        law = SaintVenantKirchhoff(plate.youngs_modulus, min(plate.poisson_ratio, 0.4999))
        bending = MidedgeBending.build(x, tri, plate.flexural_rigidity, plate.poisson_ratio,
                                       boundary="clamped")
        centre = int(np.argmin(np.linalg.norm(x[:, :2], axis=1)))
        return cls(plate, grid_size, x, membrane, law, bending, boundary_ring(grid_size, 0),
                   centre)

    def solve(self, pressure: float, start: np.ndarray | None = None) -> np.ndarray:
        """Equilibrium node positions (n, 3) m under the follower pressure ``pressure`` (Pa,
        pushing along +z), from ``start`` (default: the large-deflection estimate's shape)."""
        if start is None:
            r = np.linalg.norm(self.node_position[:, :2], axis=1) / self.plate.radius
            start = self.node_position.copy()
            start[:, 2] = large_deflection_centre(self.plate, pressure) * plate_shape(r)
        work = abs(pressure) * self.plate.thickness * np.pi * self.plate.radius**2
        return equilibrium_under_pressure(self.membrane, self.law, pressure, self.fixed, start,
                                          bending=self.bending, energy_scale=work)

    def centre_deflections(self, pressures) -> np.ndarray:
        """w0 (m) at each of ``pressures`` (Pa, increasing), by continuation."""
        out, x = [], None
        for q in pressures:
            x = self.solve(float(q), x)
            out.append(x[self.centre, 2])
        return np.asarray(out)

    def newton_model(self, density: float = 1000.0):
        """The same energies for Newton's method (:class:`structure.newton.system.NewtonModel`
        on the disc grid's :class:`structure.model.MembraneModel`, the outer ring held; the
        lumped masses from ``density`` kg/m^3, which a static solve does not use)."""
        from .model import Material, disc_model
        from .newton.system import NewtonModel
        from .tangent.bending import BendingTerm
        from .tangent.membrane import MembraneTerm

        p = self.plate
        base = disc_model(self.grid_size, p.radius,
                          Material(p.thickness, density, p.youngs_modulus, p.poisson_ratio),
                          "simply-supported")
        terms = [MembraneTerm.from_triangle_membrane(self.membrane, self.law),
                 BendingTerm(self.bending)]
        return NewtonModel.build(base, terms, "energy")

    def newton_centre_deflections(self, pressures, model=None):
        """w0 (m) at each of ``pressures`` (Pa, increasing) by Newton under the held pressure
        (:func:`structure.newton.statics.newton_at_level`), by continuation from the flat disc
        nudged off its bifurcation point; and whether every load converged."""
        from .load import Load
        from .newton.statics import newton_at_level

        model = model or self.newton_model()
        x = self.node_position.copy()
        x[~model.base.node_fixed, 2] += 1e-6
        out, converged = [], True
        for q in pressures:
            load = Load(np.zeros(len(x)), np.zeros(3), None, float(q), 0.0)
            x, _, ok, _ = newton_at_level(model, x, load)
            converged &= bool(ok)
            out.append(x[self.centre, 2])
        return np.asarray(out), converged
