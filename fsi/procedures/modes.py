"""``modes``: the linear slosh modes at each tank fraction, one eigenvalue problem per fill.

The rung between the hydrostatic and the coupled dynamic models: for small amplitudes the
question is linear, and the standard engineering tools (NASTRAN's virtual fluid mass, the
coupled acoustic-structural frequency steps, Morand & Ohayon's hydroelastic forms) answer it
with an eigenvalue problem instead of a time history.

* Start: the liquid at rest at each tank fraction V / (4/3 pi R^3) of ``modes.fills``, under
  ``liquid.body_acceleration`` (gravity along -z).
* Liquid: incompressible and inviscid, on the 3-D immersed-boundary tank grid of
  ``fluid.cells`` cells, moved by less than a cell so that the level is a plane of faces
  (:func:`fluid.tank.tank_grid`), with the liquid step's own pressure operator
  (:func:`fluid.modes.surface_modes`).
* Surface (``modes.surface``): ``limp``, the slack diaphragm, i.e. the free surface with
  gravity; ``tensioned``, a massless flat membrane of uniform tension ``modes.tension`` (N/m)
  lying on the level and pinned where it meets the wall (the hydroelastic model of the
  closed form it is checked against); ``diaphragm``, the scene's ``[membrane]`` about its
  static equilibrium at each fill, its tangent stiffness and mass with the liquid's added
  mass (:mod:`fsi.slosh.hydroelastic`; no surface shapes, no SP-106 height).
* Per fill (group ``fills``): the first lateral mode's frequency, lambda1 = omega^2 R / g and
  spring-mass equivalent (slosh mass along x, its height, the pendulum and its hinge: the
  names and units of the ``slosh`` procedure's), the first axial mode's frequency, the lateral
  modes' sum m_n / (M omega_n^2) against the surface's static lateral compliance |z_c| / g.
* Per mode (group ``modes``, ``modes.count`` per fill, by ascending frequency): its kind
  (lateral, axial, higher), azimuthal order, direction, frequency, lambda and equivalent
  (:mod:`fsi.slosh.modal`); group ``shapes``: each fill's mode shapes, the surface's elevation
  over the grid's columns (m per sqrt(kg)).
"""
from __future__ import annotations

import time as _time
from dataclasses import replace

import numpy as np

from fluid.container import SphericalTank
from fluid.free_surface import column_index
from fluid.linear import single_blas_thread
from fluid.model import FluidModel
from fluid.solver import FluidSolver
from fluid.tank import tank_grid
from structure.newton.window import settled
from structure.volume import tank_volume
from structure.xpbd import XpbdModel, XpbdSettings

from fsi.lifecycle import Progress, Run, RunResult
from fsi.registry import Key, Procedure, SceneError, Table, one_of, register_procedure
from fsi.setup.models import XPBD_DYNAMIC_SWEEPS, hydrostatic_load, statics_substep
from fsi.slosh.hydroelastic import DiaphragmModes, coupled_modes
from fsi.slosh.modal import tank_modes
from fsi.procedures.coupled import (FLUID, START_SOLVER, START_SOLVER_DOC,
                                   check_start_solver, membrane_surface)
from fsi.procedures.coupled_fill import START_MAX_STEPS, START_TOLERANCE
from fsi.setup.static_start import START_SOLVERS, on_wall, seed_attrs
from fsi.procedures.slosh import MIN_DEPTH_CELLS

MODE_SURFACES = {"limp": "the slack diaphragm: the liquid's free surface under gravity",
                 "tensioned": "a massless flat membrane of uniform tension modes.tension "
                              "lying on the level, pinned where it meets the wall",
                 "diaphragm": "the [membrane] at its loaded equilibrium: its tangent "
                              "stiffness and mass, the liquid's added mass"}
"""modes.surface -> what it is."""
MODES_PER_COLUMN = 0.25
"""Most modes asked per column of fluid cells the surface spans: the highest of them are
resolved by two columns per half wave at best."""


def _fills(v) -> bool:
    return isinstance(v, list) and len(v) >= 1 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 < c < 1.0 for c in v)


MODES = Table({
    "fills": Key(list, [0.5], _fills, "non-empty list of numbers in (0, 1)",
                 "tank fractions V / (4/3 pi R^3) of the liquid at rest"),
    "surface": Key(str, "limp", *one_of(MODE_SURFACES),
                   "the diaphragm model: limp (slack: the free surface under gravity), "
                   "tensioned (a massless flat membrane of uniform tension modes.tension on "
                   "the level, pinned at the wall) or diaphragm (the [membrane] about its "
                   "loaded equilibrium, with the liquid's added mass)"),
    "tension": Key(float, 0.0, lambda v: 0 <= v <= 1e6, "0..1e6 N/m",
                   "tensioned: the membrane's uniform tension (N/m)"),
    "count": Key(int, 8, lambda v: 1 <= v <= 40, "1..40",
                 "modes computed per fill, by ascending frequency"),
    "start_solver": replace(START_SOLVER, doc="diaphragm: " + START_SOLVER_DOC
                            + "; then settled under the Newton model's energies"),
}, lambda t: _check_tension(t))
"""[modes]: the fills, surface model and number of modes of a modes run."""


def _check_tension(table: dict) -> None:
    if (table["surface"] == "tensioned") != (table["tension"] > 0):
        raise SceneError(f"scene key 'modes.tension' = {table['tension']!r} N/m with "
                         f"modes.surface = {table['surface']!r}: allowed > 0 for 'tensioned' "
                         f"and 0 for 'limp'")


def check_setup(setup) -> None:
    """Gravity along -z; the liquid and the gas each :data:`MIN_DEPTH_CELLS` cells deep at
    every fill."""
    scene = setup.scene
    gravity = np.asarray(scene["liquid"]["body_acceleration"], dtype=float)
    if not (gravity[2] < 0 and np.allclose(gravity[:2], 0.0)):
        raise SceneError(f"scene key 'liquid.body_acceleration' = {gravity.tolist()!r}: a "
                         f"modes run needs gravity along -z (0, 0, -g), g > 0")
    radius = scene["tank"]["radius"]
    tank = SphericalTank(radius)
    h = 2 * radius / (scene["fluid"]["cells"] - 3)
    count = scene["modes"]["count"]
    check_start_solver(scene, "modes")
    for fill in scene["modes"]["fills"]:
        level = tank.level_holding(fill * tank_volume(radius))
        depth = min(radius + level, radius - level)
        if depth < MIN_DEPTH_CELLS * h:
            raise SceneError(f"scene key 'modes.fills' holds {fill!r}: the liquid or the gas "
                             f"is {depth / h:.2f} fluid cells deep at fluid.cells = "
                             f"{scene['fluid']['cells']} (allowed at least "
                             f"{MIN_DEPTH_CELLS:g}); refine the grid")
        columns = int(np.pi * (radius**2 - level**2) / h**2)
        if count > MODES_PER_COLUMN * columns:
            raise SceneError(f"scene key 'modes.count' = {count}: the surface at tank fraction "
                             f"{fill} spans about {columns} columns of fluid cells, allowed "
                             f"at most {int(MODES_PER_COLUMN * columns)} modes; refine the "
                             f"grid (fluid.cells)")


def fill_modes(setup, fill: float, count: int):
    """The modes of the limp (or tensioned) surface at tank fraction ``fill``: (the fill's
    record, the modes' records, the shapes' record). The static compliance |z_c| / g is the
    free surface's (NaN under a membrane)."""
    body = np.asarray(setup.liquid.body_acceleration, dtype=float)
    gravity = -float(body[2])
    found = tank_modes(setup.model.radius, fill, setup.scene["fluid"]["cells"],
                       setup.liquid.density, body, count,
                       tension=setup.scene["modes"]["tension"])
    equivalents = found.equivalents
    records = [dict(tank_fraction=fill, mode=j + 1, azimuthal_order=e.order,
                    direction_deg=e.direction_deg, frequency_hz=e.frequency_hz,
                    omega=e.omega, eigenvalue=e.lambda1, slosh_mass=e.slosh_mass,
                    slosh_mass_fraction=e.slosh_mass_fraction, lateral_mass=e.lateral_mass,
                    slosh_mass_height=e.slosh_mass_height, pendulum_length=e.pendulum_length,
                    hinge_height=e.hinge_height, spring_stiffness=e.spring_stiffness)
               for j, e in enumerate(equivalents)]
    lateral = [e for e in equivalents if e.kind == "lateral" and e.slosh_mass > 0]
    first, axial = found.first("lateral"), found.first("axial")
    mass = found.mass

    def of_first(name):
        return getattr(first, name) if first is not None else np.nan

    record = dict(
        tank_fraction=fill, level=found.level, liquid_mass=mass,
        centre_height=found.centre_height,
        **{name: of_first(name) for name in ("lambda1", "frequency_hz", "omega", "slosh_mass",
                                             "slosh_mass_fraction", "slosh_mass_height",
                                             "pendulum_length", "hinge_height")},
        axial_frequency_hz=axial.frequency_hz if axial is not None else np.nan,
        modal_compliance=sum(e.slosh_mass / e.omega**2 for e in lateral) / mass,
        static_compliance=(abs(found.centre_height) / gravity
                           if setup.scene["modes"]["tension"] == 0 else np.nan),
        surface_faces=len(found.modes.faces), wall_seconds=found.seconds)
    shape = _column_shapes(found.model, found.modes, found.elevation, count)
    return record, records, dict(tank_fraction=fill, elevation=shape)


def diaphragm_modes(setup, fill: float, cells: int, count: int,
                    start_solver: str = "relaxation") -> DiaphragmModes:
    """The first ``count`` modes of the scene's membrane over the liquid at tank fraction
    ``fill`` on ``cells`` fluid cells (:func:`fsi.slosh.hydroelastic.coupled_modes`): its
    static start by ``start_solver`` (a name in :data:`fsi.setup.static_start.START_SOLVERS`;
    the relaxation with the slosh keys' defaults; a minimisation's wall contacts put on the
    wall), settled under the Newton model's energies. ``seconds`` is the whole."""
    tic = _time.perf_counter()
    radius = setup.model.radius
    volume = fill * tank_volume(radius)
    xpbd = XpbdModel.from_membrane(setup.model)
    settings = XpbdSettings(dt=statics_substep(setup), iterations=XPBD_DYNAMIC_SWEEPS,
                            warm_start=False, tolerance=START_TOLERANCE,
                            max_steps=START_MAX_STEPS)
    solver = START_SOLVERS[start_solver]
    state, info = solver.solve(setup, xpbd, settings, volume)
    if not solver.at_rest:
        state, info = on_wall(setup, state, info)
    load = hydrostatic_load(setup.liquid, volume_target=volume,
                            pressure_level=info.pressure_level)
    state, equilibrium = settled(xpbd, state, load)
    model = FluidModel(grid=tank_grid(radius, cells, axisymmetric=False),
                       container=SphericalTank(radius), density=setup.liquid.density,
                       viscosity=0.0,
                       body_acceleration=np.asarray(setup.liquid.body_acceleration, float))
    geometry = FluidSolver(model, membrane_surface(setup, xpbd, model).of(state)).state.geometry
    found = coupled_modes(xpbd, state, equilibrium, load, model, geometry, count)
    return replace(found, seconds=_time.perf_counter() - tic, seed=info.seed)


def diaphragm_fill_modes(setup, fill: float, count: int):
    """The modes of the scene's membrane about its loaded equilibrium at tank fraction
    ``fill`` (:func:`fsi.slosh.hydroelastic.diaphragm_modes`; its static start by
    ``modes.start_solver``): (the fill's record, the modes' records, None: no surface shapes)."""
    found = diaphragm_modes(setup, fill, setup.scene["fluid"]["cells"], count,
                            setup.scene["modes"]["start_solver"])
    radius = setup.model.radius
    gravity = -float(setup.liquid.body_acceleration[2])
    omega = np.sqrt(found.omega2)
    records = [dict(tank_fraction=fill, mode=j + 1, azimuthal_order=-1,
                    direction_deg=float(found.direction_deg[j]),
                    frequency_hz=float(omega[j] / (2 * np.pi)), omega=float(omega[j]),
                    eigenvalue=float(found.omega2[j] * radius / gravity),
                    slosh_mass=float(found.slosh_mass[j]),
                    slosh_mass_fraction=float(found.slosh_mass[j] / found.mass),
                    lateral_mass=float(found.lateral_mass[j]), slosh_mass_height=np.nan,
                    pendulum_length=float(gravity / found.omega2[j]), hinge_height=np.nan,
                    spring_stiffness=float(found.slosh_mass[j] * found.omega2[j]))
               for j in range(len(omega))]
    along = np.flatnonzero(found.lateral & (found.slosh_mass > 0.5 * found.lateral_mass))
    j = int(along[0]) if len(along) else None
    level = SphericalTank(radius).level_holding(fill * tank_volume(radius))

    def of_first(name):
        return records[j][name] if j is not None else np.nan

    record = dict(
        tank_fraction=fill, level=level, liquid_mass=found.mass, centre_height=np.nan,
        lambda1=of_first("eigenvalue"),
        **{name: of_first(name) for name in ("frequency_hz", "omega", "slosh_mass",
                                             "slosh_mass_fraction", "slosh_mass_height",
                                             "pendulum_length", "hinge_height")},
        axial_frequency_hz=np.nan,
        modal_compliance=float(np.sum(found.slosh_mass[found.lateral]
                                      / found.omega2[found.lateral]) / found.mass),
        static_compliance=np.nan, surface_faces=0, wall_seconds=found.seconds,
        unstable_directions=found.unstable, membrane_dofs=found.dofs,
        start_pressure_level=found.level, converged=found.converged, **seed_attrs(found))
    return record, records, None


FILL_MODES = {"limp": fill_modes, "tensioned": fill_modes, "diaphragm": diaphragm_fill_modes}
"""modes.surface -> the function giving one fill's records."""


def _column_shapes(model, modes, elevation: np.ndarray, count: int) -> np.ndarray:
    """(nx, ny, count) m per sqrt(kg): each mode's ``elevation`` (k, n) over the grid's
    columns (NaN
    where a column has no surface face; the modes beyond those computed NaN)."""
    g = model.grid
    nx, ny = g.shape[0], g.shape[1]
    column = column_index(g, modes.surface.cell[modes.faces])
    out = np.full((nx * ny, count), np.nan)
    out[column, :elevation.shape[1]] = elevation
    return out.reshape(nx, ny, count)


def modes(setup, progress: Progress) -> RunResult:
    """The modes at each fill of ``modes.fills``."""
    table = setup.scene["modes"]
    fills = list(table["fills"])
    run = Run(progress, len(fills))
    with single_blas_thread():
        for k, fill in enumerate(fills):
            record, records, shape = FILL_MODES[table["surface"]](setup, fill, table["count"])
            run.record("fills", record)
            for r in records:
                run.record("modes", r)
            if shape is not None:
                run.record("shapes", shape)
            run.progress(k + 1, f"tank fraction {fill:.3f}: lambda1 {record['lambda1']:.4f}")
    first = run.groups["fills"][0]
    headline = {k: first[k] for k in ("tank_fraction", "lambda1", "frequency_hz",
                                      "slosh_mass_fraction", "hinge_height")}
    start = {"start_solver": table["start_solver"]} if table["surface"] == "diaphragm" else {}
    return run.result(surface=table["surface"], fluid_cells=setup.scene["fluid"]["cells"],
                      count=table["count"], radius=setup.model.radius,
                      wall_seconds=run.elapsed(), **headline, **start)


def report(result: RunResult) -> None:
    """The table ``fsi run`` prints after a modes run."""
    a, f = result.attrs, result.groups["fills"]
    print(f"modes ({a['surface']} surface) on {a['fluid_cells']}^3 cells, "
          f"{len(f['tank_fraction'])} fill(s) in {a['wall_seconds']:.1f} s")
    print("tank fraction  lambda1   f1 (Hz)  slosh mass  (of M)  mass z (m)  hinge z (m)  "
          "axial f (Hz)")
    for k, fill in enumerate(f["tank_fraction"]):
        print(f"{fill:13.3f}  {f['lambda1'][k]:7.4f}  {f['frequency_hz'][k]:8.4f}  "
              f"{f['slosh_mass'][k]:8.3f} kg  {f['slosh_mass_fraction'][k]:6.3f}  "
              f"{f['slosh_mass_height'][k]:10.4f}  {f['hinge_height'][k]:11.4f}  "
              f"{f['axial_frequency_hz'][k]:12.4f}")


PROCEDURE = register_procedure(Procedure(
    name="modes",
    summary="linear slosh modes by tank fraction, one eigenvalue problem each: frequency, "
            "lambda, spring-mass equivalent, mode shapes",
    run=modes,
    tables={"modes": MODES, "fluid": FLUID},
    membrane_shapes=("hemisphere", "disc"),
    check_setup=check_setup,
    report=report,
    headline=report,
))
