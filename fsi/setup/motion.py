"""Tank motion of a dynamic scene: the tank's acceleration a(t) (m/s^2, along the tank's axes),
in a registry by ``motion.kind``. The liquid and the membrane feel the body acceleration
b(t) = g - a(t) in the tank frame (:func:`body_acceleration`).

* ``none``: a = 0;
* ``sine``: a = ``amplitude`` sin(2 pi ``frequency`` t) (zero at t = 0, so a static start is
  at rest);
* ``impulse``: a = ``amplitude`` sin^2(pi t / ``duration``) for t < ``duration``, then 0 (a
  smooth pulse, zero with its slope at both ends, then free motion; its velocity change is
  ``amplitude`` ``duration`` / 2);
* ``table``: a piecewise linear in time through the rows [t, ax, ay, az] of ``history``, held
  at the first row's value before it and at the last row's after it.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

Acceleration = Callable[[float], np.ndarray]

MOTIONS: dict[str, Callable[[dict], Acceleration]] = {}


def register_motion(name: str):
    """Decorator: register a builder motion table -> a(t) under ``name``."""
    def deco(func):
        MOTIONS[name] = func
        return func
    return deco


@register_motion("none")
def _none(motion: dict) -> Acceleration:
    return lambda t: np.zeros(3)


@register_motion("sine")
def _sine(motion: dict) -> Acceleration:
    amplitude = np.asarray(motion["amplitude"], dtype=float)
    omega = 2.0 * np.pi * float(motion["frequency"])
    return lambda t: amplitude * np.sin(omega * t)


@register_motion("impulse")
def _impulse(motion: dict) -> Acceleration:
    amplitude = np.asarray(motion["amplitude"], dtype=float)
    duration = float(motion["duration"])
    return lambda t: amplitude * np.sin(np.pi * t / duration) ** 2 if 0 <= t < duration \
        else np.zeros(3)


@register_motion("table")
def _table(motion: dict) -> Acceleration:
    rows = np.asarray(motion["history"], dtype=float)
    times, values = rows[:, 0], rows[:, 1:]
    return lambda t: np.array([np.interp(t, times, values[:, k]) for k in range(3)])


def tank_acceleration(motion: dict) -> Acceleration:
    """a(t) (3,) m/s^2 of the scene's ``[motion]`` table."""
    return MOTIONS[motion["kind"]](motion)


def body_acceleration(gravity, motion: dict) -> Callable[[float], np.ndarray]:
    """b(t) = gravity - a(t) (3,) m/s^2 in the tank frame; ``gravity`` (3,) m/s^2 is the
    scene's ``liquid.body_acceleration`` (the tank at rest)."""
    g = np.asarray(gravity, dtype=float)
    a = tank_acceleration(motion)
    return lambda t: g - a(t)
