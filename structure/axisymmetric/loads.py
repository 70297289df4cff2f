"""The loads on the shell of revolution and their potentials, as densities per unit rest arc
length S of the local variables u = (r, r', r'', z, z', z'') with their derivatives.

**Enclosed volume.** The volume between the sheet and the plane of its rim (the disc the rim
spans) is

    V_b = pi Int_0^L r^2 z' dS                                                   (m^3)

(divergence theorem with F = (x, y, 0) / 2, whose flux through the rim's disc vanishes), > 0
when the sheet hangs below its rim. A uniform pressure p on the sheet's rim side (above the
hanging sheet, inside the bowl) has the potential -p V_b: its work on any admissible motion.

**Liquid below the sheet.** The tank is the sphere of radius a, the rim's radius, centred on
the rim's centre (z = 0), the rim on its equator. With the sheet inside the sphere and not
crossing itself, the liquid fills the region bounded by the lower hemisphere of the tank, the
rim's disc and the sheet:

    V_liquid = 2/3 pi a^3 - V_b,        M_liquid = Int z dV = -pi a^4 / 4 - M_b,
    M_b = pi Int_0^L r^2 z z' dS                                                  (m^4)

(the lower hemisphere's volume and first moment minus the region between sheet and rim
plane, as :mod:`structure.volume` sums them over triangles). Under gravity g along -z the
liquid pressure is p_ref - rho g z (p_ref the pressure level at z = 0, Pa), with the
potential rho g M_liquid - p_ref V_liquid. Held at a liquid volume V*, p_ref is the Lagrange
multiplier of V_liquid = V* (the equivalent liquid level is p_ref / (rho g) above z = 0).
The tank wall acts through its own barrier (:mod:`~structure.axisymmetric.wall`), which keeps
the sheet within the band d_hat beyond the sphere: the liquid counted there is the band's.

**Own weight.** rho_m t g Int z dA_0, dA_0 = 2 pi R A dS the rest area.

Summed, up to constants, the load potential is

    Pi_load = rho_m t g Int z dA_0 - rho g M_b - mu V_b,    mu = p - p_ref,

mu the net uniform pressure into the bowl (Pa). Held at a volume, the multiplier is mu.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

CONTROLLED = ("liquid", "enclosed")
"""What a volume target holds: the liquid volume (multiplier: the pressure level) or the
enclosed volume V_b (multiplier: the pressure)."""


@dataclass(frozen=True)
class AxisymmetricLoad:
    """The load on the shell of revolution (module doc).

    * pressure : p (Pa), uniform, on the sheet's rim side; held, or found when a volume target
      on the enclosed volume holds it;
    * pressure_level : p_ref (Pa), the liquid's pressure at z = 0; held, or found when a volume
      target on the liquid holds it;
    * liquid_density : rho (kg/m^3) of the liquid below the sheet;
    * gravity : g (m/s^2) along -z, on the liquid and on the sheet (its material's density);
    * volume_target : None (pressure control) or the volume (m^3) to hold, of the liquid or
      the enclosed region (``controlled``, one of :data:`CONTROLLED`).
    """

    pressure: float = 0.0
    pressure_level: float = 0.0
    liquid_density: float = 0.0
    gravity: float = 0.0
    volume_target: Optional[float] = None
    controlled: str = "liquid"

    def __post_init__(self):
        if self.controlled not in CONTROLLED:
            raise ValueError(f"controlled must be one of {CONTROLLED}, got {self.controlled!r}")
        if self.liquid_density < 0 or self.gravity < 0:
            raise ValueError("liquid_density and gravity must be >= 0")

    @property
    def net_pressure(self) -> float:
        """mu = p - p_ref (Pa), the net uniform pressure into the bowl (module doc)."""
        return self.pressure - self.pressure_level


def lower_hemisphere(radius: float) -> tuple[float, float]:
    """(volume m^3, first moment Int z dV m^4) of the tank's lower hemisphere of ``radius`` m
    centred at z = 0."""
    return 2.0 / 3.0 * np.pi * radius**3, -0.25 * np.pi * radius**4


def enclosed_target(load: AxisymmetricLoad, radius: float) -> float:
    """V_b* (m^3): the enclosed volume that ``load``'s volume target holds (module doc)."""
    if load.controlled == "enclosed":
        return float(load.volume_target)
    return lower_hemisphere(radius)[0] - float(load.volume_target)


def volume_density(u: np.ndarray, order: int = 2):
    """pi r^2 z' (P,) m^2 and, by ``order``, its gradient (P, 6) and Hessian (P, 6, 6) in
    u (P, 6): V_b per unit S."""
    r, z1 = u[:, 0], u[:, 4]
    v = np.pi * r * r * z1
    if order == 0:
        return v
    g = np.zeros(u.shape)
    g[:, 0], g[:, 4] = 2 * np.pi * r * z1, np.pi * r * r
    if order == 1:
        return v, g
    h = np.zeros(u.shape + (6,))
    h[:, 0, 0] = 2 * np.pi * z1
    h[:, 0, 4] = h[:, 4, 0] = 2 * np.pi * r
    return v, g, h


def moment_density(u: np.ndarray, order: int = 2):
    """pi r^2 z z' (P,) m^3 and, by ``order``, its gradient (P, 6) and Hessian (P, 6, 6) in
    u (P, 6): M_b per unit S."""
    r, z, z1 = u[:, 0], u[:, 3], u[:, 4]
    m = np.pi * r * r * z * z1
    if order == 0:
        return m
    g = np.zeros(u.shape)
    g[:, 0], g[:, 3], g[:, 4] = 2 * np.pi * r * z * z1, np.pi * r * r * z1, np.pi * r * r * z
    if order == 1:
        return m, g
    h = np.zeros(u.shape + (6,))
    h[:, 0, 0] = 2 * np.pi * z * z1
    h[:, 0, 3] = h[:, 3, 0] = 2 * np.pi * r * z1
    h[:, 0, 4] = h[:, 4, 0] = 2 * np.pi * r * z
    h[:, 3, 4] = h[:, 4, 3] = np.pi * r * r
    return m, g, h
