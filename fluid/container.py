"""Containers as level sets: negative inside (m), zero on the wall, in the tank frame.

A container is evaluated on coordinate arrays: (r, z) on an axisymmetric grid, (x, y, z) on a
3-D grid (broadcasting). Distances are exact for the sphere and the side of a cylinder and
take the max/min of the pieces elsewhere, which is all the cut-cell geometry needs (the zero
set is exact).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def _radius(coords) -> np.ndarray:
    """Distance from the z axis: r itself (2-D) or hypot(x, y) (3-D)."""
    return coords[0] if len(coords) == 2 else np.hypot(coords[0], coords[1])


@dataclass(frozen=True)
class SphericalTank:
    """Sphere of ``radius`` (m) centred at the origin, with a port stub of ``port_radius`` (m)
    running straight down from the bottom pole (through the grid's bottom boundary, where the
    port condition is applied). ``port_radius`` 0: no stub."""

    radius: float
    port_radius: float = 0.0

    def __post_init__(self):
        if not self.radius > 0:
            raise ValueError(f"tank radius must be > 0 m, got {self.radius}")
        if not 0 <= self.port_radius < self.radius:
            raise ValueError(f"port radius must be in [0, {self.radius}) m, got {self.port_radius}")

    def level_set(self, coords) -> np.ndarray:
        r = _radius(coords)
        z = coords[-1]
        sphere = np.sqrt(r * r + z * z) - self.radius
        if self.port_radius == 0:
            return sphere
        stub = np.maximum(r - self.port_radius, z + 0.5 * self.radius)
        return np.minimum(sphere, stub)

    def bounds(self, port_length: float):
        """(r_max, z_min, z_max) of a grid that holds the tank and ``port_length`` m of stub."""
        return self.radius, -self.radius - port_length, self.radius

    def stub_volume(self, z_bottom: float) -> float:
        """Volume (m^3) of the port stub outside the sphere, from the sphere down to
        ``z_bottom`` (m, below the bottom pole): the cylinder r < r_p below
        z = -sqrt(R^2 - r^2), pi r_p^2 (-z_bottom) - 2 pi / 3 (R^3 - (R^2 - r_p^2)^(3/2))."""
        if self.port_radius == 0:
            return 0.0
        if not z_bottom <= -self.radius:
            raise ValueError(f"the stub's bottom must lie at or below the bottom pole "
                             f"(-{self.radius} m), got {z_bottom} m")
        r2, rp2 = self.radius**2, self.port_radius**2
        return float(np.pi * rp2 * -z_bottom
                     - 2 * np.pi / 3 * (self.radius**3 - (r2 - rp2)**1.5))

    def volume_below(self, level: float) -> float:
        """Volume (m^3) of the sphere below z = ``level`` (m, clipped to [-R, R]; the stub
        not counted): pi (R^2 z - z^3 / 3 + 2 R^3 / 3)."""
        z = float(np.clip(level, -self.radius, self.radius))
        return float(np.pi * (self.radius**2 * z - z**3 / 3 + 2 * self.radius**3 / 3))

    def level_holding(self, volume: float) -> float:
        """The level z (m) below which the sphere holds ``volume`` (m^3), 0 < volume <
        4/3 pi R^3 (bisection to machine precision: the volume rises monotonically)."""
        full = 4.0 / 3.0 * np.pi * self.radius**3
        if not 0 < volume < full:
            raise ValueError(f"volume must be in (0, {full:.6g}) m^3, got {volume}")
        low, high = -self.radius, self.radius
        for _ in range(200):
            mid = 0.5 * (low + high)
            if self.volume_below(mid) < volume:
                low = mid
            else:
                high = mid
            if high - low <= 4 * np.finfo(float).eps * self.radius:
                break
        return 0.5 * (low + high)

    def centroid_below(self, level: float) -> float:
        """Height (m) of the centroid of the sphere's part below z = ``level`` (m):
        int z (R^2 - z^2) dz / int (R^2 - z^2) dz over [-R, level]."""
        z = float(np.clip(level, -self.radius, self.radius))
        r2 = self.radius**2
        moment = np.pi * (r2 * z**2 / 2 - z**4 / 4 - r2**2 / 4)
        return float(moment / self.volume_below(z))


@dataclass(frozen=True)
class UprightCylinder:
    """Cylinder of ``radius`` (m) about the z axis between ``z_min`` and ``z_max`` (m); an end
    beyond the grid is open there (a port on that grid side)."""

    radius: float
    z_min: float
    z_max: float

    def __post_init__(self):
        if not self.radius > 0 or not self.z_max > self.z_min:
            raise ValueError(f"cylinder needs radius > 0 m and z_max > z_min, got radius="
                             f"{self.radius}, z_min={self.z_min}, z_max={self.z_max}")

    def level_set(self, coords) -> np.ndarray:
        r = _radius(coords)
        z = coords[-1]
        return np.maximum(r - self.radius, np.maximum(self.z_min - z, z - self.z_max))

