"""Fixed data, settings, evolving state and multipliers of the XPBD membrane."""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Optional

import numpy as np

from ..bending import MidedgeBending
from ..grid import triangles_from_quads
from ..hyperelastic import TriangleMembrane
from ..load import external_force
from ..model import MembraneModel, MembraneState
from ..volume import liquid_volume_gradient
from .kernels import membrane_energy

WRINKLING = {"none": False, "tension-field": True}
"""The material's ``wrinkling`` -> whether the XPBD membrane blocks are relaxed by the
tension field (:func:`.kernels.relax_strain`)."""


@dataclass(frozen=True)
class XpbdModel:
    """Fixed data of the XPBD membrane built on a :class:`MembraneModel`'s grid, masses and
    fixed nodes.

    triangles (m, 3) int64 (the quads split as App. D does); rest_inverse (m, 2, 2) and
    rest_area (m,) m^2 of the reference triangles; membrane_compliance (m, 3, 3) 1/J (alpha of
    the Green-strain block); bending (:class:`MidedgeBending`); bending_compliance (m, 3, 3)
    1/(N m) (alpha of the angle block, zero rows on edges without an angle). With the
    material's ``wrinkling = "tension-field"`` the membrane blocks carry no compression
    (:func:`.kernels.relax_strain`, :attr:`tension_field`).
    """

    base: MembraneModel
    triangles: np.ndarray
    rest_inverse: np.ndarray
    rest_area: np.ndarray
    membrane_compliance: np.ndarray
    bending: MidedgeBending
    bending_compliance: np.ndarray

    @cached_property
    def angle_on_circle(self) -> np.ndarray:
        """(m, 3) rad zeros: the bending's reference turn for XPBD, which reads each angle
        change on the circle (:func:`structure.xpbd.substep.sweep`); made once, not per
        sweep."""
        return np.zeros_like(self.bending.rest_angle)

    @property
    def tension_field(self) -> bool:
        """Whether the membrane blocks are relaxed by the tension field (the material's
        ``wrinkling``)."""
        return WRINKLING[self.base.material.wrinkling]

    @classmethod
    def from_membrane(cls, base: MembraneModel, bending_boundary: str = "clamped") -> "XpbdModel":
        """XPBD constraints for ``base``: its material's E (Pa), t (m) and nu (-, <= 0.5)."""
        mat = base.material
        if not 0.0 <= mat.poisson_ratio <= 0.5:
            raise ValueError(f"poisson_ratio must be in [0, 0.5], got {mat.poisson_ratio}")
        tri = triangles_from_quads(base.face_nodes)
        # the grid's quads wind with their normal to the gas side; orientation does not matter
        # for strains and angles
        membrane = TriangleMembrane(base.node_rest_position, tri, mat.thickness)
        nu = mat.poisson_ratio
        k = mat.youngs_modulus / (1.0 - nu * nu)
        plane_stress = k * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 2.0 * (1.0 - nu)]])
        stiffness = (mat.thickness * membrane.rest_area)[:, None, None] * plane_stress
        bending = MidedgeBending.build(base.node_rest_position, tri, mat.flexural_rigidity,
                                       nu, bending_boundary)
        return cls(base, tri, membrane.rest_inverse, membrane.rest_area,
                   np.ascontiguousarray(np.linalg.inv(stiffness)), bending,
                   np.ascontiguousarray(np.linalg.pinv(bending.stiffness, hermitian=True)))

    def membrane_energy(self, node_position: np.ndarray) -> float:
        """Potential (J) of the membrane blocks at ``node_position`` (n, 3) m (relaxed by the
        tension field when it is on)."""
        return float(membrane_energy(np.ascontiguousarray(node_position, dtype=float),
                                     self.triangles, self.rest_inverse,
                                     self.membrane_compliance, self.tension_field,
                                     self.base.material.poisson_ratio))


@dataclass(frozen=True)
class XpbdSettings:
    """Substep settings.

    dt : substep (s); iterations : Gauss-Seidel sweeps per substep (-); warm_start : carry the
    multipliers between substeps, quasi-static (module doc); bending : include the bending
    block; kinetic_damping : without warm start, zero the velocities at each kinetic-energy
    peak;
    tolerance : converged when max |dx| / L_node per substep < tolerance (-);
    level_tolerance : and the level changes by less than this per substep (Pa);
    ramp_rate : the volume target moves by at most this fraction of the tank volume per substep;
    max_steps : cap on substeps per solve;
    node_damping : c (N s/m) of the dynamic substeps' damping of each node's velocity relative
    to its neighbours' (:mod:`structure.xpbd.damping`; 0: none).
    """

    dt: float = 1e-3
    iterations: int = 1
    warm_start: bool = True
    bending: bool = True
    kinetic_damping: bool = True
    tolerance: float = 1e-6
    level_tolerance: float = 0.01
    ramp_rate: float = 1e-3
    max_steps: int = 200_000
    node_damping: float = 0.0

    def __post_init__(self):
        if not self.dt > 0:
            raise ValueError(f"xpbd dt must be > 0 s, got {self.dt!r}")
        if self.iterations < 1:
            raise ValueError(f"xpbd iterations must be >= 1, got {self.iterations!r}")
        if not self.tolerance > 0:
            raise ValueError(f"xpbd tolerance must be > 0, got {self.tolerance!r}")
        if not 0 < self.ramp_rate <= 1:
            raise ValueError(f"xpbd ramp_rate must be in (0, 1], got {self.ramp_rate!r}")
        if not self.node_damping >= 0:
            raise ValueError(f"xpbd node_damping must be >= 0 N s/m, got {self.node_damping!r}")

@dataclass
class XpbdMultipliers:
    """Accumulated multipliers lambda (units of constraint^-1 J s^2): membrane (m, 3),
    bending (m, 3), volume (1,); the pressure level is volume[0] / dt^2 (Pa)."""

    membrane: np.ndarray
    bending: np.ndarray
    volume: np.ndarray

    @classmethod
    def zeros(cls, m: int) -> "XpbdMultipliers":
        return cls(np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(1))



def node_external_force(model: XpbdModel, x: np.ndarray, node_pressure: np.ndarray,
                        body_acceleration) -> np.ndarray:
    """Liquid-side pressure (n,) Pa on the node area vectors dV_liquid/dx (pointing out of the
    liquid) plus gravity on the node masses: (n, 3) N (:func:`structure.load.external_force`)."""
    base = model.base
    return external_force(node_pressure, liquid_volume_gradient(base, x), base.node_mass,
                          body_acceleration)


class XpbdDivergence(RuntimeError):
    """A substep moved a node by more than its own length, or produced non-finite positions."""


@dataclass
class XpbdState(MembraneState):
    """Positions (n, 3) m, velocities (n, 3) m/s and the multipliers of the last substep
    (None: start from zero)."""

    multipliers: Optional[XpbdMultipliers] = None

