"""Hydrostatic liquid: pressure at points for a uniform body acceleration.

In the tank frame the liquid at rest obeys grad p = rho b, with b the body acceleration
(gravity minus the tank's acceleration), so

    p(x) = p_ref + rho b . x                                     (Pa, gauge to the gas)

with p_ref the pressure at the tank centre. For upright gravity b = (0, 0, -g) this is the
thesis's Eqn 4.5, p = rho g (h - z), with the equivalent fluid height h = p_ref / (rho g).
For any direction, h is measured along -b: p = rho |b| (h - (-b/|b|) . x).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class HydrostaticLiquid:
    """Liquid of density ``density`` (kg/m^3) under body acceleration ``body_acceleration``
    (3,) m/s^2 (tank frame; gravity (0, 0, -g) for an upright tank at rest)."""

    density: float
    body_acceleration: tuple

    def __post_init__(self):
        if not self.density > 0:
            raise ValueError(f"density must be > 0 kg/m^3, got {self.density!r}")
        b = np.asarray(self.body_acceleration, dtype=float)
        if b.shape != (3,) or not np.all(np.isfinite(b)):
            raise ValueError(f"body_acceleration must be 3 finite numbers (m/s^2), got {b!r}")

    @property
    def acceleration_magnitude(self) -> float:
        """|b| (m/s^2)."""
        return float(np.linalg.norm(self.body_acceleration))

    def pressure(self, points: np.ndarray, reference_pressure: float = 0.0) -> np.ndarray:
        """Gauge pressure (Pa) at ``points`` (n, 3) m for pressure ``reference_pressure`` (Pa)
        at the tank centre: p = p_ref + rho b . x."""
        b = np.asarray(self.body_acceleration, dtype=float)
        return reference_pressure + self.density * (np.asarray(points) @ b)

    def equivalent_height(self, reference_pressure: float) -> float:
        """Equivalent fluid height h = p_ref / (rho |b|) (m); NaN in zero g."""
        g = self.acceleration_magnitude
        return reference_pressure / (self.density * g) if g > 0 else float("nan")

    def reference_pressure(self, equivalent_height: float) -> float:
        """Inverse of :meth:`equivalent_height`: p_ref = rho |b| h (Pa)."""
        return self.density * self.acceleration_magnitude * equivalent_height
