"""The linearised free surface (:mod:`fluid.linear_surface`, ``slosh.surface = "linear"``):
linear slosh theory's model, checked against its closed form. The half-full sphere's first
lateral mode converges to Budiansky's lambda1 = 1.5602 at second order, and the inviscid free
decay keeps its energy (the surface never changes cell layer)."""
import numpy as np
import pytest

from fluid.container import SphericalTank, UprightCylinder
from fluid.grid import cartesian_grid
from fluid.linear_surface import column_heights, surface_energy, surface_of
from fluid.measures import kinetic_energy, momentum
from fluid.model import FluidModel
from fluid.solver import FluidSolver
from fluid.tank import tank_grid, tank_spacing
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY
from fsi.slosh.limp import HeightSurface
from fsi.analysis.extrapolation import observed_order, richardson
from fsi.slosh.analysis import fit_free_decay

G = STANDARD_GRAVITY
R = TANK_RADIUS
LAMBDA1_HALF_SPHERE = 1.5602
"""omega^2 R / g of the half-full rigid sphere's first lateral mode (Budiansky 1960, J.
Aerospace Sci. 27, 161; NASTRAN demonstration problem d03031a, which uses linear free-surface
elements)."""


def _sphere(cells: int, fill: float = 0.5, pulse: float = 0.5):
    """The linearised surface in the sphere at tank fraction ``fill``, a lateral sin^2 pulse of
    peak ``pulse`` m/s^2 over 0.1 s: (model, solver)."""
    tank = SphericalTank(R)
    level = tank.level_holding(fill * 4.0 / 3.0 * np.pi * R**3)
    grid = tank_grid(R, cells, axisymmetric=False)

    def body(t):
        a = pulse * np.sin(np.pi * t / 0.1) ** 2 if t < 0.1 else 0.0
        return np.array([-a, 0.0, -G])

    model = FluidModel(grid=grid, container=tank, density=WATER_DENSITY, viscosity=0.0,
                       body_acceleration=body, convection=False,
                       interface_condition="free-linear")
    surface = HeightSurface(grid, bottom=-2 * R)
    return model, FluidSolver(model, surface.interface(surface.flat(level)))


def _decay(cells: int, window: float, end_time: float):
    """(time, the liquid's centre-of-mass x, total energy K + U) of the half-full sphere's
    free decay, per window."""
    model, solver = _sphere(cells)
    mass = WATER_DENSITY * solver.liquid_volume
    times, centre, energy = [], [], []
    x = 0.0
    for k in range(int(round(end_time / window))):
        before = momentum(model, solver.state)[0]
        solver.advance(window)
        x += 0.5 * (before + momentum(model, solver.state)[0]) * window / mass
        times.append((k + 1) * window)
        centre.append(x)
        energy.append(kinetic_energy(model, solver.state) + surface_energy(model, solver.state))
    return np.array(times), np.array(centre), np.array(energy)


def test_a_level_linear_surface_at_rest_stays_at_rest():
    """No pulse: one step moves nothing and the elevation stays zero."""
    model, solver = _sphere(12, pulse=0.0)
    solver.advance(2e-3)
    state = solver.state
    fluid = state.geometry.fluid_centre
    assert np.abs(state.cell_velocity[fluid]).max() < 1e-12
    assert np.abs(state.surface_height).max() < 1e-14
    rise, has = column_heights(model, state)
    assert has.sum() > 0 and np.abs(rise).max() < 1e-14


def test_the_mean_surface_is_fixed():
    """A linearised surface is advanced under the interface it started with: another one is
    refused."""
    model, solver = _sphere(12)
    surface = HeightSurface(model.grid, bottom=-2 * R)
    with pytest.raises(ValueError, match="keeps its mean surface"):
        solver.advance(2e-3, surface.interface(surface.flat(0.3 * R)))


def test_elevation_starts_on_every_column_and_holds_the_volume():
    """After the pulse every surface face has moved, and the elevation's volume
    sum A_s eta_s stays zero (each face's own flux raises it: exact bookkeeping)."""
    model, solver = _sphere(12)
    for _ in range(40):
        solver.advance(2e-3)
    surface = surface_of(model, solver.state.geometry)
    area = surface.view.face_fraction[surface.faces] * model.grid.face_area[surface.faces]
    eta = solver.state.surface_height
    assert np.abs(eta).max() > 1e-4
    assert abs(np.sum(area * eta)) < 1e-9 * np.sum(area) * np.abs(eta).max()


def test_half_full_sphere_converges_to_budiansky_and_keeps_its_energy():
    """12^3 and 16^3 cells, 2 ms windows, 2 s (2.5 periods after the pulse). Measured:
    lambda1 -9.13 % and -4.95 % from Budiansky's 1.5602 (observed order 1.67; 1.75, 1.75 and
    1.80 over 16-20-24-32, where -1.17 % at 32^3 and Richardson's value from 24^3 and 32^3
    at order 2 is within 0.12 %: docs/validation/slosh.md, 'The linearised free surface');
    zeta 1e-5 and 2e-4; the energy's period means within 2e-5 of each other. The moving free
    surface (:mod:`fluid.free_surface`) loses 35 % of its energy over five periods at this
    fill on 16^3 (its surface changes cell layer twice a period)."""
    errors, spacing = [], []
    for cells in (12, 16):
        time, x, energy = _decay(cells, 2e-3, 2.0)
        fit = fit_free_decay(time, x, start=0.15)
        lam = fit.omega**2 * R / G
        errors.append(lam / LAMBDA1_HALF_SPHERE - 1)
        spacing.append(tank_spacing(R, cells, axisymmetric=False))
        assert abs(fit.zeta) < 0.0004  # a tenth of water's physical damping here
        period = 2 * np.pi / fit.omega
        means = [energy[(time >= 0.1 + k * period) & (time < 0.1 + (k + 1) * period)].mean()
                 for k in range(2)]
        assert means[1] == pytest.approx(means[0], rel=1e-4)
    assert errors[0] < errors[1] < 0  # below it, and closer on the finer grid
    order = np.log(errors[0] / errors[1]) / np.log(spacing[0] / spacing[1])
    assert 1.5 < order < 2.5


XI_11 = 1.8412
"""First root of J1': the first antisymmetric mode of a circular cylinder."""


def _cylinder_error(cells: int, end_time: float = 1.3) -> float:
    """The upright cylinder (radius a = depth H = 0.15 m, 0.3 h below a plane of cell
    centres, as tests/test_free_surface.py's) on ``cells``^3, linearised surface, 2 ms
    windows, a lateral sin^2 pulse of 0.5 m/s^2 over 0.1 s: the first mode's omega against
    omega^2 = (g xi / a) tanh(xi H / a) (Lamb 1932, art. 257), relative."""
    radius = depth = 0.15
    h = 2 * radius / (cells - 3)
    half = 0.5 * cells * h
    grid = cartesian_grid((-half, -half, -depth - 1.7 * h),
                          (half, half, -depth - 1.7 * h + cells * h), cells)

    def body(t):
        a = 0.5 * np.sin(np.pi * t / 0.1) ** 2 if t < 0.1 else 0.0
        return np.array([-a, 0.0, -G])

    model = FluidModel(grid=grid, container=UprightCylinder(radius, -depth, 1.0),
                       density=WATER_DENSITY, viscosity=0.0, body_acceleration=body,
                       convection=False, interface_condition="free-linear")
    surface = HeightSurface(grid, bottom=-4 * depth)
    solver = FluidSolver(model, surface.interface(surface.flat(0.0)))
    mass = WATER_DENSITY * solver.liquid_volume
    times, centre, x = [], [], 0.0
    for k in range(int(round(end_time / 2e-3))):
        before = momentum(model, solver.state)[0]
        solver.advance(2e-3)
        x += 0.5 * (before + momentum(model, solver.state)[0]) * 2e-3 / mass
        times.append((k + 1) * 2e-3)
        centre.append(x)
    fit = fit_free_decay(np.array(times), np.array(centre), start=0.15)
    exact = np.sqrt(G * XI_11 / radius * np.tanh(XI_11 * depth / radius))
    return fit.omega / exact - 1


def test_cylinder_converges_to_lamb_at_second_order():
    """Lamb's cylinder, a vertical wall at the surface: measured -2.81 % (12^3) and -1.38 %
    (16^3), order 1.94; -0.80, -0.52 and -0.27 % on 20^3, 24^3 and 32^3 (order 2.03, 2.02,
    2.07). Over 4 s on 16^3 the decay's zeta is -0.0001 (over this 1.3 s record the fit
    reads -0.0017: too short to separate the next mode)."""
    errors = [_cylinder_error(cells) for cells in (12, 16)]
    assert -0.035 < errors[0] < errors[1] < 0
    order = np.log(errors[0] / errors[1]) / np.log((16 - 3) / (12 - 3))
    assert 1.7 < order < 2.4


@pytest.mark.slow
def test_half_full_sphere_extrapolates_to_budiansky():
    """16^3, 24^3 and 32^3 cells, 2.5 s each (about 3 min): measured over 5 s, lambda1
    1.4830, 1.5269, 1.5419, observed order 1.66 from the three, and Richardson's value from
    24^3 and 32^3 at order 2, 1.5584 (-0.12 %) (docs/validation/slosh.md, 'The linearised
    free surface')."""
    lam, h = [], []
    for cells in (16, 24, 32):
        time, x, _ = _decay(cells, 2e-3, 2.5)
        fit = fit_free_decay(time, x, start=0.15)
        lam.append(fit.omega**2 * R / G)
        h.append(tank_spacing(R, cells, axisymmetric=False))
    order = observed_order(lam[1] - lam[0], lam[2] - lam[1], h)
    assert order is not None and 1.4 < order < 2.3
    assert richardson(lam[1], lam[2], h[1], h[2], 2.0) == pytest.approx(LAMBDA1_HALF_SPHERE,
                                                                         rel=0.005)
