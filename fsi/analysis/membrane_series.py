"""The closed-form oracle of a tensioned membrane on a liquid: the first antisymmetric mode
of a flat membrane of uniform tension, pinned at the wall of an upright circular cylinder
and lying on its liquid (Bauer's hydroelastic membrane), as a Rayleigh-Ritz series.

The trial functions are the free surface's modes psi_n = J1(k_n r) cos(theta) with
J1'(k_n a) = 0, each with its potential cosh(k_n (z + h)) (Laplace, no flow through the wall
or the bottom). With a = rho = g = 1 each carries

    stiffness   (1 + Gamma k_n^2) N_n          gravity, and T int |grad psi|^2 = T k_n^2 N_n
    mass        N_n / (k_n tanh(k_n h)) + m N_n   the liquid's added mass, the sheet's own
    N_n       = int psi_n^2 dA = pi / 2 (1 - 1 / k_n^2) J1(k_n)^2

with Gamma = T / (rho g a^2) and m = mu / (rho a) the sheet's areal density mu (kg/m^2)
over the liquid's; the pinned edge sum_n c_n J1(k_n a) = 0 is imposed on the coefficients.
lambda = omega^2 a / g converges as 1 / terms (Richardson over two truncations).
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import eigh
from scipy.special import j1, jnp_zeros


def pinned_membrane_lambda(gamma: float, depth_ratio: float, terms: int,
                           mass_ratio: float = 0.0) -> float:
    """lambda = omega^2 a / g of the first antisymmetric mode with ``terms`` trial functions
    (module doc): ``gamma`` = T / (rho g a^2), ``depth_ratio`` = h / a, ``mass_ratio`` =
    mu / (rho a) (0: a massless sheet)."""
    k = jnp_zeros(1, terms)
    edge = j1(k)
    norm = np.pi / 2 * (1 - 1 / k**2) * edge**2
    stiffness = (1.0 + gamma * k**2) * norm
    mass = norm / (k * np.tanh(k * depth_ratio)) + mass_ratio * norm
    basis, _ = np.linalg.qr(np.column_stack([edge, np.eye(terms)[:, :terms - 1]]))
    free = basis[:, 1:]                          # the coefficients with sum c_n J1(k_n) = 0
    return float(eigh(free.T @ np.diag(stiffness) @ free, free.T @ np.diag(mass) @ free,
                      eigvals_only=True, subset_by_index=[0, 0])[0])


def pinned_membrane_limit(gamma: float, depth_ratio: float, mass_ratio: float = 0.0,
                          terms: tuple[int, int] = (400, 800)) -> float:
    """The series' limit: Richardson at order 1 over the two truncations ``terms``."""
    coarse, fine = (pinned_membrane_lambda(gamma, depth_ratio, n, mass_ratio) for n in terms)
    return (terms[1] * fine - terms[0] * coarse) / (terms[1] - terms[0])
