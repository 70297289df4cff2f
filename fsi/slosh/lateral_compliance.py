"""The contents' static lateral compliance and what it says of the slosh modes.

Tilt the body acceleration by a small lateral b_x and let the contents (liquid and
membrane) settle: their centre of mass moves along it by C b_x, and

    C = d x_c / d b_x                                                          (s^2)

is a static quantity, from two hydrostatic solves. A linear slosh system's static response
is the sum of its modes' (the NASA SP-106 spring-mass equivalent, slosh mass m_n on a spring
k_n = m_n omega_n^2; Abramson 1966, Ch. 6), so for contents of mass M

    M C = sum_n m_n / omega_n^2,                                               (1)

and since the slosh masses leave a fixed mass M - sum m_n >= 0, omega_1^2 <= 1 / C: the first
mode's frequency is at most 1 / (2 pi sqrt(C)) (2). For a free surface in a sphere the liquid
turns rigidly about the centre as b turns, so C = |z_c| / g with z_c the liquid's centroid
height (3R / (8 g) at half fill), and (1) with the first mode alone gives the slosh mass
fraction m_1 / M = lambda1 |z_c| / R (0.585 at half fill, lambda1 = 1.5602).

A diaphragm makes C smaller (its stiffness holds the liquid), and C needs no fluid grid, no
time step and no coupling: it is the hydrostatic tier's measure of the lateral stiffness, the
check of a coupled run's fitted modes by (1), and the membrane grid's convergence test.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from structure.volume import liquid_first_moment

DEFAULT_TILT = 0.05
"""Lateral body acceleration (m/s^2) of the two tilted solves, +- this: 0.5 % of g. The
Table 4.1 diaphragm's start at half fill gives C at 0.05 and at 0.01 m/s^2 within 0.4 / 2.7 /
9 / 0.5 / 1.5 % at N = 10 / 14 / 20 / 26 / 38 (docs/notes/lateral-compliance.md)."""


@dataclass(frozen=True)
class Compliance:
    """C (s^2) from the centred difference of two tilted solves; asymmetry: their mean
    displacement over the tilt (s^2; 0 for a linear response); converged: both solves."""

    compliance: float
    asymmetry: float
    converged: bool


def contents_centre(model, node_position: np.ndarray, liquid_density: float,
                    liquid_volume: float) -> np.ndarray:
    """(3,) m: the centre of mass of the liquid (``liquid_volume`` m^3 of ``liquid_density``
    kg/m^3 below the membrane) and the membrane (its node masses at ``node_position``
    (n, 3) m) of the membrane model ``model``."""
    m1 = liquid_first_moment(model, node_position)
    mass = model.node_mass
    return (liquid_density * m1 + mass @ node_position) / (
        liquid_density * liquid_volume + float(mass.sum()))


def static_compliance(centre_at: Callable[[float], tuple], tilt: float = DEFAULT_TILT
                      ) -> Compliance:
    """C from ``centre_at(b_x)`` -> (centre (3,) m, converged) at b_x = 0 and +- ``tilt``
    (m/s^2)."""
    if not tilt > 0:
        raise ValueError(f"tilt must be > 0 m/s^2, got {tilt!r}")
    (c0, ok0), (cp, okp), (cm, okm) = (centre_at(b) for b in (0.0, tilt, -tilt))
    return Compliance(float((cp[0] - cm[0]) / (2 * tilt)),
                      float((cp[0] + cm[0] - 2 * c0[0]) / (2 * tilt)), bool(ok0 and okp and okm))


def free_surface_compliance(centroid_height: float, gravity: float) -> float:
    """C (s^2) of a free surface in a sphere: |z_c| / g, the liquid's centroid at
    ``centroid_height`` (m, from the centre) turning rigidly with b (module doc)."""
    return abs(centroid_height) / gravity


def modal_compliance(slosh_mass: np.ndarray, omega: np.ndarray, mass: float) -> float:
    """The right side of (1) over M: sum_n m_n / (M omega_n^2) (s^2), from the modes' x slosh
    masses (kg) and angular frequencies (rad/s)."""
    slosh_mass, omega = np.asarray(slosh_mass, dtype=float), np.asarray(omega, dtype=float)
    return float(np.sum(slosh_mass / omega**2) / mass)


def first_mode_bound(compliance: float) -> float:
    """The largest first-mode angular frequency (rad/s) that ``compliance`` (s^2) allows,
    1 / sqrt(C) (module doc, (2))."""
    return float(1.0 / np.sqrt(compliance))
