"""Static against dynamic (fsi.analysis.static_vs_dynamic): the pairing of frames by tank fraction and
the three differences, on shapes whose answers are known."""
import numpy as np
import pytest

from fsi.analysis.static_vs_dynamic import PAIRING_TOLERANCE, centre_of_mass, compare


def _frames(model, positions, levels):
    tank = 4.0 / 3.0 * np.pi * model.radius**3
    from structure.volume import liquid_volume
    return dict(node_position=np.array(positions),
                tank_fraction=np.array([liquid_volume(model, x) / tank for x in positions]),
                pressure_level=np.array(levels, dtype=float))


def test_centre_of_mass_below_a_flat_membrane_is_the_hemisphere_s_three_eighths_r(model26):
    """The membrane flat on the equator: the liquid is the lower hemisphere, whose centroid
    lies 3R/8 below its flat face (any statics text)."""
    flat = model26.node_rest_position * [1.0, 1.0, 0.0]
    c = centre_of_mass(model26, flat)
    assert c == pytest.approx([0.0, 0.0, -3.0 / 8.0 * model26.radius], abs=1e-12)


def test_same_shape_gives_zero_and_the_level_difference_is_dynamic_minus_static(model26):
    x = model26.node_rest_position
    static = _frames(model26, [x], [100.0])
    dynamic = _frames(model26, [x], [112.5])
    fill = float(static["tank_fraction"][0])
    (row,) = compare(dynamic, static, model26, [fill])
    assert row["eqn_6_1"] == 0.0 and row["centre_distance_mm"] == 0.0
    assert row["level_difference"] == pytest.approx(12.5)
    assert row["paired"]


def test_a_fill_without_a_frame_near_it_is_not_paired(model26):
    x = model26.node_rest_position
    frames = _frames(model26, [x], [0.0])
    fill = float(frames["tank_fraction"][0]) - 2 * PAIRING_TOLERANCE
    (row,) = compare(frames, frames, model26, [fill])
    assert not row["paired"]


def test_a_static_start_against_itself_has_no_dynamic_amplification():
    """The dynamic amplification of the sheet's peak stress (``stress_ratio``): a frame that
    is itself the static equilibrium holding its volume (the coupled fill's static start)
    is its own static reference, so its ratio is 1, and the peak is the run's stress rule's
    largest surface stress on the free sheet."""
    from fsi.analysis.membrane_fields import FIELD_RULES
    from fsi.analysis.static_vs_dynamic import against_static
    from fsi.procedures.coupled_fill import membrane_settings, static_start
    from fsi.scene import load_scene
    from fsi.setup.build import build
    from structure.topology import free_triangles
    from structure.xpbd import XpbdModel

    setup = build(load_scene("diaphragm-fill"))
    state, info = static_start(setup, XpbdModel.from_membrane(setup.model),
                               membrane_settings(setup))
    frames = {"node_position": state.node_position[None], "pressure_level":
              np.array([info.pressure_level])}
    (row,) = against_static(setup, frames)
    rule = FIELD_RULES["xpbd"](setup.model, setup.scene)
    sheet = free_triangles(setup.model.node_fixed, rule.term.triangles)
    assert row["peak_stress_dynamic"] == \
        rule.sheet(state.node_position)["surface_stress"][sheet].max()
    assert row["stress_ratio"] == pytest.approx(1.0, abs=0.01)
