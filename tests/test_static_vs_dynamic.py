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
