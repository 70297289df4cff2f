"""The 3-D membrane model of the Table 4.1 diaphragm held against the shell of revolution
(:mod:`structure.axisymmetric`): started from the axisymmetric equilibrium carried onto its
hemisphere grid (:mod:`structure.axisymmetric.mapping`), does the 3-D equilibrium stay near it
and converge toward it as the grid N grows; and past the onset of folding, seeded with the
critical harmonic's mode, does it fold with the predicted number of lobes?

    python benchmarks/axisymmetric_vs_3d.py [--smoke]

The axisymmetric states are the fill's on :data:`ELEMENTS` meridian elements
(``benchmarks/diaphragm_axisymmetric.diaphragm``). The 3-D model is the shell model of the
``diaphragm-static`` scene (App. C grid, the same incompressible neo-Hookean law and
mid-edge bending, clamped on its two outer rings, the wall a node penalty), solved by the
bordered Newton at a held liquid volume (:func:`structure.newton.statics.newton_at_volume`).

**The volume held.** The 3-D sheet measures its liquid on its facets; the faceted rest grid
already holds 1.07 %, 0.29 % and 0.13 % of the tank at N = 14, 26 and 38, as much as a whole
0.01 fill on the coarsest grid. So each 3-D solve holds the faceted volume of the mapped
start (``hold`` "mapped"), the same surface's liquid; ``--hold fraction`` holds the tank
fraction's volume literally instead.

Prints one JSON object (a full run also writes ``docs/data/axisymmetric_vs_3d.json``):

* ``below_onset``, one row per (N, tank fraction) of :data:`GRIDS` x :data:`FRACTIONS`: the
  axisymmetric level (Pa); the 3-D one; converged, iterations and seconds; the largest and
  RMS distance (m) of the free 3-D nodes to the axisymmetric surface; Eqn 6.1 (%) of the 3-D
  sheet against the axisymmetric surface carried onto an N = 98 grid
  (:func:`fsi.analysis.compare.eqn_6_1_error`; it counts only the nodes within 0.8 a of the
  tank's centre, none at 0.01); ``negative``, the count of negative eigenvalues of the 3-D
  tangent on the volume's tangent space (0 stable; the inertia of its symmetric
  factorisation, :func:`structure.inertia.constrained_negative`: a
  strongly negative eigenvalue is not among those nearest zero);
  ``harmonics``, the amplitude (m) of the deviation's five largest circumferential
  harmonics;
* ``above_onset``, one row per N of :data:`SEED_GRIDS` at tank fraction
  :data:`SEED_FRACTION`: the axisymmetric branch's critical wave number there, the seed's
  amplitude (m), and for the seeded and the unseeded start the same figures as above, with
  ``dominant``, the 3-D deviation's largest harmonic.

``--solvers``: ``newton`` (the rows above) and ``minimisation`` (the minimisation statics,
:mod:`structure.minimise`, the wall a barrier: a descent that stops at a minimum, where
Newton stops at any stationary point; its rows under ``minimisation``, the same keys). A
solver not rerun keeps its rows from the last full run.

``--grading START STOP DENSITY`` solves on the graded grid (:class:`structure.grid.Grading`:
DENSITY times the rings per unit of meridian between the fractions START and STOP of it from
the pole) instead of App. C's; its rows go under ``graded`` (with ``band`` and ``density``)
and the App. C rows (and their ``seconds``) are kept from the last run. ``--grids``, ``--fractions`` and
``--seed-grids`` (none: ``--seed-grids``) replace :data:`GRIDS`, :data:`FRACTIONS` and
:data:`SEED_GRIDS`.

``--smoke``: N = 14 at tank fraction 0.025, and the seeded start on N = 14; the same N = 14
fill by the minimisation on the graded grid of :data:`SMOKE_GRADING`.
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from _report import DOCS_DATA, SMOKE_HELP, emit
from diaphragm_axisymmetric import diaphragm
from fsi.analysis.compare import eqn_6_1_error
from fsi.scene import load_scene
from fsi.setup.build import build, membrane_model
from fsi.setup.models import barrier_pressure, hydrostatic_load
from structure.axisymmetric import leg, meridian_fields
from structure.axisymmetric.harmonics import stability
from structure.axisymmetric.mapping import rest_arc_length, surface_points
from structure.axisymmetric.solve import equilibrium
from structure.grid import hemisphere_grid, quad_faces
from structure.inertia import constrained_negative
from structure.minimise import fill_path, inside, minimisation_model
from structure.minimise.newton import evaluate as minimise_evaluate
from structure.model import MembraneState
from structure.newton import statics
from structure.newton.system import NewtonModel
from structure.tangent.load import WallTerm
from structure.shell import ShellModel, ShellSettings
from structure.volume import tank_volume

DOC_FIELDS = ("below_onset", "above_onset", "minimisation", "graded", "elements", "seconds")
#: meridian elements of the axisymmetric states
ELEMENTS = 256
#: 3-D grids and tank fractions below the onset of folding (0.0382), past the fill's snap
#: (0.0021); and of --smoke
GRIDS = (14, 26, 38, 50, 62)
FRACTIONS = (0.01, 0.025)
SMOKE_GRIDS = (14,)
SMOKE_FRACTIONS = (0.025,)
#: the seeded start past the onset: tank fraction, grids, and the seed's largest
#: displacement (m, a tenth of the sheet's thickness would hardly show on N = 38)
SEED_FRACTION = 0.05
SEED_GRIDS = (26, 38, 50, 76)
SMOKE_SEED_GRIDS = (14,)
#: --smoke's graded pass (``--grading 0.15 0.4 3``, the minimisation) on its grids below
#: the onset
SMOKE_GRADING = {"grading_band": [0.15, 0.4], "grading_density": 3.0}
SEED_AMPLITUDE = 2e-3
#: the minimisation's barrier gap dhat (m): the barrier holds a sheet on the wall about
#: dhat / 10 inside it, and below the onset much of the sheet lies there, so the held liquid
#: is pushed into the free part. Measured at N = 62, tank fraction 0.01: the level 1.26 % off
#: the axisymmetric with the statics' default 1 mm, 0.53 % with 0.1 mm (0.025: 0.59 and 0.02 %)
BARRIER_GAP = 1e-4
#: the fine grid the axisymmetric surface is carried onto for Eqn 6.1
REFERENCE_GRID = 98
#: Newton's iterations at most per 3-D solve
MAX_ITERATIONS = 80
#: the band of rest arc length (fraction of the meridian) where harmonics are fitted, and the
#: largest wave number fitted
HARMONIC_BAND = (0.02, 0.5)
MAX_HARMONIC = 16


def axisymmetric_states(fractions):
    """{fraction: (shell, load, equilibrium)} on the fill from rest (the fill's leg through
    the tank fractions 0, 0.005, ... and ``fractions``)."""
    shell, load = diaphragm(ELEMENTS)
    end = max(fractions)
    steps = np.union1d(np.round(np.arange(0.0, end + 1e-9, 0.005), 4), np.round(fractions, 4))
    fill = leg(shell, load, equilibrium(shell, load), steps)
    out = {}
    for f, state in zip(steps, fill.states):
        if float(f) in fractions and state is not None:
            out[float(f)] = state.equilibrium
    return shell, load, out


def three_d_model(grid_size: int, grading: dict = None):
    """(Newton model, setup) of the ``diaphragm-static`` scene's shell model on ``grid_size``
    (``grading``: the scene's ``membrane.grading_band`` and ``grading_density`` keys, given
    to the sheet's model)."""
    setup = build(load_scene("diaphragm-static").with_keys(
        {"membrane": {"grid_size": grid_size},
         "structure": {"model": "shell", "shell_law": "neo-hookean"}}))
    if grading:   # the sheet alone: the scene's sweep checks its XPBD start, not run here
        scene = setup.scene.with_keys({"membrane": grading})
        setup = replace(setup, scene=scene, model=membrane_model(scene))
    shell_model = ShellModel.from_membrane(setup.model, ShellSettings(law="neo-hookean"))
    return NewtonModel.from_shell(shell_model), setup


def surface_distance(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """(n,) m: the distance of ``points`` (n, 3) to the surface of revolution of the meridian
    polyline ``curve`` (k, 2) = (r, z), in the (rho, z) half-plane; signed, positive on the
    polyline's left (the liquid's side of the sheet)."""
    q = np.stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]], axis=1)
    p0, d = curve[:-1], np.diff(curve, axis=0)
    best = np.full(len(q), np.inf)
    signed = np.zeros(len(q))
    for chunk in np.array_split(np.arange(len(q)), max(1, len(q) // 500)):
        rel = q[chunk, None, :] - p0[None]
        t = np.clip(np.einsum("kij,ij->ki", rel, d) / np.einsum("ij,ij->i", d, d), 0, 1)
        gap = rel - t[..., None] * d[None]
        dist = np.linalg.norm(gap, axis=2)
        j = np.argmin(dist, axis=1)
        best[chunk] = dist[np.arange(len(chunk)), j]
        cross = d[j, 0] * rel[np.arange(len(chunk)), j, 1] - d[j, 1] * rel[np.arange(len(chunk)),
                                                                            j, 0]
        signed[chunk] = np.sign(cross) * best[chunk]
    return signed


def harmonics(shell, rest: np.ndarray, points: np.ndarray, free: np.ndarray,
              curve: np.ndarray) -> dict:
    """{n: amplitude m}: the circumferential harmonics n = 1 ... :data:`MAX_HARMONIC` of the
    signed deviation of the free 3-D nodes from the axisymmetric surface, within
    :data:`HARMONIC_BAND` of the meridian, by least squares with a mean per band of rest arc
    length (the grid's own imprint is in the mean)."""
    s = rest_arc_length(shell, rest) / shell.meridian.shape.length
    band = free & (s > HARMONIC_BAND[0]) & (s < HARMONIC_BAND[1])
    deviation = surface_distance(points[band], curve)
    theta = np.arctan2(points[band, 1], points[band, 0])
    bins = np.floor(s[band] / 0.02)
    columns = [(bins == b).astype(float) for b in np.unique(bins)]
    top = min(MAX_HARMONIC, max(1, int(band.sum()) // 8))
    for n in range(1, top + 1):
        columns += [np.cos(n * theta), np.sin(n * theta)]
    coefficients, *_ = np.linalg.lstsq(np.stack(columns, axis=1), deviation, rcond=None)
    k = len(np.unique(bins))
    return {n: float(np.hypot(coefficients[k + 2 * n - 2], coefficients[k + 2 * n - 1]))
            for n in range(1, top + 1)}


def solve_3d(model, setup, start: np.ndarray, level: float, target: float):
    """(x, level, iterations, converged, seconds, negative) of the held-volume Newton."""
    load = hydrostatic_load(setup.liquid, volume_target=target, pressure_level=level)
    began = time.perf_counter()
    x, found, iterations, converged, lin = statics.newton_at_volume(
        model, start, level, load, target, statics.NewtonSettings(max_iterations=MAX_ITERATIONS))
    seconds = time.perf_counter() - began
    return x, float(found), int(iterations), bool(converged), seconds, _negative(model, lin)


def minimise_3d(model, setup, start: np.ndarray, level: float, target: float):
    """The same figures as :func:`solve_3d` by the minimisation statics
    (:mod:`structure.minimise`): the shell model's membrane and bending with the wall a
    barrier of gap :data:`BARRIER_GAP`, from the carried start (its nodes the barrier would not accept moved in) at the
    held volume, through any snap; ``negative`` of the exact tangent with the barrier's."""
    terms = [t for t in model.terms if not isinstance(t, WallTerm)]
    potential, wall = minimisation_model(model.base, terms, barrier_pressure(setup),
                                         dhat=BARRIER_GAP)
    load = hydrostatic_load(setup.liquid, volume_target=target, pressure_level=level)
    began = time.perf_counter()
    ((state, eq),), report = fill_path(potential, wall, MembraneState(inside(wall, start)),
                                       load, [target])
    seconds = time.perf_counter() - began
    x = state.node_position
    lin = minimise_evaluate(potential, wall, x, eq.pressure_level, load)
    return (x, float(eq.pressure_level), int(report.iterations), bool(eq.converged), seconds,
            _negative(potential, lin))


SOLVERS = {"newton": solve_3d, "minimisation": minimise_3d}
"""--solvers: how each 3-D equilibrium is found from the carried start."""


def _negative(model, lin) -> int:
    """Negative eigenvalues of the free tangent on the volume's tangent space."""
    free = np.repeat(model.free, 3)
    stiffness = sp.csr_matrix(lin.matrix)[free][:, free]
    return constrained_negative(stiffness, lin.volume_gradient[model.free].ravel())


def compare(shell, equilibrium_axi, model, setup, hold: str, fraction: float, seed=None,
            solve=solve_3d):
    """One 3-D solve by ``solve`` (:data:`SOLVERS`) from the carried start (``seed``: (mode,
    wave number, amplitude))."""
    base = setup.model
    rest, free = base.node_rest_position, ~base.node_fixed
    mode, n, amplitude = seed if seed is not None else (None, 0, 0.0)
    start = surface_points(shell, equilibrium_axi.state, rest, mode, n, amplitude)
    start[~free] = rest[~free]                              # the 3-D clamp holds both rings
    literal = fraction * tank_volume(shell.radius)
    probe = hydrostatic_load(setup.liquid, volume_target=literal,
                             pressure_level=equilibrium_axi.pressure_level)
    carried = float(statics.linearise(model, start, equilibrium_axi.pressure_level, probe,
                                      hessian=False).volume)
    target = carried if hold == "mapped" else literal
    x, level, iterations, converged, seconds, negative = solve(
        model, setup, start, equilibrium_axi.pressure_level, target)
    samples = meridian_fields(shell, equilibrium_axi.state,
                              np.linspace(0.0, shell.meridian.shape.length, 4001))
    curve = np.stack([samples["radius"], samples["height"]], axis=1)
    distance = np.abs(surface_distance(x[free], curve))
    reference_rest = hemisphere_grid(REFERENCE_GRID, shell.radius)
    reference = surface_points(shell, equilibrium_axi.state, reference_rest)
    amplitudes = harmonics(shell, rest, x, free, curve)
    largest = sorted(amplitudes.items(), key=lambda kv: -kv[1])[:5]
    return dict(nodes=int(len(rest)), tank_fraction=fraction, hold=hold,
                level_axisymmetric=float(equilibrium_axi.pressure_level), level_3d=level,
                level_difference=level - float(equilibrium_axi.pressure_level),
                converged=converged, iterations=iterations, seconds=round(seconds, 2),
                negative=negative, distance_max=float(distance.max()),
                distance_rms=float(np.sqrt(np.mean(distance**2))),
                eqn_6_1=eqn_6_1_error(reference, quad_faces(REFERENCE_GRID), x, shell.radius),
                target_volume=target, literal_volume=literal,
                harmonics=[dict(n=int(k), amplitude=v) for k, v in largest],
                dominant=int(largest[0][0]) if largest else None)


def run_solver(solve, shell, load, states, grids, fractions, seed_grids, hold,
               grading=None) -> dict:
    """below_onset and above_onset (module doc) with one solver (``grading`` as
    :func:`three_d_model`)."""
    below = []
    for n in grids:
        model, setup = three_d_model(n, grading)
        for f in fractions:
            below.append(dict(grid_size=n, **compare(shell, states[f], model, setup, hold, f,
                                                      solve=solve)))
    above = []
    if not seed_grids:
        return dict(below_onset=below, above_onset=above)
    axi = states[SEED_FRACTION]
    table = stability(shell, axi.state, load.liquid_density * load.gravity,
                      axi.pressure - axi.pressure_level)
    critical = table.critical
    mode = table.modes[list(table.wave_numbers).index(critical)]
    mode = mode * np.sign(mode[np.argmax(np.abs(mode))])     # ARPACK's sign is arbitrary
    peak = float(np.abs(mode.reshape(-1, 6)[:, [0, 2, 4]]).max())
    amplitude = SEED_AMPLITUDE / peak
    for n in seed_grids:
        model, setup = three_d_model(n, grading)
        seeded = compare(shell, axi, model, setup, hold, SEED_FRACTION,
                         (mode, critical, amplitude), solve=solve)
        plain = compare(shell, axi, model, setup, hold, SEED_FRACTION, solve=solve)
        above.append(dict(grid_size=n, critical_wave_number=critical,
                          critical_eigenvalue=float(table.eigenvalue.min()),
                          seed_amplitude=SEED_AMPLITUDE, seeded=seeded, unseeded=plain))
    return dict(below_onset=below, above_onset=above)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    parser.add_argument("--hold", choices=("mapped", "fraction"), default="mapped",
                        help="the liquid volume each 3-D solve holds (module doc)")
    parser.add_argument("--solvers", nargs="+", choices=sorted(SOLVERS),
                        default=sorted(SOLVERS), help="the 3-D solvers to run (module doc)")
    parser.add_argument("--grading", nargs=3, type=float, metavar=("START", "STOP", "DENSITY"),
                        help="solve on the graded grid (module doc)")
    parser.add_argument("--grids", nargs="+", type=int, help="3-D grids below the onset")
    parser.add_argument("--fractions", nargs="+", type=float,
                        help="tank fractions below the onset")
    parser.add_argument("--seed-grids", nargs="*", type=int, help="3-D grids past the onset")
    args = parser.parse_args(argv)
    began = time.perf_counter()
    grids = args.grids or (SMOKE_GRIDS if args.smoke else GRIDS)
    fractions = args.fractions or (SMOKE_FRACTIONS if args.smoke else FRACTIONS)
    shell, load, states = axisymmetric_states(tuple(fractions) + (SEED_FRACTION,))
    seed_grids = (args.seed_grids if args.seed_grids is not None
                  else SMOKE_SEED_GRIDS if args.smoke else SEED_GRIDS)
    grading = (None if args.grading is None else
               {"grading_band": list(args.grading[:2]), "grading_density": args.grading[2]})
    results = {name: run_solver(SOLVERS[name], shell, load, states, grids, fractions,
                                seed_grids, args.hold, grading) for name in args.solvers}
    out = dict(elements=ELEMENTS, hold=args.hold, **_earlier(args.smoke))
    out.pop("seconds", None)
    if grading is not None:
        out["graded"] = dict(band=grading["grading_band"], density=grading["grading_density"],
                             **results)
        results = {}
    elif args.smoke:
        out["graded"] = dict(band=SMOKE_GRADING["grading_band"],
                             density=SMOKE_GRADING["grading_density"],
                             minimisation=run_solver(minimise_3d, shell, load, states, grids,
                                                     fractions, (), args.hold, SMOKE_GRADING))
    if "newton" in results:
        out.update(results["newton"])
    if "minimisation" in results:
        out["minimisation"] = results["minimisation"]
    seconds = round(time.perf_counter() - began, 1)
    if grading is not None:    # the App. C rows' seconds stay theirs
        out["graded"]["seconds"] = seconds
        seconds = _earlier(args.smoke).get("seconds", seconds)
    out["seconds"] = seconds
    emit("axisymmetric_vs_3d", out, args.smoke)
    return out


def _earlier(smoke: bool) -> dict:
    """The solvers' rows of the last full run, kept where this one does not rerun them."""
    path = DOCS_DATA / "axisymmetric_vs_3d.json"
    if smoke or not path.is_file():
        return {}
    earlier = json.loads(path.read_text())
    return {k: earlier[k] for k in ("below_onset", "above_onset", "minimisation", "graded",
                                    "seconds") if k in earlier}


if __name__ == "__main__":
    main()
