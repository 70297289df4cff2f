"""Comparisons and studies: Eqn 6.1, grid extrapolation, static against dynamic, the regime map behind `fsi advise`, the coupled convergence study."""
