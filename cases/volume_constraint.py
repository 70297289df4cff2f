"""The incompressibility dilemma and its cure: a liquid column with prescribed inflow closed by
an elastic lid (Kuettler, Foerster & Wall 2006).

Lid: a string of tension T (N/m) over width l (m), n interior nodes at spacing h, deflection
w (m) up; quasi-static: K w = h p with K = (T/h) tridiag(-1, 2, -1). Liquid below it, density
rho, gravity g; the column receives the prescribed volume V_in(t) = Q t (m^3 per m of width).
The liquid's pressure on the lid is hydrostatic about a uniform level p_0 (Pa):
p_j = p_0 - rho g w_j.

An incompressible liquid fixes the lid volume, h sum(w) = V_in(t), but not p_0: a fluid solver
given a lid motion that violates the volume has no solution, and given one that meets it cannot
tell the level. Two ways to couple:

* ``unconstrained``: the fluid side stands in a near-incompressible liquid of bulk modulus B,
  p_0 = B (V_in - h sum(w)) / V_column. The coupling iteration then carries the gain
  (B / V_column) h^2 1^T K^-1 1, huge for a liquid: Gauss-Seidel with constant relaxation needs
  omega < 2 / (1 + gain) and diverges otherwise;
* ``constrained`` (this project's design): the structure receives the target volume from the
  fluid and solves K w = h (p_dyn + p_0) with h sum(w) = V_in as a Lagrange multiplier p_0 (the
  uniform pressure level it returns); the fluid sends only p_dyn = -rho g w. The iteration gain
  is rho g h^2 |K^-1| << 1 and plain Gauss-Seidel converges in a few iterations, for any B.
"""
from __future__ import annotations

import numpy as np

from coupling import (AccelerationSettings, ConvergenceMeasure, CouplingError,
                      CouplingSettings, run)
from fsi.constants import STANDARD_GRAVITY

WATER_BULK_MODULUS = 2.2e9  # Pa


class Lid:
    """Elastic lid participant. Reads 'pressure' (n,) Pa [and 'target_volume' (1,) m^3/m];
    writes 'displacement' (n,) m and 'pressure_level' (1,) Pa (NaN when unconstrained)."""

    name = "lid"
    write_fields = ("displacement", "pressure_level")

    def __init__(self, n=20, width=0.2, tension=50.0, constrained=True):
        self.n, self.h = n, width / (n + 1)
        self.K = (tension / self.h) * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
        self.constrained = constrained

    def initial_data(self):
        return {"displacement": np.zeros(self.n), "pressure_level": np.zeros(1)}

    def solve_window(self, time, dt, data_in):
        f = self.h * data_in["pressure"]
        if not self.constrained:
            return {"displacement": np.linalg.solve(self.K, f), "pressure_level": np.full(1, np.nan)}
        a = np.full(self.n, self.h)
        kkt = np.block([[self.K, -a[:, None]], [a[None, :], np.zeros((1, 1))]])
        sol = np.linalg.solve(kkt, np.concatenate([f, data_in["target_volume"]]))
        return {"displacement": sol[:-1], "pressure_level": sol[-1:]}

    def store_checkpoint(self):
        return None

    def restore_checkpoint(self, checkpoint):
        pass


class Column:
    """Liquid column participant with prescribed inflow Q (m^2/s), density rho (kg/m^3),
    gravity g (m/s^2) and, when not None, the bulk modulus B (Pa) of a near-incompressible
    stand-in. Reads 'displacement'; writes 'pressure' (n,) Pa and 'target_volume' (1,) m^3/m."""

    name = "column"
    write_fields = ("pressure", "target_volume")

    def __init__(self, n=20, width=0.2, depth=0.3, inflow=0.01, density=1000.0,
                 gravity=STANDARD_GRAVITY, bulk_modulus=None):
        self.n, self.h = n, width / (n + 1)
        self.volume0 = width * depth
        self.q, self.rho, self.g, self.bulk = inflow, density, gravity, bulk_modulus

    def target(self, time, dt):
        return self.q * (time + dt)

    def initial_data(self):
        return {"pressure": np.zeros(self.n), "target_volume": np.zeros(1)}

    def solve_window(self, time, dt, data_in):
        w = data_in["displacement"]
        p = -self.rho * self.g * w
        if self.bulk is not None:  # near-incompressible stand-in: the level from compression
            p = p + self.bulk * (self.target(time, dt) - self.h * w.sum()) / self.volume0
        return {"pressure": p, "target_volume": np.full(1, self.target(time, dt))}

    def store_checkpoint(self):
        return None

    def restore_checkpoint(self, checkpoint):
        pass


def monolithic(lid: Lid, column: Column, time: float, dt: float):
    """Direct solve of lid + incompressible liquid at the end of the window: (w, p_0)."""
    a = np.full(lid.n, lid.h)
    kkt = np.block([[lid.K + column.rho * column.g * lid.h * np.eye(lid.n), -a[:, None]],
                    [a[None, :], np.zeros((1, 1))]])
    sol = np.linalg.solve(kkt, np.concatenate([np.zeros(lid.n),
                                               [column.target(time, dt)]]))
    return sol[:-1], sol[-1]


def couple(constrained: bool, bulk_modulus, acceleration="constant", relaxation=1.0,
           n_windows=5, dt=0.1, max_iterations=100):
    """Run the coupled column; returns (CouplingLog or None, error text, last data)."""
    lid = Lid(constrained=constrained)
    column = Column(bulk_modulus=None if constrained else bulk_modulus)
    settings = CouplingSettings(
        scheme="implicit-serial", acceleration=acceleration,
        acceleration_settings=AccelerationSettings(relaxation=relaxation,
                                                   initial_relaxation=relaxation),
        measures=[ConvergenceMeasure("displacement", "relative", 1e-10),
                  ConvergenceMeasure("pressure", "relative", 1e-10)],
        max_iterations=max_iterations, accelerated_fields=("displacement",))
    data = {}
    try:
        # the column goes first: the lid then solves with this window's target volume
        with np.errstate(over="ignore", invalid="ignore"):  # a diverging run overflows
            log = run(column, lid, settings, dt, n_windows,
                      on_window=lambda w, d: data.update(d))
    except CouplingError as exc:
        return None, str(exc).split(";")[0], data
    return log, "", data
