"""The added-mass effect in partitioned fluid-structure coupling (Causin, Gerbeau & Nobile 2005).

Reference: P. Causin, J.-F. Gerbeau, F. Nobile, "Added-mass effect in the design of partitioned
algorithms for fluid-structure problems", Comput. Methods Appl. Mech. Engrg. 194 (2005)
4506-4527.

Model
-----
A 2-D channel 0 < x < L, 0 < y < R (m) of inviscid incompressible fluid (density rho_f, kg/m^3),
rigid bottom, open ends (p = 0 at x = 0, L). Its top y = R is a thin elastic wall (generalized
string without the tension term) of mass per area m = rho_s h (kg/m^2) and stiffness per area
k (Pa/m) with vertical displacement eta(x, t) (m), fixed at both ends::

    m eta_tt + k eta = p                       (structure; p: fluid pressure on the wall, Pa)
    p = -rho_f M eta_tt                        (fluid: linearised Euler, Laplace for p)

The added-mass operator M is diagonal in the wall's sine modes sin(i pi x / L)::

    mu_i = L / (i pi tanh(i pi R / L))   (m),   mu_max = mu_1,

so mode i of the coupled system has the mass m + rho_f mu_i. The mass ratio of the case is
q = rho_f mu_max / m (-).

Discretisation (both participants): the wall's N interior nodes x_j = j L / (N + 1) carry the
exchanged fields ``displacement`` (m) and ``pressure`` (Pa); modes by the orthonormal DST-I.
Time: implicit (backward) Euler in windows of dt (s),
v^{n+1} = (eta^{n+1} - eta^n) / dt, a^{n+1} = (v^{n+1} - v^n) / dt::

    structure:  m a^{n+1} + k eta^{n+1} = p^{n+1}
                => eta^{n+1} = (eta^n + dt v^n + dt^2 p / m) / (1 + beta),  beta = k dt^2 / m
    fluid:      p_i^{n+1} = -rho_f mu_i a_i^{n+1}      (same backward differences of eta)

Dirichlet-Neumann coupling: the structure (first) receives the pressure, the fluid (second)
the wall displacement.

Theory
------
*Implicit (Gauss-Seidel) iteration within a window*, on the pressure x = p: one pass
p -> p_tilde has per mode the slope d p_tilde_i / d p_i = -lambda_i,
lambda_i = rho_f mu_i / (m (1 + beta)). Constant relaxation x+ = x + omega (x_tilde - x) has the
error gain 1 - omega (1 + lambda_i), so it converges iff 0 < omega < 2 / (1 + lambda_1). When the
structure is inertia-dominated within the window (beta = k dt^2 / m = (2 pi dt / T)^2 << 1, with
T = 2 pi sqrt(m / k) the wall's in-vacuo period: the spring barely reacts within one window),
this is Causin et al.'s bound::

    omega_max = 2 rho_s h / (rho_s h + rho_f mu_max).

The parameters below keep beta <= 5.4e-4 for every q in [0.1, 100] (k = 4e6 Pa/m, dt = 1e-5 s, so
dt <= T / 270), and the exact discrete bound 2 / (1 + q / (1 + beta)) differs from omega_max by
< 0.06 %. (With a stiff wall or long windows, beta >> 1, the spring carries the pressure and
the bound rises to 2 / (1 + q / (1 + beta)): the added-mass instability is an inertial one.)
Measured: the largest omega for which every window converges (relative pressure change <= tol)
within ``max_iterations``, by bisection. Finite iteration counts bias it low: near the edge the gain
|1 - omega (1 + lambda_1)| must stay below about tol^(1 / max_iterations) (0.964 for 1e-8 and
500 iterations), i.e. the measured value is ~2 % below omega_max.

*Explicit (staggered) scheme*: the structure advances with the pressure of the previous window,
m a^{n+1} + k eta^{n+1} = -rho_f mu a^n. Per mode, with q_i = rho_f mu_i / m, eta^n ~ z^n::

    (z - 1)^2 (z + q_i) + beta z^3 = 0.

For beta -> 0 the roots are z = 1 (double: the physical motion) and the parasitic z = -q_i; at
z = -1 the polynomial is -4 (1 - q_i) - beta, so the scheme is stable iff

    q = rho_f mu_max / (rho_s h) < 1 + k dt^2 / (4 rho_s h)     (backward Euler, lagged pressure)

i.e. q < q* = 1 / (1 - k dt^2 / (4 rho_f mu_max)) (= 1 + 1.3e-6 here); beyond it the parasitic
mode grows by the factor ~q per window. Measured: the growth of the second difference of the
pressure history over 1000 windows (the parasitic mode alternates sign each window; the physical
motion's second difference is O((dt omega_n)^2) small). For diverging runs its rate per window
is the measured spectral radius (it matches the largest root to 5 digits); for stable runs it is
the decay of the start-up kick to the physical level (< 1).

*Aitken and IQN-ILS*: no bound; they should converge for every q.

Parameters are of the order of Causin et al.'s hemodynamic example: L = 6 cm, R = 0.5 cm,
rho_f = 1000 kg/m^3, h = 1 mm, k = E h / ((1 - nu^2) R^2) with E = 75 kPa (0.75e6 dyn/cm^2),
nu = 0.5 (4e6 Pa/m); the mass ratio is swept through the wall's mass per area rho_s h (at h = 1 mm,
rho_s = 1100 kg/m^3 gives q = 68; q = 0.1 needs an unphysically heavy wall, which is the point
of a map).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.fft import dst

from coupling import (AccelerationSettings, ConvergenceMeasure, CouplingError,
                      CouplingSettings, run)

REFERENCE = ("P. Causin, J.-F. Gerbeau, F. Nobile, Added-mass effect in the design of partitioned "
             "algorithms for fluid-structure problems, CMAME 194 (2005) 4506-4527")


@dataclass(frozen=True)
class Problem:
    """The channel and its wall (SI units).

    length L (m), height R (m), rho_f (kg/m^3), rho_s (kg/m^3), thickness h (m),
    stiffness k (Pa/m, per area), n_nodes (interior wall nodes), amplitude of the initial
    displacement bump (m), dt window size (s).
    """

    length: float = 0.06
    height: float = 0.005
    rho_f: float = 1000.0
    rho_s: float = 1100.0
    thickness: float = 1e-3
    stiffness: float = 4e6
    n_nodes: int = 31
    amplitude: float = 1e-4
    dt: float = 1e-5

    @property
    def x(self) -> np.ndarray:
        """Interior wall nodes (m)."""
        return self.length * np.arange(1, self.n_nodes + 1) / (self.n_nodes + 1)

    @property
    def mu(self) -> np.ndarray:
        """Added-mass eigenvalues mu_i = L / (i pi tanh(i pi R / L)) (m), i = 1..N."""
        i = np.arange(1, self.n_nodes + 1)
        return self.length / (i * np.pi * np.tanh(i * np.pi * self.height / self.length))

    @property
    def mass(self) -> float:
        """Wall mass per area rho_s h (kg/m^2)."""
        return self.rho_s * self.thickness

    @property
    def mass_ratio(self) -> float:
        """q = rho_f mu_max / (rho_s h) (-)."""
        return self.rho_f * self.mu[0] / self.mass

    @property
    def beta(self) -> float:
        """k dt^2 / (rho_s h) (-): stiffness against inertia over one window."""
        return self.stiffness * self.dt ** 2 / self.mass

    @property
    def omega_max(self) -> float:
        """Causin et al.'s bound 2 rho_s h / (rho_s h + rho_f mu_max) (-)."""
        return 2.0 * self.mass / (self.mass + self.rho_f * self.mu[0])

    @property
    def omega_max_discrete(self) -> float:
        """Exact bound of this discretisation, 2 / (1 + q / (1 + beta)) (-)."""
        return 2.0 / (1.0 + self.mass_ratio / (1.0 + self.beta))

    def omega_max_finite_iterations(self, max_iterations: int, tol: float) -> float:
        """Where bisection on 'converged within max_iterations to tol' should land (-): the
        gain |1 - omega (1 + lambda_1)| = tol^(1 / max_iterations) at the upper edge, i.e.
        (1 + tol^(1 / max_iterations)) / (1 + q / (1 + beta)) (initial error ~ the solution)."""
        return (1.0 + tol ** (1.0 / max_iterations)) / (1.0 + self.mass_ratio / (1.0 + self.beta))

    @property
    def explicit_critical_mass_ratio(self) -> float:
        """q* = 1 / (1 - k dt^2 / (4 rho_f mu_max)) (-): the explicit scheme is stable iff
        q < q* (q = 1 + beta / 4 solved for q at fixed k, dt, fluid)."""
        return 1.0 / (1.0 - self.stiffness * self.dt ** 2 / (4.0 * self.rho_f * self.mu[0]))

    @property
    def explicit_spectral_radius(self) -> float:
        """Largest |z| over the modes of (z - 1)^2 (z + q_i) + beta z^3 = 0 (-)."""
        q_i = self.rho_f * self.mu / self.mass
        return max(float(np.max(np.abs(np.roots([1.0 + self.beta, qi - 2.0, 1.0 - 2.0 * qi,
                                                  qi])))) for qi in q_i)

    def initial_displacement(self) -> np.ndarray:
        """Bump 4 A x (L - x) / L^2 (m): every odd mode, amplitude ~ 1 / i^3."""
        x = self.x
        return 4.0 * self.amplitude * x * (self.length - x) / self.length ** 2

    def with_mass_ratio(self, q: float) -> "Problem":
        """The same channel and stiffness with rho_s chosen so that q = rho_f mu_max / (rho_s h)."""
        return replace(self, rho_s=self.rho_f * self.mu[0] / (q * self.thickness))


def to_modes(f: np.ndarray) -> np.ndarray:
    """Nodal values -> sine-mode coefficients (orthonormal DST-I, its own inverse)."""
    return dst(f, type=1, norm="ortho")


to_nodes = to_modes


class Wall:
    """Structure participant (first): the elastic wall, backward Euler.

    Reads ``pressure`` (N,) Pa; writes ``displacement`` (N,) m. State: displacement eta (m) and
    velocity v (m/s) at the nodes.
    """

    name = "structure"
    write_fields = ("displacement",)

    def __init__(self, problem: Problem):
        self.p = problem
        self.eta = problem.initial_displacement()
        self.v = np.zeros(problem.n_nodes)

    def initial_data(self):
        return {"displacement": self.eta.copy()}

    def solve_window(self, time, dt, data_in):
        m, k = self.p.mass, self.p.stiffness
        beta = k * dt ** 2 / m
        eta = (self.eta + dt * self.v + dt ** 2 / m * data_in["pressure"]) / (1.0 + beta)
        self.v = (eta - self.eta) / dt
        self.eta = eta
        return {"displacement": eta.copy()}

    def store_checkpoint(self):
        return self.eta.copy(), self.v.copy()

    def restore_checkpoint(self, checkpoint):
        self.eta, self.v = checkpoint[0].copy(), checkpoint[1].copy()


class AddedMassFluid:
    """Fluid participant (second): inviscid incompressible channel as its added-mass operator.

    Reads ``displacement`` (N,) m; writes ``pressure`` (N,) Pa,
    p_i = -rho_f mu_i a_i with the wall acceleration a from the same backward differences as
    :class:`Wall`. State: the wall's last displacement (m) and velocity (m/s). The initial
    pressure is 0 (the fluid knows no acceleration at t = 0).
    """

    name = "fluid"
    write_fields = ("pressure",)

    def __init__(self, problem: Problem):
        self.p = problem
        self.eta = problem.initial_displacement()
        self.v = np.zeros(problem.n_nodes)
        self.gain = problem.rho_f * problem.mu  # kg/m^2 per mode

    def initial_data(self):
        return {"pressure": np.zeros(self.p.n_nodes)}

    def solve_window(self, time, dt, data_in):
        eta = np.asarray(data_in["displacement"], dtype=float)
        v = (eta - self.eta) / dt
        a = (v - self.v) / dt
        self.eta, self.v = eta.copy(), v
        return {"pressure": -to_nodes(self.gain * to_modes(a))}

    def store_checkpoint(self):
        return self.eta.copy(), self.v.copy()

    def restore_checkpoint(self, checkpoint):
        self.eta, self.v = checkpoint[0].copy(), checkpoint[1].copy()


def settings_for(acceleration: str, omega: float = 0.5, tol: float = 1e-8,
                 max_iterations: int = 500, on_max_iterations: str = "error",
                 scheme: str = "implicit-serial", initial_relaxation: float = 0.1
                 ) -> CouplingSettings:
    """Coupling settings: relative change of the pressure <= tol ends a window."""
    return CouplingSettings(
        scheme=scheme, acceleration=acceleration,
        acceleration_settings=AccelerationSettings(relaxation=omega,
                                                   initial_relaxation=initial_relaxation),
        measures=[ConvergenceMeasure("pressure", "relative", tol)],
        max_iterations=max_iterations, on_max_iterations=on_max_iterations)


def couple(problem: Problem, settings: CouplingSettings, n_windows: int):
    """Run the coupling; returns (CouplingLog, list of per-window {field: array})."""
    history = []
    with np.errstate(all="ignore"):  # diverging iterations overflow on purpose
        log = run(Wall(problem), AddedMassFluid(problem), settings, problem.dt, n_windows,
                  on_window=lambda w, data: history.append(
                      {k: np.array(v) for k, v in data.items()}))
    return log, history


def monolithic(problem: Problem, n_windows: int) -> np.ndarray:
    """The coupled system solved as one, (m + rho_f mu_i) a_i + k eta_i = 0 per mode, backward
    Euler: displacement (m) after each window, shape (n_windows, N)."""
    m, k, dt = problem.mass, problem.stiffness, problem.dt
    mass = m + problem.rho_f * problem.mu
    eta = to_modes(problem.initial_displacement())
    v = np.zeros_like(eta)
    out = []
    for _ in range(n_windows):
        new = (mass * (eta + dt * v)) / (mass + k * dt ** 2)
        v, eta = (new - eta) / dt, new
        out.append(to_nodes(eta))
    return np.array(out)


def constant_converges(problem: Problem, omega: float, n_windows: int = 2,
                       max_iterations: int = 500, tol: float = 1e-8) -> bool:
    """Every window converges with constant relaxation ``omega`` (CouplingError = no)."""
    try:
        couple(problem, settings_for("constant", omega, tol, max_iterations), n_windows)
    except CouplingError:
        return False
    return True


def largest_stable_omega(problem: Problem, n_windows: int = 2, max_iterations: int = 500,
                         tol: float = 1e-8, rel_width: float = 1e-3, start: float = 3.0
                         ) -> float:
    """Largest constant omega for which the coupling converges, by bisection (-).

    Halves omega from ``start`` until a run converges (the converging omegas form an interval
    whose ends are a factor >> 2 apart, so halving cannot jump over it), then bisects between
    that omega and the twice as large one that failed, to a relative width ``rel_width``.
    """
    hi, lo = None, start
    while not constant_converges(problem, lo, n_windows, max_iterations, tol):
        hi, lo = lo, lo / 2.0
        if lo < 1e-6:
            return 0.0
    if hi is None:
        raise ValueError(f"omega = {start} already converges; raise start")
    while hi - lo > rel_width * lo:
        mid = 0.5 * (lo + hi)
        if constant_converges(problem, mid, n_windows, max_iterations, tol):
            lo = mid
        else:
            hi = mid
    return lo


def explicit_run(problem: Problem, n_windows: int = 1000) -> dict:
    """Staggered scheme over ``n_windows``.

    The parasitic mode alternates sign each window, so it lives in the second difference
    D_n = p^{n+1} - 2 p^n + p^{n-1} of the pressure history (the physical motion's D is
    O((dt omega_n)^2) |p|, and the first D is the start-up kick of size |p|). Returns
    ``amplification`` |D| of the last 10 windows over the first |D| (-, inf on overflow),
    ``growth_per_window`` (|D_n| / |D_0|)^(1/n) at the last finite n (-; for a diverging run
    the measured spectral radius), and ``diverged`` = amplification > 1.
    """
    _, history = couple(problem, settings_for("constant", scheme="explicit"), n_windows)
    p = np.array([h["pressure"] for h in history])
    p = np.vstack([np.zeros(problem.n_nodes), p])  # p^0 = 0
    with np.errstate(all="ignore"):
        d = np.linalg.norm(p[2:] - 2.0 * p[1:-1] + p[:-2], axis=1)
        amplification = float(np.max(d[-10:]) / d[0])
        finite = np.flatnonzero(np.isfinite(d) & (d > 0) & (d < 1e300))
        n = int(finite[-1])
        growth = float((d[n] / d[0]) ** (1.0 / n))
    if not np.isfinite(amplification):
        amplification = float("inf")
    return {"amplification": amplification, "growth_per_window": growth,
            "diverged": bool(amplification > 1.0)}


def accelerated_run(problem: Problem, acceleration: str, n_windows: int = 10,
                    max_iterations: int = 100, tol: float = 1e-8) -> dict:
    """Implicit-serial with ``aitken`` or ``iqn-ils``: converged (every window), mean and max
    iterations, and the largest deviation from the monolithic solution relative to the
    amplitude (-)."""
    try:
        log, history = couple(problem, settings_for(acceleration, tol=tol,
                                                    max_iterations=max_iterations), n_windows)
    except CouplingError:
        return {"converged": False, "mean_iterations": float("nan"),
                "max_iterations": max_iterations, "error_vs_monolithic": float("nan")}
    eta = np.array([h["displacement"] for h in history])
    err = float(np.max(np.abs(eta - monolithic(problem, n_windows)))) / problem.amplitude
    its = [w.iterations for w in log.windows]
    return {"converged": all(w.converged for w in log.windows),
            "mean_iterations": float(np.mean(its)), "max_iterations": int(max(its)),
            "error_vs_monolithic": err}


def constant_map(problem: Problem, ratios, omegas, max_iterations: int = 200,
                 tol: float = 1e-8) -> np.ndarray:
    """Constant relaxation over (mass ratio, omega), one window each: iterations when converged,
    -1 when diverged (last residual above the first), 0 when contracting but not converged
    within ``max_iterations``. Shape (len(omegas), len(ratios)).

    A cell whose iterates overflow raises :class:`CouplingError` (the coupling stops any window
    with non-finite data, whatever ``on_max_iterations`` says; ``accept`` with the default
    ``accept_residual`` = inf raises for nothing else): it is recorded as diverged (-1)."""
    out = np.zeros((len(omegas), len(ratios)))
    for j, q in enumerate(ratios):
        pq = problem.with_mass_ratio(q)
        for i, om in enumerate(omegas):
            try:
                log, _ = couple(pq, settings_for("constant", om, tol, max_iterations, "accept"),
                                1)
            except CouplingError:
                out[i, j] = -1
                continue
            w = log.windows[0]
            if w.converged:
                out[i, j] = w.iterations
            else:
                first, last = w.residuals[0]["pressure"], w.residuals[-1]["pressure"]
                out[i, j] = 0 if (np.isfinite(last) and last < first) else -1
    return out
