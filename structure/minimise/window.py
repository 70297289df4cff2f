"""A quasi-static coupled window's membrane by the minimisation statics: the equilibrium at
the window's end holding the delivered volume under the liquid's pressure, its inertia dropped.

The liquid hands the membrane a pressure p_i at its nodes as they were sent, x_s. Its
hydrostatic part rho b . x is kept in the potential (the energy form, consistent over the
triangles, so that its stiffness is in the minimisation), and the rest,
dp_i = p_i - rho b . x_s,i, acts as a dead load, the nodal pressure force at the sent shape,

    f_i = dp_i dV/dx_i (x_s),   Pi_window = Pi - sum_i f_i . x_i,

which is conservative, so the window is a minimisation (straight at the end volume from the
window's start or the last iteration's end, and where that fails along the path of
:mod:`structure.minimise.path`, through the snaps a fold makes); when the coupling has
converged the sent shape is the end shape and f is the follower force there; a constant in dp
is then a level: it moves the multiplier by that constant, not the shape.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..load import Load
from ..model import MembraneState
from ..newton.system import NewtonModel
from .barrier import BarrierWall
from .model import inside, minimisation_model, xpbd_terms
from .path import equilibrium_near


class DeadForce:
    """A force (n, 3) N fixed in space on every node, energy -sum f . x: a term of the
    potential without Hessian."""

    def __init__(self, n_nodes: int):
        self.force = np.zeros((n_nodes, 3))

    @property
    def element_nodes(self) -> np.ndarray:
        return np.arange(len(self.force), dtype=np.int64)[:, None]

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        return -float(np.sum(self.force * x)), -self.force.copy(), None


@dataclass
class QuasiStaticMinimiser:
    """The potential of an XPBD model's energies with its barrier wall and a dead load
    (module doc), built once per run."""

    model: NewtonModel
    wall: BarrierWall
    dead: DeadForce

    @classmethod
    def from_xpbd(cls, xpbd_model, pressure: float) -> "QuasiStaticMinimiser":
        """The minimiser of ``xpbd_model``'s energies (its own law), the wall's barrier
        calibrated to ``pressure`` (Pa, e.g. rho |b| R)."""
        dead = DeadForce(len(xpbd_model.base.node_mass))
        model, wall = minimisation_model(xpbd_model.base, xpbd_terms(xpbd_model) + [dead],
                                         pressure)
        return cls(model, wall, dead)

    def solve(self, start: np.ndarray, node_pressure: np.ndarray, sent: np.ndarray,
              body: np.ndarray, liquid_density: float, target: float, level: float,
              guess: np.ndarray | None = None):
        """The equilibrium holding ``target`` (m^3) under the liquid's ``node_pressure`` (n,)
        Pa received at the ``sent`` (n, 3) m positions (module doc), body acceleration
        ``body`` (3,) m/s^2, from ``start`` (n, 3) m, or ``guess`` (n, 3) m where given
        (the last coupling iteration's end: the same equilibrium, from nearer); the level
        (Pa) the starting guess. Returns (MembraneState, Equilibrium,
        :class:`structure.minimise.path.PathReport`)."""
        body = np.asarray(body, dtype=float)
        _, gradient, _ = self.model.volume.evaluate(np.ascontiguousarray(sent, dtype=float),
                                                    False)
        extra = np.asarray(node_pressure, dtype=float) - liquid_density * (sent @ body)
        self.dead.force[:] = extra[:, None] * gradient
        self.dead.force[self.model.base.node_fixed] = 0.0
        load = Load(lambda x: liquid_density * (x @ body), body, volume_target=target,
                    pressure_level=level, liquid_density=liquid_density)
        x = inside(self.wall, start if guess is None else guess)
        (state, info), report = equilibrium_near(self.model, self.wall, MembraneState(x), load,
                                                 target)
        return state, info, report


__all__ = ["DeadForce", "QuasiStaticMinimiser"]
