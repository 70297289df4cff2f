"""What the pole and the rim hold: the admissible states x = x_held + T y of a meridian.

**Pole** (S = 0, on the axis): r(0) = 0 and a horizontal tangent, dz/dS(0) = 0, so that the
surface is smooth there (no cone point); dr/dS(0) and z(0) are free.

**Rim** (S = L), :data:`SUPPORTS`:

* ``clamped``: r and z held and the slope held, (r', z') parallel to the rest tangent
  (cos Phi_L, sin Phi_L): one free combination, the meridional stretch at the rim;
* ``simply-supported``: r and z held, the slope free;
* ``symmetric``: z and the slope held, r free: a mirror plane through the rim, exact when the
  rest tangent there is vertical (the hemisphere at its equator: the complete sphere);
* ``roller``: r held, z and the slope free: the rim rides on a vertical wall (a sheet lying
  on a liquid whose edge moves as a free surface's contact line does).

T (4 n, k) has orthonormal columns (unit vectors of the free entries, and the clamped slope's
combination), x_held = x_rest - T T^T x_rest is the held part of the rest state, and
y_rest = T^T x_rest.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .meridian import DOFS_PER_NODE, DR, DZ, R, Z, Meridian

SUPPORTS = ("clamped", "simply-supported", "symmetric", "roller")
"""The rim supports (module doc)."""


@dataclass(frozen=True)
class Admissible:
    """x = held + basis @ y: held (4 n,) and basis (4 n, k) sparse CSR (module doc)."""

    held: np.ndarray
    basis: sp.csr_matrix

    def state(self, free: np.ndarray) -> np.ndarray:
        """(4 n,): the state of free coordinates ``free`` (k,)."""
        return self.held + self.basis @ free

    def free(self, state: np.ndarray) -> np.ndarray:
        """(k,): the free coordinates of an admissible ``state`` (4 n,)."""
        return self.basis.T @ state


def admissible(meridian: Meridian, support: str) -> Admissible:
    """The admissible states of ``meridian`` under the pole's conditions and the rim's
    ``support`` (one of :data:`SUPPORTS`)."""
    if support not in SUPPORTS:
        raise ValueError(f"rim support must be one of {SUPPORTS}, got {support!r}")
    rest = meridian.rest_state
    if abs(rest[R]) > 1e-12 * meridian.shape.radius or abs(rest[DZ]) > 1e-12:
        raise ValueError("the rest shape must meet the axis with a horizontal tangent")
    size = meridian.size
    rim = size - DOFS_PER_NODE
    held = {R, DZ}
    if support != "roller":
        held.add(rim + Z)
    if support != "symmetric":
        held.add(rim + R)
    columns = [np.eye(1, size, k).ravel() for k in range(size)
               if k not in held and k not in (rim + DR, rim + DZ)]
    tangent = rest[[rim + DR, rim + DZ]] / np.hypot(rest[rim + DR], rest[rim + DZ])
    if support == "symmetric" and abs(tangent[0]) > 1e-9:
        raise ValueError("a symmetric rim needs a vertical rest tangent there (a mirror "
                         f"plane), got slope angle cos = {tangent[0]:.3g}")
    if support in ("simply-supported", "roller"):
        columns += [np.eye(1, size, rim + DR).ravel(), np.eye(1, size, rim + DZ).ravel()]
    else:
        column = np.zeros(size)
        column[[rim + DR, rim + DZ]] = tangent
        columns.append(column)
    basis = sp.csr_matrix(np.column_stack(columns))
    return Admissible(rest - basis @ (basis.T @ rest), basis)
