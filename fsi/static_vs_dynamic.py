"""Static against dynamic: a coupled fill or drain against the static sweep of the same
membrane model and grid, at the same tank fraction V / (4/3 pi R^3).

At each tank fraction asked for, the dynamic run's frame nearest to it and the static
sweep's frame nearest to it are compared by

* the shape, thesis Eqn 6.1 (%), the static frame as reference (:mod:`fsi.compare`);
* the pressure level, dynamic minus static (Pa, the uniform level at the tank centre);
* the liquid's centre of mass, the distance between the two (mm), from the membrane's
  enclosed volume and first moment (:func:`structure.volume.liquid_first_moment`).

Each row also carries both frames' tank fractions, so a pair further apart than
``pairing_tolerance`` is visible (``paired``: False).
"""
from __future__ import annotations

import numpy as np

from structure.model import MembraneModel
from structure.volume import liquid_first_moment, liquid_volume

from .compare import eqn_6_1_error

PAIRING_TOLERANCE = 0.01
"""Frames whose tank fractions are further apart than this are not the same fill (-)."""


def centre_of_mass(model: MembraneModel, node_position: np.ndarray) -> np.ndarray:
    """The liquid's centre of mass (3,) m below the membrane at ``node_position`` (n, 3) m."""
    return liquid_first_moment(model, node_position) / liquid_volume(model, node_position)


def compare(dynamic_frames: dict, static_frames: dict, model: MembraneModel, fills,
            pairing_tolerance: float = PAIRING_TOLERANCE) -> list[dict]:
    """Rows, one per tank fraction in ``fills``: fill, tank_dynamic, tank_static (-),
    eqn_6_1 (%), level_difference (Pa), centre_distance_mm (mm), paired (bool).

    ``dynamic_frames`` and ``static_frames``: a result's ``frames`` group (node_position
    (k, n, 3) m, tank_fraction (k,), pressure_level (k,) Pa), both on ``model``'s grid."""
    rows = []
    for fill in fills:
        k = int(np.argmin(np.abs(dynamic_frames["tank_fraction"] - fill)))
        j = int(np.argmin(np.abs(static_frames["tank_fraction"] - fill)))
        x_dyn = dynamic_frames["node_position"][k]
        x_sta = static_frames["node_position"][j]
        tank_dyn = float(dynamic_frames["tank_fraction"][k])
        tank_sta = float(static_frames["tank_fraction"][j])
        rows.append(dict(
            fill=float(fill), tank_dynamic=tank_dyn, tank_static=tank_sta,
            eqn_6_1=eqn_6_1_error(x_sta, model.face_nodes, x_dyn, model.radius),
            level_difference=float(dynamic_frames["pressure_level"][k]
                                   - static_frames["pressure_level"][j]),
            centre_distance_mm=1e3 * float(np.linalg.norm(centre_of_mass(model, x_dyn)
                                                          - centre_of_mass(model, x_sta))),
            paired=bool(abs(tank_dyn - fill) <= pairing_tolerance
                        and abs(tank_sta - fill) <= pairing_tolerance)))
    return rows
