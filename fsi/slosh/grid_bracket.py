"""What a slosh run with the folded hemispherical diaphragm may and may not claim.

The Table 4.1 hemisphere folds in a layer about 16 mm wide (sqrt(R t) / [3 (1 - nu^2)]^1/4),
narrower than the cells of every membrane grid this machine's solvers reach, so the first
slosh mode a run with it measures is its membrane grid's, not converged in the grid. The
notes measure the bracket that holds it, both at half fill:

- the soft side, :data:`TENSION_FIELD_HZ`: the same diaphragm as a tension field (no
  compressive stiffness; N = 14, 24^3 cells; docs/notes/tension-field.md, measured at commit
  0435144 by ``python benchmarks/slosh_diaphragm.py --no-limp --cells 24 --cases "tension
  field"``);
- the stiff side, :data:`FOLD_STATE_BOUND_HZ`: one fold state carried through the membrane
  grids, its static lateral compliance's upper bound on the first mode, still falling with N
  (docs/notes/one-fold-state.md, measured at commit e8de957 by
  ``python benchmarks/nested_compliance.py``).

:func:`grid_caveat` says it in one line, for the run's summary and ``fsi show``.
"""
from __future__ import annotations

TENSION_FIELD_HZ = 1.34
"""Hz: the first mode of the Table 4.1 diaphragm as a tension field at half fill (N = 14)."""

FOLD_STATE_BOUND_HZ = {14: 10.15, 20: 9.27, 26: 5.26, 32: 4.90, 38: 4.61, 54: 4.43, 76: 3.44}
"""membrane grid N -> Hz: one fold state's first-mode upper bound at half fill."""


def grid_caveat(grid_size: int) -> str:
    """One line: a hemispherical diaphragm's first mode on membrane grid ``grid_size`` is that
    grid's, with the bracket the notes measure."""
    finest = max(FOLD_STATE_BOUND_HZ)
    return (f"the N = {grid_size} membrane grid's value, not converged in the grid (the "
            f"hemisphere's folds, about 16 mm, are narrower than its cells): at half fill the "
            f"notes bracket the first mode between {TENSION_FIELD_HZ:.2f} Hz (the tension "
            f"field) and {FOLD_STATE_BOUND_HZ[finest]:.2f} Hz (one fold state's upper bound "
            f"at N = {finest}, still falling with N)")
