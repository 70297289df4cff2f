"""The registry of liquid steppers: how the liquid meets its interface, one entry per
``FluidModel.interface_condition``.

Each stepper module registers itself here with :func:`register_stepper`: the moving wall
(:mod:`fluid.projection`, ``'wall'``), the free surface (:mod:`fluid.free_surface`,
``'free'``) and the linearised free surface (:mod:`fluid.linear_surface`, ``'free-linear'``).
This module imports nothing of the package, so the stepper modules import it and not each
other's registry; :mod:`fluid.solver`, the liquid's API, imports all three.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Stepper:
    """How the liquid meets its interface: ``step(model, ops, state, geometry, dt)`` ->
    (state, report) and ``initial_pressure(model, ops, geometry, time)`` -> (n_cells,) Pa,
    the reduced pressure of the liquid at rest."""

    step: Callable
    initial_pressure: Callable


#: ``FluidModel.interface_condition`` -> :class:`Stepper` ('wall': the moving wall of
#: :mod:`fluid.projection`; 'free': the free surface of :mod:`fluid.free_surface`;
#: 'free-linear': the linearised surface of :mod:`fluid.linear_surface`)
STEPPERS: dict[str, Stepper] = {}


def register_stepper(name: str, initial_pressure: Callable):
    """Decorator: register a step function and its initial pressure under ``name``."""
    def register(func):
        STEPPERS[name] = Stepper(func, initial_pressure)
        return func
    return register
