"""Time accuracy of the moving-wall liquid step and of the coupled window.

Oracles:
* a rigid liquid column of depth h behind a piston moving as z(t) has the pressure
  p(piston) - p(top) = rho (g + z'') h (uniform column; e.g. Blevins, Formulas for Natural
  Frequency and Mode Shape, 1979, Ch. 14): the step's pressure converges to it at the
  order of its time derivative, 1 for backward Euler, 2 for BDF2 (Guermond, Minev & Shen
  2006, the BDF2 incremental projection);
* a massless spring piston under the column is an undamped oscillator of frequency
  sqrt(k / m_added): backward Euler damps it at zeta ~ omega dt / 2, BDF2 at
  zeta ~ (omega dt)^3 / 4 (Hairer & Wanner, Solving ODEs II, Sec. V.1: BDF2's error
  constant on the imaginary axis).
"""
from dataclasses import replace

import numpy as np
import pytest

from coupling.scheme import run
from fluid.solver import FluidSolver
from fluid.validation import PistonCase, flat_interface
from fsi.coupled.adapters import POINTS, PRESSURE, VELOCITIES, FluidParticipant
from fsi.slosh.modes import fit_modes

import test_fluid_coupling as column

AMPLITUDE, FREQUENCY = 2e-3, 5.0  # m, Hz: the piston's z = z0 + A (1 - cos omega t)


def piston_pressure(scheme: str, dt: float, end: float = 0.16) -> float:
    """Mean pressure (Pa) on the oscillating piston at ``end`` (s), steps of ``dt`` (s)."""
    case = PistonCase(gravity=9.81, cells_across=16)
    model = replace(case.model(), time_scheme=scheme)
    omega = 2 * np.pi * FREQUENCY

    def piston(t):
        z = case.start_height + AMPLITUDE * (1 - np.cos(omega * t))
        return flat_interface(z, 1.5 * case.radius, AMPLITUDE * omega * np.sin(omega * t),
                              True, True)

    solver = FluidSolver(model, piston(0.0))
    n = int(round(end / dt))
    for k in range(1, n + 1):
        solver.advance(dt, piston(k * dt))
    z = solver.interface.points[0, 2]
    points = np.stack([np.linspace(0, 0.9 * case.radius, 8), np.zeros(8), np.full(8, z)], 1)
    return float(solver.pressure_at(points).mean())


@pytest.mark.parametrize("scheme, lowest, highest", [("euler", 0.8, 1.2), ("bdf2", 1.8, 3.0)])
def test_liquid_pressure_converges_at_the_schemes_order(scheme, lowest, highest):
    """Self-convergence of the piston pressure at t = 0.16 s (where z''' is largest) over
    dt = 4, 2, 1, 0.5 ms: observed order 1 +- 0.2 for backward Euler, at least 1.8 for BDF2
    (measured 1.01 and 2.47)."""
    p = [piston_pressure(scheme, dt) for dt in (4e-3, 2e-3, 1e-3, 5e-4)]
    d = np.abs(np.diff(p))
    observed = np.log2(d[:-1] / d[1:])
    print(scheme, p, observed)
    assert np.all((observed >= lowest) & (observed <= highest))


class MasslessSpringPiston:
    """A massless piston on a spring k under the liquid column: k (z - z_rest) = F, F minus
    the liquid's pressure force on it (every force at the window's end)."""

    name = "structure"
    write_fields = (POINTS, VELOCITIES)

    def __init__(self, stiffness: float, z: float):
        self.stiffness, self.z, self.v = stiffness, z, 0.0
        r = np.linspace(0.0, column.RADIUS, column.N_POINTS)
        w = np.full(column.N_POINTS, r[1] - r[0])
        w[[0, -1]] *= 0.5
        self.weights = 2 * np.pi * r * w

    def _fields(self):
        itf = column.piston_interface(self.z, self.v)
        return {POINTS: itf.points.ravel(), VELOCITIES: itf.velocities.ravel()}

    def initial_data(self):
        return self._fields()

    def solve_window(self, time, dt, data_in):
        z = column.Z_REST - float(self.weights @ np.asarray(data_in[PRESSURE])) / self.stiffness
        self.z, self.v = z, (z - self.z) / dt
        return self._fields()

    def store_checkpoint(self):
        return self.z, self.v

    def restore_checkpoint(self, checkpoint):
        self.z, self.v = checkpoint


def spring_column(scheme: str, steps_per_period: int, periods: int = 4):
    """(frequency Hz, zeta, exact frequency Hz) of the inviscid column on the massless spring,
    coupled by IQN-ILS, from a 1 mm displacement at rest."""
    fluid, top = column.fluid_participant()
    model = replace(fluid.solver.model, time_scheme=scheme, viscosity=0.0,
                    body_acceleration=(0.0, 0.0, 0.0))
    start = column.Z_REST + column.AMPLITUDE
    fluid = FluidParticipant(FluidSolver(model, column.piston_interface(start, 0.0)))
    stiffness = 1000.0
    added_mass = column.RHO * np.pi * column.RADIUS**2 * (top - column.Z_REST)
    omega = np.sqrt(stiffness / added_mass)
    dt = 2 * np.pi / omega / steps_per_period
    piston = MasslessSpringPiston(stiffness, start)
    z = []
    n = periods * steps_per_period
    run(fluid, piston, column.settings("iqn-ils"), dt, n,
        on_window=lambda w, data: z.append(piston.z - column.Z_REST))
    t = dt * np.arange(1, n + 1)
    mode = fit_modes(t, np.stack([z, np.zeros(n)], axis=1), 0.0, t[-1]).first
    return mode.frequency_hz, mode.zeta, omega / (2 * np.pi)


def test_bdf2_window_keeps_an_inviscid_oscillation():
    """Backward Euler damps the spring-column mode at zeta = omega dt / 2 within 10 %; BDF2 at
    under a tenth of that, falling at order >= 2 when dt halves; both frequencies within 2 %
    of sqrt(k / m_added)."""
    _, zeta_euler, _ = spring_column("euler", 32)
    f16, zeta16, exact = spring_column("bdf2", 16)
    f32, zeta32, _ = spring_column("bdf2", 32)
    omega_dt = 2 * np.pi / 32
    print(zeta_euler, zeta16, zeta32, f16, f32, exact)
    assert zeta_euler == pytest.approx(omega_dt / 2, rel=0.1)
    assert 0 < zeta32 < 0.1 * zeta_euler
    assert np.log2(zeta16 / zeta32) >= 2.0
    assert abs(f32 / exact - 1) < 0.02
