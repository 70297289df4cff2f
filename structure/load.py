"""What the liquid and the tank put on the membrane, and what a solve reports back: the one
load description and the one pair of outcome types that every structure model speaks.

A :class:`Load` is

* the liquid-side node pressure without the uniform level: an array (n,) Pa held during a
  step (the coupled liquid's), or a field ``p(x)`` of the node positions (n, 3) m (the
  hydrostatic liquid, re-evaluated as the membrane moves);
* the body acceleration b (3,) m/s^2 in the tank frame (gravity minus the tank's
  acceleration), felt by the membrane's mass (and, in the energy models, by the liquid);
* either a liquid volume to hold (``volume_target``, m^3), whose Lagrange multiplier is the
  uniform pressure level (the thesis's equivalent fluid height, found), or a uniform level to
  hold (``pressure_level``, Pa, added to the node pressure); with a volume target the level
  is the solve's starting guess;
* the liquid density (kg/m^3) where a model needs the pressure's potential (the shell model's
  energy: the pressure is then the hydrostatic p = p_ref + rho b . x).

The pressure acts on the membrane as the external force of every model,

    F_i = (A_i p_i) n_i + m_i b                                                      (N)

with A_i n_i the node's area vector: the thesis's App. D area along its surfnorm normal, or
the gradient of the liquid volume dV/dx_i (pointing out of the liquid) in the continuum models.

Static solves return (state, :class:`Equilibrium`); dynamic steppers share the signature
``step(model, state_in, load, dt, settings) -> (state_out, StepInfo)``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

PressureField = Callable[[np.ndarray], np.ndarray]
"""Pressure (n,) Pa on the liquid side at node positions (n, 3) m, without the uniform level."""


@dataclass(frozen=True)
class Load:
    """The load on the membrane (module doc).

    node_pressure : (n,) Pa or :data:`PressureField`; body_acceleration : (3,) m/s^2;
    volume_target : liquid volume to hold (m^3) or None; pressure_level : uniform level (Pa),
    held without a volume target, the starting guess with one; liquid_density : kg/m^3 or None.
    """

    node_pressure: object
    body_acceleration: object
    volume_target: Optional[float] = None
    pressure_level: float = 0.0
    liquid_density: Optional[float] = None

    def pressure(self, node_position: np.ndarray) -> np.ndarray:
        """Liquid-side pressure (n,) Pa at the nodes, without the uniform level."""
        p = self.node_pressure
        return p(node_position) if callable(p) else p


def external_force(node_pressure: np.ndarray, node_normal: np.ndarray, node_mass: np.ndarray,
                   body_acceleration, node_area: Optional[np.ndarray] = None) -> np.ndarray:
    """F_i = (A_i p_i) n_i + m_i b, (n, 3) N.

    node_pressure (n,) Pa; node_normal (n, 3): the unit normal with ``node_area`` (n,) m^2, or
    the area vector A_i n_i (m^2) when ``node_area`` is None; node_mass (n,) kg (zero on fixed
    nodes where they carry no load); body_acceleration (3,) m/s^2.
    """
    load = node_pressure if node_area is None else node_area * node_pressure
    return (load[:, None] * node_normal
            + node_mass[:, None] * np.asarray(body_acceleration, dtype=float)[None, :])


@dataclass
class Equilibrium:
    """Outcome of a static solve, every model.

    steps : solver iterations (pseudo-steps, substeps or L-BFGS iterations); converged;
    pressure_level : uniform level (Pa) at the tank centre, NaN when the tank wall alone fixes
    the volume; liquid_volume (m^3); move_ratio : largest free-node move of the last step over
    its length scale (-); strain_error, strain_max : the thesis's in-plane strain measures (-);
    force_ratio : largest free-node residual force over the pressure force scale (-). A
    measure a model does not take is NaN. limit_points : the snaps a path of volume steps
    crossed on its way to this state, each a :class:`LimitPoint` (empty where the solver
    does not follow a path). seed : the imperfection the solve started from, (circumferential
    wave number, largest displacement m); empty where it started unseeded.
    """

    steps: int
    converged: bool
    pressure_level: float
    liquid_volume: float
    move_ratio: float = float("nan")
    strain_error: float = float("nan")
    strain_max: float = float("nan")
    force_ratio: float = float("nan")
    limit_points: tuple = ()
    seed: tuple = ()


@dataclass(frozen=True)
class LimitPoint:
    """A snap a path of volume steps crossed (its predicted state was not stable on the
    volume's tangent space, so the branch it came along had ended): the liquid volume where
    it was crossed (m^3), the level before and after (Pa), and how (``shifted Newton``: the
    tangent shifted until positive definite there; ``pseudo-inertia``: the undamped sheet's
    implicit steps)."""

    liquid_volume: float
    level_before: float
    level_after: float
    crossed_by: str


@dataclass
class StepInfo:
    """Outcome of a dynamic step: substeps taken, and the uniform pressure level (Pa) of its
    end, the volume target's multiplier or the held level."""

    substeps: int
    pressure_level: float
