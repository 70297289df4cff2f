"""The fluid driven through the coupling participant API: a rigid piston on a spring under a
liquid column (strong added mass), coupled implicitly.

Oracle: the liquid column of depth h and section A moves with the piston as a rigid added
mass rho A h (uniformly accelerated column; e.g. Blevins, Formulas for Natural Frequency and
Mode Shape, 1979, Ch. 14), so piston + liquid follow the same time recurrence as a mass
M + rho A h on the spring, oscillating at omega = sqrt(k / (M + rho A h)). With
M / (rho A h) ~ 0.1, plain Gauss-Seidel without relaxation is unstable (Causin, Gerbeau &
Nobile 2005); IQN-ILS converges.
"""
import numpy as np
import pytest

from coupling.acceleration import AccelerationSettings
from coupling.convergence import ConvergenceMeasure
from coupling.scheme import CouplingError, CouplingSettings, run
from fluid.container import UprightCylinder
from fluid.grid import axisymmetric_grid
from fluid.interface import Interface
from fluid.model import FluidModel, Port
from fluid.solver import FluidSolver
from fluid.validation import OFF_GRID
from fsi.coupled.adapters import POINTS, PRESSURE, VELOCITIES, FluidParticipant

RADIUS, DEPTH, RHO = 0.1, 0.3, 1000.0
MASS, STIFFNESS, Z_REST, AMPLITUDE = 1.0, 1000.0, 0.01, 1.0e-3
N_POINTS = 9


def piston_interface(z: float, v: float) -> Interface:
    r = np.linspace(0.0, RADIUS, N_POINTS)
    points = np.stack([r, np.zeros(N_POINTS), np.full(N_POINTS, z)], axis=1)
    vel = np.zeros_like(points)
    vel[:, 2] = v
    return Interface(points, np.stack([np.arange(N_POINTS - 1), np.arange(1, N_POINTS)], 1), vel)


class SpringPiston:
    """Rigid piston, central differences in time with the spring explicit and the liquid force
    at the end of the window: M (z1 - 2 z + z0) / dt^2 = -k (z - z_rest) + F1. The fluid's
    backward-Euler column sees the flux (z1 - z)/dt, so its pressure force is
    -m_added (z1 - 2 z + z0)/dt^2 and the pair is the Stormer-Verlet scheme for the total mass.
    F = minus the integral of the liquid pressure over the piston (liquid above; trapezoid in
    r, 2 pi r dr). Starts from rest: z0 = z."""

    name = "structure"
    write_fields = (POINTS, VELOCITIES)

    def __init__(self):
        self.z_old = self.z = Z_REST + AMPLITUDE
        r = np.linspace(0.0, RADIUS, N_POINTS)
        w = np.full(N_POINTS, r[1] - r[0])
        w[[0, -1]] *= 0.5
        self.weights = 2 * np.pi * r * w
        self.dt = 1.0

    def _fields(self):
        itf = piston_interface(self.z, (self.z - self.z_old) / self.dt)
        return {POINTS: itf.points.ravel(), VELOCITIES: itf.velocities.ravel()}

    def initial_data(self):
        return self._fields()

    def solve_window(self, time, dt, data_in):
        force = -float(self.weights @ np.asarray(data_in[PRESSURE]))
        z_new = 2 * self.z - self.z_old + dt * dt / MASS * (-STIFFNESS * (self.z - Z_REST) + force)
        self.z_old, self.z, self.dt = self.z, z_new, dt
        return self._fields()

    def store_checkpoint(self):
        return self.z_old, self.z, self.dt

    def restore_checkpoint(self, checkpoint):
        self.z_old, self.z, self.dt = checkpoint


def monolithic(added_mass: float, dt: float, n: int) -> np.ndarray:
    """The same recurrence with the liquid as a rigid added mass: z after each window (m)."""
    z_old = z = Z_REST + AMPLITUDE
    out = []
    for _ in range(n):
        z_old, z = z, 2 * z - z_old - dt * dt * STIFFNESS * (z - Z_REST) / (MASS + added_mass)
        out.append(z)
    return np.array(out)


def fluid_participant() -> FluidParticipant:
    h = RADIUS / (32 - 2 + OFF_GRID)
    grid = axisymmetric_grid(32 * h, 0.0, Z_REST + DEPTH, 32)
    top = grid.lower[1] + grid.shape[1] * grid.spacing
    model = FluidModel(grid=grid, container=UprightCylinder(RADIUS, -1.0, top + 1.0),
                       density=RHO, viscosity=1e-3, ports=(Port("top", "pressure", 0.0),),
                       body_acceleration=(0.0, 0.0, 0.0), momentum_solver="bicgstab-jacobi",
                       pressure_solver="pcg-jacobi")
    return FluidParticipant(FluidSolver(model, piston_interface(Z_REST + AMPLITUDE, 0.0))), top


def settings(acceleration, relaxation=1.0, max_iterations=30):
    return CouplingSettings(
        scheme="implicit-serial", acceleration=acceleration,
        acceleration_settings=AccelerationSettings(relaxation=relaxation, initial_relaxation=0.1,
                                                   reuse=4),
        measures=[ConvergenceMeasure(POINTS, "absolute", 1e-9)], max_iterations=max_iterations)


def test_coupled_piston_oscillates_at_the_added_mass_frequency():
    fluid, top = fluid_participant()
    added_mass = RHO * np.pi * RADIUS**2 * (top - Z_REST)
    omega = np.sqrt(STIFFNESS / (MASS + added_mass))
    dt = 2 * np.pi / omega / 64
    trajectory = []
    log = run(fluid, SpringPiston(), settings("iqn-ils"), dt, 24,
              on_window=lambda w, data: trajectory.append(data[POINTS][2]))
    reference = monolithic(added_mass, dt, 24)
    assert np.max(np.abs(np.array(trajectory) - reference)) < 0.02 * AMPLITUDE
    assert all(w.converged for w in log.windows)
    print("mean coupling iterations (IQN-ILS):", log.mean_iterations)
    assert log.mean_iterations < 10


def test_plain_gauss_seidel_diverges_under_strong_added_mass():
    """Gauss-Seidel without relaxation: each iteration multiplies the displacement error by
    about m_added / M (~ 9 here)."""
    fluid, top = fluid_participant()
    ratio = RHO * np.pi * RADIUS**2 * (top - Z_REST) / MASS
    with pytest.raises(CouplingError) as failure, np.errstate(all="ignore"):
        run(fluid, SpringPiston(), settings("constant", relaxation=1.0, max_iterations=4),
            0.01, 1)
    residuals = [r[POINTS] for r in failure.value.window.residuals]
    growth = np.array(residuals[2:]) / np.array(residuals[1:-1])
    assert np.all(growth > 0.5 * ratio), (growth, ratio)
