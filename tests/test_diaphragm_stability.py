"""Partitioned schemes on the Table 4.1 diaphragm (mass ratio m / (rho_f R) = 0.009): constant
under-relaxation is stable below the added-mass bound and not above it, the explicit scheme
diverges (Causin, Gerbeau & Nobile 2005; README, 'On the diaphragm itself').  The bound was
measured between omega = 0.07 (converges) and 0.1 (does not) by
``benchmarks/diaphragm_stability.py``; the sphere's n = 1 estimate 2 m / (m + rho_f R) = 0.018
lies below it (safe)."""
from dataclasses import replace

import numpy as np
import pytest

from fsi.build import build
from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, TANK_RADIUS, WATER_DENSITY
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene


def _run(coupling: dict, windows: int):
    scene = load_scene("diaphragm-fill")
    values = {**scene.values, "coupling": {**scene["coupling"], **coupling},
              "dynamics": {**scene["dynamics"], "end_time": windows * 0.002,
                           "frame_interval": windows}}
    return PROCEDURES["coupled-fill"](build(replace(scene, values=values)), lambda f, m: None)


def test_constant_relaxation_converges_below_the_bound_and_not_above():
    m = MEMBRANE_DENSITY * MEMBRANE_THICKNESS
    estimate = 2 * m / (m + WATER_DENSITY * TANK_RADIUS)
    assert estimate == pytest.approx(0.018, abs=5e-4)
    below = _run(dict(acceleration="constant", relaxation=0.05, max_iterations=300), 1)
    assert below.attrs["failure"] == "" and below.groups["windows"]["converged"].all()
    above = _run(dict(acceleration="constant", relaxation=0.2, max_iterations=100), 1)
    assert "not converged after 100 iterations" in above.attrs["failure"]
    residual = float(above.attrs["failure"].split("'interface_pressure': ")[1].split(",")[0])
    assert residual > 0.5  # not slow: the iterates keep changing by their own size


def test_explicit_scheme_diverges_where_iqn_ils_does_not():
    explicit = _run(dict(scheme="explicit"), 25)
    implicit = _run(dict(), 2)
    speed = lambda r: float(np.nanmax(r.groups["frames"]["node_speed_max"]))  # noqa: E731
    assert speed(implicit) < 0.01  # m/s: the membrane follows the slow fill
    assert speed(explicit) > 100 * speed(implicit)
