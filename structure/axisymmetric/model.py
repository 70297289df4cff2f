"""The shell of revolution: its discretised meridian, its section and law, its rim support.

The section is a :class:`structure.model.Material` (thickness t, density rho_m, Young's modulus
E, Poisson ratio nu, ``wrinkling`` "tension-field" for a sheet that carries no compression);
the membrane law a :class:`structure.hyperelastic.SaintVenantKirchhoff` or
:class:`structure.hyperelastic.HyperelasticLaw` (:func:`structure.axisymmetric.laws.law_of`
makes either from the material); the bending stiffness the material's
D = E t^3 / (12 (1 - nu^2)) (:attr:`structure.model.Material.flexural_rigidity`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import scipy.sparse as sp

from ..hyperelastic import SaintVenantKirchhoff
from ..model import Material
from .assembly import Scatter, scatter
from .meridian import Meridian, RestShape, build_meridian
from .supports import Admissible, admissible
from .wall import BarrierWall


@dataclass(frozen=True)
class ShellOfRevolution:
    """meridian : :class:`~structure.axisymmetric.meridian.Meridian`; material :
    :class:`structure.model.Material`; law : the membrane law; support : the rim's, one of
    :data:`structure.axisymmetric.supports.SUPPORTS`; bending : include the bending energy;
    wall : the tank wall's barrier (:class:`~structure.axisymmetric.wall.BarrierWall`), or
    None (no contact); residual_stiffness : under the tension field, the fraction of the
    full law kept, (1 - e) W_relaxed + e W, in [0, 1) (0 the pure tension field;
    :mod:`~structure.axisymmetric.laws`). ``admissible``
    (:class:`~structure.axisymmetric.supports.Admissible`) is derived."""

    meridian: Meridian
    material: Material
    law: object
    support: str = "clamped"
    bending: bool = True
    wall: Optional[BarrierWall] = None
    residual_stiffness: float = 0.0
    admissible: Admissible = field(init=False, repr=False)

    def __post_init__(self):
        if isinstance(self.law, SaintVenantKirchhoff) and \
                self.law.poisson_ratio != self.material.poisson_ratio:
            raise ValueError(f"the law's Poisson ratio {self.law.poisson_ratio} is not the "
                             f"material's {self.material.poisson_ratio}")
        if not 0.0 <= self.residual_stiffness < 1.0:
            raise ValueError(f"residual_stiffness must be in [0, 1), got "
                             f"{self.residual_stiffness}")
        object.__setattr__(self, "admissible", admissible(self.meridian, self.support))

    @property
    def tension_field(self) -> bool:
        """The sheet carries no compression (the material's ``wrinkling``)."""
        return self.material.wrinkling == "tension-field"

    @property
    def flexural_rigidity(self) -> float:
        """D (N m), zero without bending."""
        return self.material.flexural_rigidity if self.bending else 0.0

    @property
    def radius(self) -> float:
        """The rim's radius a (m), the tank's."""
        return self.meridian.shape.radius

    @cached_property
    def state_scatter(self) -> Scatter:
        """Element matrices into the (4 n, 4 n) matrix of a state's entries."""
        return scatter(self.meridian.element_dofs, sp.identity(self.meridian.size))

    @cached_property
    def free_scatter(self) -> Scatter:
        """Element matrices into the (k, k) matrix T^T H T of the free coordinates."""
        return scatter(self.meridian.element_dofs, self.admissible.basis)


def shell_of_revolution(kind: str, radius: float, material: Material, law, elements: int,
                        support: str = "clamped", bending: bool = True, points: int = 4,
                        pole_ratio: float = 1.0, rim_ratio: float = 1.0,
                        wall: Optional[BarrierWall] = None,
                        sphere_radius: Optional[float] = None) -> ShellOfRevolution:
    """The shell of the rest shape ``kind`` (``hemisphere``, ``disc`` or ``cap``, whose
    sphere has ``sphere_radius`` m) of ``radius`` m on ``elements`` elements
    (:func:`~structure.axisymmetric.meridian.build_meridian`), inside ``wall`` (or free)."""
    meridian = build_meridian(RestShape(kind, radius, sphere_radius), elements, points,
                              pole_ratio, rim_ratio)
    return ShellOfRevolution(meridian, material, law, support, bending, wall)
