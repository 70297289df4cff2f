"""The maps that carry the liquid's cell pressure to the membrane's nodes (fsi.coupled.pressure_maps).

Oracles: the subdivision rule's closed-form moments (int over a triangle of lambda_1^2 dA =
A / 6, from int lambda1^a lambda2^b lambda3^c dA = 2 A a! b! c! / (a + b + c + 2)!), and a
linear pressure field set on the cells, which the fit reproduces exactly wherever it is
evaluated, and the cells' own values reproduce to within half a cell's diagonal times its
gradient.
"""
from dataclasses import replace

import numpy as np
import pytest

from fluid.geometry import HELD_LEVEL_CELLS, hold_liquid_centres
from fluid.sampling import CELL_WEIGHTS, FIT_KERNELS, MIN_FRACTION, sample_cells, threshold_weight
from fluid.solver import FluidSolver
from fluid.tank import sphere_model, tank_grid
from fsi.coupled.adapters import FluidParticipant, MembraneSurface
from fsi.constants import (MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS,
                           STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY)
from fsi.coupled.pressure_maps import (PRESSURE_MAPS, QUADRATURE_LEVELS, membrane_quadrature,
                                       subdivision_barycentres)
from structure.model import Material, MembraneState, hemisphere_model
from structure.xpbd import XpbdModel

GRAVITY = np.array([0.0, 0.0, -STANDARD_GRAVITY])
GRADIENT = np.array([120.0, -40.0, 75.0])  # Pa/m, the reduced pressure's set on the cells
OFFSET, LEVEL = 35.0, 250.0  # Pa


@pytest.mark.parametrize("levels", [1, 2, 3, 5])
def test_the_subdivision_rule_is_a_partition_with_the_triangles_centroid(levels):
    bary = subdivision_barycentres(levels)
    assert bary.shape == (levels * levels, 3)
    assert np.all(bary > 0) and np.allclose(bary.sum(axis=1), 1.0)
    # each sub-triangle's centroid: the rule integrates every linear function exactly
    assert np.allclose(bary.mean(axis=0), 1.0 / 3.0, atol=1e-15)


def test_the_subdivision_rule_converges_at_second_order_on_a_quadratic():
    exact = 1.0 / 6.0  # int lambda_1^2 dA over a triangle of unit area
    errors = [abs(np.mean(subdivision_barycentres(k)[:, 0] ** 2) - exact) for k in (3, 6, 12)]
    assert errors[0] > 0
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=1e-9)
    assert errors[1] / errors[2] == pytest.approx(4.0, rel=1e-9)


def test_the_quadrature_weights_split_each_triangles_area_among_its_corners():
    points = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 1.0]])
    triangles = np.array([[0, 1, 2], [0, 1, 3]])
    quad, weight = membrane_quadrature(points, triangles, QUADRATURE_LEVELS)
    assert quad.shape == (2 * QUADRATURE_LEVELS ** 2, 3)
    # each corner carries a third of the triangle's area (int N_v dA = A / 3)
    assert np.allclose(weight.sum(axis=1), [[1.0] * 3, [1.0 / 3.0] * 3])  # areas 3 and 1 m^2
    assert np.all(quad[: QUADRATURE_LEVELS ** 2, 2] == 0.0)  # first triangle in z = 0


@pytest.fixture(scope="module")
def linear_field():
    """(fluid solver with the reduced pressure OFFSET + GRADIENT . x_c on its cells, the
    membrane surface, its triangles, the free nodes away from the rim): the rest hemisphere
    flattened to a bowl a third as deep, so that the liquid under it spans the cells."""
    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    base = hemisphere_model(14, TANK_RADIUS, material, "clamped")
    model = XpbdModel.from_membrane(base)
    surface = MembraneSurface(model)
    grid = tank_grid(TANK_RADIUS, 16, axisymmetric=False)
    solver = FluidSolver(sphere_model(TANK_RADIUS, grid, [], density=WATER_DENSITY,
                                      body_acceleration=GRAVITY),
                         surface.of(MembraneState(base.node_rest_position * [1.0, 1.0, 0.3])))
    solver.state = replace(solver.state,
                           pressure=OFFSET + grid.cell_centre @ GRADIENT)
    triangles = surface.faces[np.all(surface.faces < surface.n_points, axis=1)]
    assert len(triangles) == len(model.triangles)
    x = solver.interface.points[:surface.n_points]
    # where the fit has liquid on every side: the clamped rings on the wall have not
    inner = np.hypot(x[:, 0], x[:, 1]) < TANK_RADIUS - 1.5 * grid.spacing
    return solver, surface, triangles, inner


def _field(x):
    """The total pressure (Pa) at points x (n, 3) m of the linear field."""
    return OFFSET + x @ GRADIENT + WATER_DENSITY * x @ GRAVITY + LEVEL


def _hat_mean(surface, triangles, weight, values):
    n = surface.n_points
    values = values.reshape(weight.shape[:2])
    num, den = np.zeros(n), np.zeros(n)
    for v in range(3):
        np.add.at(num, triangles[:, v], np.sum(weight[:, :, v] * values, axis=1))
        np.add.at(den, triangles[:, v], np.sum(weight[:, :, v], axis=1))
    return num / den


def test_node_fit_reproduces_a_linear_pressure_at_the_nodes(linear_field):
    solver, surface, _, inner = linear_field
    p = PRESSURE_MAPS["node-fit"](solver, surface, LEVEL)
    x = solver.interface.points[:surface.n_points]
    assert p.shape == (surface.n_points,)
    assert inner.sum() > 40
    assert np.allclose(p[inner], _field(x[inner]), rtol=0, atol=1e-9 * np.abs(_field(x)).max())


def test_surface_mean_is_the_hat_weighted_mean_of_the_field(linear_field):
    solver, surface, triangles, inner = linear_field
    quad, weight = membrane_quadrature(solver.interface.points, triangles, QUADRATURE_LEVELS)
    expected = _hat_mean(surface, triangles, weight, _field(quad))
    p = PRESSURE_MAPS["surface-mean"](solver, surface, LEVEL)
    assert np.allclose(p[inner], expected[inner], rtol=0, atol=1e-9 * np.abs(expected).max())
    # the hat-weighted mean of a linear field is the field at the patch's weighted centre
    centre = np.stack([_hat_mean(surface, triangles, weight, quad[:, a]) for a in range(3)], 1)
    assert np.allclose(p[inner], _field(centre[inner]), rtol=0,
                       atol=1e-9 * np.abs(expected).max())
    x = solver.interface.points[:surface.n_points]
    assert np.abs(p - _field(x))[inner].max() > 1.0  # Pa: not the node's own value


def test_cell_mean_takes_each_points_own_cell(linear_field):
    solver, surface, triangles, inner = linear_field
    grid = solver.model.grid
    quad, weight = membrane_quadrature(solver.interface.points, triangles, QUADRATURE_LEVELS)
    cell = grid.cell_of(quad)
    assert np.all(cell >= 0)
    # the cell really holds the point
    assert np.all(np.abs(quad - grid.cell_centre[cell]) <= 0.5 * grid.spacing * (1 + 1e-12))
    wet = solver.state.geometry.cell_fraction[cell] >= MIN_FRACTION
    assert wet.mean() > 0.5
    own = OFFSET + grid.cell_centre[cell] @ GRADIENT + WATER_DENSITY * quad @ GRAVITY + LEVEL
    values = np.where(wet, own, solver.pressure_at(quad, LEVEL))
    expected = _hat_mean(surface, triangles, weight, values)
    p = PRESSURE_MAPS["cell-mean"](solver, surface, LEVEL)
    assert np.allclose(p, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    # piecewise constant over the cells: off the smooth mean by at most half a diagonal
    smooth = PRESSURE_MAPS["surface-mean"](solver, surface, LEVEL)
    bound = np.linalg.norm(GRADIENT) * 0.5 * np.sqrt(3) * grid.spacing
    assert 0 < np.abs(p - smooth)[inner].max() <= bound


def test_the_fluid_participant_sends_what_its_map_gives(linear_field):
    solver, surface, _, inner = linear_field
    for name, pressure_map in PRESSURE_MAPS.items():
        side = FluidParticipant(solver, level=LEVEL, surface=surface, pressure_map=pressure_map)
        sent = side.initial_data()["interface_pressure"]
        assert np.array_equal(sent, pressure_map(solver, surface, LEVEL)), name
    default = FluidParticipant(solver, level=LEVEL, surface=surface)
    assert np.array_equal(default.initial_data()["interface_pressure"],
                          PRESSURE_MAPS["node-fit"](solver, surface, LEVEL))


def _a_stencil_cell(solver, surface, inner):
    """An inner node (1, 3) m and a liquid cell of its sampling block (fraction >= MIN_FRACTION)."""
    grid, fraction = solver.model.grid, solver.state.geometry.cell_fraction
    x = solver.interface.points[:surface.n_points][inner]
    for point in x:
        near = np.flatnonzero((np.max(np.abs(grid.cell_centre - point), axis=1) <= grid.spacing)
                              & (fraction >= MIN_FRACTION))
        if len(near) > 4:
            return point[None, :], near[0]
    raise AssertionError("no inner node with a full stencil")


def test_window_cells_make_the_fit_continuous_where_a_cell_crosses_the_threshold(linear_field):
    """A cell of a node's block whose fraction crosses MIN_FRACTION, its pressure off the plane
    by 5 kPa (a barely wetted cut cell): chosen anew each call the node's value jumps; with
    the cells of the window's start it moves by what the fraction's change weighs."""
    solver, surface, _, inner = linear_field
    grid, start = solver.model.grid, solver.state.geometry.cell_fraction
    point, cell = _a_stencil_cell(solver, surface, inner)
    pressure = solver.state.pressure.copy()
    pressure[cell] += 5000.0
    values = {}
    for name, weight in CELL_WEIGHTS.items():
        for side, alpha in (("below", MIN_FRACTION - 1e-9), ("above", MIN_FRACTION + 1e-9)):
            fraction = start.copy()
            fraction[cell] = alpha
            values[name, side] = sample_cells(grid, pressure, fraction, point,
                                              cell_weight=weight(fraction, start))[0]
    assert abs(values["iteration", "above"] - values["iteration", "below"]) > 1.0  # Pa
    assert abs(values["window", "above"] - values["window", "below"]) < 1e-3  # Pa
    # faded out below half the threshold: the fit without the cell, as chosen anew
    fraction = start.copy()
    fraction[cell] = 0.5 * MIN_FRACTION
    weight = CELL_WEIGHTS["window"](fraction, start)
    assert weight[cell] == 0.0
    assert np.array_equal(weight > 0, threshold_weight(fraction) > 0)
    # outside a window (no start) and with every fraction as at the start: the threshold's
    assert np.array_equal(CELL_WEIGHTS["window"](start, None), threshold_weight(start))
    assert np.array_equal(CELL_WEIGHTS["window"](start, start), threshold_weight(start))


def test_the_fluid_participant_fits_from_its_windows_start_cells(linear_field):
    solver, surface, _, inner = linear_field
    start_state = solver.state
    _, cell = _a_stencil_cell(solver, surface, inner)
    sides = {name: FluidParticipant(solver, level=LEVEL, surface=surface, pressure_cells=name)
             for name in CELL_WEIGHTS}
    try:
        for side in sides.values():
            side.store_checkpoint()  # the window starts
        fraction = start_state.geometry.cell_fraction.copy()
        fraction[cell] = 0.75 * MIN_FRACTION  # the cell dries within the window
        solver.state = replace(start_state,
                               geometry=replace(start_state.geometry, cell_fraction=fraction))
        sent = {name: side.initial_data()["interface_pressure"] for name, side in sides.items()}
        start = start_state.geometry.cell_fraction
        for name, weight in CELL_WEIGHTS.items():
            assert np.array_equal(sent[name], PRESSURE_MAPS["node-fit"](
                solver, surface, LEVEL, weight(fraction, start))), name
        # the linear field is fitted exactly either way: the two differ only by round-off
        assert np.allclose(sent["window"], sent["iteration"], rtol=0, atol=1e-6)
        assert not np.array_equal(sent["window"], sent["iteration"])
    finally:
        solver.state = start_state
    with pytest.raises(ValueError, match="pressure cells"):
        FluidParticipant(solver, surface=surface, pressure_cells="every")


def test_the_tapered_fit_is_continuous_where_a_point_crosses_a_plane_of_cell_centres(
        linear_field):
    """A node moved across a plane of cell centres by 2e-9 h, the cells' pressure a plane plus
    a curvature of 1 kPa/m^2: the plain block gains and drops a layer of cells there and the
    fitted value jumps; the tapered weights (zero at the block's edge) move it by what the
    plane's slope moves it. Both fit a plane exactly (moving least squares)."""
    solver, surface, _, inner = linear_field
    grid = solver.model.grid
    x = solver.interface.points[:surface.n_points][inner][0]
    h = grid.spacing
    plane = np.floor((x[0] - grid.lower[0]) / h - 0.5) + 1.5  # the next plane of centres, in h
    fraction = solver.state.geometry.cell_fraction
    c = grid.cell_centre
    curved = solver.state.pressure + 1e5 * np.sum((c - x) ** 2, axis=1)
    values = {}
    for kernel in FIT_KERNELS:
        for side in (-1e-9, 1e-9):
            point = x.copy()
            point[0] = grid.lower[0] + (plane + side) * h
            values[kernel, side] = sample_cells(grid, curved, fraction, point[None],
                                                kernel=kernel)[0]
        # a plane is fitted exactly by either kernel
        assert np.isclose(sample_cells(grid, solver.state.pressure, fraction, x[None],
                                       kernel=kernel)[0],
                          OFFSET + x @ GRADIENT, rtol=0, atol=1e-6)
    assert abs(values["block", 1e-9] - values["block", -1e-9]) > 1.0  # Pa
    assert abs(values["tapered", 1e-9] - values["tapered", -1e-9]) < 1e-5  # Pa
    with pytest.raises(ValueError, match="pressure fit"):
        sample_cells(grid, curved, fraction, x[None], kernel="smooth")


def test_held_centre_cells_keep_their_side_where_the_interface_crosses_them(linear_field):
    solver, _, _, _ = linear_field
    g = solver.state.geometry
    h = solver.model.grid.spacing
    held = g.fluid_centre.copy()
    flip = np.flatnonzero(held)[:3]
    held[flip] = False  # three liquid-centre cells held as wall cells
    wet = np.flatnonzero(~g.fluid_centre & (g.cell_fraction > 0))[:3]
    held[wet] = True  # and three wall-centre cells (cut, in the tank) held as liquid
    out = hold_liquid_centres(g, held, h)
    assert np.array_equal(out.fluid_centre, held)
    assert np.allclose(out.centre_level[flip], HELD_LEVEL_CELLS * h)
    assert np.allclose(out.centre_level[wet], -HELD_LEVEL_CELLS * h)
    same = np.ones(len(held), bool)
    same[np.r_[flip, wet]] = False
    assert np.array_equal(out.centre_level[same], g.centre_level[same])
    assert np.array_equal(out.cell_fraction, g.cell_fraction)
    # held at their own side: only a centre closer to the interface than the held distance
    # moves, to it
    own = hold_liquid_centres(g, g.fluid_centre, h)
    far = np.abs(g.centre_level) >= HELD_LEVEL_CELLS * h
    assert np.array_equal(own.fluid_centre, g.fluid_centre)
    assert np.array_equal(own.centre_level[far], g.centre_level[far])


def test_the_fluid_participant_holds_its_windows_start_centres(linear_field, monkeypatch):
    solver, surface, _, _ = linear_field
    start_state = solver.state
    seen = []
    monkeypatch.setattr(solver, "advance",
                        lambda dt, interface=None, liquid_centre=None: seen.append(liquid_centre))
    points = solver.interface.points[:surface.n_points]
    data = {"interface_points": points, "interface_velocities": np.zeros_like(points)}
    for name in ("iteration", "window"):
        side = FluidParticipant(solver, level=LEVEL, surface=surface, centre_cells=name)
        side.store_checkpoint()
        side.solve_window(0.0, 1e-3, data)
    assert seen[0] is None  # called without it
    assert np.array_equal(seen[1], start_state.geometry.fluid_centre)
    with pytest.raises(ValueError, match="centre cells"):
        FluidParticipant(solver, surface=surface, centre_cells="every")


def test_cell_of_finds_points_and_refuses_the_outside():
    grid = tank_grid(TANK_RADIUS, 8, axisymmetric=False)
    centres = grid.cell_centre
    assert np.array_equal(grid.cell_of(centres), np.arange(grid.n_cells))
    outside = np.asarray(grid.lower) - grid.spacing
    assert grid.cell_of(outside[None, :])[0] == -1
    axi = tank_grid(TANK_RADIUS, 8, axisymmetric=True)
    r, z = axi.cell_centre[5]
    point = np.array([[r / np.sqrt(2), r / np.sqrt(2), z]])
    assert grid.n_cells > axi.n_cells and axi.cell_of(point)[0] == 5
