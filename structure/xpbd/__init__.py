"""XPBD membrane: Saint Venant-Kirchhoff triangles and calibrated bending as compliant
constraints (Macklin, Mueller & Chentanez 2016), stepped in small substeps (Macklin et al.
2019), with the liquid volume as a hard constraint whose multiplier is the pressure level.

Constraints, each a block of three with a compliance matrix alpha (inverse stiffness) derived
from E, t and nu only, so that the stiffness does not depend on the iteration count or the
time step (the point of XPBD over the thesis's strain limiting):

* membrane, per triangle: the Green strain (E00, E11, E01) in the triangle's reference frame,
  energy 1/2 C^T S C with S = A t E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, 2 (1 - nu)]]
  (plane stress), alpha = S^-1;
* bending, per triangle: the three dihedral-angle changes of :mod:`structure.bending`,
  alpha = K_T^-1 (K_T built from D = E t^3 / 12 (1 - nu^2) and the triangle's shape);
* volume: V(x) - V_target with alpha = 0 (the liquid is incompressible); its multiplier over
  dt^2 is the uniform pressure level (Pa) added to the hydrostatic field;
* tank wall: |x| <= R for every free node (inequality, projected).

Each substep: v += dt W f_ext (hydrostatic pressure p(x) on the node area vectors dV/dx,
gravity), x = x + dt v, then ``iterations`` Gauss-Seidel sweeps of
dlambda = -(J W J^T + alpha / dt^2)^-1 (C + alpha lambda / dt^2), x += W J^T dlambda,
and v = (x - x_start) / dt.

Warm start (statics).  Plain XPBD sets lambda = 0 each substep; with a finite number of
sweeps its steady state then carries a bias of relative size ~ dt^2 k / m (each constraint is
met against positions part-way through the sweep): measured on a Hencky disc, the membrane
looks 2.8x too soft at dt = 2 ms and 1.3x at 0.5 ms.  With ``warm_start`` each substep starts
from the previous multipliers and the positions displaced by W J^T lambda (the implicit-Euler
relation M (x - x_pred) = J^T lambda) and the velocities are removed after each substep (a
quasi-static fixed-point iteration): a steady state then has dlambda = 0 and x = x_start,
which is exactly grad(elastic energy) = f_ext + level dV/dx, whatever dt and the sweep count.
This iteration treats the constraint directions explicitly and is not robust where the
membrane is compressed and buckles (the inversion of the hemisphere): there it can collapse
triangles, and :func:`solve_equilibrium` raises :class:`XpbdDivergence`.  Without warm start
the substeps are dynamic (velocities kept) with kinetic damping (velocities removed at each
kinetic-energy peak), robust but biased as above.

Dynamics.  :func:`step` advances one time window of a coupled run: plain substeps with the
liquid-side pressure of the window held on the nodes and the liquid volume prescribed, the
membrane's own inertia kept (its stiffness bias ~ dt^2, as measured above, sets the substep).
:func:`bdf2_step` takes the window as one implicit BDF2 step from the state one window back,
every force at the window's end, the partner of a liquid collocated there (second order).
:mod:`.damping` damps each node's velocity relative to its neighbours' in :func:`step`'s
substeps (``XpbdSettings.node_damping``).

Layout: :mod:`.model` (fixed data, settings, state, multipliers), :mod:`.kernels` (numba
constraint sweeps), :mod:`.substep` (one substep), :mod:`.statics`
(:func:`solve_equilibrium`), :mod:`.damping` (relative node damping), :mod:`.dynamics`
(:func:`step`, :func:`bdf2_step`, :func:`quasi_static_step`).
"""
from .dynamics import WINDOW_SCHEMES, bdf2_step, quasi_static_step, step
from .model import (XpbdDivergence, XpbdModel, XpbdMultipliers, XpbdSettings, XpbdState,
                    node_external_force)
from .statics import solve_equilibrium

__all__ = ["XpbdDivergence", "XpbdModel", "XpbdMultipliers", "XpbdSettings", "XpbdState",
           "node_external_force", "solve_equilibrium", "step", "bdf2_step",
           "quasi_static_step", "WINDOW_SCHEMES"]
