"""The membrane's residual and tangent stiffness under the liquid's load, on the free degrees
of freedom, for Newton's method.

With the pressure level p0 (Pa) the multiplier of the liquid volume V(x) = V*, the residual is

    r(x, p0) = grad W(x) - F(x, p0),

W the membrane's internal energy (in-plane law, bending, the tank wall's penalty;
:mod:`structure.tangent`) and F the load, in one of two forms (:data:`LOAD_FORMS`):

* ``follower``: F_i = (p_i(x) + p0) dV/dx_i + m_i b, the node pressure on the node's area
  vector (:func:`structure.load.external_force`, what the XPBD membrane and the coupled runs
  apply); its stiffness -dF/dx = -sum_i (p_i + p0) d2V/dx_i dx - dV/dx_i (x) dp_i/dx_i, with
  dp_i/dx_i = rho b for the hydrostatic field p = rho b . x (``load.liquid_density``) and 0
  for a held node pressure (an array);
* ``energy``: F = -grad(-rho b . M1 - p0 V) + m b, the hydrostatic load's potential
  (:mod:`structure.shell`); its stiffness is the Hessian of -rho b . M1 - p0 V.

The fixed nodes' rows and columns are replaced by the identity (their residual is zero), so
that every matrix keeps the one pattern built with the model.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..load import Load
from ..model import MembraneModel
from ..tangent.bending import BendingTerm
from ..tangent.load import LiquidTerm, WallTerm
from ..tangent.membrane import MembraneTerm
from ..tangent.pattern import BlockPattern, assemble
from ..volume import lower_hemisphere_volume

LOAD_FORMS = ("follower", "energy")
WALL_STIFFNESS = 2.5e5
"""Default penalty stiffness (N/m) of the tank wall per node (:class:`structure.shell.
ShellSettings`'s)."""


@dataclass(frozen=True)
class NewtonModel:
    """Fixed data: the grid (``base``), the internal-energy terms, the volume term, the load
    form and the block pattern of their sum (built once)."""

    base: MembraneModel
    terms: tuple
    volume: LiquidTerm
    load_form: str
    pattern: BlockPattern
    fixed_block: np.ndarray
    diagonal_block: np.ndarray

    @classmethod
    def build(cls, base: MembraneModel, terms, load_form: str = "follower") -> "NewtonModel":
        """The model of ``base`` with internal-energy ``terms`` (each with ``element_nodes``
        and ``evaluate``) and the load in ``load_form``."""
        if load_form not in LOAD_FORMS:
            raise ValueError(f"load_form must be one of {LOAD_FORMS}, got {load_form!r}")
        terms = tuple(terms)
        volume = LiquidTerm.of_model(base, 1.0)
        n = len(base.node_mass)
        nodes = np.arange(n, dtype=np.int64)[:, None]
        pattern = BlockPattern.build(n, [t.element_nodes for t in terms]
                                     + [volume.element_nodes, nodes])
        row = np.repeat(np.arange(n), np.diff(pattern.indptr))
        fixed = base.node_fixed
        fixed_block = fixed[row] | fixed[pattern.indices]
        diagonal = np.flatnonzero(fixed)
        diagonal_block = pattern.slots[-1][diagonal, 0, 0]
        return cls(base, terms, volume, load_form, pattern, fixed_block, diagonal_block)

    @classmethod
    def from_xpbd(cls, model, bending: bool = True, wall_stiffness: float = WALL_STIFFNESS,
                  load_form: str = "follower") -> "NewtonModel":
        """The energies of a :class:`structure.xpbd.model.XpbdModel` (its membrane blocks,
        relaxed by the tension field when its material says so, and its bending), with the
        wall as a penalty of ``wall_stiffness`` N/m instead of its projection."""
        base = model.base
        terms = [MembraneTerm.from_xpbd(model)]
        if bending:
            terms.append(BendingTerm(model.bending))
        terms.append(WallTerm(~base.node_fixed, base.radius, wall_stiffness))
        return cls.build(base, terms, load_form)

    @classmethod
    def from_shell(cls, model, wall_stiffness: float = WALL_STIFFNESS,
                   load_form: str = "energy") -> "NewtonModel":
        """The energies of a :class:`structure.shell.ShellModel`."""
        base = model.base
        terms = [MembraneTerm.from_triangle_membrane(model.membrane, model.law)]
        if model.bending is not None:
            terms.append(BendingTerm(model.bending))
        terms.append(WallTerm(~base.node_fixed, base.radius, wall_stiffness))
        return cls.build(base, terms, load_form)

    @property
    def free(self) -> np.ndarray:
        """(n,) bool: the nodes that move."""
        return ~self.base.node_fixed

    @property
    def dof_mass(self) -> np.ndarray:
        """(3n,) kg: each degree of freedom's lumped node mass, zero on the fixed nodes (the
        diagonal of M in a shifted or dynamic tangent)."""
        return np.repeat(np.where(self.free, self.base.node_mass, 0.0), 3)

    def follow(self, x: np.ndarray) -> None:
        """Carry every term's state that follows the path (the bending's hinge turns,
        :meth:`structure.bending.MidedgeBending.follow`) to the accepted positions ``x``."""
        for term in self.terms:
            if hasattr(term, "follow"):
                term.follow(x)

    def path_state(self) -> list:
        """What :meth:`follow` carries, copied (each following term's
        ``path_state()``): a failed step's iterates are taken back by :meth:`restore_path`."""
        return [term.path_state() for term in self.terms if hasattr(term, "follow")]

    def restore_path(self, saved: list) -> None:
        """The following terms back to ``saved`` (:meth:`path_state`)."""
        for term, state in zip((t for t in self.terms if hasattr(t, "follow")), saved):
            term.restore_path(state)

    def liquid_volume(self, x: np.ndarray) -> float:
        """V(x) (m^3): the liquid below the membrane."""
        return lower_hemisphere_volume(self.base.radius) + self.volume.evaluate(x, False)[0]


@dataclass
class Linearisation:
    """The model at one state: residual (n, 3) N (zero on fixed nodes), the tangent (3n, 3n)
    BSR N/m (identity on fixed degrees of freedom), the volume V (m^3) and its gradient
    (n, 3) m^2 (zero on fixed nodes), and the energy (J): the potential without the level's
    term, Pi = W - rho b . M1 - sum m b . x, in the energy form; W alone in the follower
    form, whose load has no potential on the discrete grid; ``blocks``: the element blocks
    the tangent was assembled from, one family per term of the pattern (None without the
    tangent); ``extra``: a matrix (3n, 3n) added to the tangent outside the pattern (a
    self-contact's, whose pairs change), or None."""

    residual: np.ndarray
    matrix: object
    volume: float
    volume_gradient: np.ndarray
    energy: float
    blocks: list | None = None
    extra: object = None


def linearise(model: NewtonModel, x: np.ndarray, level: float, load: Load,
              hessian: bool = True) -> Linearisation:
    """The residual and tangent at positions ``x`` (n, 3) m and pressure level ``level``
    (Pa) under ``load`` (its node pressure without the level, body acceleration and, for the
    hydrostatic field or the energy form, liquid density)."""
    x = np.ascontiguousarray(x, dtype=float)
    base = model.base
    body = np.asarray(load.body_acceleration, dtype=float)
    families, energy = [], 0.0
    grad = np.zeros_like(x)
    for term in model.terms:
        e, g, b = term.evaluate(x, hessian)
        energy += e
        grad += g
        families.append(b)
    v, gv, hv = model.volume.evaluate(x, hessian and model.load_form != "energy")
    volume = lower_hemisphere_volume(base.radius) + v
    if model.load_form == "energy":
        if load.liquid_density is None:
            raise ValueError("the energy form of the load needs load.liquid_density")
        liquid = LiquidTerm(model.volume.triangles, model.volume.sign, -float(level),
                            tuple(-load.liquid_density * body))
        e, g, b = liquid.evaluate(x, hessian)
        energy += e + level * v - float(base.node_mass @ (x @ body))
        grad += g
        families.append(b)
        families.append(None)
    else:
        pressure = np.asarray(load.pressure(x), dtype=float) + level
        grad -= pressure[:, None] * gv
        if hessian:
            tri = model.volume.triangles
            families.append(-pressure[tri][:, :, None, None, None] * hv)
            slope = _pressure_slope(load)
            families.append(None if slope is None else
                            -(gv[:, :, None] * slope[None, None, :])[:, None, None])
        else:
            families.extend([None, None])
    grad -= base.node_mass[:, None] * body[None, :]
    fixed = base.node_fixed
    grad[fixed] = 0.0
    gv[fixed] = 0.0
    matrix = tangent_matrix(model, families) if hessian else None
    return Linearisation(grad, matrix, float(volume), gv, float(energy),
                         families if hessian else None)


def tangent_matrix(model: NewtonModel, families) -> object:
    """The tangent (3n, 3n) BSR N/m of element ``families`` (one per pattern family, None:
    left out), identity on the fixed degrees of freedom."""
    data = assemble(model.pattern, families)
    data[model.fixed_block] = 0.0
    data[model.diagonal_block] = np.eye(3)
    return model.pattern.matrix(data)


def _pressure_slope(load: Load):
    """dp_i/dx_i (3,) Pa/m of the load's node pressure: rho b for the hydrostatic field,
    None for a held array."""
    if not callable(load.node_pressure):
        return None
    if load.liquid_density is None:
        raise ValueError("a node-pressure field needs load.liquid_density for its stiffness "
                         "(the hydrostatic field p = rho b . x)")
    return load.liquid_density * np.asarray(load.body_acceleration, dtype=float)
