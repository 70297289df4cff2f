"""The total potential of the shell of revolution, its gradient and its Hessian, assembled
over the meridian's elements into a sparse matrix (SciPy).

At a state x (4 n,) and a net uniform pressure mu (Pa) into the bowl,

    Pi(x; mu) = Int [t W(E_s, E_t) + D/2 (kappa_s^2 + 2 nu kappa_s kappa_t + kappa_t^2)] dA_0
                + rho_m t g Int z dA_0 - rho g M_b(x) - mu V_b(x)
                + Int kappa b(d(x)) dA_0                                     (J, up to constants)

with dA_0 = 2 pi R A dS (:mod:`~structure.axisymmetric.kinematics` for the strains,
:mod:`~structure.axisymmetric.laws` for W and the bending density,
:mod:`~structure.axisymmetric.loads` for the loads, :mod:`~structure.axisymmetric.wall` for the
tank wall's barrier, where the shell has one). Each integral is a Gauss sum over the
elements; at a Gauss point the integrand is a function f(u) of the local variables u (6,) with
its exact gradient and Hessian (the strains' chain rule: f_u = f_q q_u, f_uu = q_u^T f_qq q_u +
f_q q_uu), and u = B d (B: :attr:`~structure.axisymmetric.meridian.Meridian.point_basis`) gives
the element's gradient B^T f_u and Hessian B^T f_uu B (8 x 8), added into the global ones.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import numpy as np
import scipy.sparse as sp

from .kinematics import ES, ET, KS, KT, strains
from .laws import bending_density, membrane_density
from .loads import AxisymmetricLoad, moment_density, volume_density
from .meridian import Meridian, local_variables
from .model import ShellOfRevolution
from .wall import wall_density


@dataclass(frozen=True)
class Evaluation:
    """The potential at one state (module doc).

    * energy : Pi (J), inf where the law is undefined (a fold of the meridian, |x'| = 0);
    * internal : (4 n,) the strain energy's gradient (N for r, z entries; N m for r', z');
    * external : (4 n,) the load potential's gradient, the -mu V_b term included;
    * element : (m, 8, 8) the elements' Hessians, or None when not asked for (or where the
      energy is infinite);
    * volume : V_b (m^3), the enclosed volume; volume_gradient : (4 n,) dV_b/dx;
    * shell : the shell evaluated (its scatters assemble the Hessians).
    """

    energy: float
    internal: np.ndarray
    external: np.ndarray
    element: Optional[np.ndarray]
    volume: float
    volume_gradient: np.ndarray
    shell: Optional[ShellOfRevolution] = field(default=None, repr=False)

    @property
    def gradient(self) -> np.ndarray:
        """(4 n,): dPi/dx."""
        return self.internal + self.external

    @cached_property
    def hessian(self) -> Optional[sp.csr_matrix]:
        """(4 n, 4 n) CSR, d2 Pi / dx2; None without element Hessians."""
        return None if self.element is None else self.shell.state_scatter.matrix(self.element)

    @cached_property
    def free_hessian(self) -> Optional[sp.csr_matrix]:
        """(k, k) CSR, T^T (d2 Pi / dx2) T on the free coordinates; None without element
        Hessians."""
        return None if self.element is None else self.shell.free_scatter.matrix(self.element)


def rest_at_points(meridian: Meridian) -> dict:
    """The rest geometry at the Gauss points, flattened to (P,) = (m q,) arrays (the rest's
    local variables u to (P, 6))."""
    return dict(u=meridian.point_rest.reshape(-1, 6), radius=meridian.point_radius.ravel(),
                metric=meridian.point_metric.ravel(),
                sin_angle=meridian.point_sin_angle.ravel(),
                turning=meridian.point_turning.ravel(), area=meridian.point_area.ravel())


def internal_density(shell: ShellOfRevolution, u: np.ndarray, rest: dict, order: int = 2):
    """The strain energy per unit S (P,) J/m at local variables ``u`` (P, 6) and, by
    ``order``, its gradient (P, 6) and Hessian (P, 6, 6) in u."""
    mat = shell.material
    out = strains(u, rest, order)
    q, derivatives = (out, ()) if order == 0 else (out[0], out[1:])
    w, wc, wcc = membrane_density(shell.law, q[:, ES], q[:, ET], shell.tension_field,
                                  shell.residual_stiffness)
    b, bk, bkk = bending_density(shell.flexural_rigidity, mat.poisson_ratio, q[:, KS], q[:, KT])
    area, t = rest["area"], mat.thickness
    f = area * (t * w + b)
    if order == 0:
        return f
    fq = area[:, None] * np.concatenate([t * wc, bk], axis=1)
    g = np.einsum("pa,pai->pi", fq, derivatives[0])
    if order == 1:
        return f, g
    fqq = np.zeros((len(f), 4, 4))
    fqq[:, :2, :2] = t * wcc
    fqq[:, 2:, 2:] = bkk
    fqq *= area[:, None, None]
    dq, ddq = derivatives
    h = np.swapaxes(dq, 1, 2) @ fqq @ dq + np.einsum("pa,paij->pij", fq, ddq)
    return f, g, h


def load_density(shell: ShellOfRevolution, load: AxisymmetricLoad, net_pressure: float,
                 u: np.ndarray, rest: dict, order: int = 2):
    """The load potential per unit S (P,) J/m at ``u`` (P, 6) under ``net_pressure`` mu (Pa)
    and, by ``order``, its gradient (P, 6) and Hessian (P, 6, 6) (module doc)."""
    weight = shell.material.density * shell.material.thickness * load.gravity * rest["area"]
    liquid = load.liquid_density * load.gravity
    vol = volume_density(u, order)
    mom = moment_density(u, order)
    if order == 0:
        f = weight * u[:, 3] - liquid * mom - net_pressure * vol
        return f if shell.wall is None else f + wall_density(shell.wall, u, rest["area"], 0)
    f = weight * u[:, 3] - liquid * mom[0] - net_pressure * vol[0]
    g = -liquid * mom[1] - net_pressure * vol[1]
    g[:, 3] += weight
    h = None if order == 1 else -liquid * mom[2] - net_pressure * vol[2]
    if shell.wall is not None:
        wall = wall_density(shell.wall, u, rest["area"], order)
        f, g = f + wall[0], g + wall[1]
        h = None if order == 1 else h + wall[2]
    return (f, g) if order == 1 else (f, g, h)


def _element_vector(meridian: Meridian, point: np.ndarray) -> np.ndarray:
    """(4 n,): the assembled sum of w B^T g over Gauss points of point gradients (P, 6)."""
    m, q = meridian.point_weight.shape
    per = (meridian.point_weight.ravel()[:, None] * point).reshape(m, q, 6)
    element = np.einsum("mqi,mqij->mj", per, meridian.point_basis)
    return np.bincount(meridian.element_dofs.ravel(), element.ravel(), minlength=meridian.size)


def _element_matrices(meridian: Meridian, point: np.ndarray) -> np.ndarray:
    """(m, 8, 8): each element's sum of w B^T H B of point Hessians (P, 6, 6)."""
    m, q = meridian.point_weight.shape
    per = (meridian.point_weight.ravel()[:, None, None] * point).reshape(m, q, 6, 6)
    basis = meridian.point_basis
    return (np.swapaxes(basis, 2, 3) @ per @ basis).sum(axis=1)


def evaluate(shell: ShellOfRevolution, load: AxisymmetricLoad, state: np.ndarray,
             net_pressure: float, order: int = 2) -> Evaluation:
    """Pi, its gradient and (``order`` 2) its Hessian at ``state`` (4 n,) under ``load`` with
    the net uniform pressure ``net_pressure`` mu (Pa) (module doc); ``order`` 0 gives the
    energy and the enclosed volume only (gradients empty)."""
    if shell.support == "roller" and (load.liquid_density * load.gravity != 0
                                      or net_pressure != 0):
        raise NotImplementedError("a roller rim's static load (the band of wall it slides "
                                  "over) is not modelled: it serves the second variation "
                                  "(structure.axisymmetric.harmonics.roller_closure)")
    meridian = shell.meridian
    weight = meridian.point_weight.ravel()
    u = local_variables(meridian, state).reshape(-1, 6)
    rest = rest_at_points(meridian)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inner = internal_density(shell, u, rest, order)
        outer = load_density(shell, load, net_pressure, u, rest, order)
        vol = volume_density(u, min(order, 1))
    if order == 0:
        energy = float(weight @ (inner + outer))
        volume = float(weight @ vol)
        empty = np.zeros(0)
        return Evaluation(energy if np.isfinite(energy) else np.inf, empty, empty, None,
                          volume, empty)
    energy = float(weight @ (inner[0] + outer[0]))
    if not np.isfinite(energy) or not np.all(np.isfinite(inner[1])):
        empty = np.zeros(meridian.size)
        return Evaluation(np.inf, empty, empty, None, np.nan, empty)
    element = _element_matrices(meridian, inner[2] + outer[2]) if order == 2 else None
    return Evaluation(energy, _element_vector(meridian, inner[1]),
                      _element_vector(meridian, outer[1]), element, float(weight @ vol[0]),
                      _element_vector(meridian, vol[1]), shell)
