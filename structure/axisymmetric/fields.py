"""What an equilibrium of the shell of revolution carries, at points of the meridian: its
shape, stretches, changes of curvature, membrane resultants, stresses and moments.

With Psi(lambda_s, lambda_t) = t W the membrane energy per rest area (relaxed by the tension
field where the material wrinkles; :mod:`~structure.axisymmetric.laws`), the Cauchy
resultants per current length are n_s = (1 / lambda_t) dPsi/dlambda_s = t S_s lambda_s /
lambda_t and n_t = (1 / lambda_s) dPsi/dlambda_t = t S_t lambda_t / lambda_s (N/m), S = dW/dE
the second Piola-Kirchhoff stresses: the force across a parallel is 2 pi r n_s along the
meridian's tangent, the transverse shear (the bending's) beside it. Where the sheet is
wrinkled n is per length of the smoothed (wrinkled) surface. The moments per rest length are
the bending density's gradient, M = D (kappa_s + nu kappa_t, kappa_t + nu kappa_s) (N m/m).

The membrane stresses (Pa) are the material's: for the incompressible law those of
:func:`structure.stress.incompressible_stress` at (lambda_s, lambda_t) (the thickness
t / (lambda_s lambda_t), or at a wrinkled point the natural width's), for Saint
Venant-Kirchhoff n / (t lambda_3) with the thickness stretch of
:func:`structure.stress.thickness_stretch`.

At the pole (R = 0) the hoop quantities take their limits (lambda_t = lambda_s,
kappa_t = kappa_s; :func:`structure.axisymmetric.kinematics.pole_limits`).
"""
from __future__ import annotations

import numpy as np

from ..hyperelastic import HyperelasticLaw
from ..stress import incompressible_stress, thickness_stretch
from .kinematics import ES, ET, KS, KT, pole_limits, strains
from .laws import bending_density, membrane_density, regimes
from .meridian import element_basis, locate, rest_geometry
from .model import ShellOfRevolution


def _variables(shell: ShellOfRevolution, state: np.ndarray, arc_length: np.ndarray):
    """u (k, 6) of ``state`` and of the rest at rest arc lengths ``arc_length`` (k,) m."""
    meridian = shell.meridian
    element, xi = locate(meridian, arc_length)
    basis = element_basis(xi, meridian.element_length[element])
    dofs = meridian.element_dofs[element]
    return (np.einsum("kij,kj->ki", basis, state[dofs]),
            np.einsum("kij,kj->ki", basis, meridian.rest_state[dofs]))


def _stresses(shell: ShellOfRevolution, stretch: np.ndarray, resultant: np.ndarray):
    """(stress (k, 2) Pa, thickness (k,) m) of the material (module doc)."""
    t = shell.material.thickness
    if isinstance(shell.law, HyperelasticLaw):
        order = np.argsort(-stretch, axis=1)
        ordered = np.take_along_axis(stretch, order, 1)
        sigma, lam3 = incompressible_stress(shell.law, ordered, shell.tension_field)
        if shell.tension_field and shell.residual_stiffness > 0:
            full, _ = incompressible_stress(shell.law, ordered, False)
            sigma = (1 - shell.residual_stiffness) * sigma + shell.residual_stiffness * full
        back = np.empty_like(sigma)
        np.put_along_axis(back, order, sigma, 1)
        return back, t * lam3
    thickness = t * thickness_stretch(stretch, shell.law.poisson_ratio)
    return resultant / thickness[:, None], thickness


def meridian_fields(shell: ShellOfRevolution, state: np.ndarray,
                    arc_length: np.ndarray) -> dict:
    """At rest arc lengths ``arc_length`` (k,) m in [0, L] of ``state`` (4 n,) (module doc):

    * ``radius`` r and ``height`` z (k,) m;
    * ``stretch`` (k, 2) 1: (lambda_s, lambda_t);
    * ``curvature_change`` (k, 2) 1/m: (kappa_s, kappa_t);
    * ``resultant`` (k, 2) N/m: (n_s, n_t), Cauchy, per current length;
    * ``moment`` (k, 2) N m/m: (M_s, M_t), per rest length;
    * ``stress`` (k, 2) Pa: the membrane stresses; ``thickness`` (k,) m, the current one;
    * ``regime`` (k,) int: TAUT, WRINKLED or SLACK (:mod:`structure.axisymmetric.laws`;
      TAUT throughout without the tension field)."""
    s = np.atleast_1d(np.asarray(arc_length, dtype=float))
    u, u0 = _variables(shell, state, s)
    rest = rest_geometry(u0)
    pole = rest["radius"] <= 1e-12 * shell.radius
    rest["radius"] = np.where(pole, 1.0, rest["radius"])
    with np.errstate(divide="ignore", invalid="ignore"):
        q = strains(u, rest, order=0)
    q[pole] = pole_limits(u[pole], {k: v[pole] for k, v in rest.items()})
    _, stress_2pk, _ = membrane_density(shell.law, q[:, ES], q[:, ET], shell.tension_field,
                                        shell.residual_stiffness)
    stretch = np.sqrt(1.0 + 2.0 * q[:, [ES, ET]])
    resultant = shell.material.thickness * stress_2pk * stretch / stretch[:, ::-1]
    _, moment, _ = bending_density(shell.flexural_rigidity, shell.material.poisson_ratio,
                                   q[:, KS], q[:, KT])
    stress, thickness = _stresses(shell, stretch, resultant)
    regime = regimes(shell.law, q[:, ES], q[:, ET])
    return dict(radius=u[:, 0], height=u[:, 3], stretch=stretch,
                curvature_change=q[:, [KS, KT]], resultant=resultant, moment=moment,
                stress=stress, thickness=thickness,
                regime=regime if shell.tension_field else np.zeros_like(regime))
