"""The static start of a dynamic run by its registered solver (:mod:`fsi.setup.static_start`):
the minimisation's start is a minimum of the run's own law holding the start's volume, which
XPBD's substeps put at rest in the same fold state; a solver outside the registry is refused
by its key."""
from dataclasses import replace

import numpy as np
import pytest

from fsi.scene import SceneError, load_scene
from fsi.setup.build import build
from fsi.setup.static_start import (SEED_AMPLITUDE, START_SOLVERS, seed_attrs,
                                    static_equilibrium)
from structure.minimise import fill_path, inside, minimisation_model, xpbd_terms
from structure.model import MembraneState
from structure.volume import liquid_volume, tank_volume
from structure.xpbd import XpbdModel

from fsi.procedures.coupled_fill import membrane_settings, static_start
from fsi.setup.models import XPBD_DYNAMIC_SWEEPS, barrier_pressure, hydrostatic_load

GRID = 10


def _setup(**dynamics):
    keys = {"membrane": {"grid_size": GRID}, "dynamics": {"start_fill": 0.5, **dynamics}}
    return build(load_scene("diaphragm-fill").with_keys(keys))


def test_the_minimisation_start_is_a_minimum_of_the_full_law_at_the_volume():
    """Converged on the full law (force ratio within the minimisation's test), holding the
    volume, every free node inside the wall (the barrier's); the full law's
    minimum is another state than the tension field's it starts from."""
    setup = _setup()
    xpbd = XpbdModel.from_membrane(setup.model)
    volume = 0.5 * tank_volume(setup.model.radius)
    state, info = START_SOLVERS["minimisation"].solve(setup, xpbd, membrane_settings(setup),
                                                      volume)
    assert info.converged and info.force_ratio <= 1e-6
    assert liquid_volume(setup.model, state.node_position) == pytest.approx(volume, rel=1e-8)
    free = ~setup.model.node_fixed
    r = np.linalg.norm(state.node_position[free], axis=1)
    assert np.all(r < setup.model.radius)
    # the tension field's own minimum, the first stage
    model, wall = minimisation_model(setup.model, xpbd_terms(xpbd, tension_field=True),
                                     barrier_pressure(setup))
    ((tf, tf_info),), _ = fill_path(model, wall, MembraneState(
        inside(wall, setup.model.node_rest_position)), hydrostatic_load(setup.liquid, volume),
        [volume])
    assert tf_info.converged
    assert np.abs(tf.node_position - state.node_position).max() > 1e-4


def test_xpbd_settles_the_minimisation_start_in_its_fold_state():
    """At the dynamics' substep with the slosh diaphragm's converged sweeps, XPBD from the
    minimisation's start comes to rest moving no node more than a millimetre (the same fold
    state; measured 0.45 mm here, 0.06 mm at N = 14), its level within 2 % (XPBD's stiffness
    bias at this substep is about 1 %). With one sweep, the coupled fill's default, XPBD's
    membrane is softer and moves the sheet 10-15 mm: the reason the start is settled under the
    windows' own substeps."""
    setup = _setup()
    xpbd = XpbdModel.from_membrane(setup.model)
    settings = replace(membrane_settings(setup), iterations=XPBD_DYNAMIC_SWEEPS)
    volume = 0.5 * tank_volume(setup.model.radius)
    start, minimum = START_SOLVERS["minimisation"].solve(setup, xpbd, settings, volume)
    settled, info = static_equilibrium(setup, xpbd, settings, volume, start)
    assert info.converged
    assert np.abs(settled.node_position - start.node_position).max() <= 1e-3
    assert info.pressure_level == pytest.approx(minimum.pressure_level, rel=0.02)


def test_a_coupled_fill_starts_at_rest_under_its_substeps_from_either_solver():
    """dynamics.start_solver: the state returned is XPBD's rest at the dynamics' substep;
    the axisymmetric start's seed (half the tank is past the onset) is kept through the
    settle, for the result's attributes."""
    for name in START_SOLVERS:
        setup = _setup(start_solver=name)
        xpbd = XpbdModel.from_membrane(setup.model)
        state, info = static_start(setup, xpbd, membrane_settings(setup))
        assert info.converged, name
        seeded = seed_attrs(info)
        if name == "axisymmetric":
            assert seeded["start_seed_wave_number"] > 0
            assert seeded["start_seed_amplitude"] == SEED_AMPLITUDE
        else:
            assert seeded == dict(start_seed_wave_number=0, start_seed_amplitude=0.0)
        assert liquid_volume(setup.model, state.node_position) == pytest.approx(
            0.5 * tank_volume(setup.model.radius), rel=1e-3)


@pytest.mark.parametrize("table", ["dynamics", "slosh"])
def test_a_start_solver_outside_the_registry_is_refused_by_name(table):
    scene = "diaphragm-fill" if table == "dynamics" else "slosh-diaphragm"
    with pytest.raises(SceneError, match=rf"{table}\.start_solver.*'minimisation'.*"
                                         r"'relaxation'"):
        build(load_scene(scene).with_keys({table: {"start_solver": "newton"}}))


def test_the_newton_window_settles_the_minimisation_start_in_a_few_iterations():
    """The generalised-alpha window's settle (its penalty wall) from the minimisation's
    start with its wall contacts put on the wall (:func:`fsi.setup.static_start.on_wall`, as
    the coupled runs do): converged in at most 10 iterations, no node moved more than a
    millimetre."""
    from structure.newton.window import settled

    from fsi.setup.static_start import on_wall

    setup = _setup()
    xpbd = XpbdModel.from_membrane(setup.model)
    volume = 0.5 * tank_volume(setup.model.radius)
    start, info = on_wall(setup, *START_SOLVERS["minimisation"].solve(setup, xpbd, None,
                                                                       volume))
    out, eq = settled(xpbd, start, hydrostatic_load(setup.liquid, volume, info.pressure_level))
    assert eq.converged and eq.steps <= 10
    assert np.abs(out.node_position - start.node_position).max() <= 1e-3


def _axisymmetric_start(grid_size: int, fraction: float):
    setup = build(load_scene("diaphragm-fill").with_keys({"membrane": {"grid_size": grid_size}}))
    xpbd = XpbdModel.from_membrane(setup.model)
    volume = fraction * tank_volume(setup.model.radius)
    return setup, volume, START_SOLVERS["axisymmetric"].solve(setup, xpbd, None, volume)


def test_the_axisymmetric_start_below_the_onset_stays_on_the_shell_of_revolution(caplog):
    """Tank fraction 0.025, below the onset of folding (0.038): the shell of revolution's
    state is stable to every harmonic, carried unseeded, and minimised at the scene's volume
    stays near its surface (RMS 1.7 mm measured on N = 26; the faceted grid holds 0.29 % of
    the tank more than the sphere, 12 % of this liquid, docs/notes/axisymmetric-onset-vs-3d.md)."""
    import logging

    from structure.axisymmetric import meridian_fields
    from fsi.setup.static_start import _axisymmetric_fill

    with caplog.at_level(logging.INFO, logger="fsi.setup.static_start"):
        setup, volume, (state, info) = _axisymmetric_start(26, 0.025)
    assert info.converged and info.seed == ()
    assert "not seeded" in caplog.text
    shell, _, axi = _axisymmetric_fill(setup, volume)
    samples = meridian_fields(shell, axi.state, np.linspace(0, shell.meridian.shape.length, 2001))
    curve = np.stack([samples["radius"], samples["height"]], axis=1)
    free = state.node_position[~setup.model.node_fixed]
    q = np.stack([np.hypot(free[:, 0], free[:, 1]), free[:, 2]], axis=1)
    distance = np.min(np.linalg.norm(q[:, None, :] - curve[None], axis=2), axis=1)
    assert np.sqrt(np.mean(distance**2)) <= 2.5e-3


def test_the_axisymmetric_start_past_the_onset_is_seeded_with_the_critical_harmonic(caplog):
    """Tank fraction 0.05, past the onset: the carried state is seeded with n = 10, the
    critical harmonic there (docs/notes/axisymmetric-onset-vs-3d.md), and minimised."""
    import logging

    with caplog.at_level(logging.INFO, logger="fsi.setup.static_start"):
        _, _, (_, info) = _axisymmetric_start(14, 0.05)
    assert info.converged
    assert "seeded with n = 10, 2 mm" in caplog.text
    assert info.seed == (10, SEED_AMPLITUDE)


def test_the_axisymmetric_start_is_refused_for_a_flat_sheet():
    """The shell of revolution carried is a hemisphere's: a disc scene's axisymmetric start is
    refused by its key, naming what is allowed."""
    with pytest.raises(SceneError, match=r"slosh\.start_solver.*membrane\.shape = 'disc'.*"
                                         r"allowed: 'minimisation', 'relaxation'"):
        build(load_scene("slosh-diaphragm").with_keys(
            {"membrane": {"shape": "disc"}, "slosh": {"start_solver": "axisymmetric"}}))
