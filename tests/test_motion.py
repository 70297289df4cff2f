"""Tank motion of dynamic scenes (fsi/motion.py): a(t) by kind and b(t) = g - a(t)."""
import numpy as np
import pytest

from fsi.setup.motion import MOTIONS, body_acceleration, tank_acceleration
from fsi.scene import SceneError, parse_scene


def test_motion_kinds():
    assert {"none", "sine", "table"} <= set(MOTIONS)
    sine = tank_acceleration(dict(kind="sine", amplitude=[2.0, 0.0, -1.0], frequency=4.0))
    assert np.allclose(sine(0.0), 0.0)
    assert np.allclose(sine(1 / 16), [2.0, 0.0, -1.0])  # a quarter period
    table = tank_acceleration(dict(kind="table", history=[[0.1, 0, 0, 0], [0.3, 2, -4, 6]]))
    assert np.allclose(table(0.0), 0.0)           # held before the first row
    assert np.allclose(table(0.2), [1, -2, 3])    # linear between rows
    assert np.allclose(table(9.0), [2, -4, 6])    # held after the last row
    b = body_acceleration([0.0, 0.0, -9.81], dict(kind="table",
                                                 history=[[0, 0, 0, 0], [1, 1, 0, 0]]))
    assert np.allclose(b(0.5), [-0.5, 0.0, -9.81])  # the liquid lags the tank: g - a


@pytest.mark.parametrize("text, key", [
    ("[motion]\nkind = 'shake'", "motion.kind"),
    ("[motion]\nkind = 'table'", "motion.history"),
    ("[motion]\nhistory = [[0, 0, 0, 0], [0, 1, 0, 0]]", "motion.history"),
    ("[motion]\nfrequency = -1.0", "motion.frequency"),
])
def test_bad_motion_is_named(text, key):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        parse_scene(text)
