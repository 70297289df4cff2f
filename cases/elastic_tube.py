"""Elastic tube 1D: a stiff partitioned FSI case for the accelerations of the coupling library.

References: J. Degroote, P. Bruggeman, R. Haelterman, J. Vierendeels, "Stability of a coupling
technique for partitioned solvers in FSI applications", Comput. Struct. 86 (2008) 2224-2234;
the preCICE tutorial ``elastic-tube-1d`` (github.com/precice/tutorials: ``fluid-python``,
``solid-python``, ``precice-config.xml``), whose Python solvers are reimplemented here.

Units: nondimensional with fluid density 1; lengths m, times s, velocities m/s, cross-sections
m^2, pressures and E in m^2/s^2 (Pa per unit density).

Fluid
-----
Quasi-1D incompressible flow in a flexible tube 0 <= x <= L; velocity v and pressure p at the
nodes x_i = i dx, dx = L / N, i = 0..N; the cross-section a comes from the solid::

    d a / d t + d (a v) / d x = 0,
    d (a v) / d t + d (a v^2) / d x + a d p / d x = 0.

Implicit Euler in time (level n -> n + 1), finite volumes around the interior nodes with face
areas A_{i+1/2} = (a_i + a_{i+1}) / 2, face velocities (v_i + v_{i+1}) / 2, upwind momentum
(flow in +x) and a pressure stabilisation of intensity alpha; with h = dx / dt and everything
without a superscript at n + 1, for i = 1..N-1::

    (a_i - a_i^n) h + A_{i+1/2} (v_i + v_{i+1})/2 - A_{i-1/2} (v_{i-1} + v_i)/2
        + alpha (p_{i-1} - 2 p_i + p_{i+1}) = 0,
    (a_i v_i - a_i^n v_i^n) h + A_{i+1/2} (v_i + v_{i+1})/2 v_i
        - A_{i-1/2} (v_{i-1} + v_i)/2 v_{i-1}
        + A_{i+1/2} (p_i + p_{i+1})/2 - A_{i-1/2} (p_{i-1} + p_i)/2
        - (A_{i+1/2} - A_{i-1/2}) p_i = 0.

Boundaries: inflow v_0 = 10 + 3 sin(10 pi t^{n+1}); linear extrapolation p_0 = 2 p_1 - p_2 and
v_N = 2 v_{N-1} - v_{N-2}; non-reflecting outlet (Degroote et al. 2008, eq. 15)
p_N = 2 (c^2 - s^2), s = sqrt(c^2 - p_N^n / 2) - (v_N - v_N^n) / 4. Newton's method (exact
Jacobian) started from level n, to |F| / |(v, p)| <= 1e-10 (as the tutorial).

Two discretisations (:data:`DISCRETISATIONS`), differing only in dx (which enters h alone)
and alpha: ``python``, the published case and the tutorial's Python fluid, dx = L / N = 0.1,
alpha = 0; and ``cpp-2020``, the tutorial's C++ fluid as it was run for the iterations log
behind preCICE's 3.9 iterations per window, dx = 0.001, alpha = 50 (precice/tutorials#195,
where that fluid's results were found to differ from the Python fluid's; it was since changed
to dx = 0.1, alpha = 0). With h 100 times smaller and the pressure Laplacian in continuity,
``cpp-2020`` is a much weaker coupling: its first window needs 5 iterations without any
reused history, the published case's 17.

Solid
-----
Algebraic tube law per node, a = a0 ((p0 - 2 c^2) / (p - 2 c^2))^2 with c^2 = E / (2 r0);
E = 10000, r0 = 1 / sqrt(pi), a0 = 1, p0 = 0. Case: L = 10, N = 100, initial v = 10, p = 0,
a = 1; windows of dt = 0.01 s to t = 1 s (100 windows).

Coupling
--------
Serial-implicit with relative convergence 1e-5 on pressure and on cross-section (as the
tutorial), each window started from preCICE's second-order extrapolation of the past windows'
converged fields (``extrapolation_order = 2``), one set of acceleration settings
(:data:`ACCELERATION_SETTINGS`) for every acceleration.

Order: **solid first, fluid second, pressure accelerated**, unlike the tutorial (fluid first,
cross-section accelerated; :func:`precice_tutorial_settings`, which this code runs too and
which needs 8.39 iterations per window here against preCICE's 8.57). On the cross-section the
interface map is strongly nonlinear: the first fluid solve of a window, with a predicted
cross-section, returns a pressure that is several times the converged one, where the tube law
is far from linear, so even an exact interface Newton needs 4.78 iterations per window on the
cross-section but 3.0 on the pressure (:func:`interface_newton`). The fluid keeps as its a^n
the cross-section of its last solve of the window.

Reference: a monolithic Newton solve of fluid and tube law together (a = a(p) substituted in
the fluid equations, Jacobian by the chain rule), to |F| / |(v, p)| <= 1e-13 per window.

Goal and what limits it
-----------------------
The goal (IQN-ILS <= 4.0 iterations per window) was set from preCICE's 3.9 with its C++ fluid,
that is on ``cpp-2020``. There it holds: IQN-ILS needs 3.01 (the exact interface Newton 3.0)
and the tutorial's own setup 3.87 against preCICE's 3.90, as on ``python`` it needs 8.39
against preCICE's 8.57. On the published case it does not hold, for the reasons below.

Iterations are counted as preCICE counts them: every iteration of a window, the one in which
convergence is detected included (relative measure |x_tilde - x| / |x_tilde| of that
iteration, per field, all must hold). As preCICE, IQN-ILS keeps for reuse the secant of the
iteration in which a window converged (``Acceleration.converged``); before that it was dropped
and IQN-ILS needed 5.26 iterations per window, now 5.11 (IQN-IMVJ 6.45, now 6.27; tutorial
setup 8.73, now 8.39).

On ``python`` the best IQN-ILS setting found needs 5.11 (reuse
8..30 windows with QR2 filter 1e-3 or 1e-2 give 5.11..5.37 now; before the fix a sweep of reuse
8..30, filter 1e-4..3e-2, 20..200 columns and initial relaxation 0.01..0.5 gave 5.2..6.2, without
extrapolation 6.1). The extrapolated pressure of a window is 5 % off the converged one
(third-order Lagrange extrapolation: 1 %), and the interface Jacobian (eigenvalues down to about
-120 at t = 0.2 s, 30 of them beyond 0.1 in modulus) turns that into a first residual of the
order of the pressure itself; the relative measure on the pressure residual then asks for the
pressure to about 1e-7. The Jacobian changes by about 3 % per window, so information reused from
past windows is stale: with the *exact* interface Jacobian of the previous window (converged
state), as a chord or with this window's secants added as IQN-IMVJ does, 3.88 iterations per
window are needed after the first window, 4.0 with it (exact Newton 3.0), while IQN-ILS starts
without history and needs 17 iterations in the first window. IQN-ILS's first step of a window is
about as good as that chord (3 % off the Newton step), its later steps 10-20 % off, because the
20-25 columns that survive the filter come from up to 20 windows (a period of the inflow) back.
Tried without gain (measured means): a better predictor (Lagrange extrapolation of orders 2, 3,
4: 5.34, 5.35, 5.20 before the fix; orders 3, 4 after it, over reuse 10..40 and filter
1e-3..3e-2: 5.02..5.71), relaxing the part of the residual outside the secant span (omega
0.5..0.003: 5.9..13), a linear or quadratic drift-in-time model of the reused secants
(5.6..17.8), IQN-ILS's reuse matrix as the base of in-window multi-vector updates (5.3..5.8,
extrapolated in time 6.0..7.4; these before the fix), parallel-implicit coupling (fails in
window 4). Extrapolating the *exact* Jacobian in time (linear 3.42, quadratic 3.0 after the first
windows) shows what would be needed: a Jacobian good to well under 1 % in the current window,
which a few secants per window from up to a period back cannot supply. preCICE's 3.9
(tutorial's C++ fluid) is for a different discretisation: that fluid used dx = 0.001 and
alpha = 50 instead of dx = 0.1 and alpha = 0 (precice/tutorials issue #195), and its results
differ from the Python fluid's. Run on that discretisation, this code reproduces it.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import MatrixRankWarning, spsolve

from coupling import (EXTRAPOLATION_WEIGHTS, AccelerationSettings, ConvergenceMeasure,
                      CouplingError, CouplingSettings, run)

LENGTH = 10.0              # L (m)
N_CELLS = 100              # N: nodes x_i = i L / N, i = 0..N
E_MODULUS = 10000.0        # E (m^2/s^2)
R0 = 1.0 / np.sqrt(np.pi)  # r0 (m)
A0 = 1.0                   # a0 = pi r0^2 (m^2)
P0 = 0.0                   # p0 (m^2/s^2)
C2 = E_MODULUS / (2.0 * R0)  # c^2 (m^2/s^2)
V_INITIAL = 10.0           # initial velocity (m/s)
DT = 0.01                  # time-window size (s)
N_WINDOWS = 100            # to t = 1 s
NEWTON_TOLERANCE = 1e-10     # fluid Newton: |F| / |(v, p)|
REFERENCE_TOLERANCE = 1e-13  # monolithic Newton: |F| / |(v, p)|
COUPLING_TOLERANCE = 1e-5    # relative, on pressure and on cross-section
MAX_ITERATIONS = 100         # per window; more is a failure (on_max_iterations = "error")

ACCELERATION_SETTINGS = AccelerationSettings(
    relaxation=0.01,          # constant: stable needs omega < 2 / (1 - lambda_min) ~ 0.016
    initial_relaxation=0.01,  # Aitken's first omega per window; IQN-ILS's very first step
    reuse=20,                 # IQN-ILS: past windows kept
    filter_limit=1e-2,        # IQN-ILS: QR2 filter
    max_columns=100,          # IQN-ILS: about the number of interface values (101)
)
EXTRAPOLATION_ORDER = 2


@dataclass(frozen=True)
class Discretisation:
    """The fluid's discretisation constants and preCICE's IQN-ILS mean on it.

    ``cell_length`` dx (m) enters only the time-derivative terms (h = dx / dt); ``alpha``
    (m^3 s^-1 per m^2 s^-2) is the pressure-stabilisation intensity of the continuity rows,
    + alpha (p_{i-1} - 2 p_i + p_{i+1}); ``precice_mean_iterations`` is preCICE's iterations
    per window with the tutorial's coupling setup on this discretisation.
    """

    name: str
    cell_length: float
    alpha: float
    precice_mean_iterations: float
    source: str


DISCRETISATIONS = {d.name: d for d in (
    Discretisation(
        "python", LENGTH / N_CELLS, 0.0, 8.57,
        "the tutorial's fluid-python and the published case: dx = L / N = 0.1, alpha = 0 "
        "(preCICE: precice-Solid-iterations.log, 857 iterations / 100 windows)"),
    Discretisation(
        "cpp-2020", 0.001, 50.0, 3.9,
        "the tutorial's fluid-cpp as it was run for its iterations log (precice/tutorials "
        "commit 174d2db): dx = 0.001, alpha = 50 (precice/tutorials#195); "
        "precice-Fluid-iterations.log, 390 iterations / 100 windows"),
)}
"""Registry of fluid discretisations; ``python`` is the case as published and specified."""
PUBLISHED = DISCRETISATIONS["python"]


class FluidDiverged(RuntimeError):
    """The fluid's Newton iteration failed (the coupling fed it an unphysical cross-section)."""


def inflow_velocity(t: float) -> float:
    """Inlet velocity v_0 (m/s) at time t (s)."""
    return 10.0 + 3.0 * np.sin(10.0 * np.pi * t)


def tube_area(p: np.ndarray) -> np.ndarray:
    """Cross-section a (m^2) of the tube law at pressure p (m^2/s^2)."""
    return A0 * ((P0 - 2.0 * C2) / (p - 2.0 * C2)) ** 2


def tube_area_slope(p: np.ndarray) -> np.ndarray:
    """d a / d p (s^2) of :func:`tube_area`."""
    return 2.0 * tube_area(p) / (2.0 * C2 - p)


@dataclass
class FluidState:
    """One time level: velocity v (m/s), pressure p (m^2/s^2), cross-section a (m^2), at the
    N + 1 nodes."""

    v: np.ndarray
    p: np.ndarray
    a: np.ndarray

    def copy(self) -> "FluidState":
        return FluidState(self.v.copy(), self.p.copy(), self.a.copy())


def initial_state(n: int = N_CELLS) -> FluidState:
    """v = 10 m/s, p = p0, a = a0 at every node."""
    return FluidState(np.full(n + 1, V_INITIAL), np.full(n + 1, P0), np.full(n + 1, A0))


def _outlet_s(v, old: FluidState) -> float:
    """s = sqrt(c^2 - p_N^n / 2) - (v_N - v_N^n) / 4 (m/s) of the non-reflecting outlet."""
    return np.sqrt(C2 - old.p[-1] / 2.0) - (v[-1] - old.v[-1]) / 4.0


def fluid_residual(v, p, a, old: FluidState, dt: float, t_new: float,
                   disc: Discretisation = PUBLISHED) -> np.ndarray:
    """Residual F (2N + 2) of the fluid equations at level n + 1 = (v, p, a), from ``old``,
    discretised as ``disc``.

    Rows 0..N: inlet velocity (m/s), momentum at i = 1..N-1 (m^3/s^2), outlet velocity;
    rows N+1..2N+1: inlet pressure (m^2/s^2), continuity at i = 1..N-1 (m^3/s), outlet pressure.
    """
    n = v.size - 1
    h = disc.cell_length / dt
    am, ai, ap = a[:-2], a[1:-1], a[2:]
    vm, vi, vp = v[:-2], v[1:-1], v[2:]
    sm, sp_ = am + ai, ai + ap  # 2 A_{i-1/2}, 2 A_{i+1/2}
    f = np.empty(2 * n + 2)
    f[0] = inflow_velocity(t_new) - v[0]
    f[1:n] = (h * (old.v[1:-1] * old.a[1:-1] - vi * ai) - 0.25 * sp_ * vi * (vi + vp)
              + 0.25 * sm * vm * (vm + vi)
              + 0.25 * (sm * p[:-2] + (ap - am) * p[1:-1] - sp_ * p[2:]))
    f[n] = -v[n] + 2.0 * v[n - 1] - v[n - 2]
    f[n + 1] = -p[0] + 2.0 * p[1] - p[2]
    f[n + 2:2 * n + 1] = h * (old.a[1:-1] - ai) + 0.25 * (sm * (vm + vi) - sp_ * (vi + vp))
    if disc.alpha:
        f[n + 2:2 * n + 1] += disc.alpha * (p[:-2] - 2.0 * p[1:-1] + p[2:])
    f[2 * n + 1] = -p[-1] + 2.0 * (C2 - _outlet_s(v, old) ** 2)
    return f


def _sparse(entries, shape) -> sp.csc_array:
    """CSC matrix from (rows, cols, values) triples, each broadcast to a common shape."""
    triples = [[x.ravel() for x in np.broadcast_arrays(r, c, val)] for r, c, val in entries]
    rows, cols, vals = (np.concatenate(x) for x in zip(*triples))
    return sp.csc_array((vals, (rows, cols)), shape=shape)


def fluid_jacobians(v, p, a, old: FluidState, dt: float, disc: Discretisation = PUBLISHED):
    """(dF/d(v, p), dF/da) of :func:`fluid_residual`: sparse, (2N+2) x (2N+2) with the unknowns
    ordered (v_0..v_N, p_0..p_N), and (2N+2) x (N+1)."""
    n = v.size - 1
    h = disc.cell_length / dt
    am, ai, ap = a[:-2], a[1:-1], a[2:]
    vm, vi, vp = v[:-2], v[1:-1], v[2:]
    pm, pi, pp = p[:-2], p[1:-1], p[2:]
    sm, sp_ = am + ai, ai + ap
    qm, qp = vm + vi, vi + vp  # 2 x face velocities
    i = np.arange(1, n)
    mom, con = i, n + 1 + i  # rows of momentum and continuity at node i
    stabilisation = ([(con, n + i, disc.alpha), (con, n + 1 + i, -2.0 * disc.alpha),
                      (con, n + 2 + i, disc.alpha)] if disc.alpha else [])
    j_vp = _sparse(stabilisation + [
        (mom, i - 1, 0.25 * sm * (vm + qm)),
        (mom, i, -h * ai - 0.25 * sp_ * (vi + qp) + 0.25 * sm * vm),
        (mom, i + 1, -0.25 * sp_ * vi),
        (mom, n + i, 0.25 * sm),
        (mom, n + 1 + i, 0.25 * (ap - am)),
        (mom, n + 2 + i, -0.25 * sp_),
        (con, i - 1, 0.25 * sm),
        (con, i, 0.25 * (am - ap)),
        (con, i + 1, -0.25 * sp_),
        (0, 0, -1.0),
        (n, [n, n - 1, n - 2], [-1.0, 2.0, -1.0]),
        (n + 1, [n + 1, n + 2, n + 3], [-1.0, 2.0, -1.0]),
        (2 * n + 1, [n, 2 * n + 1], [_outlet_s(v, old), -1.0]),
    ], (2 * n + 2, 2 * n + 2))
    j_a = _sparse([
        (mom, i - 1, 0.25 * (vm * qm + pm - pi)),
        (mom, i, -h * vi + 0.25 * (vm * qm - vi * qp + pm - pp)),
        (mom, i + 1, 0.25 * (pi - pp - vi * qp)),
        (con, i - 1, 0.25 * qm),
        (con, i, -h + 0.25 * (vm - vp)),
        (con, i + 1, -0.25 * qp),
    ], (2 * n + 2, n + 1))
    return j_vp, j_a


def _newton(system, v, p, tolerance, max_iterations=50):
    """Newton on (v, p) from the given values until |F| / |(v, p)| <= tolerance after at least
    one update; ``system(v, p)`` returns (F, dF/d(v, p)). Raises :class:`FluidDiverged`."""
    n1 = v.size
    y = np.concatenate([v, p])
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", MatrixRankWarning)
        for k in range(max_iterations + 1):
            f, jac = system(y[:n1], y[n1:])
            if not np.all(np.isfinite(f)):
                break
            if k > 0 and np.linalg.norm(f) <= tolerance * np.linalg.norm(y):
                return y[:n1], y[n1:]
            y = y + spsolve(jac, -f)
    raise FluidDiverged(f"fluid Newton failed after {k} iterations")


class TubeFluid:
    """Fluid participant: reads ``area`` (m^2), writes ``pressure`` (m^2/s^2) at the nodes."""

    name = "fluid"
    write_fields = ("pressure",)

    def __init__(self, n: int = N_CELLS, disc: Discretisation = PUBLISHED):
        self.state = initial_state(n)
        self.disc = disc

    def initial_data(self):
        return {"pressure": self.state.p.copy()}

    def solve_window(self, time, dt, data_in):
        a = np.array(data_in["area"], dtype=float)
        old = self.state

        def system(v, p):
            return (fluid_residual(v, p, a, old, dt, time + dt, self.disc),
                    fluid_jacobians(v, p, a, old, dt, self.disc)[0])

        v, p = _newton(system, old.v, old.p, NEWTON_TOLERANCE)
        self.state = FluidState(v, p, a)
        return {"pressure": p.copy()}

    def store_checkpoint(self):
        return self.state.copy()

    def restore_checkpoint(self, checkpoint):
        self.state = checkpoint.copy()


class TubeSolid:
    """Solid participant, the stateless tube law: reads ``pressure``, writes ``area``."""

    name = "solid"
    write_fields = ("area",)

    def __init__(self, n: int = N_CELLS):
        self.n = n

    def initial_data(self):
        return {"area": np.full(self.n + 1, A0)}

    def solve_window(self, time, dt, data_in):
        return {"area": tube_area(np.asarray(data_in["pressure"], dtype=float))}

    def store_checkpoint(self):
        return None

    def restore_checkpoint(self, checkpoint):
        pass


def monolithic_reference(n_windows: int = N_WINDOWS, n: int = N_CELLS,
                         disc: Discretisation = PUBLISHED):
    """Pressure (m^2/s^2) and cross-section (m^2), arrays (n_windows, N + 1), at the window
    ends, of Newton on the fluid equations with a = tube_area(p), to REFERENCE_TOLERANCE."""
    state = initial_state(n)
    zero = sp.csc_array((2 * n + 2, n + 1))
    pressures, areas = [], []
    for k in range(n_windows):
        old = state

        def system(v, p):
            a = tube_area(p)
            j_vp, j_a = fluid_jacobians(v, p, a, old, DT, disc)
            j = j_vp + sp.hstack([zero, j_a @ sp.diags_array(tube_area_slope(p))], format="csc")
            return fluid_residual(v, p, a, old, DT, (k + 1) * DT, disc), j

        v, p = _newton(system, old.v, old.p, REFERENCE_TOLERANCE)
        state = FluidState(v, p, tube_area(p))
        pressures.append(p)
        areas.append(state.a)
    return np.array(pressures), np.array(areas)


def coupling_settings(acceleration: str,
                      acceleration_settings: AccelerationSettings = ACCELERATION_SETTINGS,
                      extrapolation_order: int = EXTRAPOLATION_ORDER) -> CouplingSettings:
    """Serial-implicit settings of this case for ``acceleration``."""
    return CouplingSettings(
        scheme="implicit-serial", acceleration=acceleration,
        acceleration_settings=acceleration_settings,
        measures=[ConvergenceMeasure("pressure", "relative", COUPLING_TOLERANCE),
                  ConvergenceMeasure("area", "relative", COUPLING_TOLERANCE)],
        max_iterations=MAX_ITERATIONS, on_max_iterations="error",
        extrapolation_order=extrapolation_order)


def precice_tutorial_settings() -> CouplingSettings:
    """The tutorial's ``precice-config.xml`` (to be run fluid first): IQN-ILS on the
    cross-section, initial relaxation 0.01, 50 columns, 8 windows reused, QR2 filter 1e-3, no
    extrapolation."""
    return coupling_settings("iqn-ils", AccelerationSettings(
        initial_relaxation=0.01, reuse=8, filter_limit=1e-3, max_columns=50),
        extrapolation_order=0)


@dataclass
class Outcome:
    """One coupled run: iterations per window done (the failing window, if any, counted with
    MAX_ITERATIONS), pressure and cross-section at the window ends (n_done, N + 1), and the
    failure message (None when every window converged)."""

    iterations: list
    pressure: np.ndarray
    area: np.ndarray
    failure: str | None

    @property
    def mean_iterations(self) -> float | None:
        return None if self.failure else float(np.mean(self.iterations))


def couple(settings: CouplingSettings, solid_first: bool = True,
           n_windows: int = N_WINDOWS, disc: Discretisation = PUBLISHED) -> Outcome:
    """Run the partitioned case; a window reaching ``max_iterations`` or a failed fluid solve
    ends the run and is recorded as the failure."""
    iterations, pressures, areas = [], [], []

    def record(window, data):
        iterations.append(window.iterations)
        pressures.append(data["pressure"].copy())
        areas.append(data["area"].copy())

    fluid = TubeFluid(disc=disc)
    pair = (TubeSolid(), fluid) if solid_first else (fluid, TubeSolid())
    failure = None
    try:
        run(*pair, settings, DT, n_windows, on_window=record)
    except CouplingError as err:
        failure = str(err)
    except FluidDiverged as err:
        failure = f"window {len(iterations)} (t = {len(iterations) * DT:g} s): {err}"
    if failure:
        iterations.append(settings.max_iterations)
    return Outcome(iterations, np.array(pressures), np.array(areas), failure)


def relative_difference(values: np.ndarray, reference: np.ndarray) -> float:
    """max over windows of max_i |u_i - u_ref_i| / max_i |u_ref_i| (rows: windows)."""
    return float(np.max(np.max(np.abs(values - reference), axis=1)
                        / np.max(np.abs(reference), axis=1)))


def interface_newton(accelerate: str = "pressure", chord: bool = False,
                     n_windows: int = N_WINDOWS, disc: Discretisation = PUBLISHED) -> list:
    """Iterations per window of Newton's method on the interface fixed point with the exact
    interface Jacobian: a bound for what a quasi-Newton acceleration can reach.

    ``accelerate = "pressure"``: x = pressure, solid then fluid (this case's order);
    ``"area"``: x = cross-section, fluid then solid (the tutorial's order). Same measures and
    extrapolation as :func:`coupling_settings`. ``chord``: use throughout a window the Jacobian
    of the previous window's first iteration (what perfectly reused information would give).
    """
    other = "area" if accelerate == "pressure" else "pressure"
    fluid = TubeFluid(disc=disc)
    history = [{"pressure": fluid.state.p, "area": fluid.state.a}]
    stale, iterations = None, []
    for k in range(n_windows):
        weights = EXTRAPOLATION_WEIGHTS[min(EXTRAPOLATION_ORDER, len(history) - 1)]
        guess = {f: sum(w * h[f] for w, h in zip(weights, history)) for f in history[0]}
        x, previous = guess[accelerate], guess[other]
        checkpoint, fresh = fluid.store_checkpoint(), None
        for it in range(1, MAX_ITERATIONS + 1):
            fluid.restore_checkpoint(checkpoint)
            a_in = tube_area(x) if accelerate == "pressure" else x
            p = fluid.solve_window(k * DT, DT, {"area": a_in})["pressure"]
            out = {"pressure": p, "area": tube_area(p) if accelerate == "area" else a_in}
            residuals = (np.linalg.norm(out[accelerate] - x) / np.linalg.norm(out[accelerate]),
                         np.linalg.norm(out[other] - previous) / np.linalg.norm(out[other]))
            if max(residuals) <= COUPLING_TOLERANCE:
                break
            j_vp, j_a = fluid_jacobians(fluid.state.v, p, a_in, checkpoint, DT, disc)
            dp_da = -spsolve(j_vp, j_a.toarray())[N_CELLS + 1:]
            jac = (dp_da * tube_area_slope(x) if accelerate == "pressure"
                   else tube_area_slope(p)[:, None] * dp_da)
            fresh = jac if fresh is None else fresh
            jac = stale if chord and stale is not None else jac
            x = x - np.linalg.solve(jac - np.eye(x.size), out[accelerate] - x)
            previous = out[other]
        stale = fresh
        iterations.append(it)
        history = [out] + history[:EXTRAPOLATION_ORDER]
    return iterations
