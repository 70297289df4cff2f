"""Liquid volume enclosed between the lower tank wall and the membrane.

With the rim on the equator, the divergence theorem with F = (0, 0, z) over the liquid region
(bounded by the lower tank wall and the membrane) gives

    V_liquid = (2/3) pi R^3 + sum over membrane triangles of zbar * A_xy,

the triangle terms taken with normals pointing out of the liquid (Levine 2014, App. J computes
the same sum, per quad). The formula holds for any non-self-intersecting membrane inside the
tank, folded or not, and is exact for the faceted (triangulated) membrane.

The fill scale (:class:`FillScale`) maps volume to fill fraction between an empty and a full
volume; :mod:`fsi.setup.fill` defines the project's scale (docs/user-guide/scenes.md, 'Fill
fraction and volume').
"""
from __future__ import annotations

import numpy as np

from .kernels import closed_volume_gradient, closed_volume_term, first_moment
from .model import MembraneModel


def tank_volume(radius: float) -> float:
    """4/3 pi R^3 (m^3): the spherical tank's volume, of which a tank fraction is a fraction."""
    return 4.0 / 3.0 * np.pi * radius**3


def lower_hemisphere_volume(radius: float) -> float:
    """(2/3) pi R^3 (m^3)."""
    return 2.0 / 3.0 * np.pi * radius**3


def liquid_volume(model: MembraneModel, node_position: np.ndarray) -> float:
    """Liquid volume (m^3) below the membrane at ``node_position`` (n, 3) m."""
    return lower_hemisphere_volume(model.radius) + closed_volume_term(
        node_position, model.face_nodes, model.volume_sign)


def liquid_volume_gradient(model: MembraneModel, node_position: np.ndarray) -> np.ndarray:
    """d V_liquid / d node_position, (n, 3) m^2."""
    return closed_volume_gradient(node_position, model.face_nodes, model.volume_sign)


def liquid_first_moment(model: MembraneModel, node_position: np.ndarray) -> np.ndarray:
    """First moment of the liquid below the membrane, the integral of x over it, (3,) m^4:
    the membrane's triangles (divergence theorem, F = (x_k^2 / 2) e_k) plus the lower
    hemisphere's (0, 0, -pi R^4 / 4). The liquid's centroid is this over its volume."""
    m1, _ = first_moment(np.ascontiguousarray(node_position, dtype=float), model.face_nodes,
                         model.volume_sign)
    return m1 + np.array([0.0, 0.0, -0.25 * np.pi * model.radius**4])


def mirrored_rest_position(model: MembraneModel) -> np.ndarray:
    """Rest shape mirrored through z = 0 (the fully inverted membrane), (n, 3) m."""
    p = model.node_rest_position.copy()
    p[:, 2] *= -1.0
    return p


class FillScale:
    """Maps liquid volume (m^3) to fill fraction (-) and back:
    phi = (V - empty_volume) / (full_volume - empty_volume)."""

    def __init__(self, empty_volume: float, full_volume: float):
        if not full_volume > empty_volume:
            raise ValueError(f"full volume {full_volume!r} m^3 must exceed the empty volume "
                             f"{empty_volume!r} m^3")
        self.empty_volume = float(empty_volume)
        self.full_volume = float(full_volume)

    @classmethod
    def mirrored(cls, model: MembraneModel) -> "FillScale":
        """Geometric scale: empty = rest shape, full = rest shape mirrored through z = 0."""
        return cls(liquid_volume(model, model.node_rest_position),
                   liquid_volume(model, mirrored_rest_position(model)))

    @classmethod
    def tank(cls, radius: float) -> "FillScale":
        """The tank fraction V / ((4/3) pi R^3): empty = 0, full = the tank's volume."""
        return cls(0.0, tank_volume(radius))

    def volume(self, fill_fraction):
        """Liquid volume (m^3) at fill fraction ``fill_fraction`` (-)."""
        return self.empty_volume + np.asarray(fill_fraction) * (self.full_volume - self.empty_volume)

    def fill(self, volume):
        """Fill fraction (-) of liquid volume ``volume`` (m^3)."""
        return (np.asarray(volume) - self.empty_volume) / (self.full_volume - self.empty_volume)
